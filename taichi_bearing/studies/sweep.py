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

Faults: the local pool is threads of this process, each waiting on its cell's child, so
the only process a fault can take (out of memory, ``kill -9``) is one cell's own; that cell
is reported failed with the reason and its folder's ``summary.json`` says ``status:
failed`` and why (:func:`mark_failed`), the other cells run on. A child dies with the
process that started it (:mod:`taichi_bearing.studies.child`): a lost Dask worker takes
its cell's child along, and Dask runs the task again on another worker (or, past the
scheduler's ``allowed-failures``, reports it failed, marked the same way). Running the
same command again runs only the cells not finished; finished folders are not touched.
"""

from __future__ import annotations

import os
import uuid
from collections.abc import Callable, Sequence

from taichi_bearing.errors import InputError
from taichi_bearing.studies.cell_task import (
    CellResult,
    failure_text,
    is_finished,
    local_threads,
    mark_failed,
    result_of,
    run_cell,
)
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
    "failure_text",
    "is_finished",
    "local_threads",
    "make_cells",
    "mark_failed",
    "numeric_axis",
    "parse_values",
    "parse_vary",
    "run_cell",
    "run_sweep",
]


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
    ensemble: int | str = 1,
) -> list[CellResult]:
    """Run the cells not yet finished; return one result per cell, in the cells' order.

    Parameters
    ----------
    cells : sequence of SweepCell
    workers : int, optional
        Tasks run at once on this machine, each in its own child process (default: the
        number of cores, at most the cells to run). Ignored with ``scheduler``.
    scheduler : str or distributed.Client, optional
        Dask scheduler address (``tcp://host:8786``) or a connected client: the same
        :func:`run_cell` tasks go to that cluster instead of the local pool.
    progress : bool
        A progress bar over cases.
    on_result : callable, optional
        Called with each result as it arrives.
    ensemble : int or "auto"
        At most this many cells stepped together as one model, only cells that can share
        one (:func:`taichi_bearing.studies.ensemble_task.group_cells`); 1 (default): each
        cell on its own; ``"auto"``: one on the CPU, many on a GPU.

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
            results[c.out_dir] = result_of(c, "finished")
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
        from taichi_bearing.studies.ensemble_task import group_cells

        groups = group_cells(todo, ensemble)
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
    """At most ``workers`` tasks at a time, each a thread waiting on its cells' child
    process: no pool worker process whose loss would break the pool (a
    ``ProcessPoolExecutor`` fails every pending cell when one worker dies)."""
    from concurrent.futures import ThreadPoolExecutor, as_completed

    n = max(1, min(workers or os.cpu_count() or 1, len(groups)))
    threads = local_threads(n)
    groups = [[c if c.threads is not None else _with_threads(c, threads) for c in g]
              for g in groups]  # fmt: skip
    with ThreadPoolExecutor(max_workers=n, thread_name_prefix="cell") as pool:
        futures = {pool.submit(_task, g): g for g in groups}
        try:
            for fut in as_completed(futures):
                for r in _outcome(fut, futures[fut]):
                    done(r)
        except BaseException:
            # Ctrl-C: start no further cell (those running end with their children)
            for fut in futures:
                fut.cancel()
            raise


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


_LOST_WORKER = (
    "its Dask worker died while running it, past the scheduler's allowed failures (out of "
    "memory, a lost node or kill -9)"
)


def _outcome(fut, group: list[SweepCell]) -> list[CellResult]:
    """The future's results, or a failed result per cell naming the exception (a lost
    worker: Dask's ``KilledWorker``), each cell's folder marked so (:func:`mark_failed`)."""
    try:
        return fut.result()
    except Exception as exc:  # noqa: BLE001 - one lost case must not stop the sweep
        kind = type(exc).__name__
        # Dask's message names the task key and a worker address: not what a user needs
        text = _LOST_WORKER if kind == "KilledWorker" else " ".join(str(exc).split())
        out = []
        for cell in group:
            r = result_of(cell, "failed")
            r.error = f"{kind}: {text}"
            mark_failed(cell.out_dir, r.error)
            out.append(r)
        return out
