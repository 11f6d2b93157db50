"""diagnostics: bearing vibration diagnostics on measured or simulated signals.

Plain functions over numpy arrays with the sampling rate ``fs`` in Hz, in the manner of
``scipy.signal``; figures live apart in :mod:`diagnostics.plots`. numpy/scipy only (pandas
for tables, matplotlib for plots); this package never imports taichi.

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
:func:`diagnostics.diagnose.diagnose`.
"""

import importlib
import sys
import types

# Public name -> the module that defines it. The modules load on first use (PEP 562), so
# ``python -m diagnostics --help`` does not wait a second for scipy.signal.
_EXPORTS = {
    "defect_size": ("DefectSize", "contact_speed", "estimate_defect_size",
                    "spall_length_from_travel"),
    "diagnose": ("Diagnosis", "FamilyScore", "diagnose", "kurtogram_band", "prewhiten"),
    "envelope": ("envelope", "envelope_spectrum"),
    "filters": ("bandpass_filter", "lowpass_filter", "notch_filter"),
    "frequencies": ("BearingGeometry", "FaultFrequencies", "bearing_frequencies"),
    "io": ("Signal", "read_signal", "read_speed_profile"),
    "kurtosis": ("Infogram", "Kurtogram", "infogram", "kurtogram", "sk_threshold",
                 "spectral_kurtosis"),
    "resolution": ("choose_nlevel", "choose_nperseg", "choose_sk_windows",
                   "third_octave_f_min"),
    "separation": ("Separation", "discrete_random_separation"),
    "spectral": ("psd", "stft", "third_octave"),
    "speed": ("OrderTrack", "ShaftLines", "SpeedEstimate", "estimate_speed", "order_track",
              "shaft_angle", "shaft_lines", "speed_check", "speed_from_tacho"),
}  # fmt: skip
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}

__all__ = sorted(_MODULE_OF)


def __getattr__(name: str):
    module = _MODULE_OF.get(name)
    if module is None:  # a submodule, as `import diagnostics` made them all attributes
        try:
            return importlib.import_module(f"diagnostics.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"diagnostics.{name}":
                raise
        raise AttributeError(f"module 'diagnostics' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"diagnostics.{module}"), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


class _Package(types.ModuleType):
    """This package, keeping its public functions ``diagnose`` and ``envelope`` over the
    submodules of the same names: importing a submodule binds it on the package, and
    once bound a name never reaches ``__getattr__``."""

    def __setattr__(self, name: str, value) -> None:
        if isinstance(value, types.ModuleType) and _MODULE_OF.get(name) == name:
            value = getattr(value, name)  # the function, as an eager import gave
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package
