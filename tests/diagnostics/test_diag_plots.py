"""diagnostics.plots: figures build headless and hold what they claim to show."""

from __future__ import annotations

import os
import subprocess
import sys

import numpy as np
import pytest
from matplotlib.figure import Figure

from diagnostics import (
    BearingGeometry,
    bearing_frequencies,
    envelope_spectrum,
    kurtogram,
    plots,
    third_octave,
)

FS = 12000.0
FREQS = bearing_frequencies(BearingGeometry(9, 7.94e-3, 39.04e-3), 29.95)


def bursts(rate_hz: float, noise: float = 0.1, seed: int = 0):
    """3 kHz resonance bursts repeating at ``rate_hz`` in white noise (1 s), and their times."""
    rng = np.random.default_rng(seed)
    x = noise * rng.standard_normal(int(FS))
    tail = np.arange(120) / FS
    burst = np.exp(-600.0 * tail) * np.sin(2 * np.pi * 3000.0 * tail)
    times = np.arange(0.01, 0.98, 1.0 / rate_hz)
    for t in times:
        i = int(t * FS)
        x[i : i + burst.size] += burst
    return x, times


@pytest.fixture(scope="module")
def impacts():
    """Bursts at BPFO, as an outer-race fault gives."""
    return bursts(FREQS.bpfo)


def _vlines(ax) -> list[float]:
    """x positions of the vertical marker lines on an axes."""
    out = []
    for line in ax.get_lines():
        xd = np.asarray(line.get_xdata(), dtype=float)
        if xd.size == 2 and xd[0] == xd[1]:
            out.append(float(xd[0]))
    return out


def test_import_needs_no_display():
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "MPLBACKEND")}
    code = "import sys, diagnostics.plots; print('matplotlib.pyplot' in sys.modules)"
    out = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    assert out.stdout.strip() == "False"


def test_envelope_spectrum_marks_fault_harmonics(impacts, tmp_path):
    x, _ = impacts
    f, amp = envelope_spectrum(x, FS, band=(2000.0, 4000.0))
    fig = plots.plot_envelope_spectrum(f, amp, FREQS, n_harmonics=4)
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    marks = _vlines(ax)
    for f0 in (FREQS.bpfo, FREQS.bpfi, 2 * FREQS.bsf):
        for k in range(1, 5):
            assert min(abs(m - k * f0) for m in marks) < 1e-9
    # The spectrum drawn peaks at BPFO, where the bursts repeat.
    spectrum = ax.get_lines()[0]
    fx, fy = (np.asarray(a) for a in spectrum.get_data())
    assert abs(fx[np.argmax(fy)] - FREQS.bpfo) < 2.0
    fig.savefig(tmp_path / "ses.png")
    assert (tmp_path / "ses.png").stat().st_size > 0


def test_kurtogram_map_levels_down_the_y_axis(impacts):
    x, _ = impacts
    kg = kurtogram(x, FS, nlevel=5)
    fig = plots.plot_kurtogram(kg)
    ax = fig.axes[0]
    image = ax.get_images()[0]
    assert image.get_array().shape == kg.K.shape
    labels = [t.get_text() for t in ax.get_yticklabels()]
    assert labels == [f"{lv:.1f}" for lv in kg.levels]
    bottom, top = ax.get_ylim()
    assert bottom > top  # level 0 at the top, as Antoni draws it
    assert ax.get_xlim() == (0.0, FS / 2)
    assert kg.band[0] <= 3000.0 <= kg.band[1]


