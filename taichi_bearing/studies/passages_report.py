"""Outputs of ``python -m taichi_bearing passages``: ``passages.csv`` (one row per
passage), ``runs.csv`` (one per run), a box and strip plot of every passage quantity and
``passages_report.md`` / ``.html``, which leads with the verdict (what the rollers did at
the spall's entry and exit: median and range over every passage, and the runs that did
not finish), then the median and interquartile range of each quantity, the figure, the
per-run and per-passage tables, and how the study was made."""

from __future__ import annotations

import os
import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from taichi_bearing.checks.passages import PASSAGE_QUANTITIES
from taichi_bearing.checks.quantities import QUANTITIES, QUANTITY
from taichi_bearing.post.document import Heading, Image, Para, Table, fmt, write_documents
from taichi_bearing.post.spall_report import passage_sentences, statistics_table
from taichi_bearing.studies.passage_study import group_statistics
from taichi_bearing.studies.report import failed_blocks, save_figure, write_csv

__all__ = ["passages_figure", "write_passages_outputs"]


def passages_figure(passages: pd.DataFrame, path: Path, by: str = "run") -> Path:
    """One panel per passage quantity: a box (median, quartiles, whiskers to 1.5 IQR) over
    every passage, with each passage as a dot coloured by its ``by`` column."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    names = list(PASSAGE_QUANTITIES)
    fig, axes = plt.subplots(1, len(names), figsize=(1.9 * len(names), 3.8), squeeze=False)
    groups = list(dict.fromkeys(passages[by])) if len(passages) else []
    colours = plt.get_cmap("viridis")(np.linspace(0, 0.9, max(1, len(groups))))
    rng = np.random.default_rng(0)  # the same jitter on every redraw
    for ax, name in zip(axes[0], names, strict=True):
        q = QUANTITY[name]
        v = pd.to_numeric(passages[name], errors="coerce").to_numpy(dtype=float) * q.scale
        ok = np.isfinite(v)
        if ok.any():
            ax.boxplot(v[ok], widths=0.5, showfliers=False)
        for colour, g in zip(colours, groups, strict=False):
            sel = ok & (passages[by] == g).to_numpy()
            ax.plot(1 + rng.uniform(-0.18, 0.18, sel.sum()), v[sel], "o", ms=4,
                    color=colour, alpha=0.8)  # fmt: skip
        ax.set_title("\n".join(textwrap.wrap(q.label, 22)), fontsize=7)
        ax.set_ylabel(q.unit, fontsize=8)
        ax.set_xticks([])
        ax.tick_params(labelsize=7)
        ax.grid(True, axis="y", alpha=0.3)
    fig.suptitle(f"{int(len(passages))} passages; dots coloured by {by}", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path)


def _per_passage(passages: pd.DataFrame, angle: str | None) -> Table:
    names = list(PASSAGE_QUANTITIES)
    head = ["run", *([angle] if angle else []), "roller"]
    head += [f"{QUANTITY[n].label} ({QUANTITY[n].unit})" for n in names]
    rows = []
    for p in passages.to_dict("records"):
        cells = [str(p["run"]), *([fmt(p[angle])] if angle else []), fmt(p["roller"])]
        cells += [fmt(None if pd.isna(p[n]) else float(p[n]) * QUANTITY[n].scale) for n in names]
        rows.append(cells)
    return Table(head, rows)


def write_passages_outputs(
    passages: pd.DataFrame,
    runs: pd.DataFrame,
    out: str | os.PathLike,
    *,
    title: str,
    intro: str,
    angle: str | None,
    results: Sequence = (),
    how: Sequence = (),
) -> dict[str, Path]:
    """Write ``passages.csv``, ``runs.csv``, ``figures/passages.png`` and
    ``passages_report.md`` / ``.html`` into ``out``.

    Parameters
    ----------
    passages, runs : DataFrame
        :func:`taichi_bearing.studies.passage_study.collect`.
    out : path
    title, intro : str
        The report's heading and first paragraph (what was run).
    angle : str or None
        The column of the varied starting angle, shown per passage.
    results : sequence of CellResult
        The runs, to name those that did not finish.
    how : sequence of blocks
        The closing section (:func:`~taichi_bearing.studies.report.how_made_blocks`).

    Returns
    -------
    dict
        The paths written, by name.
    """
    out = Path(out)
    paths = {
        "passages": write_csv(out / "passages.csv", passages),
        "runs": write_csv(out / "runs.csv", runs),
        "figure": passages_figure(passages, out / "figures" / "passages.png"),
    }
    stats = group_statistics(passages, runs)[None]
    n_runs = int((runs["status"] == "finished").sum()) if len(runs) else 0
    blocks: list = [Heading(title, 1), Heading("Verdict", 2)]
    words = passage_sentences(passages.to_dict("records"), "any finished run")
    blocks.append(Para(f"{len(passages)} passages from {n_runs} of {len(runs)} runs "
                       "finished. " + " ".join(words)))  # fmt: skip
    blocks += [*failed_blocks(results), Para(intro)]
    blocks += [Heading("Each quantity over the passages", 2)]
    blocks.append(
        Para(
            "One passage is one sample of a chaotic bounce (where the roller is in its "
            "radial flight when the exit edge meets it), so the finding is each quantity's "
            "median and interquartile range over the passages, never one passage's value."
        )
    )
    blocks.append(statistics_table(stats, PASSAGE_QUANTITIES))
    blocks.append(Image(paths["figure"], "Every passage quantity: box over the passages "
                        "(median, quartiles), one dot per passage."))  # fmt: skip
    run_names = [q.name for q in QUANTITIES if q.per == "run"]
    blocks += [Heading("Per run", 2), Para("The preload and the run's spall size estimate, "
               "over the finished runs (they differ only by where the rollers start):"),
               statistics_table(stats, run_names)]  # fmt: skip
    blocks += [Heading("Per passage", 2), _per_passage(passages, angle), *how]
    paths["report"], paths["html"] = write_documents(blocks, out / "passages_report.md")
    return paths
