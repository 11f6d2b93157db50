"""Figures of a run folder: ``make_run_figures(run_dir)`` -> ``run_dir/figures/*.png``.

The signal analyses are those of :mod:`diagnostics` and its plots; this module picks the
signal (the first sensor's radial acceleration), the marks (spall entry and exit times from
``summary.json``) and resolutions that fit the record length, and says on each figure what
it chose. Alongside the pictures, ``figures/figures.json`` holds each figure's caption and
the numbers it shows, for the report.

A simulated record may hold only a few milliseconds: windows and kurtogram levels are
chosen from its length, and an analysis the record is too short for gives a figure that
says so instead of an error.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from bearing_io.files import atomic_path, write_json
from diagnostics import (
    choose_nlevel,
    choose_nperseg,
    choose_sk_windows,
    envelope_spectrum,
    kurtogram,
    notch_filter,
    psd,
    third_octave_f_min,
)
from diagnostics import plots as dplots
from taichi_bearing.checks.modulation import analysis_band
from taichi_bearing.output.layout import FIGURES_DIR, FIGURES_INDEX_FILE
from taichi_bearing.output.run_folder import RunData, load_run, passage_events, sensor_acceleration
from taichi_bearing.post.spall_figures import (
    OVERLAP_FIGURE,
    contact_forces,
    deformed,
    fault_rate,
    load_sharing,
    overlaps,
)

__all__ = [
    "FIGURE_NAMES",
    "make_run_figures",
    "notch_attenuation",
    "draw_run_figure",
]

FIGURE_NAMES = (
    "acceleration",
    "contact_forces",
    "spectrogram",
    "spectral_kurtosis",
    "kurtogram",
    "envelope_spectrum",
    "psd_notch",
    "third_octave",
    "deformed_spall",
)
ENTRY_LABEL = "entry (de-stressing)"
EXIT_LABEL = "exit (re-stressing)"
NOTCH_Q = 30.0
_ROLLER_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink")


# --------------------------------------------------------------------------- helpers


def _event_marks(run: RunData) -> dict[str, np.ndarray]:
    """Entry and exit times relative to the first history row (the plots start at 0)."""
    ev = passage_events(run.summary)
    entries = np.array([e["entry_time_s"] for e in ev], dtype=float) - run.t0
    exits = np.array([e["exit_time_s"] for e in ev], dtype=float) - run.t0
    return {ENTRY_LABEL: entries[np.isfinite(entries)], EXIT_LABEL: exits[np.isfinite(exits)]}


def _shown(marks: dict[str, np.ndarray]) -> dict[str, np.ndarray] | None:
    """The non-empty mark series, or None (no legend without marks)."""
    shown = {k: v for k, v in marks.items() if len(v)}
    return shown or None


def _placeholder(title: str, message: str) -> Figure:
    fig = Figure(figsize=(8.0, 3.0), layout="constrained")
    ax = fig.add_subplot()
    ax.set_axis_off()
    ax.set_title(title)
    ax.text(0.5, 0.5, message, ha="center", va="center", wrap=True)
    return fig


def _note(fig: Figure, text: str) -> None:
    """A line at the bottom of the figure saying what was chosen and why."""
    fig.supxlabel(text, fontsize="small", color="dimgray")


def _save(fig: Figure, path: Path) -> Path:
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    return path


def notch_attenuation(
    x: np.ndarray, fs: float, frequencies, Q: float = NOTCH_Q, nperseg: int = 4096
) -> list[dict]:
    r"""Attenuation (dB) of each notch at its tone, measured on Welch PSDs of the signal
    before and after all notches.

    For each frequency the PSD bin with the largest level within two bins of it is taken
    (the tone's peak), and the attenuation is
    :math:`10 \log_{10}(\mathrm{before} / \mathrm{after})` at that bin.
    Frequencies outside ``(0, fs/2)`` are listed with NaN and a note.
    """
    freqs = [float(f) for f in frequencies]
    usable = [f for f in freqs if 0.0 < f < fs / 2.0]
    y = np.asarray(x, dtype=float)
    for f0 in usable:
        y = notch_filter(y, fs, f0, Q=Q)
    nperseg = min(nperseg, len(x))
    f, before = psd(x, fs, nperseg=nperseg)
    _, after = psd(y, fs, nperseg=nperseg)
    df = f[1] - f[0]
    out = []
    tiny = np.finfo(float).tiny
    for f0 in freqs:
        if f0 not in usable:
            out.append(
                {
                    "frequency_hz": f0,
                    "peak_hz": math.nan,
                    "before": math.nan,
                    "after": math.nan,
                    "attenuation_db": math.nan,
                    "note": "outside 0..fs/2",
                }
            )
            continue
        k0 = int(round(f0 / df))
        lo, hi = max(k0 - 2, 0), min(k0 + 3, f.size)
        k = lo + int(np.argmax(before[lo:hi]))
        out.append(
            {
                "frequency_hz": f0,
                "peak_hz": float(f[k]),
                "before": float(before[k]),
                "after": float(after[k]),
                "attenuation_db": float(10.0 * np.log10((before[k] + tiny) / (after[k] + tiny))),
                "note": "",
            }
        )
    return out


def _noise_frequencies(summary: dict) -> list[float]:
    raw = summary.get("noise_frequencies_predicted_hz") or []
    if isinstance(raw, dict):
        raw = list(raw.values())
    out = []
    for v in raw:
        if isinstance(v, dict):
            v = v.get("frequency_hz", v.get("hz"))
        if v is not None and math.isfinite(float(v)):
            out.append(float(v))
    return out


# --------------------------------------------------------------------------- figures


def _acceleration(run: RunData, x, label, marks) -> tuple[Figure, str, dict]:
    fig = Figure(figsize=(9.0, 6.0), layout="constrained")
    top, bottom = fig.subplots(2, 1)
    dplots.plot_time_trace(x, run.fs, _shown(marks), ax=top, unit="m/s^2")
    top.set_title(f"{label}: whole record")
    duration = x.size / run.fs
    entries, exits = marks[ENTRY_LABEL], marks[EXIT_LABEL]
    # The first passage wholly inside the record (entry and a later exit).
    passage = [
        (float(te), float(exits[exits >= te][0]))
        for te in entries
        if te >= 0.0 and np.any((exits >= te) & (exits < duration))
    ]
    values: dict = {}
    if passage:
        # Zoom on the first passage: the gradual entry against the burst at exit.
        t_in, t_out = passage[0]
        sep = max(t_out - t_in, 1.0 / run.fs)
        a = max(int((t_in - 0.5 * sep) * run.fs), 0)
        b = min(int((t_out + 1.0 * sep) * run.fs), x.size)
        zoom_marks = {
            k: v[(v >= a / run.fs) & (v <= b / run.fs)] - a / run.fs for k, v in marks.items()
        }
        dplots.plot_time_trace(x[a:b], run.fs, _shown(zoom_marks), ax=bottom, unit="m/s^2")
        bottom.set_title(f"first passage, from t = {1e3 * (run.t0 + a / run.fs):.2f} ms")
        i_in, i_out = int(t_in * run.fs), int(t_out * run.fs)
        w = max(int(0.5 * sep * run.fs), 1)
        entry_peak = float(np.max(np.abs(x[i_in : max(i_out - w // 4, i_in + 1)])))
        exit_peak = float(np.max(np.abs(x[i_out : i_out + w])))
        values = {
            "entry_peak_m_s2": entry_peak,
            "exit_peak_m_s2": exit_peak,
            "exit_to_entry_ratio": exit_peak / entry_peak if entry_peak > 0 else math.nan,
        }
        caption = (
            f"{label}. Dashed lines: entry (de-stressing) and exit (re-stressing) of each "
            f"roller, from summary.json. First passage: peak |a| {entry_peak:.3g} m/s^2 "
            f"between entry and exit, {exit_peak:.3g} m/s^2 after exit "
            f"(ratio {values['exit_to_entry_ratio']:.3g})."
        )
    else:
        bottom.set_axis_off()
        bottom.text(0.5, 0.5, "no complete spall passage in the record", ha="center")
        caption = f"{label}; no complete spall passage in the record."
    values["rms_m_s2"] = float(np.sqrt(np.mean(x**2)))
    values["peak_m_s2"] = float(np.max(np.abs(x)))
    return fig, caption, values


def _spectrogram(run, x, marks):
    nperseg = choose_nperseg(x.size)
    fig = dplots.plot_spectrogram(x, run.fs, _shown(marks), nperseg=nperseg)
    _note(
        fig,
        f"STFT window {nperseg} samples ({1e3 * nperseg / run.fs:.3g} ms, "
        f"{run.fs / nperseg:.0f} Hz bins), chosen from the {x.size}-sample record",
    )
    marked = "entry and exit times marked" if marks[EXIT_LABEL].size else "no passage"
    caption = f"Spectrogram of the sensor acceleration, {nperseg}-sample windows; {marked}."
    return fig, caption, {"nperseg": nperseg}


def _spectral_kurtosis(run, x):
    nws = choose_sk_windows(x.size)
    fig = dplots.plot_spectral_kurtosis(x, run.fs, nws=nws)
    fig.axes[0].legend(loc="upper right", fontsize="small")
    _note(
        fig,
        f"windows {', '.join(map(str, nws))} samples: those giving at least 16 frames "
        f"in {x.size} samples",
    )
    return (
        fig,
        f"Spectral kurtosis for windows of {', '.join(map(str, nws))} samples.",
        {"windows": nws},
    )


def _kurtogram(run, x):
    nlevel = choose_nlevel(x.size)
    if nlevel < 1:
        raise ValueError(f"record too short for a kurtogram: {x.size} samples, need 256")
    kg = kurtogram(x, run.fs, nlevel=nlevel)
    fig = dplots.plot_kurtogram(kg)
    _note(fig, f"nlevel {nlevel}: the most the {x.size}-sample record allows (max 7)")
    caption = (
        f"Fast kurtogram, {nlevel} levels: best band {kg.band[0]:.0f}-{kg.band[1]:.0f} Hz, "
        f"kurtosis {kg.kurtosis:.3g}."
    )
    return (
        fig,
        caption,
        {"nlevel": nlevel, "band_hz": list(kg.band), "kurtosis": float(kg.kurtosis)},
        kg,
    )


def _envelope(run, x, kg):
    fs = run.fs
    name, rate = fault_rate(run.summary)
    rate = float(rate)
    band, how = analysis_band(kg, fs)
    f, amp = envelope_spectrum(x, fs, band=band)
    df = f[1] - f[0]
    n_harm = 5
    fig = dplots.plot_envelope_spectrum(
        f,
        amp,
        {name: rate},
        n_harmonics=n_harm,
        title=f"Squared envelope spectrum, band {band[0]:.0f}-{band[1]:.0f} Hz",
        ylabel="amplitude ((m/s^2)^2)",
    )
    _note(
        fig,
        f"band: {how}; resolution {df:.3g} Hz = 1 / record length; {name} "
        f"{rate:.4g} Hz from summary.json",
    )
    levels = []
    for k in range(1, n_harm + 1):
        if k * rate < f[-1]:
            i = int(round(k * rate / df))
            lo, hi = max(i - 1, 1), min(i + 2, f.size)
            levels.append(float(np.max(amp[lo:hi])))
    shown = (f >= 0.5 * rate) & (f <= (n_harm + 0.5) * rate)
    background = float(np.median(amp[shown])) if shown.any() else math.nan
    caption = (
        f"Squared envelope spectrum in {band[0]:.0f}-{band[1]:.0f} Hz with {name} = "
        f"{rate:.4g} Hz and harmonics marked; resolution {df:.3g} Hz. Level at {name} "
        f"x1..{len(levels)} over the median: "
        + ", ".join(f"{v / background:.3g}" for v in levels)
        + "."
    )
    if name == "BPFI":
        caption += _mark_sidebands(fig, run.shaft_hz, rate, n_harm, df)
    if df > 0.5 * rate:
        caption += (
            f" The record ({1e3 / df:.3g} ms) is shorter than two {name} periods: the "
            "harmonics are not resolved and these levels say nothing about the fault."
        )
    return (
        fig,
        caption,
        {
            "band_hz": list(band),
            "resolution_hz": df,
            "harmonic_levels": levels,
            "background": background,
            "markers_hz": [k * rate for k in range(1, n_harm + 1)],
        },
    )


def _mark_sidebands(fig: Figure, shaft_hz: float, rate: float, n_harm: int, df: float) -> str:
    """Dotted lines at the shaft-rate sidebands k BPFI +- f_s of an inner-race spall
    (its impacts modulated by the load zone once per turn); what the caption adds."""
    ax = fig.axes[0]
    for k in range(1, n_harm + 1):
        for sign in (-1.0, 1.0):
            ax.axvline(
                k * rate + sign * shaft_hz,
                color="tab:gray",
                ls=":",
                lw=0.8,
                label="BPFI harmonics +- shaft rate" if k == 1 and sign < 0 else None,
            )
    ax.legend(fontsize="small")
    text = f" Dotted: the shaft-rate sidebands k BPFI +- {shaft_hz:.3g} Hz (the load zone"
    if df > 0.5 * shaft_hz:
        return text + "), not resolved at this resolution (a record of two shaft turns is)."
    return text + ")."


def _psd_notch(run, x):
    freqs = _noise_frequencies(run.summary)
    nperseg = min(4096, x.size)
    fig = dplots.plot_psd_notch(
        x, run.fs, [f for f in freqs if 0 < f < run.fs / 2], Q=NOTCH_Q, nperseg=nperseg
    )
    rows = notch_attenuation(x, run.fs, freqs, nperseg=nperseg)
    ax = fig.axes[0]
    ax.set_ylabel("PSD ((m/s^2)^2/Hz)")
    ax.legend(loc="upper right", fontsize="small")
    # One label per measured peak: predicted tones closer than the bin spacing share one.
    groups: dict[float, list[dict]] = {}
    for r in rows:
        if math.isfinite(r["attenuation_db"]):
            groups.setdefault(r["peak_hz"], []).append(r)
    for peak, group in groups.items():
        lo, hi = group[0]["frequency_hz"], group[-1]["frequency_hz"]
        name = f"{lo:.0f} Hz" if len(group) == 1 else f"{lo:.0f}-{hi:.0f} Hz"
        ax.annotate(
            f"{name}: -{group[0]['attenuation_db']:.0f} dB",
            (peak, group[0]["before"]),
            xytext=(8, -4),
            textcoords="offset points",
            fontsize="small",
            color="tab:red",
            va="top",
        )
    _note(
        fig,
        f"notch Q = {NOTCH_Q:g} at each predicted numerical-noise frequency "
        f"(summary.json); Welch window {nperseg} samples",
    )
    if rows:
        caption = (
            "PSD before and after notches at the predicted numerical-noise "
            "frequencies (attenuation at the highest PSD bin within two bins of each): "
            + ", ".join(f"{r['frequency_hz']:.0f} Hz {r['attenuation_db']:.1f} dB" for r in rows)
            + f". Bins are {run.fs / nperseg:.3g} Hz apart."
        )
    else:
        caption = "PSD of the sensor acceleration; no numerical-noise frequency was predicted."
    return fig, caption, {"notches": rows, "nperseg": nperseg}


def _third_octave(run, x):
    duration = x.size / run.fs
    f_min = third_octave_f_min(duration)
    fig = dplots.plot_third_octave(x, run.fs, f_min=f_min)
    fig.axes[0].set_ylabel("level (dB re 1 m/s^2)")
    _note(
        fig,
        f"from {f_min:.0f} Hz: lower bands span fewer than 4 frequency bins of the "
        f"{1e3 * duration:.3g} ms record",
    )
    from diagnostics import third_octave

    fc, level = third_octave(x, run.fs, f_min=f_min)
    k = int(np.nanargmax(np.where(np.isfinite(level), level, -np.inf)))
    caption = (
        f"One-third-octave spectrum from {f_min:.0f} Hz; strongest band {fc[k]:.0f} Hz "
        f"at {level[k]:.1f} dB re 1 m/s^2."
    )
    return (
        fig,
        caption,
        {"f_min_hz": f_min, "peak_band_hz": float(fc[k]), "peak_level_db": float(level[k])},
    )


# --------------------------------------------------------------------------- driver


def _builders(run: RunData, sensor: str | None) -> dict[str, Callable]:
    """Drawing function of each matplotlib figure, in order (the envelope spectrum uses the
    kurtogram's band, so the kurtogram comes first)."""
    x, label = sensor_acceleration(run, sensor)
    marks = _event_marks(run)
    kg_holder: dict = {}

    def kurto():
        fig, cap, val, kg = _kurtogram(run, x)
        kg_holder["kg"] = kg
        return fig, cap, val

    def env():
        if "kg" not in kg_holder and choose_nlevel(x.size) >= 1:
            kg_holder["kg"] = kurtogram(x, run.fs, nlevel=choose_nlevel(x.size))
        return _envelope(run, x, kg_holder.get("kg"))

    builders = {
        "acceleration": lambda: _acceleration(run, x, label, marks),
        "contact_forces": lambda: contact_forces(run),
        "spectrogram": lambda: _spectrogram(run, x, marks),
        "spectral_kurtosis": lambda: _spectral_kurtosis(run, x),
        "kurtogram": kurto,
        "envelope_spectrum": env,
        "psd_notch": lambda: _psd_notch(run, x),
        "third_octave": lambda: _third_octave(run, x),
    }
    if overlaps(passage_events(run.summary)):
        builders[OVERLAP_FIGURE] = lambda: load_sharing(run)
    return builders


def draw_run_figure(
    run_dir: str | os.PathLike, name: str, sensor: str | None = None
) -> tuple[Figure, str, dict]:
    """One matplotlib figure of a run, not saved: ``(figure, caption, numbers)``.

    ``name`` is one of :data:`FIGURE_NAMES` except ``deformed_spall`` (a pyvista render).

    Raises
    ------
    ValueError
        For an unknown name, or when the record is too short for the analysis.
    """
    builders = _builders(load_run(run_dir), sensor)
    if name not in builders:
        raise ValueError(f"unknown figure {name!r}; one of {', '.join(builders)}")
    return builders[name]()


def make_run_figures(run_dir: str | os.PathLike, sensor: str | None = None) -> dict[str, Path]:
    """Draw every figure of a run into ``run_dir/figures``.

    Parameters
    ----------
    run_dir : str or path-like
        A run folder (:mod:`taichi_bearing.output.run_folder`): ``summary.json``, the histories,
        ``case.yaml`` and ``frames/``.
    sensor : str, optional
        Sensor whose acceleration is analysed; default the first of ``sensor_names``.

    Returns
    -------
    dict of str to Path
        Figure name (see :data:`FIGURE_NAMES`) to PNG file. ``figures/figures.json`` holds
        each figure's caption and numbers; an analysis that could not be drawn (record too
        short, no frames) gets a figure saying why, and its reason under ``"error"``.
    """
    run = load_run(run_dir)
    out = run.run_dir / FIGURES_DIR
    out.mkdir(parents=True, exist_ok=True)
    builders = _builders(run, sensor)
    x, label = sensor_acceleration(run, sensor)
    paths: dict[str, Path] = {}
    meta: dict = {
        "sensor": label,
        "fs_hz": run.fs,
        "n_samples": int(x.size),
        "notes": run.notes,
        "figures": {},
    }
    for name, build in builders.items():
        path = out / f"{name}.png"
        try:
            fig, caption, values = build()
            entry = {"file": path.name, "caption": caption, "values": values}
        except ValueError as exc:  # record too short or degenerate for this analysis
            fig = _placeholder(name.replace("_", " "), str(exc))
            entry = {"file": path.name, "caption": f"not drawn: {exc}", "error": str(exc)}
        _save(fig, path)
        paths[name] = path
        meta["figures"][name] = entry
    path = out / "deformed_spall.png"
    try:
        caption, values = deformed(run, path)
        meta["figures"]["deformed_spall"] = {
            "file": path.name,
            "caption": caption,
            "values": values,
        }
    except (FileNotFoundError, ValueError, KeyError) as exc:
        _save(_placeholder("deformed mesh around the spall", str(exc)), path)
        meta["figures"]["deformed_spall"] = {
            "file": path.name,
            "error": str(exc),
            "caption": f"not drawn: {exc}",
        }
    paths["deformed_spall"] = path
    write_json(out / FIGURES_INDEX_FILE, meta)
    return paths
