"""Copies between numpy arrays and Taichi fields, many fields to one kernel.

Taichi's own ``field.from_numpy``, ``to_numpy`` and ``fill`` take the field as a template
argument: each field compiles a kernel of its own at its first copy (~0.07 s on the 2-core
VM). A bearing model has some forty fields to fill when it is built, so these small
compiles took more time than the step's own (a third of the test suite's time,
``benchmarks/taichi_bearing/bench_compile.py``). Here the fields of one call share one kernel per
element type: one compile per call site and model instead of one per field. The copies
are exact (no arithmetic), so every value is what Taichi's copies give.

Fields must be one-dimensional, of scalars or of vectors (``ti.Vector.field``).
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
from collections.abc import Iterable, Sequence

import numpy as np
import taichi as ti

__all__ = ["array_shape", "constant", "download", "fill", "is_transferable", "upload"]


# the element types a field may hold: each has its own buffer in a copy kernel
_TYPES = {"f64": np.float64, "i32": np.int32, "i64": np.int64}


def _layout(field) -> tuple[int, int, int]:
    """``(items, width, type)`` of a 1-D field: width 0 for scalars, type the index of
    its element type in ``_TYPES``."""
    shape = tuple(field.shape)
    if len(shape) != 1:
        raise ValueError(f"transfer: only 1-D fields are supported, got shape {shape}")
    width = 0
    if isinstance(field, ti.MatrixField):
        if field.m != 1:
            raise ValueError(f"transfer: only vector fields are supported, got {field.n}x{field.m}")
        width = field.n
    names = [name for name in _TYPES if getattr(ti, name) == field.dtype]
    if not names:
        raise ValueError(f"transfer: fields of {field.dtype} are not supported")
    return shape[0], width, list(_TYPES).index(names[0])


def is_transferable(field) -> bool:
    """Whether :func:`upload`, :func:`download` and :func:`fill` take this field."""
    try:
        _layout(field)
    except ValueError:
        return False
    return True


def array_shape(field) -> tuple[int, ...]:
    """The shape of the numpy array that holds the field: ``(n,)`` or ``(n, width)``."""
    n, width, _ = _layout(field)
    return (n,) if width == 0 else (n, width)


def _plan(fields: Sequence) -> tuple[tuple, list[int]]:
    """Each field's static ``(type, start, items, width)`` in its type's flat buffer, and
    the buffers' sizes."""
    plan, sizes = [], [0] * len(_TYPES)
    for f in fields:
        n, width, kind = _layout(f)
        plan.append((kind, sizes[kind], n, width))
        sizes[kind] += n * max(width, 1)
    return tuple(plan), sizes


def _buffers(sizes: list[int]) -> list[np.ndarray]:
    return [np.empty(max(size, 1), dtype=t) for size, t in zip(sizes, _TYPES.values(), strict=True)]


# One loop over the items, every field's copy in its body: a loop per field costs a
# compiled task each (16 fields: 0.41 s, against 0.16 s for the one loop).
@ti.kernel
def _k_copy(fields: ti.template(), plan: ti.template(), top: ti.template(),
            into_fields: ti.template(), zero: ti.template(), b0: ti.types.ndarray(ndim=1),
            b1: ti.types.ndarray(ndim=1), b2: ti.types.ndarray(ndim=1)):  # fmt: skip
    # buffers to fields (into_fields) or fields to buffers, then the fields zeroed (zero)
    for i in range(top):
        for k in ti.static(range(len(fields))):
            f = ti.static(fields[k])
            kind, start, n, width = ti.static(plan[k])
            b = ti.static((b0, b1, b2)[kind])
            if i < n:
                for c in ti.static(range(max(width, 1))):
                    if ti.static(into_fields and width == 0):
                        f[i] = b[start + i]
                    elif ti.static(into_fields):
                        f[i][c] = b[start + i * width + c]
                    elif ti.static(width == 0):
                        b[start + i] = f[i]
                        if ti.static(zero):
                            f[i] = 0
                    else:
                        b[start + i * width + c] = f[i][c]
                        if ti.static(zero):
                            f[i][c] = 0


def _top(plan: tuple) -> int:
    return max((p[2] for p in plan), default=0)


# Fields a kernel copies at most: Taichi warns of a static loop unrolled more than 32 times.
MAX_FIELDS = 32


def _chunks(items: Sequence) -> list[Sequence]:
    return [items[k : k + MAX_FIELDS] for k in range(0, len(items), MAX_FIELDS)]


def upload(pairs: Iterable[tuple[object, np.ndarray]]) -> None:
    """Copy each array into its field, as ``field.from_numpy(array)`` does.

    Parameters
    ----------
    pairs : iterable of (field, numpy.ndarray)
        The array's shape is the field's (``(n,)`` or ``(n, width)``); its values are cast
        to the field's type, as numpy's ``astype`` casts them.

    Raises
    ------
    ValueError
        If an array's shape is not its field's, or a field is not a 1-D field of
        f64, i32 or i64 scalars or vectors.
    """
    checked = []
    for field, a in pairs:  # every shape before any field is written
        a, want = np.asarray(a), array_shape(field)
        if a.shape != want:
            raise ValueError(f"transfer: array of shape {a.shape} for a field of shape {want}")
        checked.append((field, a))
    for chunk in _chunks(checked):
        _upload(chunk)


def _upload(pairs: Sequence) -> None:
    fields = tuple(f for f, _ in pairs)
    plan, sizes = _plan(fields)
    bufs = _buffers(sizes)
    for (kind, start, _n, _width), (_, a) in zip(plan, pairs, strict=True):
        bufs[kind][start : start + a.size] = a.ravel()
    _k_copy(fields, plan, _top(plan), True, False, *bufs)


def download(fields: Sequence, zero: bool = False) -> list[np.ndarray]:
    """Copies of the fields, as ``field.to_numpy()`` gives them, in their order.

    Parameters
    ----------
    fields : sequence of fields
    zero : bool
        Set every field to zero after it is read, in the same kernel (a sum taken and
        started again), as ``field.fill(0)`` after ``to_numpy`` would.
    """
    return [a for chunk in _chunks(tuple(fields)) for a in _download(chunk, zero)]


def _download(fields: tuple, zero: bool) -> list[np.ndarray]:
    plan, sizes = _plan(fields)
    bufs = _buffers(sizes)
    _k_copy(fields, plan, _top(plan), False, bool(zero), *bufs)
    out = []
    for kind, start, n, width in plan:
        flat = bufs[kind][start : start + n * max(width, 1)].copy()
        out.append(flat if width == 0 else flat.reshape(n, width))
    return out


def constant(fields: Sequence, value: float | int = 0) -> list[tuple[object, np.ndarray]]:
    """``(field, array of value)`` pairs for :func:`upload`: fields set to a constant in
    the same kernel as other fields' values."""
    return [(f, np.full(array_shape(f), value)) for f in fields]


def fill(fields: Sequence, value: float | int = 0) -> None:
    """Set every item (every component) of each field to ``value``, as ``field.fill`` does."""
    upload(constant(fields, value))
