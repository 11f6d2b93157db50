"""Linear algebra whose answer does not depend on how many threads BLAS runs.

OpenBLAS (numpy's and scipy's) splits a long dot product or matrix-vector product among
its threads and adds the parts: with 2 threads the sum is taken in another order than
with 1, and its last bit can differ. Inside an iterative solver (ARPACK's Lanczos in
``eigsh``) that difference reaches the answer: the global critical step of the coarse
case was 8.772156283820877e-08 s with one BLAS thread and ...875e-08 s with two, and the
whole run differed from its first step (a Dask worker, which sets
``OPENBLAS_NUM_THREADS=1``, and a process pool gave different cells). The solves that set
what the simulator computes run here on one BLAS thread (threadpoolctl: it finds every
BLAS library loaded, numpy's and scipy's own, where an environment variable is read only
once at start); they are a small part of a run, so the cost is small.
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator

from threadpoolctl import threadpool_limits

__all__ = ["one_blas_thread"]


@contextlib.contextmanager
def one_blas_thread() -> Iterator[None]:
    """Context manager (or decorator): every BLAS library on one thread inside it."""
    with threadpool_limits(limits=1, user_api="blas"):
        yield
