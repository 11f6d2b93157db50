"""All checks of a run from its folder's contents: :func:`run_checks` returns the
``summary.json`` entries."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np
import pandas as pd

from taichi_bearing.analytic.bearing import fault_frequencies
from taichi_bearing.analytic.quasistatic import analytical_roller_forces
from taichi_bearing.case import Case
from taichi_bearing.checks.common import PASSAGE_WINDOW_M
from taichi_bearing.checks.events import exit_burst_check, inner_restress_check, restress_check
from taichi_bearing.checks.forces import flexible_reference_checks, static_force_checks
from taichi_bearing.checks.modulation import load_zone_check
from taichi_bearing.checks.motion import energy_balance_check, speed_checks
from taichi_bearing.checks.passages import (
    detect_spall_events,
    passage_signature,
    passage_statistics,
    spall_passages,
)
from taichi_bearing.checks.spectra import (
    defect_size_check,
    noise_check,
    noise_frequencies,
    predicted_noise_frequencies,
)
from taichi_bearing.output.layout import (
    REFERENCE_KEY,
    ROLLING_RATES_KEY,
    sensor_column,
)


def main_sensor(case: Case, hist: pd.DataFrame) -> str:
    """The sensor whose vertical acceleration is analysed (the first in the case)."""
    names = [n for n in case.sensors if sensor_column(n, "ay") in hist]
    if not names:
        raise ValueError("the histories hold no sensor acceleration")
    return names[0]


def run_checks(case: Case, info: Mapping, hist: pd.DataFrame, preload: Mapping) -> dict:
    """All checks of a run, as ``summary.json`` entries.

    Parameters
    ----------
    case : Case
        The run's ``case.yaml``.
    info : mapping
        The mesh info (``mesh_info.json``).
    hist : pandas.DataFrame
        The histories (a run that did not finish: what was recorded).
    preload : mapping
        ``preload.json``: ``outer_force_N`` and the entries written after the preload,
        the flexible-ring reference and the ideal rolling rates
        (:data:`~taichi_bearing.output.run_folder.REFERENCE_KEY`,
        :data:`~taichi_bearing.output.run_folder.ROLLING_RATES_KEY`).

    Returns
    -------
    dict
    """
    n = case.bearing.n_rollers
    freqs = fault_frequencies(case.bearing, case.operating.shaft_hz)
    inner = case.defect.present and case.defect.race == "inner"
    rates = preload[ROLLING_RATES_KEY]
    checks: dict[str, dict] = {}
    analytical = analytical_roller_forces(case)
    static = np.asarray(preload["outer_force_N"], dtype=float)
    checks.update(static_force_checks(static, analytical, case.bearing.outer_support))
    reference = np.asarray(preload[REFERENCE_KEY], dtype=float)
    checks.update(flexible_reference_checks(static, reference))
    speed, speed_values = speed_checks(case, hist, rates)
    checks.update(speed)
    checks["energy_balance"], balance = energy_balance_check(hist)
    events = detect_spall_events(hist, n, info, case.bearing.roller_radius, case.operating.speed)
    if inner:
        checks["restress_interval"] = inner_restress_check(events, freqs.bpfi)
    else:
        checks["restress_interval"] = restress_check(events, freqs.bpfo)
    fs = case.run.sample_rate
    sensor = main_sensor(case, hist)
    signal = sensor_column(sensor, "ay")
    acc = hist[signal].to_numpy()
    # windows of 1.5 mm of contact travel (the re-stressing takes longer at low speed)
    window = PASSAGE_WINDOW_M / (rates["cage"] * case.bearing.outer_raceway_radius)
    race = "inner" if inner else "outer"
    # inside an extended spall another roller's entry or exit falls in one's traverse
    signatures = [
        passage_signature(hist, e, signal, window, race, [o for o in events if o is not e])
        for e in events
    ]
    for e, sig in zip(events, signatures, strict=True):
        e.update(sig)
    checks["exit_burst"] = exit_burst_check(signatures)
    predicted = predicted_noise_frequencies(info, rates)
    measured, resolution, prominence = noise_frequencies(acc, fs, predicted)
    checks["noise_frequencies"] = noise_check(
        predicted, measured, resolution, prominence, faceted=not case.contact.smoothing
    )
    checks["defect_size"], size = defect_size_check(case, acc, fs)
    extra: dict = {}
    if inner:
        passages = spall_passages(hist, n, info, case.operating.speed)
        checks["load_zone_sidebands"], sidebands = load_zone_check(
            case, acc, fs, passages, reference
        )
        extra = {
            "spall_race": "inner",
            "bpfi_hz": freqs.bpfi,
            "passages": passages,
            "sidebands": sidebands,
        }
    return {
        "sensor_names": list(case.sensors),
        "analysed_signal": signal,
        "n_rollers": n,
        "shaft_hz": case.operating.shaft_hz,
        "ftf_hz": freqs.ftf,
        "bpfo_hz": freqs.bpfo,
        "energy_balance_error": balance,
        "static_roller_forces_N": static.tolist(),
        "analytical_roller_forces_N": analytical.tolist(),
        "reference_roller_forces_N": reference.tolist(),
        **speed_values,
        "events": [dict(e) for e in events],
        # median and interquartile range over the passages (one passage is one sample)
        "passage_statistics": passage_statistics(signatures),
        "entry_times_s": [e["entry_time_s"] for e in events],
        "restress_times_s": [e["exit_time_s"] for e in events],
        "noise_frequencies_predicted_hz": predicted,
        "noise_frequencies_measured_hz": measured,
        "noise_peak_prominence_db": prominence,
        "defect_size_estimate_m": size,
        "defect_size_true_m": case.defect.length if case.defect.present else None,
        **extra,
        "checks": checks,
    }
