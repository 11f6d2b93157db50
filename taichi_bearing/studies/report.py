"""Pieces the study reports share (``passages``, ``convergence``): the Markdown and HTML
files from one list of blocks (the run report's own renderers,
:mod:`taichi_bearing.post.report`), a quantity's distribution as table cells, the study's
tables as CSV, and how the study was made (its command and case)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import pandas as pd

from bearing_io.files import atomic_path
from taichi_bearing.post.document import Heading, Para, Table, fmt

__all__ = [
    "failed_blocks",
    "how_made_blocks",
    "save_figure",
    "write_csv",
]


def write_csv(path: Path, df: pd.DataFrame, float_format: str | None = None) -> Path:
    """``df`` as CSV (floats as ``float_format`` where given), written to a temporary name
    and renamed."""
    with atomic_path(path) as tmp:
        df.to_csv(tmp, index=False, float_format=float_format)
    return Path(path)


def save_figure(fig, path: Path) -> Path:
    """Save a matplotlib figure as PNG (temporary name, renamed) and close it."""
    import matplotlib.pyplot as plt

    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return Path(path)


def failed_blocks(results: Sequence) -> list:
    """A paragraph naming each cell that did not finish, with its error (none if all did)."""
    failed = [r for r in results if r.status != "finished"]
    if not failed:
        return []
    return [
        Para(
            "Runs that did not finish: " + "; ".join(f"`{r.name}`: {r.error}" for r in failed) + "."
        )
    ]


def _flat(d: Mapping, prefix: str = "") -> list[tuple[str, object]]:
    return [
        item
        for k, v in d.items()
        for item in (_flat(v, f"{prefix}{k}.") if isinstance(v, Mapping) else [(f"{prefix}{k}", v)])
    ]


def how_made_blocks(command: str, case_path: str | Path, overrides: Sequence[str]) -> list:
    """The section that closes a study report: the command that made it and the case it
    ran (every key, as resolved with the command's ``--set`` overrides; the varied keys
    are set per run on top of these)."""
    from taichi_bearing.case import case_to_dict, load_case

    blocks: list = [Heading("How it was made", 2), Para(f"`{command}`")]
    case = case_to_dict(load_case(case_path, overrides))
    sets = ", ".join(f"`{o}`" for o in overrides) or "none"
    blocks.append(Para(f"Case `{case_path}`, with the command's --set overrides ({sets}):"))
    blocks.append(Table(["key", "value"], [[k, fmt(v)] for k, v in _flat(case)]))
    return blocks
