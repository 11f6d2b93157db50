"""``python -m taichi_bearing.commands.ensemble_task SPEC.json``: the child process of a
study's ensemble (:func:`taichi_bearing.studies.ensemble_task.run_group`), which runs the
cells the spec lists as one model (:func:`taichi_bearing.pipeline.run_ensemble`).

A command, not part of the study package: the study sits below the pipeline it runs, and
reaches it only through a child process, as a single cell reaches it through
``python -m taichi_bearing run``.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Sequence
from pathlib import Path

__all__ = ["main"]


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
