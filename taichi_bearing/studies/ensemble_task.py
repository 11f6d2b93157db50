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

__all__ = ["AUTO", "GPU_ENSEMBLE", "group_cells", "parse_ensemble", "run_group"]


AUTO = "auto"
GPU_ENSEMBLE = 64
"""Members of an automatic ensemble on a GPU: the largest size of issue 45's table (one
passage of the default mesh a member, ~28,000 elements: ~2 GB for 64 members)."""


def parse_ensemble(text: str) -> int | str:
    """``--ensemble``'s value: a count >= 1 or ``auto``.

    Raises
    ------
    InputError
        Naming ``--ensemble``, for anything else.
    """
    if str(text).strip().lower() == AUTO:
        return AUTO
    try:
        size = int(text)
    except (TypeError, ValueError):
        raise InputError(f"--ensemble: a count >= 1 or 'auto', got {text!r}") from None
    if size < 1:
        raise InputError(f"--ensemble: must be >= 1, got {size}")
    return size


def group_cells(cells: Sequence, size: int | str) -> list[list]:
    """The cells in ensembles of at most ``size``: cells go together only where their
    cases can share one model (equal
    :func:`~taichi_bearing.simulation.ensemble.member_signature`), so that a study mixing
    meshes (a convergence study's levels) still fills its ensembles; the groups in the
    order of their first cells.

    Parameters
    ----------
    cells : sequence of SweepCell
    size : int or "auto"
        At most this many cells a model; ``"auto"``: on the CPU one (a cell runs alone), on a
        GPU (``run.arch`` not cpu) up to :data:`GPU_ENSEMBLE`, which keeps the device busy.

    Raises
    ------
    InputError
        If ``size`` is neither a count >= 1 nor ``"auto"``, or if a count > 1 would group
        no two of two or more cells (naming the first key that keeps them apart).
    """
    from taichi_bearing.case import load_case
    from taichi_bearing.simulation.ensemble import check_members, member_signature

    size = parse_ensemble(size)
    if size == 1:
        return [[c] for c in cells]
    cases = [load_case(c.case_path, list(c.overrides)) for c in cells]
    kinds: dict[tuple, list] = {}
    for cell, case in zip(cells, cases, strict=True):
        kinds.setdefault(member_signature(case), []).append((cell, case))
    if size != AUTO and len(cells) > 1 and len(kinds) == len(cells):
        try:
            check_members(cases[:2])
        except InputError as exc:
            raise InputError(f"{exc}: --ensemble {size} would group no two cells") from None
    groups = []
    for same in kinds.values():
        n = size
        if n == AUTO:
            n = 1 if same[0][1].run.arch == "cpu" else GPU_ENSEMBLE
        cells_of_kind = [cell for cell, _ in same]
        groups += [cells_of_kind[i : i + n] for i in range(0, len(same), n)]
    first = {id(c): k for k, c in enumerate(cells)}
    return sorted(groups, key=lambda g: first[id(g[0])])


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
