r"""Sweep outputs: ``sweep_summary.csv`` (a column per varied key), figures and
``sweep_report.md`` / ``.html``, all computed from the per-cell rows (nothing typed in).
The report leads with the verdict (cells finished and failed; for a load x speed sweep
whether each quantity grows with load and with speed, for any other grid each quantity's
range over the cells and where it is largest), then the tables and figures, and closes
with the quantities' definitions and how the sweep was made.

A load x speed sweep (the varied keys are ``operating.load_kN`` and
``operating.speed_rpm``) also gets percentage-increase tables and trend sentences: for
each quantity, :math:`100 (q / q_\mathrm{ref} - 1)` with :math:`q_\mathrm{ref}` the same
quantity at the lowest load
(same speed) or at the lowest speed (same load). Any other grid gets each quantity against
its first varied key, one line per combination of the others.
"""

from __future__ import annotations

import math
import os
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from taichi_bearing.checks.passages import EXIT_BURST_S
from taichi_bearing.post.document import Heading, Image, Para, Table, fmt, write_documents
from taichi_bearing.studies.metrics import METRICS, WINDOW_S
from taichi_bearing.studies.report import save_figure, write_csv

__all__ = ["LOAD_SPEED", "increase_table", "trend_sentence", "write_sweep_outputs"]

# The quantities the study's finding is about, tested for a trend in the report.
TREND_KEYS = (
    "env_bpfo",
    "outer_peak_N",
    "outer_env_max_N",
    "inner_peak_N",
    "inner_env_max_N",
    "restress_peak_N",
)
AXES = {"load_kN": ("load", "kN"), "speed_rpm": ("speed", "rpm")}
LOAD_SPEED = tuple(AXES)  # the columns of operating.load_kN and operating.speed_rpm
# figure file stem -> the quantities drawn in it
GROUPS = {
    "envelope_bpfo": ("env_bpfo",),
    "outer_forces": ("outer_peak_N", "outer_env_max_N", "restress_peak_N"),
    "inner_forces": ("inner_peak_N", "inner_env_max_N"),
}


def increase_table(df: pd.DataFrame, key: str, axis: str) -> pd.DataFrame:
    """Percentage increase of ``key`` relative to the lowest value of ``axis``.

    Parameters
    ----------
    df : DataFrame
        Rows of ``sweep_summary.csv``.
    key : str
        Quantity column.
    axis : str
        ``"load_kN"`` or ``"speed_rpm"``: the reference is the lowest value of this axis at
        the same value of the other one.

    Returns
    -------
    DataFrame
        Index: the other axis; columns: the values of ``axis``; cells: percent (NaN where
        the reference or the value is missing or the reference is zero).
    """
    other = "speed_rpm" if axis == "load_kN" else "load_kN"
    grid = df.pivot_table(index=other, columns=axis, values=key, aggfunc="first", dropna=False)
    grid = grid.reindex(sorted(grid.columns), axis=1).sort_index()
    ref = grid.iloc[:, 0].replace(0.0, np.nan)
    return grid.div(ref, axis=0).sub(1.0).mul(100.0)


def _increase_long(df: pd.DataFrame) -> pd.DataFrame:
    """All increase tables in one long table: quantity, reference axis, load, speed, %."""
    rows = []
    for key in TREND_KEYS:
        for axis in AXES:
            tab = increase_table(df, key, axis)
            other = "speed_rpm" if axis == "load_kN" else "load_kN"
            for o, row in tab.iterrows():
                for a, pct in row.items():
                    rows.append({"quantity": key, "relative_to_lowest": AXES[axis][0],
                                 axis: a, other: o, "increase_pct": pct})  # fmt: skip
    return pd.DataFrame(rows)


