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
from diagnostics.io import Signal, read_signal
from diagnostics.kurtosis import Kurtogram, kurtogram, sk_threshold, spectral_kurtosis
from diagnostics.spectral import psd, stft, third_octave

__all__ = [
    "BearingGeometry",
    "DefectSize",
    "Diagnosis",
    "FamilyScore",
    "FaultFrequencies",
    "Kurtogram",
    "Signal",
    "bandpass_filter",
    "bearing_frequencies",
    "contact_speed",
    "diagnose",
    "envelope",
    "envelope_spectrum",
    "estimate_defect_size",
    "kurtogram",
    "lowpass_filter",
    "notch_filter",
    "prewhiten",
    "psd",
    "read_signal",
    "sk_threshold",
    "spall_length_from_travel",
    "spectral_kurtosis",
    "stft",
    "third_octave",
]
