"""diagnostics: bearing vibration diagnostics on measured or simulated signals.

Plain functions over numpy arrays with the sampling rate ``fs`` in Hz, in the manner of
``scipy.signal``; figures live apart in :mod:`diagnostics.plots`. numpy/scipy only (pandas
for tables, matplotlib for plots); this package never imports taichi.

Examples
--------
>>> import diagnostics as dg
>>> sig = dg.read_signal("12k_Drive_End_OR007@6_0_130.mat", fs=12000)     # doctest: +SKIP
>>> geom = dg.BearingGeometry(9, 7.94e-3, 39.04e-3)
>>> dg.diagnose(sig.x, sig.fs, geom, sig.meta["rpm"] / 60).fault          # doctest: +SKIP
'outer'

At a varying speed, give the shaft rate per sample (from a tachometer, or estimated from
the vibration); the diagnosis is then made in the order domain:

>>> rate = dg.speed_from_tacho(sig.channel("tacho"), sig.fs, pulses_per_rev=1)  # doctest: +SKIP
>>> dg.diagnose(sig.x, sig.fs, geom, rate).domain                           # doctest: +SKIP
'order'
"""

from diagnostics.defect_size import (
    DefectSize,
    contact_speed,
    estimate_defect_size,
    spall_length_from_travel,
)
from diagnostics.diagnose import Diagnosis, FamilyScore, diagnose, prewhiten
from diagnostics.envelope import envelope, envelope_spectrum
from diagnostics.filters import bandpass_filter, lowpass_filter, notch_filter
from diagnostics.frequencies import BearingGeometry, FaultFrequencies, bearing_frequencies
from diagnostics.io import Signal, read_signal, read_speed_profile
from diagnostics.kurtosis import Kurtogram, kurtogram, sk_threshold, spectral_kurtosis
from diagnostics.separation import Separation, discrete_random_separation
from diagnostics.spectral import psd, stft, third_octave
from diagnostics.speed import (
    OrderTrack,
    SpeedEstimate,
    estimate_speed,
    order_track,
    shaft_angle,
    speed_from_tacho,
)

__all__ = [
    "BearingGeometry",
    "DefectSize",
    "Diagnosis",
    "FamilyScore",
    "FaultFrequencies",
    "Kurtogram",
    "OrderTrack",
    "Separation",
    "Signal",
    "SpeedEstimate",
    "bandpass_filter",
    "bearing_frequencies",
    "contact_speed",
    "diagnose",
    "discrete_random_separation",
    "envelope",
    "envelope_spectrum",
    "estimate_defect_size",
    "estimate_speed",
    "kurtogram",
    "lowpass_filter",
    "notch_filter",
    "order_track",
    "prewhiten",
    "psd",
    "read_signal",
    "read_speed_profile",
    "shaft_angle",
    "sk_threshold",
    "spall_length_from_travel",
    "spectral_kurtosis",
    "speed_from_tacho",
    "stft",
    "third_octave",
]