def trend_sentence(df: pd.DataFrame, key: str, axis: str) -> tuple[str, bool | None]:
    """One sentence saying whether ``key`` grows with ``axis``, with the numbers.

    Returns the sentence and True (grows at every value of the other axis), False (does
    not) or None (fewer than two finite values on every line: no trend to judge).
    """
    label, unit = METRICS[key]
    name, aunit = AXES[axis]
    other = "speed_rpm" if axis == "load_kN" else "load_kN"
    oname, ounit = AXES[other]
    grid = df.pivot_table(index=other, columns=axis, values=key, aggfunc="first", dropna=False)
    grid = grid.reindex(sorted(grid.columns), axis=1).sort_index()
    parts, verdicts = [], []
    for o in grid.index:
        vals = grid.loc[o].to_numpy(dtype=float)
        ok = np.isfinite(vals)
        if ok.sum() < 2:
            continue
        v = vals[ok]
        rising = bool(np.all(np.diff(v) > 0))
        shape = "rising" if rising else "falling" if np.all(np.diff(v) < 0) else "not monotonic"
        verdicts.append(rising)
        cols = [c for c, good in zip(grid.columns, ok, strict=True) if good]
        pct = 100.0 * (v[-1] / v[0] - 1.0) if v[0] else math.nan  # from the first finite
        parts.append(
            f"at {o:g} {ounit}: {v[0]:.4g} -> {v[-1]:.4g} {unit} from {cols[0]:g} to "
            f"{cols[-1]:g} {aunit} ({pct:+.1f} %, {shape} over {ok.sum()} "
            f"{name}s)"
        )
    if not verdicts:
        return f"{label}: not enough finished cells to judge a trend with {name}.", None
    if all(verdicts):
        head = f"{label} grows with {name} at every {oname}"
    elif any(verdicts):
        head = f"{label} grows with {name} at {sum(verdicts)} of {len(verdicts)} {oname}s"
    else:
        head = f"{label} does not grow with {name} at any {oname}"
    return head + ": " + "; ".join(parts) + ".", all(verdicts)


def _legend(column: str, value) -> str:
    if column in AXES and isinstance(value, (int, float)):
        return f"{value:g} {AXES[column][1]}"
    return f"{column}={value}"


def _plot_lines(df: pd.DataFrame, key: str, axis: str, others: Sequence[str], ax) -> None:
    """``key`` against ``axis``, one line per combination of the ``others`` columns (a
    non-numeric axis is drawn at evenly spaced ticks)."""
    numeric = pd.api.types.is_numeric_dtype(df[axis]) and not pd.api.types.is_bool_dtype(df[axis])
    ticks = sorted(df[axis].unique(), key=str) if not numeric else None
    groups = df.groupby(list(others), sort=True) if others else [((), df)]
    for combo, g in groups:
        combo = combo if isinstance(combo, tuple) else (combo,)
        g = g.sort_values(axis, key=None if numeric else (lambda c: c.astype(str)))
        x = g[axis] if numeric else [ticks.index(v) for v in g[axis]]
        label = ", ".join(_legend(o, v) for o, v in zip(others, combo, strict=True))
        ax.plot(x, g[key], "o-", label=label or None)
    if ticks is not None:
        ax.set_xticks(range(len(ticks)), [str(t) for t in ticks])
    name, unit = AXES.get(axis, (axis, ""))
    ax.set_xlabel(f"{name} ({unit})" if unit else name)
    ax.set_ylabel(f"{key} ({METRICS[key][1]})")
    ax.grid(True, alpha=0.3)
    if others:
        ax.legend(fontsize=7)


def _group_figures(df: pd.DataFrame, panels: Sequence[tuple[str, list[str]]], fig_dir: Path,
                   plt) -> list[Path]:  # fmt: skip
    """One figure per :data:`GROUPS` entry: a row per quantity, a column per panel (the
    column drawn along x, the columns that make its lines)."""
    fig_dir.mkdir(parents=True, exist_ok=True)
    written = []
    width = 4.5 * len(panels) if len(panels) > 1 else 6.5
    for stem, keys in GROUPS.items():
        fig, axes = plt.subplots(len(keys), len(panels), figsize=(width, 3.0 * len(keys)),
                                 squeeze=False)  # fmt: skip
        for i, key in enumerate(keys):
            for k, (axis, others) in enumerate(panels):
                _plot_lines(df, key, axis, others, axes[i][k])
                axes[i][k].set_title(f"{METRICS[key][0]}", fontsize=8)
        fig.tight_layout()
        written.append(save_figure(fig, fig_dir / f"sweep_{stem}.png"))
    return written


