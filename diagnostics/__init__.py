"""diagnostics: bearing vibration diagnostics on measured or simulated signals.

Plain functions over numpy arrays with the sampling rate ``fs`` in Hz, in the manner of
``scipy.signal``: every public name is here, in this one namespace, and the modules that
define them are private (``diagnostics._kurtosis``, ``diagnostics._diagnose``, ...).
Figures live apart in the public module :mod:`diagnostics.plots` (matplotlib), and the
command line, the benchmark over public data sets and the comparison of records in
:mod:`diagnostics.app`; the signal code never imports either. numpy/scipy only; this
package never imports taichi.

Examples
--------
A measured record is read with :func:`read_signal` (``sig.x``, ``sig.fs``, and for a CWRU
file the speed in ``sig.meta["rpm"]``). Here, a synthetic 2 s record of the CWRU
drive-end bearing at 1797 rpm with an outer-race fault: one impact ringing a 2.5 kHz
resonance per BPFO period, jittered by slip, in noise.

>>> import numpy as np
>>> import diagnostics as dg
>>> geom = dg.BearingGeometry(9, 7.94e-3, 39.04e-3)
>>> freqs = dg.bearing_frequencies(geom, 1797 / 60)
>>> round(freqs.bpfo, 2), round(freqs.bpfi, 2)
(107.36, 162.19)
>>> fs, rng = 12000.0, np.random.default_rng(0)
>>> strikes = np.cumsum(rng.normal(1.0, 0.01, 214)) / freqs.bpfo       # impact times, s
>>> x = np.zeros(int(2 * fs))
>>> x[np.round(strikes * fs).astype(int)] = 1.0
>>> tau = np.arange(120) / fs
>>> x = np.convolve(x, np.exp(-900 * tau) * np.sin(2 * np.pi * 2500 * tau))[: x.size]
>>> x += 0.3 * rng.standard_normal(x.size)
>>> kg = dg.kurtogram(x, fs, nlevel=5)                 # the most impulsive band
>>> kg.band                                       # Hz, around the resonance
(2000.0, 3000.0)
>>> d = dg.diagnose(x, fs, geom, 1797 / 60)
>>> d.fault, round(d.confidence, 2)
('outer', 1.0)

At a varying speed, give the shaft rate per sample (from a tachometer,
:func:`speed_from_tacho`, or estimated from the vibration, :func:`estimate_speed`); the
diagnosis is then made in the order domain (``d.domain == "order"``): see
:func:`diagnose`.
"""

import importlib

# Public name -> the private module that defines it. The modules load on first use (PEP 562
# __getattr__ below), for start-up time: ``python -m diagnostics --help`` does not wait a
# second for scipy.signal.
_EXPORTS = {
    "_defect_size": ("DefectSize", "contact_speed", "estimate_defect_size",
                     "spall_length_from_travel"),
    "_candidates": ("Candidate",),
    "_diagnose": ("Diagnosis", "diagnose", "record_requirements"),
    "_comb": ("BandScore", "FamilyScore", "normalised_envelope_spectrum"),
    "_prewhiten": ("prewhiten",),
    "_bands": ("kurtogram_band",),
    "_envelope": ("envelope", "envelope_spectrum"),
    "_filters": ("bandpass_filter", "lowpass_filter", "notch_filter"),
    "_frequencies": ("BearingGeometry", "FaultFrequencies", "bearing_frequencies"),
    "_io": ("Signal", "read_signal", "read_speed_profile"),
    "_kurtosis": ("Infogram", "Kurtogram", "infogram", "kurtogram", "kurtogram_and_infogram"),
    "_spectral_kurtosis": ("SpectralKurtosis", "sk_threshold", "spectral_kurtosis"),
    "_resolution": ("choose_nlevel", "choose_nperseg", "choose_sk_windows",
                    "third_octave_f_min"),
    "_separation": ("Separation", "discrete_random_separation"),
    "_spectral": ("psd", "stft", "third_octave", "third_octave_centres"),
    "_speed": ("OrderTrack", "order_track", "shaft_angle", "speed_from_tacho"),
    "_shaft_lines": ("ShaftLines", "shaft_lines", "speed_check"),
    "_speed_estimate": ("SpeedEstimate", "estimate_speed"),
}  # fmt: skip
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}
# The public module of figures, reached as an attribute too (``dg.plots``); not in
# ``__all__``, so that ``from diagnostics import *`` does not load matplotlib. (The
# application, ``diagnostics.app``, is imported by name: this package never loads it.)
_SUBMODULES = ("plots",)

__all__ = sorted(_MODULE_OF)


def __getattr__(name: str):
    module = _MODULE_OF.get(name)
    if module is not None:
        value = getattr(importlib.import_module(f"diagnostics.{module}"), name)
        globals()[name] = value  # later look-ups skip this function
        return value
    if name in _SUBMODULES:
        return importlib.import_module(f"diagnostics.{name}")
    raise AttributeError(f"module 'diagnostics' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__) | set(_SUBMODULES))
