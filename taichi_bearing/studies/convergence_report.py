"""Outputs of ``python -m taichi_bearing convergence``: every quantity of
:data:`taichi_bearing.studies.passage_study.QUANTITIES` at each level (static ones over the
level's runs, dynamic ones as the median and interquartile range over its passages), the
relative change between successive levels, the observed order and Richardson's estimate
(:mod:`taichi_bearing.studies.convergence`), figures and ``convergence_report.md`` / ``.html``,
which leads with the verdict: which quantities change by at most 2 % (static) or 10 %
(dynamic medians) between the two finest levels, and which do not.
"""

from __future__ import annotations

import math
import os
import textwrap
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from taichi_bearing.checks.quantities import QUANTITIES, Quantity
from taichi_bearing.post.document import Heading, Image, Para, Table, fmt, write_documents
from taichi_bearing.studies.convergence import (
    DYNAMIC_LIMIT,
    ORDER_RANGE,
    ROUNDING,
    STATIC_LIMIT,
    Assessment,
    assess,
)
from taichi_bearing.studies.passage_study import group_statistics
from taichi_bearing.studies.report import failed_blocks, save_figure, write_csv

__all__ = ["level_assessments", "write_convergence_outputs"]


def _limit(q: Quantity) -> float:
    return STATIC_LIMIT if q.kind == "static" else DYNAMIC_LIMIT


def level_assessments(
    stats: dict, levels: Sequence[float]
) -> dict[str, tuple[list[dict], Assessment]]:
    """Each quantity's statistics per level (in ``levels``' order) and its
    :class:`~taichi_bearing.studies.convergence.Assessment` from the medians."""
    out = {}
    for q in QUANTITIES:
        per_level = [stats[lv][q.name] for lv in levels]
        medians = [float(s["median"]) for s in per_level]
        out[q.name] = (per_level, assess(levels, medians, _limit(q)))
    return out


def _value(s: dict, scale: float) -> str:
    n = int(s.get("n") or 0)
    if n == 0:
        return "-"
    med = fmt(scale * float(s["median"]))
    if n == 1:
        return med
    return f"{med} ({fmt(scale * float(s['q25']))} to {fmt(scale * float(s['q75']))}, n {n})"


def _pct(v: float) -> str:
    return "-" if not math.isfinite(v) else f"{100 * v:+.2f} %"


def _names(rows: list[tuple[Quantity, Assessment]], status: str) -> str:
    parts = []
    for q, a in rows:
        if a.verdict.status != status:
            continue
        tail = _pct(a.verdict.change) if status != "not judged" else a.verdict.reason
        parts.append(f"{q.label} ({tail})")
    return "; ".join(parts) or "none"


def _verdict_blocks(assessed, key: str, levels: Sequence[float], reasons: dict) -> list:
    rows = [(q, assessed[q.name][1]) for q in QUANTITIES]
    counts = {s: sum(a.verdict.status == s for _, a in rows)
              for s in ("converged", "not converged", "not judged")}  # fmt: skip
    text = (
        f"Between the two finest levels, {key} = {levels[-2]:g} and {levels[-1]:g}, "
        f"{counts['converged']} of {len(rows)} quantities change by at most their limit "
        f"({STATIC_LIMIT:.0%} for a static quantity, {DYNAMIC_LIMIT:.0%} for the median of a "
        f"dynamic one over the passages); {counts['not converged']} change by more; "
        f"{counts['not judged']} could not be judged."
    )
    blocks: list = [Heading("Verdict", 2), Para(text)]
    blocks.append(Para("Converged: " + _names(rows, "converged") + "."))
    blocks.append(
        Para(
            "Not converged: " + _names(rows, "not converged") + ". A quantity that does not "
            f"converge is a finding: at these levels its value still depends on {key}, so "
            "the finest level's value is not yet the model's answer."
        )
    )
    judged = [(q, a) for q, a in rows if a.verdict.status == "not judged"]
    if judged:
        why = [f"{q.label}: {reasons.get(q.name) or a.verdict.reason}" for q, a in judged]
        blocks.append(Para("Not judged: " + "; ".join(why) + "."))
    return blocks


