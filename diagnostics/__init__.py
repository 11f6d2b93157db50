"""diagnostics: bearing vibration diagnostics on measured or simulated signals.

numpy/scipy only (plus pandas for tables, matplotlib for ``diagnostics.plots``); never
imports taichi.
"""

from diagnostics.frequencies import BearingGeometry, FaultFrequencies, bearing_frequencies

__all__ = ["BearingGeometry", "FaultFrequencies", "bearing_frequencies"]
