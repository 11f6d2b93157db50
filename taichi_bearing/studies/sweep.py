"""Running a study's cells on a local process pool or a Dask cluster.

Every study command (``sweep``, ``passages``, ``convergence``) makes its cells with
:mod:`taichi_bearing.studies.cells` (a grid over any case keys, each cell the case with one
value of every varied key, in its own run folder named from its key=value pairs:
``<out>/load_50kN_speed_500rpm/``; :mod:`taichi_bearing.output.run_folder`) and runs them here.
The run folders are the record: a cell whose ``summary.json`` says ``status: finished`` is
not run again. :func:`run_cell` is the one task function, sent unchanged to either engine;
it runs the case in a child Python process (``python -m taichi_bearing run``), so Taichi's
global state and thread pool belong to that case alone and a crash of one case cannot take
a pool or Dask worker down with it.
"""

from __future__ import annotations

import os
import subprocess
import sys
import uuid
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from taichi_bearing.errors import InputError
from taichi_bearing.output.layout import STATUS_FINISHED
from taichi_bearing.output.run_folder import read_summary
from taichi_bearing.studies.cells import (
    LOAD_KEY,
    SPEED_KEY,
    Axis,
    SweepCell,
    cell_dir_name,
    column_labels,
    make_cells,
    numeric_axis,
    parse_values,
    parse_vary,
)

__all__ = [
    "LOAD_KEY",
    "SPEED_KEY",
    "Axis",
    "CellResult",
    "SweepCell",
    "cell_dir_name",
    "column_labels",
    "is_finished",
    "local_threads",
    "make_cells",
    "numeric_axis",
    "parse_values",
    "parse_vary",
    "run_cell",
    "run_sweep",
]


@dataclass
class CellResult:
    """What a task reports back: the cell's values, status, error line and wall time."""

    name: str
    values: Mapping[str, object]
    out_dir: str
    status: str
    error: str = ""
    wall_s: float = 0.0
    ran: bool = False
    extra: dict = field(default_factory=dict)


def is_finished(run_dir: str | os.PathLike) -> bool:
    """Whether a run folder holds a ``summary.json`` with ``status: finished``."""
    try:
        summary = read_summary(run_dir)
    except (OSError, ValueError):
        return False
    return summary is not None and summary.get("status") == STATUS_FINISHED


