"""A study's cells run as one ensemble (:func:`taichi_bearing.pipeline.run_ensemble`): the
task a pool or Dask worker runs for a group of cells that share a mesh.

Like :func:`~taichi_bearing.studies.cell_task.run_cell`, the group runs in a child process
(``python -m taichi_bearing.commands.ensemble_task SPEC.json``, tied to this one:
:mod:`taichi_bearing.studies.child`), so that a crash takes only its own cells with it;
each member's folder is that of its cell run alone, marked failed if the child died
without a word.
"""

from __future__ import annotations

import json
import subprocess
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

from taichi_bearing.errors import InputError

__all__ = ["check_groups", "group_cells", "run_group"]


def group_cells(cells: Sequence, size: int) -> list[list]:
    """The cells in groups of at most ``size``, in order (the last may be smaller)."""
    if size < 1:
        raise InputError(f"--ensemble: must be >= 1, got {size}")
    return [list(cells[i : i + size]) for i in range(0, len(cells), size)]


def check_groups(groups: Sequence[Sequence]) -> None:
    """Refuse groups whose cells cannot share one model (one line naming the key).

    Raises
    ------
    InputError
        From :func:`~taichi_bearing.simulation.ensemble.check_members`.
    """
    from taichi_bearing.case import load_case
    from taichi_bearing.simulation.ensemble import check_members

    for group in groups:
        if len(group) > 1:
            check_members([load_case(c.case_path, list(c.overrides)) for c in group])


def run_group(cells: Sequence) -> list:
    """Run a group of cells as one ensemble in a child process; one
    :class:`~taichi_bearing.studies.cell_task.CellResult` per cell; never raises."""
    from taichi_bearing.studies.cell_task import (
        failure_text,
        is_finished,
        last_line,
        mark_failed,
        result_of,
        threads_here,
    )
    from taichi_bearing.studies.child import child_command, child_env

    results = [result_of(c, "failed") for c in cells]
    spec = {
        "threads": threads_here(cells[0]),
        "post": bool(cells[0].post),
        "members": [
            {"case": c.case_path, "overrides": list(c.overrides), "out": c.out_dir} for c in cells
        ],
    }
    with tempfile.TemporaryDirectory(prefix="ensemble_task_") as tmp:
        path = Path(tmp) / "spec.json"
        path.write_text(json.dumps(spec))
        cmd = child_command("taichi_bearing.commands.ensemble_task", str(path))
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, check=False, env=child_env())
        except OSError as exc:
            for r in results:
                r.error = f"could not start the ensemble: {exc}"
            return results
    wall = time.perf_counter() - t0
    lines = {}
    for line in proc.stderr.splitlines():
        out, _, message = line.partition("\t")
        if message:
            lines[out] = message
    for c, r in zip(cells, results, strict=True):
        r.wall_s, r.ran = wall, True
        r.extra["ensemble"] = len(cells)
        if is_finished(c.out_dir):
            r.status = "finished"
        else:
            line = lines.get(c.out_dir) or last_line(proc.stderr) or last_line(proc.stdout)
            r.error = failure_text(proc.returncode, line)
            mark_failed(c.out_dir, r.error)
    return results
