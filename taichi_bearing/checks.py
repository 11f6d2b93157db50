"""Checks a bearing run performs on its own results (numpy/pandas only, no Taichi).

Inputs are the case, the mesh's ``info`` (polygon edge counts, spall geometry), the
histories (a DataFrame with the columns of ``notes/rundir.md``) and the preload result
(static roller forces). :func:`run_checks` returns the ``summary.json`` entries; every
check is ``{value, limit, passed, note}`` (``passed`` None when it does not apply, e.g.
too short a run for two re-stressing events).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pandas as pd

from taichi_bearing.bearing import fault_frequencies
from taichi_bearing.case import Case
from taichi_bearing.quasistatic import analytical_roller_forces
from taichi_bearing.starter import rolling_rates

__all__ = [
    "SpallEvent",
    "check",
    "detect_spall_events",
    "energy_balance_check",
    "noise_frequencies",
    "predicted_noise_frequencies",
    "run_checks",
    "speed_checks",
    "static_force_checks",
]

# Limits of issue 6
STATIC_EACH_LIMIT = 0.10
STATIC_QMAX_LIMIT = 0.05
SPEED_LIMIT = 0.02
RESTRESS_LIMIT = 0.02
ENERGY_LIMIT = 0.02
NOISE_LIMIT = 0.05
DEFECT_SIZE_LIMIT = 0.5
# A roller counts as loaded when the analytical model gives it this share of Q_max.
LOADED_SHARE = 0.05


def check(value, limit, passed, note: str = "") -> dict:
    """One entry of ``summary["checks"]`` (NaN values become None)."""

    def clean(v):
        if v is None:
            return None
        v = float(v)
        return v if math.isfinite(v) else None

    return {
        "value": clean(value),
        "limit": clean(limit),
        "passed": None if passed is None else bool(passed),
        "note": note,
    }


# ------------------------------------------------------------------ static forces


def static_force_checks(static: np.ndarray, analytical: np.ndarray) -> dict[str, dict]:
    """Each loaded roller within 10 % of the analytical force, Q_max within 5 %."""
    static = np.asarray(static, dtype=float)
    analytical = np.asarray(analytical, dtype=float)
    q_max = analytical.max()
    loaded = analytical > LOADED_SHARE * q_max
    rel = np.abs(static[loaded] - analytical[loaded]) / analytical[loaded]
    worst = int(np.flatnonzero(loaded)[np.argmax(rel)])
    qmax_err = abs(static.max() - q_max) / q_max
    return {
        "static_roller_forces": check(
            rel.max(),
            STATIC_EACH_LIMIT,
            rel.max() <= STATIC_EACH_LIMIT,
            f"largest relative error over the {int(loaded.sum())} loaded rollers "
            f"(roller {worst}: {static[worst]:.5g} N vs {analytical[worst]:.5g} N)",
        ),
        "static_q_max": check(
            qmax_err,
            STATIC_QMAX_LIMIT,
            qmax_err <= STATIC_QMAX_LIMIT,
            f"FE {static.max():.5g} N vs analytical {q_max:.5g} N",
        ),
    }


# ------------------------------------------------------------------ speeds


def startup_time(case: Case) -> float:
    """End of the start-up left out of the speed checks: a fifth of the run, s."""
    return 0.2 * case.run.duration


def _slope(t: np.ndarray, y: np.ndarray) -> float:
    if len(t) < 2:
        return math.nan
    return float(np.polyfit(t, y, 1)[0])


def speed_checks(case: Case, hist: pd.DataFrame) -> tuple[dict[str, dict], dict]:
    """Cage speed (slope of the cage angle) and the spin of the loaded rollers (relative
    to the cage) after the start-up, against ideal rolling."""
    rates = rolling_rates(case)
    t = hist["time_s"].to_numpy()
    after = t >= startup_time(case)
    cage = _slope(t[after], hist["cage_angle_rad"].to_numpy()[after])
    cage_err = abs(cage - rates.cage) / abs(rates.cage)
    out = {
        "cage_speed": check(
            cage_err,
            SPEED_LIMIT,
            cage_err <= SPEED_LIMIT,
            f"{cage:.5g} rad/s vs kinematics {rates.cage:.5g} rad/s",
        )
    }
    # spin relative to the cage, of rollers in the load zone (|angle| < 60 deg)
    spins = []
    n = case.bearing.n_rollers
    for j in range(n):
        a = hist.get(f"roller{j}_angle_rad")
        s = hist.get(f"roller{j}_spin_rad_s")
        if a is None or s is None:
            continue
        a = np.asarray(a)
        zone = after & (np.abs((a + math.pi) % (2 * math.pi) - math.pi) < math.radians(60))
        if zone.sum() > 1:
            spins.append(np.asarray(s)[zone] - cage)
    if spins:
        rel_spin = float(np.median(np.concatenate(spins)))
        spin_err = abs(rel_spin - rates.roller_relative) / abs(rates.roller_relative)
        out["roller_spin"] = check(
            spin_err,
            SPEED_LIMIT,
            spin_err <= SPEED_LIMIT,
            f"median spin relative to the cage of the loaded rollers {rel_spin:.5g} rad/s "
            f"vs kinematics {rates.roller_relative:.5g} rad/s",
        )
    return out, {"cage_speed_rad_s": cage, "cage_speed_rel_error": cage_err}


# ------------------------------------------------------------------ energy


def energy_balance_check(hist: pd.DataFrame) -> tuple[dict, float]:
    """Largest |energy balance error| of the run (relative to the largest energy)."""
    err = float(np.max(np.abs(hist["energy_balance_error"].to_numpy())))
    return check(err, ENERGY_LIMIT, err <= ENERGY_LIMIT, "max over the run"), err


# ------------------------------------------------------------------ spall events


class SpallEvent(dict):
    """``roller``, ``entry_time_s`` (de-stressing starts), ``exit_time_s`` (re-stressing),
    ``force_before_N``, ``force_min_N``."""


def _spall_window(info: Mapping) -> tuple[float, float] | None:
    spall = info.get("spall")
    if not spall or spall.get("race") != "outer":
        return None
    centre = float(spall["centre_angle_from_top"])
    half = 0.5 * float(spall["length"]) / float(spall["raceway_radius"])
    return centre - half, centre + half


def detect_spall_events(
    hist: pd.DataFrame, n_rollers: int, info: Mapping, roller_radius: float
) -> list[SpallEvent]:
    """Entry and exit of every roller that passes the outer-raceway spall.

    For each roller whose centre angle crosses the spall, ``F0`` is its median normal
    force on the outer raceway while its centre is between one and two spall lengths
    before the spall. Entry: the first time, in the window from half a roller radius
    before the spall to its end, that the force falls below 0.95 F0. Exit: the first time
    after the force minimum that it rises back above 0.5 F0.
    """
    window = _spall_window(info)
    if window is None:
        return []
    start, end = window
    span = end - start
    pitch = float(info.get("pitch_radius", 1.0))
    lead = 0.5 * roller_radius / pitch
    t = hist["time_s"].to_numpy()
    events = []
    for j in range(n_rollers):
        a_col = f"roller{j}_angle_rad"
        if a_col not in hist:
            continue
        a = hist[a_col].to_numpy()
        fn = hist[f"roller{j}_outer_fn"].to_numpy()
        rel = (a - start + math.pi) % (2 * math.pi) - math.pi  # angle past the spall start
        before = (rel > -2 * span - lead) & (rel < -span - lead)
        near = (rel > -lead) & (rel < span + lead)
        if before.sum() < 2 or near.sum() < 2 or rel[-1] < span:
            continue
        f0 = float(np.median(fn[before]))
        if not f0 > 0:
            continue
        idx = np.flatnonzero(near)
        drop = idx[fn[idx] < 0.95 * f0]
        if drop.size == 0:
            continue
        i_entry = int(drop[0])
        after = np.arange(i_entry, len(t))
        # minimum within the passage, then the first return above half the load
        stop = np.flatnonzero(rel[after] > span + 2 * lead)
        seg = after[: stop[0]] if stop.size else after
        i_min = int(seg[np.argmin(fn[seg])])
        back = np.flatnonzero(fn[i_min:] > 0.5 * f0)
        if back.size == 0:
            continue
        i_exit = i_min + int(back[0])
        events.append(
            SpallEvent(
                roller=j,
                entry_time_s=float(t[i_entry]),
                exit_time_s=float(t[i_exit]),
                force_before_N=f0,
                force_min_N=float(fn[i_min]),
            )
        )
    events.sort(key=lambda e: e["entry_time_s"])
    return events


def restress_check(events: list, bpfo_hz: float) -> dict:
    """Time between consecutive re-stressing events against 1/BPFO."""
    times = np.array([e["exit_time_s"] for e in events])
    if len(times) < 2:
        return check(None, RESTRESS_LIMIT, None, f"{len(times)} re-stressing event(s): needs two")
    gaps = np.diff(times)
    err = float(np.max(np.abs(gaps * bpfo_hz - 1.0)))
    return check(
        err,
        RESTRESS_LIMIT,
        err <= RESTRESS_LIMIT,
        f"intervals {', '.join(f'{g * 1e3:.4g}' for g in gaps)} ms vs 1/BPFO "
        f"{1e3 / bpfo_hz:.4g} ms",
    )


# ------------------------------------------------------------------ numerical noise


def predicted_noise_frequencies(case: Case, info: Mapping) -> dict[str, float]:
    """Rolling-contact noise of the faceted (polygonal) surfaces, Hz: each contact crosses
    the facets of a surface at (edges) x (the surface's rotation rate relative to the
    contact): outer raceway N_o f_cage, inner N_i (f_shaft - f_cage), roller N_r f_spin
    relative to the cage."""
    rates = rolling_rates(case)
    edges = info["polygon_edges"]
    two_pi = 2 * math.pi
    return {
        "outer_raceway": edges["outer_raceway"] * abs(rates.cage) / two_pi,
        "inner_raceway": edges["inner_raceway"] * abs(rates.shaft - rates.cage) / two_pi,
        "roller": edges["roller0"] * abs(rates.roller_relative) / two_pi,
    }


def noise_frequencies(
    signal: np.ndarray, fs: float, predicted: Mapping[str, float], band: float = 0.1
) -> dict[str, float | None]:
    """Frequency of the highest spectral peak within +-``band`` of each prediction (None
    above Nyquist or for too short a signal)."""
    from diagnostics import psd

    x = np.asarray(signal, dtype=float)
    x = x - x.mean()
    if len(x) < 64:
        return dict.fromkeys(predicted)
    f, p = psd(x, fs, nperseg=min(4096, len(x)))
    out: dict[str, float | None] = {}
    for name, f0 in predicted.items():
        sel = (f >= (1 - band) * f0) & (f <= (1 + band) * f0)
        out[name] = float(f[sel][np.argmax(p[sel])]) if sel.any() and f0 < fs / 2 else None
    return out


def noise_check(predicted: Mapping[str, float], measured: Mapping[str, float | None]) -> dict:
    pairs = [(predicted[k], measured[k]) for k in predicted if measured.get(k) is not None]
    if not pairs:
        return check(None, NOISE_LIMIT, None, "no prediction below Nyquist")
    err = max(abs(m - p) / p for p, m in pairs)
    return check(
        err,
        NOISE_LIMIT,
        err <= NOISE_LIMIT,
        "largest relative distance of the spectral peak next to each predicted frequency "
        "(resolution-limited; band +-10 %): "
        + ", ".join(f"{k} {predicted[k]:.4g}->{measured[k]}" for k in predicted),
    )


# ------------------------------------------------------------------ defect size


def defect_size_check(case: Case, signal: np.ndarray, fs: float) -> tuple[dict, float | None]:
    from diagnostics import estimate_defect_size

    true = case.defect.length
    try:
        est = estimate_defect_size(
            signal,
            fs,
            case.bearing.geometry,
            case.operating.shaft_hz,
            case.defect.race,
            depth_m=case.defect.depth,
        )
    except ValueError as exc:
        return check(None, DEFECT_SIZE_LIMIT, None, f"not estimated: {exc}"), None
    err = abs(est.length_m - true) / true
    return (
        check(
            err,
            DEFECT_SIZE_LIMIT,
            err <= DEFECT_SIZE_LIMIT,
            f"estimate {est.length_m * 1e3:.4g} mm vs true {true * 1e3:.4g} mm",
        ),
        float(est.length_m),
    )


# ------------------------------------------------------------------ all


def main_sensor(case: Case, hist: pd.DataFrame) -> str:
    """The sensor whose vertical acceleration is analysed (the first in the case)."""
    names = [n for n in case.sensors if f"{n}_ay" in hist]
    if not names:
        raise ValueError("the histories hold no sensor acceleration")
    return names[0]


def run_checks(case: Case, info: Mapping, hist: pd.DataFrame, preload: Mapping) -> dict:
    """All checks of a finished run, as ``summary.json`` entries."""
    n = case.bearing.n_rollers
    freqs = fault_frequencies(case.bearing, case.operating.shaft_hz)
    checks: dict[str, dict] = {}
    analytical = analytical_roller_forces(case)
    static = np.asarray(preload["outer_force_N"], dtype=float)
    checks.update(static_force_checks(static, analytical))
    speed, speed_values = speed_checks(case, hist)
    checks.update(speed)
    checks["energy_balance"], balance = energy_balance_check(hist)
    events = detect_spall_events(hist, n, info, case.bearing.roller_radius)
    checks["restress_interval"] = restress_check(events, freqs.bpfo)
    fs = case.run.sample_rate
    sensor = main_sensor(case, hist)
    acc = hist[f"{sensor}_ay"].to_numpy()
    predicted = predicted_noise_frequencies(case, info)
    measured = noise_frequencies(acc, fs, predicted)
    checks["noise_frequencies"] = noise_check(predicted, measured)
    checks["defect_size"], size = defect_size_check(case, acc, fs)
    return {
        "sensor_names": list(case.sensors),
        "analysed_signal": f"{sensor}_ay",
        "n_rollers": n,
        "shaft_hz": case.operating.shaft_hz,
        "ftf_hz": freqs.ftf,
        "bpfo_hz": freqs.bpfo,
        "energy_balance_error": balance,
        "static_roller_forces_N": static.tolist(),
        "analytical_roller_forces_N": analytical.tolist(),
        **speed_values,
        "events": [dict(e) for e in events],
        "entry_times_s": [e["entry_time_s"] for e in events],
        "restress_times_s": [e["exit_time_s"] for e in events],
        "noise_frequencies_predicted_hz": predicted,
        "noise_frequencies_measured_hz": measured,
        "defect_size_estimate_m": size,
        "defect_size_true_m": case.defect.length if case.defect.present else None,
        "checks": checks,
    }
