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

import importlib
import sys
import types

# Public name -> the module that defines it. The modules load on first use (PEP 562), so
# ``python -m diagnostics --help`` and ``import diagnostics.files`` do not wait a second
# for scipy.signal.
_EXPORTS = {
    "defect_size": ("DefectSize", "contact_speed", "estimate_defect_size",
                    "spall_length_from_travel"),
    "diagnose": ("Diagnosis", "FamilyScore", "diagnose", "prewhiten"),
    "envelope": ("envelope", "envelope_spectrum"),
    "filters": ("bandpass_filter", "lowpass_filter", "notch_filter"),
    "frequencies": ("BearingGeometry", "FaultFrequencies", "bearing_frequencies"),
    "io": ("Signal", "read_signal", "read_speed_profile"),
    "kurtosis": ("Kurtogram", "kurtogram", "sk_threshold", "spectral_kurtosis"),
    "separation": ("Separation", "discrete_random_separation"),
    "spectral": ("psd", "stft", "third_octave"),
    "speed": ("OrderTrack", "SpeedEstimate", "estimate_speed", "order_track", "shaft_angle",
              "speed_from_tacho"),
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
