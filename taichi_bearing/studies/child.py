"""A study cell's child process, tied to the process that started it.

``python -m taichi_bearing.studies.child PARENT_PID MODULE ARGS...`` runs ``MODULE`` as
``__main__`` with ``ARGS`` (``taichi_bearing run CASE --out DIR ...``, or
:mod:`taichi_bearing.studies.ensemble_task`), having first asked the kernel to SIGKILL it
when its parent dies.

Why: a cell runs in a child of a pool thread or of a Dask worker. Were that worker lost
(out of memory, a node gone, ``kill -9``), an orphaned child would run on and write the
cell's folder while the cell's rerun (Dask reschedules a lost task; the user reruns the
command) writes the same folder: two writers, histories of neither. Tied to its parent,
the child dies with it and leaves a partial folder that a rerun starts afresh.

On Linux this is ``prctl(PR_SET_PDEATHSIG, SIGKILL)``; where the kernel offers no such
request the child runs as before (an orphan finishes its cell).
"""

from __future__ import annotations

import os
import runpy
import signal
import sys
from collections.abc import Sequence
from pathlib import Path

__all__ = ["child_command", "child_env", "die_with_parent", "main"]

_PR_SET_PDEATHSIG = 1  # <linux/prctl.h>
_MODULE = "taichi_bearing.studies.child"  # not __name__: "__main__" in the child


def die_with_parent(parent_pid: int) -> bool:
    """Have this process SIGKILLed when its parent exits; True where the kernel agreed.

    Parameters
    ----------
    parent_pid : int
        The pid of the process that started this one. If it is no longer this process's
        parent (it died before the request was made), this process kills itself now, as
        the request would have.

    Notes
    -----
    The kernel sends the signal when the *thread* that started this process ends; the
    thread of a pool or Dask worker that started it waits on it until then.
    """
    if not sys.platform.startswith("linux"):
        return False
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        if libc.prctl(_PR_SET_PDEATHSIG, int(signal.SIGKILL), 0, 0, 0) != 0:
            return False
    except (OSError, AttributeError):
        return False
    if os.getppid() != parent_pid:
        os.kill(os.getpid(), signal.SIGKILL)
    return True


def child_command(module: str, *args: str) -> list[str]:
    """The command line that runs ``python -m MODULE ARGS...`` as a child tied to this
    process (its environment: :func:`child_env`)."""
    return [sys.executable, "-m", _MODULE, str(os.getpid()), module, *args]


def child_env() -> dict[str, str]:
    """This process's environment with the folder holding this very ``taichi_bearing``
    first on ``PYTHONPATH``: the child imports the same package, wherever the worker was
    started."""
    env = dict(os.environ)
    root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
    return env


def main(argv: Sequence[str] | None = None) -> None:
    """``PARENT_PID MODULE ARGS...``: tie this process to its parent, then run ``MODULE``
    as ``__main__`` (its exit status is this process's)."""
    args = list(sys.argv[1:] if argv is None else argv)
    parent, module, rest = int(args[0]), args[1], args[2:]
    die_with_parent(parent)
    sys.argv = [module, *rest]
    runpy.run_module(module, run_name="__main__", alter_sys=True)


if __name__ == "__main__":
    main()