def _values_table(assessed, levels: Sequence[float], stats: dict) -> Table:
    head = ["quantity", "unit", "kind", *[f"level {lv:g}" for lv in levels]]
    head.append("reference (Hertz) at the finest level")
    rows = []
    for q in QUANTITIES:
        per_level, _ = assessed[q.name]
        ref = stats[levels[-1]].get(q.reference) if q.reference else None
        rows.append([q.label, q.unit, q.kind, *[_value(s, q.scale) for s in per_level],
                     _value(ref, q.scale) if ref else "-"])  # fmt: skip
    return Table(head, rows)


def _orders_table(assessed, levels: Sequence[float]) -> Table:
    pairs = [f"{a:g} to {b:g}" for a, b in zip(levels[:-1], levels[1:], strict=True)]
    triples = [
        f"p, {levels[i]:g}/{levels[i + 1]:g}/{levels[i + 2]:g}" for i in range(len(levels) - 2)
    ]
    head = ["quantity", "unit", *[f"change {p}" for p in pairs], *triples]
    head += ["Richardson (finest three)", "finest three", "verdict"]
    rows = []
    for q in QUANTITIES:
        _, a = assessed[q.name]
        last = a.orders[-1]
        orders = [fmt(o.order, 3) if math.isfinite(o.order) else "-" for o in a.orders]
        rows.append([
            q.label, q.unit, *[_pct(c) for c in a.changes], *orders,
            fmt(q.scale * last.extrapolated) if last.meaningful else "-", last.reason,
            a.verdict.status,
        ])  # fmt: skip
    return Table(head, rows)


def _definitions(key: str, levels: Sequence[float]) -> Para:
    way = "decrease" if levels[-1] < levels[0] else "increase"
    return Para(
        f"Levels of {key} from coarse to fine as given (they {way}; the spacing h of a "
        "level is the level itself for sizes that shrink and its inverse for a penalty "
        "scale that grows). Static quantities are the preload's, one value per run (the "
        "runs of a level differ only in where the rollers start); dynamic ones are the "
        "median (interquartile range, n) over the level's passages, or over its runs for "
        "the spall size. Change: (finer - coarser) / |finer|. Order p from three "
        "successive levels fitted by f0 + C h^p (with a constant ratio r: p = "
        "ln(|f3 - f2| / |f2 - f1|) / ln r); Richardson's estimate f1 + (f1 - f2) / "
        f"(r^p - 1) is given only for monotone convergence with p in [{ORDER_RANGE[0]:g}, "
        f"{ORDER_RANGE[1]:g}] (below, the extrapolation reaches further than the levels; "
        "above, the drop is faster than linear elements with penalty contact converge: "
        "chance or a pre-asymptotic range). Zone-edge share: the smallest force of a "
        "roller carrying more than 5 % of Q_max, over Q_max (the zone-edge roller is "
        "named per run in runs.csv). Contact patch: the most loaded roller's outer contact "
        "from the contact's nodal forces (half-width 2 sqrt of the force-weighted "
        "variance), beside Hertz's for the same force."
    )


def _level_ticks(ax, x: np.ndarray, log: bool) -> None:
    """The levels themselves as the x ticks (log scale when they span a factor 4)."""
    from matplotlib.ticker import NullFormatter

    if log:
        ax.set_xscale("log")
    ax.set_xticks(x, [f"{v:g}" for v in x])
    ax.xaxis.set_minor_formatter(NullFormatter())


