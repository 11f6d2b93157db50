"""
Run the coarse case and plot the contact forces
===============================================

The whole simulation (``python -m taichi_bearing cases/validation/coarse_spall.yaml``) on
the coarse validation case: the default bearing meshed with 1 mm surface elements, a 6 mm
by 0.3 mm spall at 12 o'clock, 50 kN at 1000 rpm, 2 ms that carry roller 0 into the
spall and out of it. It takes about a minute on one CPU thread: mesh, preload by dynamic
relaxation, spin-up to the ideal rolling velocities, the transient. Then the run folder is
read back with :func:`taichi_bearing.output.run_folder.load_run`.
"""

# %%
# Run the case
# ------------
# :func:`taichi_bearing.pipeline.run_case` is what the command line runs. Frames
# (VTU) and the figures and report are left out here; the histories and ``summary.json`` are
# written as always (``summary.json`` holds the run's own checks: on this short run of
# one passage, those that need two passages or a longer record are reported, not met).
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import diagnostics as dg
from taichi_bearing.case import load_case
from taichi_bearing.output.layout import roller_force_column
from taichi_bearing.output.run_folder import acceleration_signal, load_run
from taichi_bearing.pipeline import run_case


def repository_root() -> Path:
    """The checkout this example belongs to (the gallery runs it from examples/)."""
    here = Path(globals().get("__file__", "examples/plot_coarse_run.py")).resolve().parent
    return next(p for p in (here, *here.parents) if (p / "cases").is_dir())


case = load_case(repository_root() / "cases/validation/coarse_spall.yaml", ["output.frames=false"])
out = Path(tempfile.mkdtemp()) / "coarse_spall"
summary = run_case(case, out, threads=1, quiet=True, post=False)
print(f"status {summary['status']}, {summary['n_steps']} steps of {summary['dt_s'] * 1e9:.1f} ns")

# %%
# Contact forces through the spall
# --------------------------------
# Each roller's normal force on the outer raceway, against time. Roller 0 de-stresses as
# its contact patch crosses the entry edge, drops into the spall (this shallow one, it
# touches the floor), and is loaded again at the exit edge with a burst of sharp impulses;
# rollers 19 and 1 beside it carry its share of the load meanwhile.
run = load_run(out)
t_ms = 1e3 * run.histories["time_s"].to_numpy()
event = run.summary["events"][0]
f0 = event["force_before_N"]

fig, ax = plt.subplots(figsize=(8, 4))
for j in (19, 0, 1):
    fn = run.histories[roller_force_column(j, "outer", "fn")].to_numpy()
    ax.plot(t_ms, fn / f0, lw=1.0, label=f"roller {j}")
for key, label in (("entry_time_s", "entry"), ("exit_time_s", "exit")):
    ax.axvline(1e3 * event[key], color="k", ls="--", lw=0.7)
    ax.text(1e3 * event[key], 0.02, f" {label}", va="bottom")
ax.set(xlabel="time (ms)", ylabel="normal force / F0", title="outer-raceway contact forces")
ax.legend()
plt.show()
print(
    f"roller 0: F0 = {f0 / 1e3:.1f} kN, exit peak {event['exit_force_peak_ratio']:.2f} F0, "
    f"{event['exit_impulses']} impulses at the exit"
)

# %%
# The sensor's acceleration and what diagnostics makes of it
# ----------------------------------------------------------
# The simulated acceleration is a record like any other: the entry (a low-frequency
# step) and the exit (an impact ringing the ring's high-frequency modes) are the two
# events :func:`diagnostics.estimate_defect_size` times to size the spall.
sig = acceleration_signal(run)
fig, ax = plt.subplots(figsize=(8, 3))
ax.plot(t_ms, sig.x, lw=0.6)
for key in ("entry_time_s", "exit_time_s"):
    ax.axvline(1e3 * event[key], color="k", ls="--", lw=0.7)
ax.set(xlabel="time (ms)", ylabel="m/s$^2$", title=sig.label)
plt.show()

f, p = dg.psd(sig.x, run.fs, nperseg=64)
print(
    f"sampled at {run.fs / 1e3:.0f} kHz; strongest band of the PSD: {f[np.argmax(p)] / 1e3:.1f} kHz"
)
print(f"exit/entry acceleration ratio {event['exit_entry_accel_ratio']:.1f}")