def test_band_map_outlines_the_band_diagnosed(impacts):
    """A band taken from the map elsewhere is outlined dashed on its own level's row (a
    band of the tree at level k is fs / 2**(k + 1) wide); the map's best band solid."""
    x, _ = impacts
    kg = kurtogram(x, FS, nlevel=5)
    used = (FS / 8, FS / 4)  # fs / 8 wide: a band of level 2
    ax = plots.plot_kurtogram(kg, used_band=used).axes[0]
    dashed = [ln for ln in ax.get_lines() if ln.get_linestyle() == "--"]
    assert len(dashed) == 1
    xs, ys = dashed[0].get_data()
    assert (min(xs), max(xs)) == used
    row = list(kg.levels).index(2.0)
    assert (min(ys), max(ys)) == (row - 0.5, row + 0.5)
    assert "Fast kurtogram" in ax.get_title() and ax.get_legend() is not None
    assert [ln.get_linestyle() for ln in plots.plot_kurtogram(kg).axes[0].get_lines()] == ["-"]
    # A second band (the infogram's best apart from the first) dotted, on its own row.
    second = (FS / 32, 2 * FS / 32)  # fs / 32 wide: level 4
    ax = plots.plot_kurtogram(kg, used_band=used, second_band=second).axes[0]
    styles = [ln.get_linestyle() for ln in ax.get_lines()]
    assert styles == ["-", "--", ":"]
    xs, ys = ax.get_lines()[2].get_data()
    row = list(kg.levels).index(4.0)
    assert (min(xs), max(xs)) == second and (min(ys), max(ys)) == (row - 0.5, row + 0.5)


def test_spectrogram_and_trace_mark_events(impacts):
    x, times = impacts
    events = {"impact": times[:5]}
    for fig in (plots.plot_spectrogram(x, FS, events=events), plots.plot_time_trace(x, FS, events)):
        marks = _vlines(fig.axes[0])
        assert np.allclose(sorted(marks), times[:5])
        assert fig.axes[0].get_legend() is not None


def test_spectral_kurtosis_one_curve_and_threshold_per_window():
    x, _ = bursts(30.0)  # sparse impacts: high kurtosis in the resonance band
    nws = (64, 128, 256)
    fig = plots.plot_spectral_kurtosis(x, FS, nws=nws)
    ax = fig.axes[0]
    curves = [ln for ln in ax.get_lines() if np.asarray(ln.get_xdata()).size > 2]
    assert len(curves) == len(nws)
    for ln in curves:  # above the repetition-rate bins, each curve peaks at the resonance
        fx, fy = (np.asarray(a) for a in ln.get_data())
        keep = fx > 1000.0
        assert 2000.0 < fx[keep][np.argmax(fy[keep])] < 4000.0
    thresholds = [ln for ln in ax.get_lines() if np.asarray(ln.get_xdata()).size == 2]
    assert len(thresholds) == len(nws)


def test_psd_notch_removes_the_tone():
    rng = np.random.default_rng(1)
    t = np.arange(int(4 * FS)) / FS
    x = np.sin(2 * np.pi * 1000.0 * t) + 0.01 * rng.standard_normal(t.size)
    fig = plots.plot_psd_notch(x, FS, [1000.0])
    before, after = [ln for ln in fig.axes[0].get_lines() if np.asarray(ln.get_xdata()).size > 2]
    f = np.asarray(before.get_xdata())
    i = np.argmin(abs(f - 1000.0))
    drop_db = 10 * np.log10(before.get_ydata()[i] / after.get_ydata()[i])
    assert drop_db > 20.0


def test_third_octave_one_bar_per_band(impacts):
    x, _ = impacts
    fig = plots.plot_third_octave(x, FS)
    fc, level = third_octave(x, FS)
    bars = fig.axes[0].patches
    assert len(bars) == fc.size
    tops = np.array([b.get_y() + b.get_height() for b in bars])
    assert np.allclose(tops, level)


def test_draws_into_a_given_axes(impacts):
    x, _ = impacts
    fig = Figure()
    ax1, ax2 = fig.subplots(2)
    assert plots.plot_time_trace(x, FS, ax=ax2) is fig
    assert len(ax2.get_lines()) == 1 and len(ax1.get_lines()) == 0


def test_speed_in_rpm_over_time():
    rate = np.linspace(10.0, 25.0, int(2 * FS))  # Hz
    fig = plots.plot_speed(rate, FS)
    (line,) = fig.axes[0].get_lines()
    t, rpm = (np.asarray(a) for a in line.get_data())
    assert t[-1] == pytest.approx((rate.size - 1) / FS)
    assert rpm[0] == pytest.approx(600.0) and rpm[-1] == pytest.approx(1500.0)
    assert fig.axes[0].get_ylabel() == "speed (rpm)"
