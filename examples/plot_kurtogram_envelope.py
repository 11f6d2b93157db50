"""
Kurtogram and envelope analysis, step by step
=============================================

What :func:`diagnostics.diagnose` does inside, one function at a time, on a record where
the fault cannot be seen in the raw spectrum: a roller bearing (20 rollers of 24 mm on a
200 mm pitch circle, as the simulator's cases) at 1000 rpm with an outer-race spall whose
impacts ring a 4.5 kHz resonance, under a strong gear-mesh tone, mains hum and noise.

1. the power spectrum: the tones dominate, the impacts spread thin;
2. spectral kurtosis: which frequencies are impulsive;
3. the fast kurtogram: the most impulsive band and its width;
4. band-pass and Hilbert envelope: the impacts as bursts, one per BPFO period;
5. the squared envelope spectrum: lines at BPFO and its harmonics.
"""

# %%
# A record with a hidden outer-race fault
# ---------------------------------------
import matplotlib.pyplot as plt
import numpy as np

import diagnostics as dg
from diagnostics.plots import plot_envelope_spectrum, plot_kurtogram

geometry = dg.BearingGeometry(n_rollers=20, roller_diameter=24e-3, pitch_diameter=200e-3)
shaft_hz = 1000 / 60
bpfo = dg.bearing_frequencies(geometry, shaft_hz).bpfo
print(f"BPFO = {bpfo:.2f} Hz: one impact every {1e3 / bpfo:.2f} ms")

fs = 20000.0
rng = np.random.default_rng(7)
t = np.arange(int(1.5 * fs)) / fs
tau = np.arange(int(0.004 * fs)) / fs
ringing = np.exp(-0.04 * 2 * np.pi * 4500.0 * tau) * np.sin(2 * np.pi * 4500.0 * tau)
impacts = np.zeros_like(t)
for t0 in np.cumsum(rng.normal(1.0, 0.01, int(1.5 * bpfo) + 1) / bpfo):
    i = int(round(t0 * fs))
    if i + ringing.size < t.size:
        impacts[i : i + ringing.size] += rng.uniform(0.6, 1.0) * ringing
tones = 3.0 * np.sin(2 * np.pi * 1200.0 * t) + 1.0 * np.sin(2 * np.pi * 50.0 * t)
x = 1.5 * impacts + tones + 0.6 * rng.standard_normal(t.size)

# %%
# 1. The power spectrum
# ---------------------
# Welch's estimate (:func:`diagnostics.psd`): the gear tone and the hum stand far above
# everything; the resonance band the impacts excite is a broad, low hump.
f, p = dg.psd(x, fs, nperseg=2048)
fig, ax = plt.subplots(figsize=(8, 3))
ax.semilogy(f, p, lw=0.7)
ax.set(xlabel="frequency (Hz)", ylabel="PSD (unit$^2$/Hz)", title="power spectral density")
plt.show()

# %%
# 2. Spectral kurtosis
# --------------------
# The kurtosis of the short-time Fourier transform at each frequency
# (:func:`diagnostics.spectral_kurtosis`): about 0 for Gaussian noise, -1 for a steady
# tone, large where impulses are. Values above ``sk_threshold`` are unlikely (1 %) from
# noise alone.
sk = dg.spectral_kurtosis(x, fs, nw=64)
n_frames = x.size // (64 // 4)
fig, ax = plt.subplots(figsize=(8, 3))
ax.plot(sk.f, sk.sk, lw=0.8)
ax.axhline(dg.sk_threshold(n_frames), color="r", ls="--", lw=0.8, label="1 % threshold")
ax.set(xlabel="frequency (Hz)", ylabel="spectral kurtosis", title="spectral kurtosis")
ax.legend()
plt.show()
print(f"most impulsive frequency: {sk.f[np.argmax(sk.sk)]:.0f} Hz")

# %%
# 3. The fast kurtogram
# ---------------------
# Antoni's fast kurtogram (:func:`diagnostics.kurtogram`) splits the band in halves and
# thirds, level after level, and computes the kurtosis of each band's complex envelope;
# the best band balances a narrow band (less noise) against a wide one (short impulses).
kg = dg.kurtogram(x, fs, nlevel=6)
print(
    f"best band: {kg.fc:.0f} Hz centre, {kg.bw:.0f} Hz wide (level {kg.level:.1f}), "
    f"kurtosis {kg.kurtosis:.1f}"
)
plot_kurtogram(kg)
plt.show()

# %%
# 4. Band-pass and envelope
# -------------------------
# A zero-phase band-pass to the kurtogram's band (:func:`diagnostics.bandpass_filter`)
# and its Hilbert envelope (:func:`diagnostics.envelope`): one burst per roller passing
# the spall, one BPFO period apart.
low, high = kg.band
y = dg.bandpass_filter(x, fs, low, high)
env = dg.envelope(y, fs)
fig, ax = plt.subplots(figsize=(8, 3))
n = int(0.05 * fs)
ax.plot(1e3 * t[:n], y[:n], lw=0.6, label="band-passed")
ax.plot(1e3 * t[:n], env[:n], lw=1.0, label="envelope")
ax.set(xlabel="time (ms)", title=f"{low:.0f}-{high:.0f} Hz: the impacts")
ax.legend()
plt.show()

# %%
# 5. The squared envelope spectrum
# --------------------------------
# The spectrum of the squared envelope (:func:`diagnostics.envelope_spectrum`) has a line
# at the impacts' repetition rate and its harmonics: here at BPFO, the outer-race fault.
# The raw record's envelope spectrum has the line too, but the noise and the tones outside
# the resonance band fill its background: the band lifts BPFO ten times higher above it.
f_env, amp = dg.envelope_spectrum(x, fs, band=kg.band)
f_raw, amp_raw = dg.envelope_spectrum(x, fs)
fig, axes = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
markers = {"BPFO": bpfo}
plot_envelope_spectrum(
    f_raw, amp_raw, markers=markers, f_max=800.0, ax=axes[0], title="whole band (raw record)"
)
plot_envelope_spectrum(
    f_env,
    amp,
    markers=markers,
    f_max=800.0,
    ax=axes[1],
    title=f"kurtogram band {low:.0f}-{high:.0f} Hz",
)
fig.tight_layout()
plt.show()
for label, fk, ak in (("whole band", f_raw, amp_raw), ("kurtogram band", f_env, amp)):
    shown = (fk > 20) & (fk < 800)
    at_bpfo = ak[np.argmin(np.abs(fk - bpfo))] / np.median(ak[shown])
    peak = fk[shown][np.argmax(ak[shown])]
    print(f"{label}: strongest line {peak:.1f} Hz, BPFO {at_bpfo:.0f} x the median")
