"""Run figures on a synthetic run folder whose events, tones and forces are known."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from synthetic_run import make_synthetic_run

from taichi_bearing.post.deformed_render import nice_factor, rigid_and_elastic
from taichi_bearing.post.run_figures import (
    ENTRY_LABEL,
    EXIT_LABEL,
    FIGURE_NAMES,
    draw_run_figure,
    make_run_figures,
    notch_attenuation,
)


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    run_dir = tmp_path_factory.mktemp("run")
    truth = make_synthetic_run(run_dir)
    paths = make_run_figures(run_dir)
    return run_dir, truth, paths


def _vlines(ax, label=None, colour=None):
    """x of the vertical lines (axvline) drawn in ``ax`` (with a label/colour if given)."""
    xs = []
    for line in ax.get_lines():
        x = np.asarray(line.get_xdata(), dtype=float)
        y = np.asarray(line.get_ydata(), dtype=float)
        if x.size == 2 and x[0] == x[1] and (y[0], y[1]) == (0.0, 1.0):
            if colour is not None and line.get_color() != colour:
                continue
            xs.append(float(x[0]))
    return sorted(xs)


def test_every_figure_is_written_with_a_caption(run):
    run_dir, _, paths = run
    assert set(paths) == set(FIGURE_NAMES)
    meta = json.loads((run_dir / "figures" / "figures.json").read_text())
    for name, path in paths.items():
        assert path.parent == run_dir / "figures"
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert path.stat().st_size > 10_000, name
        assert "error" not in meta["figures"][name], meta["figures"][name]
        assert meta["figures"][name]["caption"]


def test_acceleration_marks_entries_and_exits_at_the_summary_times(run):
    run_dir, truth, _ = run
    fig, caption, values = draw_run_figure(run_dir, "acceleration")
    whole = fig.axes[0]
    handles = {h.get_label(): h.get_color() for h in whole.get_legend().legend_handles}
    entries = _vlines(whole, colour=handles[ENTRY_LABEL])
    exits = _vlines(whole, colour=handles[EXIT_LABEL])
    assert entries == pytest.approx(truth.entry_times_s, abs=1e-12)
    assert exits == pytest.approx(truth.exit_times_s, abs=1e-12)
    # The exit ring (2000 m/s^2) dwarfs the entry dip (50 m/s^2 plus tones and noise).
    assert values["exit_to_entry_ratio"] > 5.0
    assert f"{values['exit_to_entry_ratio']:.3g}" in caption


def test_contact_forces_show_each_roller_through_the_spall(run):
    run_dir, truth, _ = run
    fig, _, values = draw_run_figure(run_dir, "contact_forces")
    outer, inner = fig.axes[:2]
    assert sorted(line.get_label() for line in outer.get_lines() if line.get_label()[0] != "_") == [
        f"roller {j}" for j in truth.rollers
    ]
    marks = 1e3 * np.array(truth.entry_times_s + truth.exit_times_s)
    for ax in (outer, inner):
        assert _vlines(ax) == pytest.approx(sorted(marks), abs=1e-9)
    q = truth.static_forces_N[0] / 1e3
    for j in truth.rollers:
        v = values[f"roller{j}"]
        assert v["before_kN"] == pytest.approx(q, rel=1e-6)
        assert v["min_kN"] == pytest.approx(0.2 * q, rel=1e-3)  # falls to 20 %
        assert v["peak_after_exit_kN"] > 1.2 * q  # returns with impulses above static


def test_envelope_spectrum_marks_bpfo_and_harmonics(run):
    run_dir, truth, _ = run
    summary = json.loads((run_dir / "summary.json").read_text())
    fig, _, values = draw_run_figure(run_dir, "envelope_spectrum")
    marked = _vlines(fig.axes[0])
    assert marked == pytest.approx([k * summary["bpfo_hz"] for k in range(1, 6)], rel=1e-12)
    assert summary["bpfo_hz"] == pytest.approx(truth.bpfo_hz)


def test_notches_remove_the_predicted_tones(run):
    run_dir, truth, _ = run
    meta = json.loads((run_dir / "figures" / "figures.json").read_text())
    rows = meta["figures"]["psd_notch"]["values"]["notches"]
    assert [r["frequency_hz"] for r in rows] == truth.noise_hz
    for r in rows:
        assert r["attenuation_db"] >= 25.0
        assert abs(r["peak_hz"] - r["frequency_hz"]) < 50.0


def test_notch_attenuation_leaves_other_tones_alone():
    fs = 50e3
    t = np.arange(20000) / fs
    x = np.sin(2 * np.pi * 5000 * t) + np.sin(2 * np.pi * 9000 * t)
    (row,) = notch_attenuation(x, fs, [5000.0])
    assert row["attenuation_db"] >= 25.0
    y = notch_attenuation(x, fs, [9000.0])[0]
    assert y["attenuation_db"] >= 25.0
    out = notch_attenuation(x, fs, [30000.0])[0]  # above fs/2: listed, not applied
    assert math.isnan(out["attenuation_db"]) and out["note"]


def test_short_record_still_gives_every_figure(tmp_path):
    make_synthetic_run(tmp_path, duration_ms=2.0, frames=False)  # 200 samples
    paths = make_run_figures(tmp_path)
    assert set(paths) == set(FIGURE_NAMES)
    meta = json.loads((tmp_path / "figures" / "figures.json").read_text())
    assert "too short for a kurtogram" in meta["figures"]["kurtogram"]["error"]
    assert "frames" in meta["figures"]["deformed_spall"]["error"]
    # What could be drawn was drawn, with windows fitted to 200 samples.
    assert meta["figures"]["spectrogram"]["values"]["nperseg"] <= 200 // 8
    for name in ("acceleration", "spectral_kurtosis", "psd_notch"):
        assert "error" not in meta["figures"][name], meta["figures"][name]


def test_deformed_render_numbers(run):
    run_dir, _, _ = run
    meta = json.loads((run_dir / "figures" / "figures.json").read_text())
    v = meta["figures"]["deformed_spall"]["values"]
    # Synthetic last frame: von Mises peaks at 1.2 x 900 MPa under a roller at the spall.
    assert 0.5e9 < v["max_von_mises_Pa"] <= 1.08e9 + 1.0
    assert v["magnification"] == nice_factor(v["magnification"])
    assert v["time_s"] == pytest.approx(0.045)


def test_rigid_motion_is_split_from_the_elastic_part():
    rng = np.random.default_rng(1)
    p = rng.uniform(-1.0, 1.0, (50, 2))
    part = np.repeat([0, 1], 25)
    angle = [0.7, -0.2]
    shift = np.array([[0.3, -0.1], [2.0, 5.0]])
    u = np.zeros_like(p)
    for k in (0, 1):
        c, s = math.cos(angle[k]), math.sin(angle[k])
        q = p[part == k]
        u[part == k] = q @ np.array([[c, s], [-s, c]]) + shift[k] - q
    rigid, elastic = rigid_and_elastic(p, u, part)
    assert np.max(np.abs(elastic)) < 1e-12
    assert np.allclose(rigid, p + u, atol=1e-12)
    # A stretch along the symmetry axes of a square grid (no best-fit rotation, no mean
    # translation) is all elastic.
    g = np.stack(np.meshgrid(np.linspace(-1, 1, 5), np.linspace(-1, 1, 5)), -1).reshape(-1, 2)
    stretch = 1e-3 * g * np.array([1.0, -1.0])
    _, elastic = rigid_and_elastic(g, stretch, np.zeros(len(g), dtype=int))
    assert np.allclose(elastic, stretch, atol=1e-12)


def test_nice_factor():
    assert [nice_factor(v) for v in (0.5, 3.0, 7.0, 19.0, 250.0, 1e4)] == [1, 2, 5, 10, 200, 1e4]


def test_run_without_passages(tmp_path):
    """A run too short to reach the spall: no marks, the most active rollers shown."""
    make_synthetic_run(tmp_path, frames=False)
    path = tmp_path / "summary.json"
    summary = json.loads(path.read_text())
    summary.update(events=[], entry_times_s=[], restress_times_s=[])
    path.write_text(json.dumps(summary))
    fig, caption, _ = draw_run_figure(tmp_path, "contact_forces")
    assert fig._suptitle.get_text().startswith("No spall passage recorded")
    assert _vlines(fig.axes[0]) == []
    # Rollers 0-2 carry the synthetic passages, so their forces vary most.
    assert "rollers 0, 1, 2," in caption
    fig, caption, values = draw_run_figure(tmp_path, "acceleration")
    assert "no complete spall passage" in caption
    assert "exit_to_entry_ratio" not in values
