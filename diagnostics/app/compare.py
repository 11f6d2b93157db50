"""Two or more vibration records through one analysis, drawn side by side: typically a
simulated record against measured ones.

Each record is a :class:`Record`: the signal, its sampling rate, shaft speed and BPFO, and
optionally the fault frequencies and the times of its defect events (a simulation knows
them; ``python -m taichi_bearing compare`` reads them from a run folder). This module takes
arrays only: it reads no simulation output. Every record goes through one pipeline:

1. the fast kurtogram (levels from the record length) picks the demodulation band: the
   most impulsive band at least ten BPFO wide (room for the comb) above fs/16;
2. the squared envelope spectrum in that band, normalised by its median between 0.5 and
   10.5 BPFO, so records in different units and at different levels compare;
3. the one-third-octave spectrum, relative to the record's overall level;
4. time traces and spectrograms around the defect events: the given event times (e.g. a
   simulated run's re-stressing times) or, without them, the record's envelope bursts one
   BPFO apart.

When the speeds differ, the envelope spectra and the time axes are drawn in units of each
record's own BPFO (orders of BPFO, passage periods), so the fault comb falls at 1, 2, 3 ...
for every record. Structural resonances do not scale with speed: spectrograms and
one-third-octave spectra stay in Hz.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from scipy import signal as sp_signal

from bearing_io.files import write_json
from diagnostics import (
    BearingGeometry,
    FaultFrequencies,
    bearing_frequencies,
    choose_nlevel,
    choose_nperseg,
    envelope,
    envelope_spectrum,
    kurtogram,
    kurtogram_band,
    read_signal,
    stft,
    third_octave,
    third_octave_f_min,
)
from diagnostics.app._figure_files import save_figure

__all__ = [
    "Record",
    "Analysis",
    "measured_record",
    "analyse",
    "impact_times",
    "compare_figures",
    "compare_records",
    "compare_summary",
    "summary_lines",
]

N_HARMONICS = 5
_ORDERS_SHOWN = 6.5
_COLOURS = ("tab:blue", "tab:red", "tab:green", "tab:purple", "tab:orange")


@dataclass
class Record:
    """One signal with what the comparison needs to know about it.

    Attributes
    ----------
    label : str
        Name in the figures and the summary.
    source : str
        What it is, e.g. ``"simulated"`` or ``"measured"``.
    x : numpy.ndarray
        The signal.
    fs, shaft_hz, bpfo_hz : float
        Sampling rate, shaft speed and ball-pass frequency of the outer race, Hz.
    unit : str
        Unit of ``x``.
    frequencies : FaultFrequencies, optional
        All fault frequencies (the envelope figure marks BPFI and BSF too).
    events_s : numpy.ndarray, optional
        Times of the defect events from the record's start, s, when known; otherwise the
        envelope bursts are found (:func:`impact_times`).
    events_label : str
        What the given events are, for the figures' legend.
    meta : dict
        Written with the record's numbers in the summary.
    """

    label: str
    source: str
    x: np.ndarray
    fs: float
    shaft_hz: float
    bpfo_hz: float
    unit: str
    frequencies: FaultFrequencies | None = None
    events_s: np.ndarray | None = None
    events_label: str = "defect events (given)"
    meta: dict = field(default_factory=dict)


@dataclass
class Analysis:
    band: tuple[float, float]
    band_kurtosis: float
    nlevel: int
    f_env: np.ndarray
    env_norm: np.ndarray
    harmonic_ratios: list[float]
    fc: np.ndarray
    level_rel_db: np.ndarray
    events_s: np.ndarray
    events_label: str
    notes: list[str]


def measured_record(
    path: str | os.PathLike,
    geometry: BearingGeometry,
    rpm: float | None = None,
    fs: float | None = None,
    channel=None,
) -> Record:
    """A measured record read with :func:`diagnostics.read_signal`; speed from ``rpm`` or
    the file."""
    sig = read_signal(path, channel=channel, fs=fs)
    rpm = rpm if rpm is not None else sig.meta.get("rpm")
    if rpm is None:
        raise ValueError(f"{path}: the file holds no shaft speed; give --rpm")
    if not (math.isfinite(rpm) and rpm > 0):
        raise ValueError(f"--rpm must be a positive speed, got {rpm:g}")
    freqs = bearing_frequencies(geometry, rpm / 60.0)
    return Record(
        label=f"measured: {Path(path).name} ({sig.name})",
        source="measured",
        x=sig.x,
        fs=sig.fs,
        shaft_hz=rpm / 60.0,
        bpfo_hz=freqs.bpfo,
        unit=str(sig.meta.get("unit", "file units")),
        frequencies=freqs,
        meta={"file": str(path), "channel": sig.name, "rpm": rpm},
    )


def impact_times(x, fs: float, band: tuple[float, float], rate_hz: float) -> np.ndarray:
    """Times (s) of the strongest envelope burst in each fault period, for marking figures.

    Peaks of the band's Hilbert envelope at least 0.6 periods apart and at least half the
    median peak height.
    """
    lo, hi = band
    env = envelope(x, fs, band=(max(lo, 1e-3 * fs), hi) if lo > 0 or hi < fs / 2 else None)
    peaks, props = sp_signal.find_peaks(env, distance=max(int(0.6 * fs / rate_hz), 1), height=0)
    if peaks.size == 0:
        return np.empty(0)
    keep = props["peak_heights"] >= 0.5 * np.median(props["peak_heights"])
    return peaks[keep] / fs


def analyse(rec: Record) -> Analysis:
    """The comparison pipeline on one record (the four steps of this module's notes).

    Returns
    -------
    Analysis
        The demodulation band and its kurtosis, the normalised squared envelope spectrum and
        its BPFO harmonics, the one-third-octave levels and the event times.

    References
    ----------
    Antoni, J. (2007). Fast computation of the kurtogram for the detection of transient
    faults. *Mechanical Systems and Signal Processing* 21(1), 108-124.

    Randall, R. B. and Antoni, J. (2011). Rolling element bearing diagnostics: a tutorial.
    *Mechanical Systems and Signal Processing* 25(2), 485-520.
    """
    x = np.asarray(rec.x, dtype=float) - np.mean(rec.x)
    fs, bpfo = rec.fs, rec.bpfo_hz
    notes = []
    if x.size / fs * bpfo < 2.0:
        notes.append(
            "record shorter than two BPFO periods: the envelope spectrum cannot resolve BPFO"
        )
    nlevel = choose_nlevel(x.size)
    band, kurt = None, math.nan
    if nlevel >= 1:
        kg = kurtogram(x, fs, nlevel=nlevel)
        found = kurtogram_band(kg, min_bandwidth_hz=10.0 * bpfo, min_low_hz=fs / 16.0)
        if found is not None:
            band, kurt = found
    if band is None:
        band = (fs / 8.0, 0.45 * fs)
        notes.append("no kurtogram band qualified; demodulated fs/8..0.45 fs")
    band = (max(band[0], 1e-3 * fs), min(band[1], 0.499 * fs))
    f, amp = envelope_spectrum(x, fs, band=band)
    ref = (f >= 0.5 * bpfo) & (f <= 10.5 * bpfo)
    background = float(np.median(amp[ref])) if ref.any() else float(np.median(amp[1:]))
    norm = amp / background if background > 0 else amp
    df = f[1] - f[0]
    ratios = []
    for k in range(1, N_HARMONICS + 1):
        # Within 1 % of the harmonic (speed fluctuation) or one bin, whichever is wider.
        half = max(0.01 * k * bpfo, df)
        sel = (f >= k * bpfo - half) & (f <= k * bpfo + half)
        ratios.append(float(norm[sel].max()) if sel.any() else math.nan)
    f_min = third_octave_f_min(x.size / fs)
    fc, level = third_octave(x, fs, f_min=f_min)
    total = 10.0 * np.log10(np.mean(x**2) + np.finfo(float).tiny)
    if rec.events_s is not None and np.size(rec.events_s):
        events = np.asarray(rec.events_s, dtype=float)
        events_label = rec.events_label
    else:
        events = impact_times(x, fs, band, bpfo)
        events_label = "envelope burst (strongest per BPFO period)"
        notes.append("events: envelope bursts (strongest per BPFO period)")
    return Analysis(
        band=(float(band[0]), float(band[1])),
        band_kurtosis=float(kurt),
        nlevel=nlevel,
        f_env=f,
        env_norm=norm,
        harmonic_ratios=ratios,
        fc=fc,
        level_rel_db=level - total,
        events_s=events,
        events_label=events_label,
        notes=notes,
    )


# --------------------------------------------------------------------------- figures


def _window(rec: Record, an: Analysis, periods: float) -> tuple[int, int, float]:
    """Sample range of ``periods`` BPFO periods starting a quarter period before the first
    event that leaves room for them; its start time."""
    period = 1.0 / rec.bpfo_hz
    span = periods * period
    duration = rec.x.size / rec.fs
    start = 0.0
    for t in an.events_s:
        if t - 0.25 * period >= 0.0 and t - 0.25 * period + span <= duration:
            start = t - 0.25 * period
            break
    a = int(start * rec.fs)
    return a, min(a + int(math.ceil(span * rec.fs)), rec.x.size), start


def _common_periods(records: list[Record]) -> float:
    return float(min(min(r.x.size / r.fs * r.bpfo_hz for r in records), 6.0))


def compare_figures(records: list[Record], analyses: list[Analysis], out: Path) -> list[str]:
    """Draw the four comparison figures into ``out``; returns the file names."""
    # matplotlib only when figures are drawn
    from matplotlib.figure import Figure

    from diagnostics.plots import fault_markers

    n = len(records)
    periods = _common_periods(records)
    written = []

    # 1. time traces around the defect events, time in BPFO periods
    fig = Figure(figsize=(9.0, 2.6 * n), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n, 1))
    for ax, rec, an, c in zip(axes, records, analyses, _COLOURS, strict=False):
        a, b, start = _window(rec, an, periods)
        t = (np.arange(a, b) / rec.fs - start) * rec.bpfo_hz
        ax.plot(t, rec.x[a:b], lw=0.6, color=c)
        # Only the events in the window are drawn; the first of them carries the label
        # (an event before the window would leave the legend empty).
        shown = [ev for ev in an.events_s if start <= ev <= start + periods / rec.bpfo_hz]
        for k, ev in enumerate(shown):
            ax.axvline(
                (ev - start) * rec.bpfo_hz,
                color="k",
                ls="--",
                lw=0.7,
                label=an.events_label if k == 0 else None,
            )
        ax.set_ylabel(rec.unit)
        ax.set_title(f"{rec.label}: from {start:.4g} s, BPFO {rec.bpfo_hz:.4g} Hz", fontsize=10)
        if shown:
            ax.legend(loc="upper right", fontsize="small")
    axes[-1].set_xlabel("time (BPFO periods)")
    written.append(save_figure(fig, out / "compare_time.png"))

    # 2. spectrograms of the same windows
    fig = Figure(figsize=(5.0 * n, 4.0), layout="constrained")
    axes = np.atleast_1d(fig.subplots(1, n))
    for ax, rec, an in zip(axes, records, analyses, strict=False):
        a, b, start = _window(rec, an, periods)
        x = rec.x[a:b]
        nper = choose_nperseg(x.size, target=256, min_frames=8)
        f, t, Z = stft(x, rec.fs, nperseg=nper)
        level = 20.0 * np.log10(np.abs(Z) + np.finfo(float).tiny)
        top = float(np.max(level))
        mesh = ax.pcolormesh(
            t * rec.bpfo_hz,
            f / 1e3,
            level,
            shading="auto",
            cmap="viridis",
            vmin=top - 60.0,
            vmax=top,
        )
        fig.colorbar(mesh, ax=ax, label="dB (re record max)")
        for edge in an.band:
            ax.axhline(edge / 1e3, color="w", ls=":", lw=1.0)
        ax.set_xlabel("time (BPFO periods)")
        ax.set_ylabel("frequency (kHz)")
        ax.set_title(f"{rec.source}: {nper}-sample windows; dotted: envelope band", fontsize=10)
    written.append(save_figure(fig, out / "compare_spectrogram.png"))

    # 3. envelope spectra in orders of BPFO
    fig = Figure(figsize=(9.0, 2.8 * n), layout="constrained")
    axes = np.atleast_1d(fig.subplots(n, 1, sharex=True))
    for ax, rec, an, c in zip(axes, records, analyses, _COLOURS, strict=False):
        orders = an.f_env / rec.bpfo_hz
        keep = (orders > 0) & (orders <= _ORDERS_SHOWN)
        # Few bins in view (a short simulated record): show them as points too.
        style = "o-" if np.count_nonzero(keep) < 100 else "-"
        ax.plot(orders[keep], an.env_norm[keep], style, ms=3, lw=0.8, color=c)
        for k in range(1, N_HARMONICS + 1):
            ax.axvline(k, color="tab:red", ls="--", lw=0.8, label="BPFO x k" if k == 1 else None)
        if rec.frequencies is not None:
            for name, f0 in fault_markers(rec.frequencies).items():
                if name == "BPFO":
                    continue
                o = f0 / rec.bpfo_hz
                if o <= _ORDERS_SHOWN:
                    ax.axvline(
                        o,
                        color="tab:green" if name == "BPFI" else "tab:purple",
                        ls=":",
                        lw=0.9,
                        label=name,
                    )
        ax.set_ylabel("level / median")
        ratios = ", ".join(f"{v:.3g}" for v in an.harmonic_ratios)
        ax.set_title(
            f"{rec.label}\nband {an.band[0]:.0f}-{an.band[1]:.0f} Hz; BPFO x1..5: {ratios}",
            fontsize=9,
        )
        ax.legend(loc="upper right", fontsize="small")
    axes[-1].set_xlim(0.0, _ORDERS_SHOWN)
    axes[-1].set_xlabel("frequency (orders of BPFO)")
    fig.suptitle("Squared envelope spectra, each over its median (0.5-10.5 BPFO)")
    written.append(save_figure(fig, out / "compare_envelope.png"))

    # 4. one-third-octave spectra relative to the overall level
    fig = Figure(figsize=(9.0, 4.5), layout="constrained")
    ax = fig.add_subplot()
    for rec, an, c in zip(records, analyses, _COLOURS, strict=False):
        ok = np.isfinite(an.level_rel_db)
        ax.semilogx(an.fc[ok], an.level_rel_db[ok], "o-", ms=3, lw=1.0, color=c, label=rec.label)
    ax.set_xlabel("band centre frequency (Hz)")
    ax.set_ylabel("band level re overall level (dB)")
    ax.set_title("One-third-octave spectra (each relative to its own overall level)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    written.append(save_figure(fig, out / "compare_third_octave.png"))
    return written


def compare_summary(records: list[Record], analyses: list[Analysis]) -> dict:
    """Numbers of the comparison (one entry per record) and what agrees."""
    items = []
    for rec, an in zip(records, analyses, strict=True):
        x = np.asarray(rec.x, dtype=float) - np.mean(rec.x)
        rms = float(np.sqrt(np.mean(x**2)))
        finite = np.isfinite(an.level_rel_db)
        k = int(np.argmax(np.where(finite, an.level_rel_db, -np.inf)))
        items.append(
            {
                "label": rec.label,
                "source": rec.source,
                **rec.meta,
                "fs_hz": rec.fs,
                "n_samples": int(x.size),
                "duration_s": x.size / rec.fs,
                "shaft_hz": rec.shaft_hz,
                "bpfo_hz": rec.bpfo_hz,
                "bpfo_periods": x.size / rec.fs * rec.bpfo_hz,
                "unit": rec.unit,
                "rms": rms,
                "crest_factor": float(np.max(np.abs(x)) / rms) if rms > 0 else math.nan,
                "kurtosis": float(np.mean(x**4) / rms**4) if rms > 0 else math.nan,
                "kurtogram_levels": an.nlevel,
                "band_hz": list(an.band),
                "band_kurtosis": an.band_kurtosis,
                "bpfo_harmonic_ratios": an.harmonic_ratios,
                "third_octave_peak_hz": float(an.fc[k]),
                "n_events": int(an.events_s.size),
                "notes": an.notes,
            }
        )
    # A comb "shows" when BPFO x1 or x2 stands 3 times above the spectrum's median; a
    # record shorter than two periods cannot show it either way (None).
    shows = [
        bool(np.nanmax(it["bpfo_harmonic_ratios"][:2]) >= 3.0)
        if it["bpfo_periods"] >= 2.0
        else None
        for it in items
    ]
    return {
        "records": items,
        "speed_ratio": [it["shaft_hz"] / items[0]["shaft_hz"] for it in items],
        "frequency_axes": "envelope spectra in orders of each record's BPFO; time in BPFO "
        "periods; spectrogram and one-third-octave in Hz",
        "bpfo_comb_shown": shows,
        "all_show_bpfo_comb": all(shows) if None not in shows else None,
    }


def compare_records(records: list[Record], out: str | os.PathLike) -> dict:
    """Analyse every record (:func:`analyse`), draw the figures and write ``summary.json``
    into ``out``.

    Parameters
    ----------
    records : list of Record
        Two or more records; the first is the reference of ``speed_ratio``.
    out : str or path-like
        Output folder.

    Returns
    -------
    dict
        :func:`compare_summary` with the figure file names under ``"figures"``.
    """
    out = Path(out)
    analyses = [analyse(r) for r in records]
    figures = compare_figures(records, analyses, out)
    summary = compare_summary(records, analyses)
    summary["figures"] = figures
    write_json(out / "summary.json", summary)
    return summary


def summary_lines(summary: dict) -> list[str]:
    """One line per record of a :func:`compare_records` summary (and its notes)."""
    lines = []
    for it in summary["records"]:
        ratios = ", ".join(f"{v:.3g}" for v in it["bpfo_harmonic_ratios"])
        lines.append(
            f"{it['label']}: {it['fs_hz']:g} Hz, {it['duration_s']:.3g} s "
            f"({it['bpfo_periods']:.3g} BPFO periods), BPFO {it['bpfo_hz']:.4g} Hz, band "
            f"{it['band_hz'][0]:.0f}-{it['band_hz'][1]:.0f} Hz, BPFO x1..5 / median: {ratios}"
        )
        lines += [f"  note: {note}" for note in it["notes"]]
    return lines