def _figures(assessed, levels: Sequence[float], stats: dict, key: str, fig_dir: Path) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    x = np.asarray(levels, dtype=float)
    log_x = x.max() / x.min() >= 4
    ncol = 4
    nrow = math.ceil(len(QUANTITIES) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(3.2 * ncol, 2.7 * nrow), squeeze=False)
    for ax, q in zip(axes.flat, QUANTITIES, strict=False):
        per_level, a = assessed[q.name]
        med = np.array([float(s["median"]) for s in per_level]) * q.scale
        lo = med - np.array([float(s["q25"]) for s in per_level]) * q.scale
        hi = np.array([float(s["q75"]) for s in per_level]) * q.scale - med
        ax.errorbar(x, med, yerr=[np.nan_to_num(lo), np.nan_to_num(hi)], fmt="o-", capsize=3)
        if q.reference:
            ref = [float(stats[lv][q.reference]["median"]) * q.scale for lv in levels]
            ax.plot(x, ref, "x--", color="grey", label="Hertz")
            ax.legend(fontsize=6)
        if a.orders and a.orders[-1].meaningful:
            ax.axhline(q.scale * a.orders[-1].extrapolated, ls=":", color="C3")
        if not np.isfinite(med).any():
            ax.text(0.5, 0.5, "no value", ha="center", va="center", transform=ax.transAxes)
        ax.set_title("\n".join(textwrap.wrap(q.label, 34)), fontsize=7)
        ax.set_ylabel(q.unit, fontsize=7)
        ax.tick_params(labelsize=7)
        ax.grid(True, alpha=0.3)
        _level_ticks(ax, x, log_x)
    for ax in list(axes.flat)[len(QUANTITIES) :]:
        ax.axis("off")
    fig.supxlabel(key, fontsize=8)
    fig.tight_layout()
    written = [save_figure(fig, fig_dir / "convergence_values.png")]
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    for ax, kind, limit in ((axes[0], "static", STATIC_LIMIT), (axes[1], "dynamic", DYNAMIC_LIMIT)):
        for q in (q for q in QUANTITIES if q.kind == kind):
            d = np.abs(np.array(assessed[q.name][1].changes, dtype=float))
            ok = np.isfinite(d) & (d > ROUNDING)
            if ok.any():
                ax.loglog(x[1:][ok], d[ok], "o-", label=textwrap.shorten(q.label, 40))
        ax.axhline(limit, color="k", ls="--", lw=0.8, label=f"limit {limit:.0%}")
        _level_ticks(ax, x[1:], True)
        ax.set_xlabel(f"{key} (the finer level of each pair)", fontsize=8)
        ax.set_ylabel("|relative change| between successive levels", fontsize=8)
        ax.set_title(f"{kind} quantities", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=6)
    fig.tight_layout()
    written.append(save_figure(fig, fig_dir / "convergence_differences.png"))
    return written


def _missing_reasons(
    runs: pd.DataFrame, passages: pd.DataFrame, column: str, key: str, levels: Sequence[float]
) -> dict[str, str]:
    """Why a quantity has no value at one of the two finest levels: no passage recorded
    there, or the spall size estimate's own note (it needs a record of a passage period,
    which a single-passage run is not)."""
    reasons = {}
    found = set(passages[column]) if len(passages) else set()
    empty = [f"{lv:g}" for lv in levels[-2:] if lv not in found]
    if empty:
        text = f"no passage recorded at {key} = {' and '.join(empty)}"
        reasons.update(dict.fromkeys((q.name for q in QUANTITIES if q.per == "passage"), text))
    if "defect_size_note" in runs:
        size = pd.to_numeric(runs["defect_size_estimate_m"], errors="coerce").to_numpy(float)
        notes = [n for n in runs["defect_size_note"].dropna() if n]
        if notes and not np.isfinite(size).any():
            reasons["defect_size_estimate_m"] = f"the runs give none ({notes[-1]})"
    return reasons


