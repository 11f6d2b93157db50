"""Taichi initialisation: explicit arch, f64, offline cache, and a check of what was obtained."""

from __future__ import annotations

import os
import time

import taichi as ti

from taichi_bearing.errors import InputError

__all__ = [
    "ARCHS",
    "current_arch",
    "current_threads",
    "init_taichi",
    "other_load",
    "parallel_members",
    "serial_loops",
]

ARCHS = {"cpu": ti.cpu, "cuda": ti.cuda, "vulkan": ti.vulkan}

# (arch name, threads) of the live Taichi runtime started by init_taichi, or None.
_active: tuple[str, int | None] | None = None


def current_arch() -> str | None:
    """Name of the arch init_taichi started in this process (None before any call)."""
    return None if _active is None else _active[0]


def current_threads() -> int:
    """CPU threads of the live runtime (all cores when none were requested)."""
    if _active is None or _active[1] is None:
        return os.cpu_count() or 1
    return _active[1]


def serial_loops() -> tuple[bool, bool]:
    """Whether kernels should run (light, heavy) loops on the calling thread.

    A Taichi CPU parallel loop costs a thread-pool dispatch, measured at 50-90 us per loop
    on the 2-core VM even with one thread: more than a loop over a few thousand light items
    (the cage's nodes, zeroing a list) takes on its own. So on the CPU light loops are
    always serial, and heavy ones (elements, nodes, contact queries) are serial when there
    is one thread; on a GPU both stay parallel.
    """
    cpu = current_arch() == "cpu"
    return cpu, cpu and current_threads() == 1


class _OtherLoad:
    """CPU cores other processes kept busy lately: from ``/proc/stat`` (all CPUs, steal
    time counted as busy) less this process's own CPU time, over the time since the last
    reading (read at most every ``interval`` s). 0 where ``/proc/stat`` is absent."""

    interval = 0.5

    def __init__(self) -> None:
        self.last: tuple[float, float, float] | None = None  # (wall, busy, ours) in s
        self.value = 0.0

    def __call__(self) -> float:
        now = time.monotonic()
        if self.last is not None and now - self.last[0] < self.interval:
            return self.value
        try:
            with open("/proc/stat") as f:
                fields = [float(v) for v in f.readline().split()[1:]]
        except (OSError, ValueError):
            return 0.0
        tick = os.sysconf("SC_CLK_TCK")
        idle = fields[3] + (fields[4] if len(fields) > 4 else 0.0)  # idle + iowait
        busy = (sum(fields[:8]) - idle) / tick  # user ... steal, not guest (in user)
        t = os.times()
        ours = t.user + t.system
        if self.last is not None:
            wall = now - self.last[0]
            self.value = max(0.0, (busy - self.last[1]) - (ours - self.last[2])) / wall
        self.last = (now, busy, ours)
        return self.value


other_load = _OtherLoad()


# Members of a parallel launch per CPU thread: enough items for Taichi's CPU tasks (at
# least 512 items each) to reach every thread; on a GPU, about one member per GPU thread.
PARALLEL_MEMBERS_PER_THREAD = 1024
GPU_MEMBERS = 1 << 16


def parallel_members() -> int:
    """How many members share a phase run as one parallel loop (1 on one CPU thread)."""
    if current_arch() == "cpu":
        threads = current_threads()
        return 1 if threads == 1 else PARALLEL_MEMBERS_PER_THREAD * threads
    return GPU_MEMBERS


def init_taichi(
    arch: str = "cpu", threads: int | None = None, cache_dir: str | os.PathLike | None = None
) -> str:
    """Start Taichi on an explicit backend with f64 defaults, once per process.

    Parameters
    ----------
    arch : {"cpu", "cuda", "vulkan"}
        Backend. ``ti.gpu`` (auto-pick) is never used: it can crash on GPU-less machines.
    threads : int, optional
        CPU threads (``cpu_max_num_threads``); None or 0 means all cores.
    cache_dir : str or path-like, optional
        Offline kernel cache; default ``$TAICHI_BEARING_CACHE_DIR`` when set, else Taichi's.

    Returns
    -------
    str
        The arch obtained (equal to ``arch``).

    Raises
    ------
    InputError
        If ``arch`` is unknown or Taichi fell back to another backend (e.g. no GPU).

    Notes
    -----
    Calling again with the same arch and threads is a no-op; otherwise Taichi is reset and
    started again, which discards every field and compiled kernel of the old runtime.
    """
    global _active
    if arch not in ARCHS:
        raise InputError(f"arch: unknown backend {arch!r}; choose one of {sorted(ARCHS)}")
    threads = int(threads) if threads else None
    if _active == (arch, threads):
        return arch
    if _active is not None:
        ti.reset()
        _active = None
    kwargs: dict = {
        "arch": ARCHS[arch],
        "default_fp": ti.f64,
        "default_ip": ti.i32,
        "offline_cache": True,
        "log_level": ti.WARN,
    }
    cache = cache_dir if cache_dir is not None else os.environ.get("TAICHI_BEARING_CACHE_DIR")
    if cache:
        kwargs["offline_cache_file_path"] = os.fspath(cache)
    if arch == "cpu" and threads:
        kwargs["cpu_max_num_threads"] = threads
    ti.init(**kwargs)
    got = ti.lang.impl.current_cfg().arch
    if got != ARCHS[arch]:
        ti.reset()
        raise InputError(
            f"arch: requested Taichi backend {arch!r} but got {got.name!r} "
            "(no usable device or driver); rerun with --arch cpu"
        )
    _active = (arch, threads)
    return arch