def make_figures(df: pd.DataFrame, fig_dir: Path) -> list[Path]:
    """Trend figures (each quantity against load and against speed) and the increase
    tables as a figure; returns the files written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = [("load_kN", ["speed_rpm"]), ("speed_rpm", ["load_kN"])]
    written = _group_figures(df, panels, fig_dir, plt)
    # increase tables, one panel per reference axis
    fig, axes = plt.subplots(1, 2, figsize=(12, 0.5 + 0.35 * len(df) * len(TREND_KEYS) / 2))
    for ax, axis in zip(axes, AXES, strict=True):
        lines = _increase_long(df)
        lines = lines[lines["relative_to_lowest"] == AXES[axis][0]]
        cells = [[r.quantity, f"{r.load_kN:g}", f"{r.speed_rpm:g}", _pct(r.increase_pct)]
                 for r in lines.itertuples()]  # fmt: skip
        ax.axis("off")
        ax.set_title(f"increase relative to the lowest {AXES[axis][0]} (%)", fontsize=9)
        if cells:
            tab = ax.table(cellText=cells, colLabels=["quantity", "load kN", "speed rpm", "%"],
                           loc="upper center")  # fmt: skip
            tab.auto_set_font_size(False)
            tab.set_fontsize(7)
    fig.tight_layout()
    written.append(save_figure(fig, fig_dir / "sweep_increase_tables.png"))
    return written


def _pct(v: float) -> str:
    return "n/a" if not math.isfinite(v) else f"{v:+.1f}"


def make_grid_figures(df: pd.DataFrame, axes: Sequence[str], fig_dir: Path) -> list[Path]:
    """Each quantity against the first varied column, one line per combination of the
    others; returns the files written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return _group_figures(df, [(axes[0], list(axes[1:]))], fig_dir, plt)


def _table(df: pd.DataFrame, digits: int = 4) -> Table:
    """A DataFrame as a report table ('-' for a missing number)."""
    rows = [[fmt(v, digits) if isinstance(v, float) else str(v) for v in row]
            for row in df.itertuples(index=False)]  # fmt: skip
    return Table([str(c) for c in df.columns], rows)


def _cell_name(row: pd.Series, axes: Sequence[str]) -> str:
    return ", ".join(f"{a} {fmt(row[a]) if isinstance(row[a], float) else row[a]}" for a in axes)


def _status_blocks(df: pd.DataFrame) -> list:
    n_fin = int((df["status"] == "finished").sum())
    text = f"{len(df)} cells, {n_fin} finished, {len(df) - n_fin} failed."
    failed = df[df["status"] != "finished"]
    if len(failed):
        text += " Failed: " + "; ".join(f"`{r.run_dir}`: {r.error}" for r in failed.itertuples())
        text += "."
    return [Para(text)]


def _trend_blocks(df: pd.DataFrame) -> tuple[list, list]:
    """Whether each quantity grows with load and with speed (load x speed sweep): the
    verdict's count, naming each pair that does not, and the sentences with the numbers."""
    found = [trend_sentence(df, key, axis) for key in TREND_KEYS for axis in AXES]
    grows = [v for _, v in found]
    text = (
        "The study found that the re-stressing impulses and contact forces grow with load "
        f"and with speed. From these runs, {grows.count(True)} of {len(found)} quantity-axis "
        f"pairs grow at every value of the other axis, {grows.count(False)} do not, "
        f"{grows.count(None)} cannot be judged (fewer than two finished cells on a line)."
    )
    exceptions = [sentence.split(": ", 1)[0] for sentence, v in found if v is not True]
    if exceptions:
        text += " Not growing or not judged: " + "; ".join(exceptions) + "."
    periods = df["periods"].dropna() if "periods" in df else pd.Series(dtype=float)
    if len(periods):
        text += (
            f" Records hold {periods.min():.3g} to {periods.max():.3g} BPFO periods; "
            + ("below one period the BPFO level is a zero-padded reading, not a resolved "
               "spectral line." if periods.min() < 1 else "the BPFO line is resolved.")
        )  # fmt: skip
    details = [Heading("Trends with load and speed", 2)]
    return [Para(text)], details + [Para(sentence) for sentence, _ in found]


def _range_blocks(df: pd.DataFrame, axes: Sequence[str]) -> list:
    """Each quantity's range over the finished cells and the cell where it is largest."""
    done = df[df["status"] == "finished"]
    parts = []
    for key in TREND_KEYS:
        v = pd.to_numeric(done[key], errors="coerce") if key in done else pd.Series(dtype=float)
        if not v.notna().any():
            parts.append(f"{METRICS[key][0]}: unknown (no finished cell has it)")
            continue
        top = done.loc[v.idxmax()]
        parts.append(f"{METRICS[key][0]}: {fmt(v.min())} to {fmt(v.max())} {METRICS[key][1]}, "
                     f"largest at {_cell_name(top, axes)}")  # fmt: skip
    return [Para("Over the finished cells: " + "; ".join(parts) + ".")]


def _increase_blocks(df: pd.DataFrame) -> list:
    out: list = []
    for axis in AXES:
        out.append(Heading(f"Increase relative to the lowest {AXES[axis][0]} (%)", 2))
        for key in TREND_KEYS:
            tab = increase_table(df, key, axis)
            other = "speed_rpm" if axis == "load_kN" else "load_kN"
            tab.index = pd.Index([f"{v:g}" for v in tab.index], name=f"{other} \\ {axis}")
            tab.columns = [f"{c:g}" for c in tab.columns]
            out += [Para(f"{METRICS[key][0]} (`{key}`), rows: the other axis"),
                    _table(tab.reset_index(), 3)]  # fmt: skip
    return out


