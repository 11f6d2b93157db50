"""
Compare a simulated run with a measured record
==============================================

What ``python -m taichi_bearing compare RUN_DIR MEASURED ...`` does, step by step: the
simulated sensor acceleration of a run folder and a measured vibration record are analysed
the same way by :func:`diagnostics.app.compare.compare_records` (the fast kurtogram's
band, the squared envelope spectrum in orders of each record's own BPFO, the
one-third-octave levels) and drawn side by side. The two bearings differ in size and speed, so the
comparison is of shapes, in orders and in BPFO periods, not of levels.

The simulated side is the coarse validation case (1 mm surface elements, a 6 mm by
0.3 mm outer-race spall, 50 kN at 1000 rpm) run for 16 ms: three rollers pass the
spall, one BPFO period (6.8 ms) apart, and the record is long enough (2.3 periods) for
the envelope spectrum to resolve BPFO. About a minute and a half on two CPU threads.
The measured side is the CWRU drive-end record ``135`` (SKF 6205, 0.007 in outer-race
fault at 6 o'clock, 48 kHz, 1796 rpm) when it is found beside the repository
(``../shared/data/cwru/``), or else a synthetic outer-race record of the same bearing.
"""

# %%
# Simulate three passages
# -----------------------
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import diagnostics as dg
from diagnostics.app.compare import Record, compare_records, measured_record, summary_lines
from taichi_bearing.case import load_case
from taichi_bearing.commands.compare import simulated_record
from taichi_bearing.pipeline import run_case


def repository_root() -> Path:
    """The checkout this example belongs to (the gallery runs it from examples/)."""
    here = Path(globals().get("__file__", "examples/plot_compare_measured.py")).resolve().parent
    return next(p for p in (here, *here.parents) if (p / "cases").is_dir())


root = repository_root()
case = load_case(
    root / "cases/validation/coarse_spall.yaml",
    ["output.frames=false", "run.duration_ms=16", "run.checkpoint_interval_ms=4"],
)
work = Path(tempfile.mkdtemp())
summary = run_case(case, work / "coarse_spall", threads=2, quiet=True, post=False)
print(f"status {summary['status']}: {len(summary['events'])} roller passages recorded")

# %%
# The simulated record
# --------------------
# ``taichi_bearing.commands.compare.simulated_record`` reads the run folder: the
# acceleration its checks analysed (radial, at the sensor on the adapter), the sampling
# rate, the shaft speed, BPFO, and the re-stressing (exit) times, which the figures mark.
run, _, simulated = simulated_record(work / "coarse_spall")
print(
    f"{simulated.label}: {simulated.x.size} samples at {simulated.fs / 1e3:.0f} kHz, "
    f"BPFO {simulated.bpfo_hz:.1f} Hz, exits at "
    + ", ".join(f"{1e3 * t:.2f}" for t in simulated.events_s)
    + " ms"
)

# %%
# The measured record
# -------------------
# The CWRU bearing: 9 balls of 7.94 mm on a 39.04 mm pitch circle.
geometry = dg.BearingGeometry(n_rollers=9, roller_diameter=7.94e-3, pitch_diameter=39.04e-3)


def find_record(name: str) -> Path | None:
    """The record in ../shared/data/cwru beside the checkout, or None."""
    for folder in (root, *root.parents):
        path = folder.parent / "shared" / "data" / "cwru" / name
        if path.is_file():
            return path
    return None


path = find_record("48k_Drive_End_OR007@6_0_135.mat")
if path is not None:
    measured = measured_record(path, geometry, fs=48000.0)
else:
    # Each ball striking the fault rings a 3.5 kHz resonance (4 % damping) once per BPFO
    # period, with 1 % jitter (slip), under shaft harmonics and noise: 1 s at 48 kHz.
    fs, rpm = 48000.0, 1796.0
    bpfo = dg.bearing_frequencies(geometry, rpm / 60).bpfo
    rng = np.random.default_rng(3)
    t = np.arange(int(fs)) / fs
    tr = np.arange(int(0.01 * fs)) / fs
    ringing = np.exp(-0.04 * 2 * np.pi * 3500 * tr) * np.sin(2 * np.pi * 3500 * tr)
    x = 0.3 * rng.standard_normal(t.size) + np.sin(2 * np.pi * rpm / 60 * t)
    for t0 in np.cumsum(rng.normal(1.0, 0.01, int(bpfo)) / bpfo):
        i = int(t0 * fs)
        x[i : i + ringing.size] += ringing[: x.size - i]
    measured = Record(
        label="synthetic outer-race record (CWRU 135 not found)",
        source="measured",
        x=x,
        fs=fs,
        shaft_hz=rpm / 60,
        bpfo_hz=bpfo,
        unit="g",
        frequencies=dg.bearing_frequencies(geometry, rpm / 60),
    )
print(f"{measured.label}: {measured.x.size / measured.fs:.1f} s, BPFO {measured.bpfo_hz:.1f} Hz")

# %%
# Side by side
# ------------
# The same analysis of both, the figures written into a folder (as the command does) and
# shown here. The summary says, per record, the kurtogram's band, BPFO's first harmonics
# over the envelope spectrum's median, and the crest factor and kurtosis.
out = work / "compare"
result = compare_records([simulated, measured], out)
print("\n".join(summary_lines(result)))
for item in result["records"]:
    print(
        f"{item['source']}: crest factor {item['crest_factor']:.1f}, "
        f"kurtosis {item['kurtosis']:.1f}"
    )

for name in result["figures"]:
    image = plt.imread(out / name)
    fig, ax = plt.subplots(figsize=(10, 10 * image.shape[0] / image.shape[1]))
    ax.imshow(image)
    ax.set_axis_off()
    plt.show()
