"""Run the simulator of another git revision beside this checkout's (for the side-by-side
benchmarks and history comparisons): a temporary worktree, and a run in a subprocess
whose ``taichi_bearing`` is that checkout's."""

from __future__ import annotations

import contextlib
import json
import os
import subprocess
import sys
import tempfile
from collections.abc import Iterator, Sequence
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

__all__ = ["ROOT", "run_case", "worktree"]


@contextlib.contextmanager
def worktree(revision: str) -> Iterator[Path]:
    """A detached checkout of ``revision`` in a temporary folder, removed afterwards."""
    with tempfile.TemporaryDirectory(prefix="taichi_bearing_rev_") as tmp:
        path = Path(tmp) / "checkout"
        subprocess.run(
            ["git", "-C", str(ROOT), "worktree", "add", "--detach", str(path), revision],
            check=True,
            capture_output=True,
        )
        try:
            yield path
        finally:
            subprocess.run(
                ["git", "-C", str(ROOT), "worktree", "remove", "--force", str(path)],
                check=False,
                capture_output=True,
            )


def run_case(
    source: Path,
    case: str | Path,
    out: Path,
    overrides: Sequence[str],
    cache_dir: Path,
    quiet: bool = True,
) -> dict:
    """Run ``case`` with the ``taichi_bearing`` of checkout ``source`` into ``out``;
    return its ``summary.json``. A relative ``case`` is that checkout's own file (the
    keys a case file may hold change with the code).

    Each version gets its own offline kernel cache ``cache_dir`` (run once before timing
    to warm it)."""
    case_path = Path(case) if Path(case).is_absolute() else source / case
    cmd = [sys.executable, "-m", "taichi_bearing", str(case_path), "--out", str(out)]
    for item in overrides:
        cmd += ["--set", item]
    # that checkout first, then whatever the caller's path held (e.g. carried packages)
    path = os.pathsep.join(p for p in (str(source), os.environ.get("PYTHONPATH")) if p)
    env = dict(os.environ, PYTHONPATH=path, TAICHI_BEARING_CACHE_DIR=str(cache_dir))
    res = subprocess.run(cmd, cwd=source, env=env, capture_output=quiet, text=True)
    if res.returncode != 0:
        tail = (res.stderr or "")[-2000:] if quiet else ""
        raise SystemExit(f"{source}: run failed (exit {res.returncode})\n{tail}")
    return json.loads((out / "summary.json").read_text())
