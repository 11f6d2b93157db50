"""Checks a bearing run performs on its own results: post-processing of the run folder
(numpy/pandas only; no Taichi, no mesh, no solver).

Inputs are what the run folder holds (:mod:`taichi_bearing.output.run_folder`): the case, the
mesh's ``info`` (``mesh_info.json``: polygon edge counts, spall geometry), the histories
(a DataFrame with the run folder's columns) and ``preload.json`` (static roller forces,
compared with the rigid-ring analytical model and with the flexible-ring reference solved
during the run; the ideal rolling rates). :func:`run_checks` returns the ``summary.json``
entries; every check is ``{value, limit, passed, note}`` (``passed`` None when it does not
apply, e.g. too short a run for two re-stressing events).
"""

from taichi_bearing.checks.common import LOADED_SHARE, check
from taichi_bearing.checks.events import exit_burst_check, inner_restress_check, restress_check
from taichi_bearing.checks.forces import flexible_reference_checks, static_force_checks
from taichi_bearing.checks.motion import energy_balance_check, speed_checks
from taichi_bearing.checks.passages import SpallEvent, detect_spall_events, passage_signature
from taichi_bearing.checks.run import main_sensor, run_checks
from taichi_bearing.checks.spectra import (
    defect_size_check,
    noise_check,
    noise_frequencies,
    predicted_noise_frequencies,
)

__all__ = [
    "LOADED_SHARE",
    "SpallEvent",
    "check",
    "defect_size_check",
    "detect_spall_events",
    "energy_balance_check",
    "exit_burst_check",
    "flexible_reference_checks",
    "inner_restress_check",
    "main_sensor",
    "noise_check",
    "noise_frequencies",
    "passage_signature",
    "predicted_noise_frequencies",
    "restress_check",
    "run_checks",
    "speed_checks",
    "static_force_checks",
]
