"""One cell's task: its case run in a child process into its run folder, what it reports
back, and what a cell whose process was lost leaves in its folder.

:func:`run_cell` is the task a pool thread or Dask worker runs for a cell on its own
(:mod:`taichi_bearing.studies.ensemble_task` for a group); both engines are in
:mod:`taichi_bearing.studies.sweep`.
"""

from __future__ import annotations

import os
import signal
import subprocess
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path

from taichi_bearing.output.layout import STATUS_FAILED, STATUS_FINISHED, STATUS_RUNNING
from taichi_bearing.output.run_folder import read_summary
from taichi_bearing.output.summary import write_partial_summary
from taichi_bearing.studies.cells import SweepCell
from taichi_bearing.studies.child import child_command, child_env

__all__ = [
    "CellResult",
    "failure_text",
    "is_finished",
    "last_line",
    "local_threads",
    "mark_failed",
    "result_of",
    "run_cell",
    "threads_here",
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


def threads_here(cell: SweepCell) -> int:
    """The cell's threads, or on a Dask worker: its host's cores over its thread slots."""
    if cell.threads is not None:
        return cell.threads
    try:
        from distributed import get_worker

        slots = get_worker().state.nthreads
    except (ImportError, ValueError, AttributeError):
        slots = 1
    return local_threads(slots)


def last_line(text: str) -> str:
    """The last line of ``text`` that is not blank, stripped."""
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    return lines[-1] if lines else ""


def result_of(cell: SweepCell, status: str) -> CellResult:
    """A result of ``cell`` with ``status`` and nothing run yet."""
    return CellResult(cell.name, dict(cell.values), cell.out_dir, status)


def failure_text(returncode: int, line: str = "") -> str:
    """Why a cell's child did not finish: the signal that killed it, or its exit status
    and its last output line (a killed process said nothing about it: no line).

    Examples
    --------
    >>> failure_text(-9, "[Taichi] Starting on arch=x64")
    'killed by SIGKILL (out of memory, a lost worker or kill -9)'
    >>> failure_text(3, "error: a value is NaN")
    'exit status 3: error: a value is NaN'
    """
    if returncode < 0:
        try:
            name = signal.Signals(-returncode).name
        except ValueError:
            name = f"signal {-returncode}"
        why = " (out of memory, a lost worker or kill -9)" if -returncode == signal.SIGKILL else ""
        return f"killed by {name}{why}"
    head = f"exit status {returncode}"
    return f"{head}: {line}" if line else head


def mark_failed(run_dir: str | os.PathLike, reason: str) -> bool:
    """Say in a cell's folder that its run died without saying so itself.

    A run writes ``summary.json`` with status ``running`` before its transient and its
    final status at the end; a process killed hard (or one that died before the
    transient) leaves ``running`` or no summary at all. Such a folder gets status
    ``failed`` and ``stop_reason``, written atomically, the rest of its summary kept
    (``post`` checks what was recorded, as for any run that did not finish).

    Parameters
    ----------
    run_dir : str or path-like
        The cell's folder.
    reason : str
        Why it failed (:func:`failure_text`).

    Returns
    -------
    bool
        Whether the folder was marked: False when there is no folder, or its run said
        itself how it ended (finished, interrupted, stopped).
    """
    run_dir = Path(run_dir)
    if not run_dir.is_dir():
        return False
    try:
        summary = read_summary(run_dir) or {}
    except (OSError, ValueError):
        summary = {}  # unreadable: replaced by one that says what happened
    if summary.get("status", STATUS_RUNNING) != STATUS_RUNNING:
        return False
    summary.update(status=STATUS_FAILED, stop_reason=reason)
    write_partial_summary(run_dir, summary)
    return True


def run_cell(cell: SweepCell) -> CellResult:
    """Run one cell into its folder; never raises (a failure is in the result).

    The case runs as ``python -m taichi_bearing run CASE --out DIR --set ... --threads N
    --quiet`` in a child process tied to this one
    (:func:`~taichi_bearing.studies.child.child_command`); its last stderr line is the
    error of a failed run. A child that died without a word (killed) leaves its folder
    marked failed (:func:`mark_failed`).
    """
    import time

    res = result_of(cell, "failed")
    args = ["run", cell.case_path, "--out", cell.out_dir]
    for ov in cell.overrides:
        args += ["--set", ov]
    args += ["--threads", str(threads_here(cell)), "--quiet"]
    if not cell.post:
        args.append("--no-post")
    cmd = child_command("taichi_bearing", *args)
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False, env=child_env())
    except OSError as exc:
        res.error = f"could not start the run: {exc}"
        return res
    res.wall_s, res.ran = time.perf_counter() - t0, True
    if proc.returncode == 0 and is_finished(cell.out_dir):
        res.status = "finished"
    else:
        line = last_line(proc.stderr) or last_line(proc.stdout)
        res.error = failure_text(proc.returncode, line)
        mark_failed(cell.out_dir, res.error)
    return res