def _long_table(assessed, levels: Sequence[float], stats: dict) -> pd.DataFrame:
    rows = []
    for q in QUANTITIES:
        per_level, a = assessed[q.name]
        for i, (lv, s) in enumerate(zip(levels, per_level, strict=True)):
            ref = stats[lv].get(q.reference) if q.reference else None
            rows.append({
                "quantity": q.name, "kind": q.kind, "level": lv, **s,
                "reference_median": ref["median"] if ref else math.nan,
                "change_from_previous": a.changes[i - 1] if i else math.nan,
            })  # fmt: skip
    return pd.DataFrame(rows)


def _verdict_table(assessed) -> pd.DataFrame:
    rows = []
    for q in QUANTITIES:
        _, a = assessed[q.name]
        last = a.orders[-1] if a.orders else None
        rows.append({
            "quantity": q.name, "kind": q.kind, "limit": a.verdict.limit,
            "change": a.verdict.change, "verdict": a.verdict.status,
            "order": last.order if last else math.nan,
            "richardson": last.extrapolated if last else math.nan,
            "order_note": last.reason if last else "",
        })  # fmt: skip
    return pd.DataFrame(rows)


def write_convergence_outputs(
    passages: pd.DataFrame,
    runs: pd.DataFrame,
    out: str | os.PathLike,
    *,
    key: str,
    column: str,
    levels: Sequence[float],
    intro: str,
    results: Sequence = (),
    how: Sequence = (),
) -> dict[str, Path]:
    """Write ``passages.csv``, ``runs.csv``, ``convergence.csv`` (each quantity at each
    level), ``convergence_verdicts.csv``, figures and ``convergence_report.md`` / ``.html``.

    Parameters
    ----------
    passages, runs : DataFrame
        :func:`taichi_bearing.studies.passage_study.collect`, with the level in ``column``.
    out : path
    key : str
        The varied case key.
    column : str
        Its column in ``passages`` and ``runs``.
    levels : sequence of float
        The levels, coarse to fine.
    intro : str
        The report's first paragraph (what was run).
    results, how
        The runs (to name failures) and the closing section.

    Returns
    -------
    dict
        The paths written, by name.
    """
    out = Path(out)
    grouped = group_statistics(passages, runs, by=column)
    empty = group_statistics(passages.iloc[0:0], runs.iloc[0:0])[None]
    stats = {lv: grouped.get(lv, empty) for lv in levels}
    assessed = level_assessments(stats, levels)
    reasons = _missing_reasons(runs, passages, column, key, levels)
    paths = {
        "passages": write_csv(out / "passages.csv", passages),
        "runs": write_csv(out / "runs.csv", runs),
        "table": write_csv(out / "convergence.csv", _long_table(assessed, levels, stats)),
        "verdicts": write_csv(out / "convergence_verdicts.csv", _verdict_table(assessed)),
    }
    figures = _figures(assessed, levels, stats, key, out / "figures")
    blocks: list = [Heading(f"Convergence: {key} = {', '.join(f'{v:g}' for v in levels)}", 1)]
    blocks += _verdict_blocks(assessed, key, levels, reasons)
    blocks += [Para(intro), *failed_blocks(results)]
    blocks += [Heading("Values per level", 2), _values_table(assessed, levels, stats)]
    blocks += [Heading("Changes, order and extrapolation", 2), _orders_table(assessed, levels)]
    blocks.append(_definitions(key, levels))
    blocks += [Heading("Figures", 2)]
    blocks.append(Image(figures[0], "Each quantity against the level: median with the "
                        "interquartile range as bars; Hertz dashed; Richardson's estimate "
                        "dotted where the order is meaningful."))  # fmt: skip
    blocks.append(Image(figures[1], "Relative change between successive levels, log-log, "
                        "against the finer level of each pair (changes below 1e-12, "
                        "rounding, left out); the limit dashed."))  # fmt: skip
    blocks += list(how)
    paths["report"], paths["html"] = write_documents(blocks, out / "convergence_report.md")
    return paths
