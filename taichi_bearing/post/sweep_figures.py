"""Sweep outputs: ``sweep_summary.csv`` (a column per varied key), figures and
``sweep_report.md``, all computed from the per-cell rows (nothing typed in).

A load x speed sweep (the varied keys are ``operating.load_kN`` and
``operating.speed_rpm``) also gets percentage-increase tables and trend sentences: for
each quantity, ``100 (q / q_ref - 1)`` with ``q_ref`` the same quantity at the lowest load
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

from diagnostics.files import atomic_path
from taichi_bearing.passages import EXIT_BURST_S
from taichi_bearing.sweep_metrics import METRICS, WINDOW_S

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


def _write_text(path: Path, text: str) -> None:
    with atomic_path(path) as tmp:
        Path(tmp).write_text(text)


def _write_csv(path: Path, df: pd.DataFrame) -> None:
    with atomic_path(path) as tmp:
        df.to_csv(tmp, index=False)


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
    tab = increase_table(df, key, axis)
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
        pct = tab.loc[o, cols[-1]]
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
        written.append(_save(fig, fig_dir / f"sweep_{stem}.png", plt))
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
    written.append(_save(fig, fig_dir / "sweep_increase_tables.png", plt))
    return written


def _save(fig, path: Path, plt) -> Path:
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110, format="png")
    plt.close(fig)
    return path


def _pct(v: float) -> str:
    return "n/a" if not math.isfinite(v) else f"{v:+.1f}"


def _markdown(df: pd.DataFrame, digits: int = 4) -> str:
    cols = list(df.columns)
    out = ["| " + " | ".join(str(c) for c in cols) + " |", "|" + "---|" * len(cols)]
    for row in df.itertuples(index=False):
        cells = []
        for v in row:
            if isinstance(v, float):
                cells.append("n/a" if not math.isfinite(v) else f"{v:.{digits}g}")
            else:
                cells.append(str(v))
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def _report(df: pd.DataFrame, figures: list[Path], out: Path) -> str:
    lines = ["# Load x speed sweep", ""]
    n_fin = int((df["status"] == "finished").sum())
    lines += [f"{len(df)} cells, {n_fin} finished, {len(df) - n_fin} failed.", ""]
    failed = df[df["status"] != "finished"]
    for r in failed.itertuples():
        lines.append(f"- FAILED {r.run_dir}: {r.error}")
    if len(failed):
        lines.append("")
    periods = df["periods"].dropna()
    if len(periods):
        lines += [
            f"Records hold {periods.min():.3g} to {periods.max():.3g} BPFO periods; "
            + ("below one period the BPFO level is a zero-padded reading, not a resolved "
               "spectral line." if periods.min() < 1 else "the BPFO line is resolved."),
            "",
        ]  # fmt: skip
    w = WINDOW_S * 1e3
    lines += ["Quantities (each run's files; forces of the rollers in `summary.json` events):", ""]
    lines += [f"- `{k}`: {label} ({unit})" for k, (label, unit) in METRICS.items()]
    lines += [
        "",
        f"Passage window: entry minus {w:g} ms to re-stressing plus {w:g} ms; re-stressing "
        f"burst: the first {max(w, EXIT_BURST_S * 1e3):g} ms after the first impact on the "
        "exit edge, either raceway; envelope: Hilbert envelope of the force minus its median "
        "before the window; envelope spectrum at BPFO over the last whole BPFO periods of "
        "the record.",
        "",
        "## Does the model agree with the study?",
        "",
    ]
    lines += ["The study found that the re-stressing impulses and contact forces grow with "
              "load and with speed. From these runs:", ""]  # fmt: skip
    for key in TREND_KEYS:
        for axis in AXES:
            sentence, _ = trend_sentence(df, key, axis)
            lines.append(f"- {sentence}")
    lines += ["", "## Per-cell values", ""]
    show = ["load_kN", "speed_rpm", "status", "n_passages", *TREND_KEYS, "static_outer_N"]
    lines += [_markdown(df[show]), ""]
    for axis in AXES:
        lines += [f"## Increase relative to the lowest {AXES[axis][0]} (%)", ""]
        for key in TREND_KEYS:
            tab = increase_table(df, key, axis)
            other = "speed_rpm" if axis == "load_kN" else "load_kN"
            tab.index = pd.Index([f"{v:g}" for v in tab.index], name=f"{other} \\ {axis}")
            tab.columns = [f"{c:g}" for c in tab.columns]
            tab = tab.reset_index()
            lines += [f"{METRICS[key][0]} (`{key}`), rows: the other axis", "",
                      _markdown(tab, 3), ""]  # fmt: skip
    lines += ["## Figures", ""]
    lines += [f"![{p.stem}]({os.path.relpath(p, out)})" for p in figures]
    return "\n".join(lines) + "\n"


def make_grid_figures(df: pd.DataFrame, axes: Sequence[str], fig_dir: Path) -> list[Path]:
    """Each quantity against the first varied column, one line per combination of the
    others; returns the files written."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return _group_figures(df, [(axes[0], list(axes[1:]))], fig_dir, plt)


def _grid_report(df: pd.DataFrame, axes: Sequence[str], figures: list[Path], out: Path) -> str:
    lines = [f"# Sweep over {' x '.join(axes)}", ""]
    n_fin = int((df["status"] == "finished").sum())
    lines += [f"{len(df)} cells, {n_fin} finished, {len(df) - n_fin} failed.", ""]
    lines += [
        f"- FAILED {r.run_dir}: {r.error}" for r in df[df["status"] != "finished"].itertuples()
    ]
    lines += [
        "",
        "Quantities (each run's files; forces of the rollers in `summary.json` events):",
        "",
    ]
    lines += [f"- `{k}`: {label} ({unit})" for k, (label, unit) in METRICS.items()]
    lines += ["", "## Per-cell values", ""]
    show = [*axes, "status", "n_passages", *TREND_KEYS, "static_outer_N"]
    lines += [_markdown(df[show]), "", "## Figures", ""]
    lines += [
        f"Each quantity against {axes[0]}"
        + (f", one line per {' and '.join(axes[1:])}." if len(axes) > 1 else "."),
        "",
    ]
    lines += [f"![{p.stem}]({os.path.relpath(p, out)})" for p in figures]
    return "\n".join(lines) + "\n"


def write_sweep_outputs(
    rows: list[dict], out_dir: str | os.PathLike, axes: Sequence[str] = LOAD_SPEED
) -> dict[str, Path]:
    """Write ``sweep_summary.csv``, figures and ``sweep_report.md`` (and, for a load x
    speed sweep, ``sweep_increase.csv``).

    Parameters
    ----------
    rows : list of dict
        One per cell (:func:`taichi_bearing.sweep_metrics.summary_rows`).
    out_dir : path
    axes : sequence of str
        The varied keys' columns, in the order of the grid.

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
    paths = {"summary": out / "sweep_summary.csv"}
    _write_csv(paths["summary"], df)
    paths["report"] = out / "sweep_report.md"
    if load_speed:
        paths["increase"] = out / "sweep_increase.csv"
        _write_csv(paths["increase"], _increase_long(df))
        figures = make_figures(df, out / "figures")
        _write_text(paths["report"], _report(df, figures, out))
    else:
        figures = make_grid_figures(df, axes, out / "figures")
        _write_text(paths["report"], _grid_report(df, axes, figures, out))
    return paths
