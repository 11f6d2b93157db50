"""A study's cells run as one ensemble (:func:`taichi_bearing.pipeline.run_ensemble`): the
task a pool or Dask worker runs for a group of cells that share a mesh.

Like :func:`~taichi_bearing.studies.sweep.run_cell`, the group runs in a child process
(``python -m taichi_bearing.studies.ensemble_task SPEC.json``), so that a crash takes
only its own cells with it; each member's folder is that of its cell run alone.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

from taichi_bearing.errors import InputError

__all__ = ["check_groups", "group_cells", "main", "run_group"]


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
    :class:`~taichi_bearing.studies.sweep.CellResult` per cell; never raises."""
    from taichi_bearing.studies.sweep import _last_line, _result, _threads_here, is_finished

    results = [_result(c, "failed") for c in cells]
    spec = {
        "threads": _threads_here(cells[0]),
        "post": bool(cells[0].post),
        "members": [
            {"case": c.case_path, "overrides": list(c.overrides), "out": c.out_dir} for c in cells
        ],
    }
    env = dict(os.environ)
    root = str(Path(__file__).resolve().parents[2])
    env["PYTHONPATH"] = os.pathsep.join(p for p in (root, env.get("PYTHONPATH")) if p)
    with tempfile.TemporaryDirectory(prefix="ensemble_task_") as tmp:
        path = Path(tmp) / "spec.json"
        path.write_text(json.dumps(spec))
        cmd = [sys.executable, "-m", "taichi_bearing.studies.ensemble_task", str(path)]
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, check=False, env=env)
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
            line = lines.get(c.out_dir) or _last_line(proc.stderr) or _last_line(proc.stdout)
            r.error = f"exit status {proc.returncode}: {line}" if line else (
                f"exit status {proc.returncode}"
            )  # fmt: skip
    return results


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ensemble a spec file describes; each member that did not finish gets one
    stderr line ``OUT_DIR<TAB>reason``. Exit status 0 if every member finished."""
    from taichi_bearing.case import load_case_for_cli
    from taichi_bearing.pipeline import run_ensemble

    args = list(sys.argv[1:] if argv is None else argv)
    spec = json.loads(Path(args[0]).read_text())
    members = spec["members"]
    cases = [load_case_for_cli(m["case"], m["overrides"]) for m in members]
    outs = [m["out"] for m in members]
    try:
        done = run_ensemble(cases, outs, threads=spec["threads"], quiet=True, post=spec["post"])
    except Exception as exc:  # noqa: BLE001 - every member is told why
        reason = " ".join(str(exc).split()) or type(exc).__name__
        for out in outs:
            print(f"{out}\t{reason}", file=sys.stderr)
        return 1
    failed = 0
    for out, d in zip(outs, done, strict=True):
        if isinstance(d, Exception):
            failed += 1
            print(f"{out}\t{' '.join(str(d).split())}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
