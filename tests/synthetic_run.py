"""A small run folder (the layout of taichi_bearing.output.run_folder) built from a synthetic
signal with known content.

Used by the post-processing and compare tests: the histories, frames and summary are
written with the project's own writers, so the readers see exactly what a run writes,
while every event time, tone and force is known in advance.

Content (line_spall case, 500 rpm, coarse mesh):

* rollers 0, 1, 2 cross the outer-race spall one BPFO period apart; on entry the outer
  contact force of the roller falls gradually (a 1 ms cosine ramp) to 20 % of its static
  value, on exit it returns with a burst of three short impulses;
* the sensor's radial acceleration holds a smooth low-frequency dip at each entry, a decaying
  20 kHz ring at each exit (40 times larger), two steady "numerical noise" tones at the
  predicted frequencies, and a little white noise.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np
import yaml

from bearing_io.files import write_json
from diagnostics import bearing_frequencies
from taichi_bearing.case import apply_overrides, parse_case
from taichi_bearing.output.histories import HistoryWriter, history_columns
from taichi_bearing.output.summary import write_summary

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "cases" / "line_spall.yaml"
NOISE_SOURCES = ("outer_raceway", "roller")
OVERRIDES = ("mesh.surface_size_mm=3", "mesh.max_size_mm=6", "run.frame_interval_ms=0.5")


@dataclass
class SyntheticTruth:
    fs: float
    bpfo_hz: float
    shaft_hz: float
    entry_times_s: list[float]
    exit_times_s: list[float]
    rollers: list[int]
    noise_hz: list[float]
    ring_hz: float
    static_forces_N: list[float]
    analytical_forces_N: list[float]


def _raised_cosine(t: np.ndarray, t0: float, width: float) -> np.ndarray:
    """0 before t0, 1 after t0 + width, a smooth cosine ramp between."""
    s = np.clip((t - t0) / width, 0.0, 1.0)
    return 0.5 - 0.5 * np.cos(np.pi * s)


def make_synthetic_run(
    run_dir: Path,
    fs: float = 100e3,
    frames: bool = True,
    seed: int = 0,
    duration_ms: float = 45.0,
) -> SyntheticTruth:
    """Write a synthetic run folder into ``run_dir``; return what it holds. A short
    ``duration_ms`` cuts the record (events after its end stay in the summary)."""
    run_dir = Path(run_dir)
    run_dir.mkdir(parents=True, exist_ok=True)
    overrides = (*OVERRIDES, f"run.duration_ms={duration_ms}")
    raw = apply_overrides(yaml.safe_load(CASE.read_text()), overrides)
    case = parse_case(raw, source=CASE)
    (run_dir / "case.yaml").write_text(yaml.safe_dump(raw, sort_keys=False))

    shaft_hz = case.operating.shaft_hz
    freqs = bearing_frequencies(case.bearing.geometry, shaft_hz)
    period = 1.0 / freqs.bpfo
    duration = case.run.duration
    t = np.arange(int(round(duration * fs))) / fs
    rng = np.random.default_rng(seed)

    n = case.bearing.n_rollers
    angles = case.run.first_roller_angle + 2 * np.pi * np.arange(n) / n
    load_zone = np.clip(np.cos(angles), 0.0, None) ** 1.11
    static = 12e3 * load_zone
    analytical = static * (1.0 + 0.03 * np.cos(3.0 * np.arange(n)))

    rollers = [0, 1, 2]
    entries = [3e-3 + k * period for k in rollers]
    sep = 1.9e-3
    exits = [e + sep for e in entries]
    noise_hz = [6250.0, 12800.0]
    ring_hz = 20e3

    outer_fn = np.tile(static[:, None], (1, t.size))
    inner_fn = outer_fn * 1.02
    accel = 5.0 * rng.standard_normal(t.size)
    for f0, amp in zip(noise_hz, (40.0, 25.0), strict=True):
        accel += amp * np.sin(2 * np.pi * f0 * t)
    for j, te, tx in zip(rollers, entries, exits, strict=True):
        q = static[0]
        drop = _raised_cosine(t, te, 1e-3) - _raised_cosine(t, tx, 5e-5)
        burst = np.zeros_like(t)
        for i in range(3):
            ti = tx + i * 1.5e-4
            burst += (0.6 / (i + 1)) * q * np.exp(-(((t - ti) / 2e-5) ** 2))
        outer_fn[j] = q * (1.0 - 0.8 * drop) + burst
        inner_fn[j] = 1.02 * q * (1.0 - 0.8 * drop) + 0.5 * burst
        accel -= 50.0 * np.exp(-(((t - te - 5e-4) / 4e-4) ** 2))
        after = t >= tx
        if not after.any():
            continue
        dt = t[after] - tx
        # a smooth onset (30 us rise) keeps the ring's energy near its 20 kHz resonance
        ring = (1.0 - np.exp(-dt / 3e-5)) * np.exp(-dt / 3e-4) * np.sin(2 * np.pi * ring_hz * dt)
        accel[after] += 2000.0 * ring

    sensors = list(case.sensors)
    columns = history_columns(sensors, n_rollers=n)
    data = {c: np.zeros(t.size) for c in columns}
    data["time_s"] = t
    data[f"{sensors[0]}_ay"] = accel
    data[f"{sensors[1]}_ay"] = 0.5 * accel
    for j in range(n):
        for race, fn in (("outer", outer_fn[j]), ("inner", inner_fn[j])):
            data[f"roller{j}_{race}_fn"] = fn
            data[f"roller{j}_{race}_fx"] = -fn * math.sin(angles[j])
            data[f"roller{j}_{race}_fy"] = fn * math.cos(angles[j])
    data["energy_kinetic"] = 1.0 + 0.0 * t
    with HistoryWriter(run_dir, columns, chunk_rows=1024) as hist:
        hist.append(np.column_stack([data[c] for c in columns]))

    mesh_stats = None
    if frames:
        mesh_stats = _write_frames(run_dir, case)

    checks = {
        "static_forces_vs_analytical": {
            "value": 0.03,
            "limit": 0.10,
            "passed": True,
            "note": "max relative error over loaded rollers",
        },
        "restress_interval_vs_bpfo": {
            "value": 0.004,
            "limit": 0.02,
            "passed": True,
            "note": "relative error of mean interval",
        },
        "energy_balance": {"value": 0.07, "limit": 0.05, "passed": False, "note": ""},
    }
    summary = {
        "case_name": case.name,
        "status": "finished",
        "n_elements": mesh_stats["n_elements"] if mesh_stats else 4038,
        "n_nodes": mesh_stats["n_nodes"] if mesh_stats else 4644,
        "dt_s": 2.1e-7,
        "n_steps": int(duration / 2.1e-7),
        "wall_time_s": 123.4,
        "element_steps_per_s": 4.2e6,
        "energy_balance_error": 0.07,
        "static_roller_forces_N": static,
        "analytical_roller_forces_N": analytical,
        "reference_roller_forces_N": static * 0.98,
        "cage_speed_rel_error": 0.011,
        "bpfo_hz": freqs.bpfo,
        "ftf_hz": freqs.ftf,
        "shaft_hz": shaft_hz,
        "restress_times_s": exits,
        "entry_times_s": entries,
        "events": [
            {"roller": j, "entry_time_s": te, "exit_time_s": tx}
            for j, te, tx in zip(rollers, entries, exits, strict=True)
        ],
        "noise_frequencies_predicted_hz": dict(zip(NOISE_SOURCES, noise_hz, strict=True)),
        "noise_frequencies_measured_hz": {
            k: f + 25.0 for k, f in zip(NOISE_SOURCES, noise_hz, strict=True)
        },
        "analysed_signal": f"{sensors[0]}_ay",
        "defect_size_estimate_m": 9.3e-3,
        "defect_size_true_m": case.defect.length,
        "stage_times_s": {"mesh": 1.5, "preload": 40.2, "transient": 80.1, "post": 1.6},
        "sensor_names": sensors,
        "n_rollers": n,
        "checks": checks,
        "mesh_statistics": mesh_stats or {},
    }
    write_summary(run_dir, summary)
    return SyntheticTruth(
        fs=fs,
        bpfo_hz=freqs.bpfo,
        shaft_hz=shaft_hz,
        entry_times_s=entries,
        exit_times_s=exits,
        rollers=rollers,
        noise_hz=noise_hz,
        ring_hz=ring_hz,
        static_forces_N=static.tolist(),
        analytical_forces_N=analytical.tolist(),
    )


def _write_frames(run_dir: Path, case) -> dict:
    """Frames of the coarse mesh: a dent of the outer raceway over the spall and Hertz-like
    stress spots under the loaded rollers; returns the mesh statistics written."""
    from taichi_bearing.mesh import build_bearing_mesh, mesh_statistics, spec_from_case
    from taichi_bearing.output.vtk import FrameWriter

    mesh = build_bearing_mesh(spec_from_case(case))
    stats = asdict(mesh_statistics(mesh))
    write_json(run_dir / "mesh_statistics.json", stats)
    spall = mesh.info["spall"]
    a = spall["centre_angle"]
    r = np.hypot(mesh.nodes[:, 0], mesh.nodes[:, 1])
    theta = np.arctan2(mesh.nodes[:, 1], mesh.nodes[:, 0])
    centroids = mesh.nodes[mesh.elements].mean(axis=1)
    contacts = [
        spall["raceway_radius"] * np.array([math.cos(b), math.sin(b)])
        for b in np.asarray(mesh.info["roller_angles"])
        if math.cos(b - a) > 0.5
    ]
    dist = np.min([np.hypot(*(centroids - p).T) for p in contacts], axis=0)
    von_mises = 900e6 * np.exp(-((dist / 4e-3) ** 2))
    writer = FrameWriter(run_dir, mesh)
    for k, time in enumerate(np.linspace(0.0, case.run.duration, 3)):
        dent = 5e-6 * (k + 1) * np.exp(-(((theta - a) * r / 8e-3) ** 2))
        u = np.column_stack([-dent * np.cos(theta), -dent * np.sin(theta)])
        u[:, 1] -= 2e-6 * (k + 1)
        writer.write(time, u, np.zeros_like(u), von_mises * (1 + 0.1 * k))
    return stats