def _definition_blocks(load_speed: bool) -> list:
    w = WINDOW_S * 1e3
    out: list = [
        Heading("Definitions", 2),
        Para("Quantities (each run's files; forces of the rollers in `summary.json` events):"),
        Table(
            ["column", "quantity", "unit"],
            [[k, label, unit] for k, (label, unit) in METRICS.items()],
        ),  # fmt: skip
    ]
    if load_speed:
        out.append(Para(
            f"Passage window: entry minus {w:g} ms to re-stressing plus {w:g} ms; re-stressing "
            f"burst: the first {max(w, EXIT_BURST_S * 1e3):g} ms after the first impact on "
            "the exit edge, either raceway; envelope: Hilbert envelope of the force minus its "
            "median before the window; envelope spectrum at BPFO over the last whole BPFO "
            "periods of the record."
        ))  # fmt: skip
    return out


_CAPTIONS = {
    "sweep_envelope_bpfo": "Squared-envelope spectrum level at BPFO",
    "sweep_outer_forces": "Outer-raceway force peak and envelope maximum, and the re-stressing "
    "burst peak, of the rollers through the spall",
    "sweep_inner_forces": "Inner-raceway force peak and envelope maximum",
    "sweep_increase_tables": "The increase tables above as a figure",
}


def _report_blocks(df: pd.DataFrame, axes: Sequence[str], figures: list[Path],
                   load_speed: bool, how: Sequence = ()) -> list:  # fmt: skip
    """The sweep report: the verdict, the per-cell table (and, for load x speed, the
    increase tables), the figures, then the definitions and how it was made."""
    title = "Load x speed sweep" if load_speed else f"Sweep over {' x '.join(axes)}"
    blocks: list = [Heading(title, 1), Heading("Verdict", 2), *_status_blocks(df)]
    verdict, trends = _trend_blocks(df) if load_speed else (_range_blocks(df, axes), [])
    show = [*(LOAD_SPEED if load_speed else axes), "status", "n_passages", *TREND_KEYS,
            "static_outer_N"]  # fmt: skip
    blocks += [*verdict, *trends, Heading("Per-cell values", 2), _table(df[show])]
    if load_speed:
        blocks += _increase_blocks(df)
        against = "load and against speed, one line per value of the other"
    else:
        against = axes[0] + (f", one line per {' and '.join(axes[1:])}" if len(axes) > 1 else "")
    blocks.append(Heading("Figures", 2))
    blocks += [Image(p, f"{_CAPTIONS.get(p.stem, p.stem)}: each quantity against {against}."
                     if p.stem != "sweep_increase_tables" else _CAPTIONS[p.stem])
               for p in figures]  # fmt: skip
    return blocks + _definition_blocks(load_speed) + list(how)


def write_sweep_outputs(
    rows: list[dict],
    out_dir: str | os.PathLike,
    axes: Sequence[str] = LOAD_SPEED,
    how: Sequence = (),
) -> dict[str, Path]:
    """Write ``sweep_summary.csv``, figures and ``sweep_report.md`` / ``.html`` (and, for a
    load x speed sweep, ``sweep_increase.csv``).

    Parameters
    ----------
    rows : list of dict
        One per cell (:func:`taichi_bearing.studies.metrics.summary_rows`).
    out_dir : path
    axes : sequence of str
        The varied keys' columns, in the order of the grid.
    how : sequence of blocks
        The closing section (:func:`~taichi_bearing.studies.report.how_made_blocks`).

    Returns
    -------
    dict
        The paths written, by name.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    axes = list(axes)
    load_speed = sorted(axes) == sorted(LOAD_SPEED)
    order = list(LOAD_SPEED) if load_speed else axes
    df = pd.DataFrame(rows).sort_values(order).reset_index(drop=True)
    paths = {"summary": write_csv(out / "sweep_summary.csv", df)}
    if load_speed:
        paths["increase"] = write_csv(out / "sweep_increase.csv", _increase_long(df))
        figures = make_figures(df, out / "figures")
    else:
        figures = make_grid_figures(df, axes, out / "figures")
    blocks = _report_blocks(df, axes, figures, load_speed, how)
    paths["report"], paths["html"] = write_documents(blocks, out / "sweep_report.md")
    return paths