def local_threads(workers: int, cores: int | None = None) -> int:
    """Taichi threads for each of ``workers`` concurrent cases: ``max(1, cores // workers)``."""
    cores = (os.cpu_count() or 1) if cores is None else cores
    return max(1, cores // max(1, workers))


def _threads_here(cell: SweepCell) -> int:
    """The cell's threads, or on a Dask worker: its host's cores over its thread slots."""
    if cell.threads is not None:
        return cell.threads
    try:
        from distributed import get_worker

        slots = get_worker().state.nthreads
    except (ImportError, ValueError, AttributeError):
        slots = 1
    return local_threads(slots)


def _last_line(text: str) -> str:
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[-1] if lines else ""


def _result(cell: SweepCell, status: str) -> CellResult:
    return CellResult(cell.name, dict(cell.values), cell.out_dir, status)


def run_cell(cell: SweepCell) -> CellResult:
    """Run one cell into its folder; never raises (a failure is in the result).

    The case runs as ``python -m taichi_bearing run CASE --out DIR --set ... --threads N
    --quiet`` in a child process; its last stderr line is the error of a failed run.
    """
    import time

    res = _result(cell, "failed")
    cmd = [sys.executable, "-m", "taichi_bearing", "run", cell.case_path, "--out", cell.out_dir]
    for ov in cell.overrides:
        cmd += ["--set", ov]
    cmd += ["--threads", str(_threads_here(cell)), "--quiet"]
    if not cell.post:
        cmd.append("--no-post")
    # the child imports this very package, wherever the worker was started
    env = dict(os.environ)
    root = str(Path(__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False, env=env)
    except OSError as exc:
        res.error = f"could not start the run: {exc}"
        return res
    res.wall_s, res.ran = time.perf_counter() - t0, True
    if proc.returncode == 0 and is_finished(cell.out_dir):
        res.status = "finished"
    else:
        line = _last_line(proc.stderr) or _last_line(proc.stdout)
        res.error = f"exit status {proc.returncode}: {line}" if line else (
            f"exit status {proc.returncode}"
        )  # fmt: skip
    return res


def _dask_threads(client) -> int:
    """Threads per task on a Dask cluster: on each host, its cores over the thread slots of
    its workers; the smallest over hosts."""
    cores = client.run(os.cpu_count)
    slots: dict[str, int] = {}
    host_cores: dict[str, int] = {}
    for addr, info in client.scheduler_info()["workers"].items():
        host = info.get("host", addr)
        slots[host] = slots.get(host, 0) + int(info.get("nthreads", 1))
        host_cores[host] = int(cores.get(addr) or 1)
    if not slots:
        return 1
    return min(max(1, host_cores[h] // slots[h]) for h in slots)


def run_sweep(
    cells: Sequence[SweepCell],
    *,
    workers: int | None = None,
    scheduler: str | object | None = None,
    progress: bool = True,
    on_result: Callable[[CellResult], None] | None = None,
    ensemble: int = 1,
) -> list[CellResult]:
    """Run the cells not yet finished; return one result per cell, in the cells' order.

    Parameters
    ----------
    cells : sequence of SweepCell
    workers : int, optional
        Local process pool size (default: the number of cores, at most the cells to run).
        Ignored with ``scheduler``.
    scheduler : str or distributed.Client, optional
        Dask scheduler address (``tcp://host:8786``) or a connected client: the same
        :func:`run_cell` tasks go to that cluster instead of the local pool.
    progress : bool
        A progress bar over cases.
    on_result : callable, optional
        Called with each result as it arrives.
    ensemble : int
        Cells stepped together as one model (:mod:`taichi_bearing.studies.ensemble_task`),
        in groups of this many, in order; 1 (default): each cell on its own. The cells of a
        group must be able to share one model (checked before anything runs).

    Returns
    -------
    list of CellResult
        ``ran`` is False for cells skipped because their folder already held a finished run.
    """
    from tqdm import tqdm

    results: dict[str, CellResult] = {}
    todo = []
    for c in cells:
        if is_finished(c.out_dir):
            results[c.out_dir] = _result(c, "finished")
        else:
            todo.append(c)
    bar = tqdm(total=len(cells), initial=len(cells) - len(todo), unit="case",
               disable=not progress, desc="sweep")  # fmt: skip

    def done(r: CellResult) -> None:
        results[r.out_dir] = r
        bar.update(1)
        bar.set_postfix_str(f"{r.name}: {r.status}")
        if on_result is not None:
            on_result(r)

    if todo:
        from taichi_bearing.studies.ensemble_task import check_groups, group_cells

        groups = group_cells(todo, ensemble)
        check_groups(groups)
        if scheduler is not None:
            _run_dask(groups, scheduler, done)
        else:
            _run_pool(groups, workers, done)
    bar.close()
    return [results[c.out_dir] for c in cells]


def _task(group: list[SweepCell]) -> list[CellResult]:
    """One task: a cell on its own, or a group of cells as one ensemble."""
    if len(group) == 1:
        return [run_cell(group[0])]
    from taichi_bearing.studies.ensemble_task import run_group

    return run_group(group)


def _run_pool(groups: list[list[SweepCell]], workers: int | None, done) -> None:
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed

    n = max(1, min(workers or os.cpu_count() or 1, len(groups)))
    threads = local_threads(n)
    groups = [[c if c.threads is not None else _with_threads(c, threads) for c in g]
              for g in groups]  # fmt: skip
    with ProcessPoolExecutor(max_workers=n, mp_context=mp.get_context("spawn")) as pool:
        futures = {pool.submit(_task, g): g for g in groups}
        for fut in as_completed(futures):
            for r in _outcome(fut, futures[fut]):
                done(r)


def _run_dask(groups: list[list[SweepCell]], scheduler, done) -> None:
    try:
        from distributed import Client, as_completed
    except ImportError:
        raise InputError(
            "--scheduler: dask.distributed is not installed (pip install 'taichi-bearing"
            "[distributed]')"
        ) from None
    own = not hasattr(scheduler, "submit")
    try:
        client = Client(scheduler, timeout="10s") if own else scheduler
    except (OSError, TimeoutError) as exc:
        raise InputError(f"--scheduler: cannot reach {scheduler} ({exc})") from None
    try:
        threads = _dask_threads(client)
        groups = [[c if c.threads is not None else _with_threads(c, threads) for c in g]
                  for g in groups]  # fmt: skip
        # a fresh key per submission: a rerun of a failed cell is a new task, not the
        # cluster's remembered result
        futures = {client.submit(_task, g, key=f"sweep-{g[0].name}-{uuid.uuid4().hex}"): g
                   for g in groups}  # fmt: skip
        for fut in as_completed(list(futures)):
            for r in _outcome(fut, futures[fut]):
                done(r)
    finally:
        if own:
            client.close()


def _with_threads(cell: SweepCell, threads: int) -> SweepCell:
    import dataclasses

    return dataclasses.replace(cell, threads=threads)


def _outcome(fut, group: list[SweepCell]) -> list[CellResult]:
    """The future's results, or a failed result per cell naming the exception (a lost
    worker)."""
    try:
        return fut.result()
    except Exception as exc:  # noqa: BLE001 - one lost case must not stop the sweep
        out = []
        for cell in group:
            r = _result(cell, "failed")
            r.error = f"{type(exc).__name__}: {exc}"
            out.append(r)
        return out
