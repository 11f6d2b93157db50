"""Matplotlib figures for each analysis of ``diagnostics``.

Importing this module needs no display: figures are built with the object-oriented API on
``matplotlib.figure.Figure`` (no pyplot state, no GUI backend). Every function returns the
Figure and accepts an optional ``ax`` to draw into an existing one. Save with
``fig.savefig(path)``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from diagnostics._checks import check_signal, normalise
from diagnostics._filters import notch_filter
from diagnostics._frequencies import FaultFrequencies
from diagnostics._kurtosis import Kurtogram
from diagnostics._spectral import psd, stft, third_octave
from diagnostics._spectral_kurtosis import spectral_kurtosis

__all__ = [
    "plot_spectrogram",
    "plot_spectral_kurtosis",
    "plot_kurtogram",
    "plot_envelope_spectrum",
    "plot_psd_notch",
    "plot_third_octave",
    "plot_time_trace",
    "plot_speed",
    "fault_markers",
]

_EVENT_COLOURS = ("tab:red", "tab:green", "tab:purple", "tab:orange", "tab:brown")
_FAMILY_COLOURS = {"BPFO": "tab:red", "BPFI": "tab:green", "2xBSF": "tab:purple", "FTF": "tab:gray"}


def _axes(ax: Axes | None, figsize=(8.0, 4.0)) -> tuple[Figure, Axes]:
    if ax is not None:
        return ax.figure, ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot()


def _events(events) -> dict[str, np.ndarray]:
    """Events as ``{label: times}``; a bare sequence becomes one series called 'event'."""
    if events is None:
        return {}
    if isinstance(events, Mapping):
        return {str(k): np.atleast_1d(np.asarray(v, dtype=float)) for k, v in events.items()}
    return {"event": np.atleast_1d(np.asarray(events, dtype=float))}


def _mark_events(ax: Axes, events) -> None:
    for i, (label, times) in enumerate(_events(events).items()):
        colour = _EVENT_COLOURS[i % len(_EVENT_COLOURS)]
        for j, t in enumerate(times):
            ax.axvline(t, color=colour, lw=0.8, ls="--", label=label if j == 0 else None)
    if events is not None and len(_events(events)):
        ax.legend(loc="upper right", fontsize="small")


def _comb_colour(label: str, i: int) -> str:
    """A fault comb's colour from the name its label starts with ('BPFI sidebands'), else
    the ``i``-th event colour."""
    return _FAMILY_COLOURS.get(label.split()[0], _EVENT_COLOURS[i % len(_EVENT_COLOURS)])


def fault_markers(freqs: FaultFrequencies) -> dict[str, float]:
    """Marker frequencies of the fault families: BPFO, BPFI and 2xBSF (Hz)."""
    return {"BPFO": freqs.bpfo, "BPFI": freqs.bpfi, "2xBSF": 2.0 * freqs.bsf}


def plot_time_trace(x, fs: float, events=None, ax: Axes | None = None, unit: str = "") -> Figure:
    """Time trace with optional event markers.

    Parameters
    ----------
    x : array_like
        1-D signal.
    fs : float
        Sampling rate in Hz.
    events : array_like or mapping, optional
        Event times in s, or ``{label: times}`` (e.g. entry and exit of each passage).
    ax : matplotlib.axes.Axes, optional
        Axes to draw into.
    unit : str
        Unit of ``x`` for the y label. A record of values near 1e300 or 1e-300 is drawn
        in a unit :math:`10^k` times it, which the label names.
    """
    x, decade = _in_decimal_unit(check_signal(x, fs))
    if decade:
        unit = f"1e{decade} {unit or 'unit'}"
    fig, ax = _axes(ax)
    ax.plot(np.arange(x.size) / fs, x, lw=0.6, color="tab:blue")
    _mark_events(ax, events)
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"signal ({unit})" if unit else "signal")
    return fig


def plot_speed(shaft_hz, fs: float, ax: Axes | None = None, title: str = "Shaft speed") -> Figure:
    """Shaft speed (rpm) over a record, one rate per sample (a tachometer's, a profile's or
    :func:`diagnostics.estimate_speed`'s).

    Parameters
    ----------
    shaft_hz : array_like
        Shaft rate in Hz at every sample.
    fs : float
        Sampling rate in Hz.
    ax : matplotlib.axes.Axes, optional
        Axes to draw into.
    title : str
        Figure title.
    """
    rate = check_signal(shaft_hz, fs)
    fig, ax = _axes(ax)
    ax.plot(np.arange(rate.size) / fs, rate * 60.0, lw=1.0, color="tab:blue")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("speed (rpm)")
    ax.set_title(title)
    return fig


def plot_spectrogram(
    x, fs: float, events=None, nperseg: int = 256, ax: Axes | None = None
) -> Figure:
    """STFT magnitude (dB) over time and frequency, with optional event markers."""
    f, t, Z = stft(x, fs, nperseg=nperseg)
    fig, ax = _axes(ax)
    level = 20.0 * np.log10(np.abs(Z) + np.finfo(float).tiny)
    top = np.max(level)
    mesh = ax.pcolormesh(t, f, level, shading="auto", cmap="viridis", vmin=top - 80.0, vmax=top)
    fig.colorbar(mesh, ax=ax, label="dB")
    _mark_events(ax, events)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title("Spectrogram")
    return fig


def plot_spectral_kurtosis(
    x, fs: float, nws: Sequence[int] = (64, 128, 256, 512), p: float = 0.01, ax: Axes | None = None
) -> Figure:
    """Spectral kurtosis for several STFT window lengths, with the Gaussian-noise threshold.

    Short windows resolve impulses in time but not in frequency, long windows the opposite;
    drawing several shows which band is impulsive at which resolution.

    References
    ----------
    Antoni, J. (2006). The spectral kurtosis: a useful tool for characterising
    non-stationary signals. *Mechanical Systems and Signal Processing* 20(2), 282-307.
    """
    fig, ax = _axes(ax)
    for nw in nws:
        result = spectral_kurtosis(x, fs, nw=int(nw))
        line = ax.plot(result.f, result.sk, lw=0.9, label=f"Nw = {nw}")[0]
        ax.axhline(result.threshold(p), color=line.get_color(), lw=0.6, ls=":")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("spectral kurtosis")
    ax.set_title(f"Spectral kurtosis (dotted: threshold, p = {p:g})")
    ax.legend(fontsize="small")
    return fig


def plot_kurtogram(
    kg: Kurtogram,
    ax: Axes | None = None,
    used_band: tuple[float, float] | None = None,
    second_band: tuple[float, float] | None = None,
) -> Figure:
    """Fast kurtogram map as Antoni draws it: frequency on x, level on y (0 at the top).

    Each row is one decomposition level; the best band is outlined. An
    :class:`~diagnostics.Infogram` is drawn the same way, its negentropy in colour.
    ``used_band`` (Hz), a band of the map demodulated elsewhere (``diagnose`` takes the
    best band wide enough for two fault harmonics and above the combs' range), is outlined
    dashed; ``second_band`` (the infogram's best band apart from that one, which
    ``diagnose`` demodulates too) dotted.

    References
    ----------
    Antoni, J. (2007). Fast computation of the kurtogram for the detection of transient
    faults. *Mechanical Systems and Signal Processing* 21(1), 108-124.

    Antoni, J. (2016). The infogram: entropic evidence of the signature of repetitive
    transients. *Mechanical Systems and Signal Processing* 74, 73-94.
    """
    fig, ax = _axes(ax, figsize=(8.0, 5.0))
    K = np.asarray(kg.K, dtype=float)
    levels = np.asarray(kg.levels, dtype=float)
    n_rows = K.shape[0]
    image = ax.imshow(
        K,
        aspect="auto",
        cmap="jet",
        interpolation="nearest",
        extent=(0.0, kg.fs / 2.0, n_rows - 0.5, -0.5),
    )
    fig.colorbar(image, ax=ax, label=kg.quantity)
    ax.set_yticks(np.arange(n_rows))
    ax.set_yticklabels([f"{lv:.1f}" for lv in levels])
    lo, hi = kg.band
    row = int(np.argmin(np.abs(levels - kg.level)))
    box = [row - 0.5, row - 0.5, row + 0.5, row + 0.5, row - 0.5]
    ax.plot([lo, hi, hi, lo, lo], box, "w-", label="best band")
    marked = [(used_band, "w--", "band diagnosed"), (second_band, "w:", "second band diagnosed")]
    for band, style, label in marked:
        if band is None:
            continue
        lo, hi = band
        # A band of the tree at level k is fs / 2**(k + 1) wide.
        level = math.log2(kg.fs / 2.0 / (hi - lo))
        row = int(np.argmin(np.abs(levels - level)))
        box = [row - 0.5, row - 0.5, row + 0.5, row + 0.5, row - 0.5]
        ax.plot([lo, hi, hi, lo, lo], box, style, label=label)
    if used_band is not None or second_band is not None:
        ax.legend(loc="lower right", fontsize="small")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("level k")
    name = "Infogram" if kg.quantity != "kurtosis" else "Fast kurtogram"
    ax.set_title(
        f"{name}: best band {kg.fc:.0f} Hz +- {kg.bw / 2:.0f} Hz, "
        f"level {kg.level:.1f}, {kg.quantity} {kg.kurtosis:.2f}"
    )
    return fig


def plot_envelope_spectrum(
    f,
    amplitude,
    markers: FaultFrequencies | Mapping[str, float] | None = None,
    n_harmonics: int = 5,
    f_max: float | None = None,
    ax: Axes | None = None,
    title: str = "Squared envelope spectrum",
    ylabel: str = "amplitude",
    sidebands: Mapping[str, tuple[float, float]] | None = None,
    scale_from: float | None = None,
) -> Figure:
    """Envelope spectrum with markers at the harmonics of the fault frequencies.

    Parameters
    ----------
    f, amplitude : array_like
        Spectrum, e.g. from :func:`diagnostics.envelope_spectrum`.
    markers : FaultFrequencies or mapping, optional
        Frequencies to mark with their harmonics; a FaultFrequencies gives BPFO, BPFI and
        2xBSF.
    n_harmonics : int
        Harmonics marked per frequency.
    f_max : float, optional
        Upper frequency shown; default just above the highest marker.
    sidebands : mapping, optional
        ``{label: (f0, spacing)}``: dotted markers at ``k * f0 +- spacing`` for each
        harmonic ``k`` drawn (an inner race's lines at the shaft rate either side, a ball's
        at the cage rate), coloured as the comb the label starts with.
    scale_from : float, optional
        Lowest frequency whose lines set the y range; default half the lowest marker.
    """
    f = np.asarray(f, dtype=float)
    amplitude = np.asarray(amplitude, dtype=float)
    if isinstance(markers, FaultFrequencies):
        markers = fault_markers(markers)
    markers = dict(markers or {})
    if f_max is None:
        f_max = 1.1 * n_harmonics * max(markers.values()) if markers else f[-1]
    fig, ax = _axes(ax)
    keep = (f > 0) & (f <= f_max)
    ax.plot(f[keep], amplitude[keep], lw=0.7, color="k")
    # Scale to the lines from half the lowest marker up: the near-DC bins of an envelope
    # spectrum (slow level changes) would otherwise flatten everything else.
    f_lo = scale_from
    if f_lo is None:
        f_lo = 0.5 * min(markers.values()) if markers else 0.0
    shown = keep & (f >= f_lo)
    if shown.any() and np.max(amplitude[shown]) > 0:
        ax.set_ylim(0.0, 1.05 * np.max(amplitude[shown]))
    for i, (name, f0) in enumerate(markers.items()):
        colour = _comb_colour(name, i)
        for k in range(1, n_harmonics + 1):
            if k * f0 <= f_max:
                ax.axvline(k * f0, color=colour, lw=0.8, ls="--", label=name if k == 1 else None)
    for i, (name, (f0, spacing)) in enumerate((sidebands or {}).items()):
        colour = _comb_colour(name, i)
        lines = [k * f0 + j * spacing for k in range(1, n_harmonics + 1) for j in (-1, 1)]
        for n, f_sb in enumerate(v for v in lines if 0.0 < v <= f_max):
            ax.axvline(f_sb, color=colour, lw=0.7, ls=":", label=name if n == 0 else None)
    ax.set_xlim(0.0, f_max)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    if markers or sidebands:
        ax.legend(fontsize="small")
    return fig


def plot_psd_notch(
    x,
    fs: float,
    notch_hz: Sequence[float],
    Q: float = 30.0,
    nperseg: int = 4096,
    ax: Axes | None = None,
) -> Figure:
    """Welch PSD before and after notching each frequency in ``notch_hz``.

    A record whose squares would leave the range of float64 (values near 1e300 or 1e-300)
    is drawn in a unit :math:`10^k` times its own, which the y label names.
    """
    raw, decade = _in_decimal_unit(check_signal(x, fs))
    y = raw
    for f0 in notch_hz:
        y = notch_filter(y, fs, f0, Q=Q)
    nperseg = min(nperseg, y.size)
    f, before = psd(raw, fs, nperseg=nperseg)
    _, after = psd(y, fs, nperseg=nperseg)
    fig, ax = _axes(ax)
    tiny = np.finfo(float).tiny
    ax.semilogy(f, before + tiny, lw=0.8, label="before")
    ax.semilogy(f, after + tiny, lw=0.8, label="after notch")
    for f0 in notch_hz:
        ax.axvline(f0, color="tab:red", lw=0.6, ls=":")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("PSD (unit^2/Hz)" if decade == 0 else f"PSD ((1e{decade} unit)^2/Hz)")
    ax.set_title(
        "PSD before and after notch"
        + (f" ({', '.join(f'{v:g}' for v in notch_hz)} Hz)" if len(notch_hz) else "")
    )
    ax.legend(fontsize="small")
    return fig


def _in_decimal_unit(x: np.ndarray) -> tuple[np.ndarray, int]:
    """``(x, 0)``, or for a record whose squares would leave float64 (one that
    :func:`diagnostics._checks.normalise` rescales) ``x`` in a unit :math:`10^k` times its own,
    and ``k``."""
    rescaled, scale = normalise(x)
    if scale.identity:
        return x, 0
    # x = rescaled * 2**e = rescaled * 10**(e log10 2): keep the decade k in the unit.
    exponent = scale.exponent.item() * math.log10(2.0)
    decade = round(exponent)
    return rescaled * 10.0 ** (exponent - decade), decade


def plot_third_octave(
    x, fs: float, f_min: float = 20.0, f_max: float | None = None, ax: Axes | None = None
) -> Figure:
    """One-third-octave band levels as bars (dB re 1)."""
    fc, level = third_octave(x, fs, f_min=f_min, f_max=f_max)
    fig, ax = _axes(ax)
    finite = np.isfinite(level)
    floor = np.min(level[finite]) - 10.0 if finite.any() else 0.0
    heights = np.where(finite, level, floor) - floor
    ax.bar(np.arange(fc.size), heights, bottom=floor, color="tab:blue")
    step = max(1, fc.size // 12)
    ax.set_xticks(np.arange(0, fc.size, step))
    ax.set_xticklabels([f"{v:.0f}" for v in fc[::step]], rotation=45)
    ax.set_xlabel("band centre (Hz)")
    ax.set_ylabel("level (dB re 1)")
    ax.set_title("One-third-octave spectrum")
    return fig
