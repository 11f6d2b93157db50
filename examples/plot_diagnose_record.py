"""
Diagnose a bearing record
=========================

:func:`diagnostics.diagnose` takes one vibration record, its sampling rate, the bearing
geometry and the shaft rate, and names the fault: ``"outer"``, ``"inner"``, ``"ball"`` or
``"none"``, with a confidence and the evidence of each fault family.

This example makes a synthetic record of the Case Western Reserve University (CWRU)
drive-end bearing, an SKF 6205 at 1797 rpm with an outer-race fault, sampled at 12 kHz, as
the data center's record ``130`` (``12k_Drive_End_OR007@6_0_130.mat``) was. When that
record is found beside the repository (``../shared/data/cwru/``) the same lines diagnose
it too; without it that step says so and the example still runs.
"""

# %%
# The bearing and its fault frequencies
# -------------------------------------
# Pure rolling with a stationary outer ring: the cage (FTF), a roller passing a point of
# the outer race (BPFO) or of the inner race (BPFI), and a roller's spin (BSF), in Hz.
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

import diagnostics as dg
from diagnostics.plots import plot_envelope_spectrum

geometry = dg.BearingGeometry(n_rollers=9, roller_diameter=7.94e-3, pitch_diameter=39.04e-3)
shaft_hz = 1797 / 60
freqs = dg.bearing_frequencies(geometry, shaft_hz)
for name in ("shaft", "ftf", "bpfo", "bpfi", "bsf"):
    print(f"{name.upper():5s} {getattr(freqs, name):7.2f} Hz")

# %%
# A synthetic outer-race fault record
# -----------------------------------
# Each roller that strikes the fault rings a structural resonance (here 3 kHz, 5 %
# damping) once per BPFO period; the strikes jitter by 1 % because rollers slip. Strong
# shaft harmonics and broadband noise hide them in the raw signal.
fs = 12000.0
rng = np.random.default_rng(1)
t = np.arange(int(2.0 * fs)) / fs
strikes = np.cumsum(rng.normal(1.0, 0.01, int(2.0 * freqs.bpfo) + 2) / freqs.bpfo)
ringing_t = np.arange(int(0.01 * fs)) / fs
ringing = np.exp(-0.05 * 2 * np.pi * 3000.0 * ringing_t) * np.sin(2 * np.pi * 3000.0 * ringing_t)
impacts = np.zeros_like(t)
for t0 in strikes[strikes < t[-1] - 0.01]:
    i = int(round(t0 * fs))
    impacts[i : i + ringing.size] += ringing
shaft = 2.0 * np.sin(2 * np.pi * shaft_hz * t) + 0.8 * np.sin(2 * np.pi * 2 * shaft_hz * t + 1.0)
x = impacts + shaft + 0.4 * rng.standard_normal(t.size)

fig, ax = plt.subplots(figsize=(8, 3))
ax.plot(t[:2400] * 1e3, x[:2400], lw=0.6)
ax.set(xlabel="time (ms)", ylabel="acceleration", title="synthetic record: the first 0.2 s")
plt.show()

# %%
# The diagnosis
# -------------
# Inside: cepstral prewhitening, the band of the infogram whose envelope holds the most
# lines (beside the whole band), the squared envelope spectrum normalised by its
# background, and a harmonic comb per fault family tested against a false-alarm
# probability of 1e-4 (see the theory pages).
d = dg.diagnose(x, fs, geometry, shaft_hz)
print(f"fault: {d.fault}, confidence {d.confidence:.2f}, band {d.band[0]:.0f}-{d.band[1]:.0f} Hz")
print({family: round(score, 1) for family, score in d.scores.items()})

# %%
# What it saw: the squared envelope spectrum of the chosen band, with the fault
# frequencies' harmonics marked. The comb at BPFO stands out.
f, amp = dg.envelope_spectrum(dg.prewhiten(x, fs), fs, band=d.band)
plot_envelope_spectrum(f, amp, markers=d.frequencies, f_max=600.0)
plt.show()

# %%
# A measured CWRU record, when one is at hand
# -------------------------------------------
# :func:`diagnostics.read_signal` reads the ``*_DE_time`` channel of a CWRU ``.mat`` file
# and the shaft speed in rpm from the file (``sig.meta["rpm"]``).


def find_record(name: str) -> Path | None:
    """The record in ../shared/data/cwru beside the checkout, or None."""
    here = Path(globals().get("__file__", "examples/x.py")).resolve().parent
    for folder in (here, *here.parents):
        path = folder.parent / "shared" / "data" / "cwru" / name
        if path.is_file():
            return path
    return None


path = find_record("12k_Drive_End_OR007@6_0_130.mat")
if path is None:
    print("CWRU record 130 not found beside the repository: skipped")
else:
    sig = dg.read_signal(path, fs=12000)
    measured = dg.diagnose(sig.x, sig.fs, geometry, sig.meta["rpm"] / 60)
    print(f"{path.name}: {sig.x.size / sig.fs:.1f} s at {sig.meta['rpm']} rpm")
    print(f"fault: {measured.fault}, confidence {measured.confidence:.2f}")
