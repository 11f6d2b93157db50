"""Checks a bearing run performs on its own results: post-processing of the run folder
(numpy/pandas only; no Taichi, no mesh, no solver).

Inputs are what the run folder holds (:mod:`taichi_bearing.run_folder`): the case, the
mesh's ``info`` (``mesh_info.json``: polygon edge counts, spall geometry), the histories
(a DataFrame with the run folder's columns) and ``preload.json`` (static roller forces,
compared with the rigid-ring analytical model and with the flexible-ring reference solved
during the run; the ideal rolling rates). :func:`run_checks` returns the ``summary.json``
entries; every check is ``{value, limit, passed, note}`` (``passed`` None when it does not
apply, e.g. too short a run for two re-stressing events).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pandas as pd

from taichi_bearing.bearing import fault_frequencies
from taichi_bearing.case import Case
from taichi_bearing.passages import (
    SpallEvent,
    detect_spall_events,
    passage_signature,
    passage_statistics,
    spall_passages,
)
from taichi_bearing.quasistatic import analytical_roller_forces
from taichi_bearing.run_folder import (
    BALANCE_COLUMN,
    CAGE_COLUMNS,
    REFERENCE_KEY,
    ROLLING_RATES_KEY,
    TIME_COLUMN,
    roller_motion_column,
    sensor_column,
)

__all__ = [
    "SpallEvent",
    "check",
    "detect_spall_events",
    "energy_balance_check",
    "exit_burst_check",
    "flexible_reference_checks",
    "inner_restress_check",
    "passage_signature",
    "noise_frequencies",
    "predicted_noise_frequencies",
    "run_checks",
    "speed_checks",
    "static_force_checks",
]

# Limits of the run's own checks
STATIC_EACH_LIMIT = 0.10
STATIC_QMAX_LIMIT = 0.05
SPEED_LIMIT = 0.02
RESTRESS_LIMIT = 0.02
ENERGY_LIMIT = 0.02
NOISE_LIMIT = 0.05
TONE_DB = 10.0  # a spectral peak this far above its band's median is a tone
DEFECT_SIZE_LIMIT = 0.5
DEFECT_ENTRY_CUTOFF_SHARE = 0.125  # entry low-pass cut-off / exit band's lower edge
EXIT_BURST_LIMIT = 2.0
PASSAGE_WINDOW_M = 1.5e-3  # contact travel of the entry and exit windows, m
# A roller counts as loaded when the analytical model gives it this share of Q_max.
LOADED_SHARE = 0.05
# An inner-race passage is in the load zone when its roller carried this share of the
# most loaded passing roller's force.
LOAD_ZONE_SHARE = 0.5
# Floor of each loaded roller's tolerance, as a share of Q_max (the zone-edge rollers).
STATIC_EDGE_SHARE = 0.05


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


def _force_checks(static, expected, names: tuple[str, str], what: str) -> dict[str, dict]:
    """Each loaded roller within 10 % of ``expected`` (or within 5 % of Q_max, whichever
    is larger), Q_max within 5 %.

    The absolute floor is for the zone-edge rollers: their force is the small difference
    of two ring displacements some 50 um large, so a difference of about 1 um in the
    approach (0.05 Q_max at the edge of the default load zone) moves them by tens of
    percent while leaving the load distribution as it is.
    """
    static = np.asarray(static, dtype=float)
    expected = np.asarray(expected, dtype=float)
    q_max = expected.max()
    loaded = expected > LOADED_SHARE * q_max
    allowed = np.maximum(STATIC_EACH_LIMIT * expected, STATIC_EDGE_SHARE * q_max)
    excess = np.abs(static - expected)[loaded] / allowed[loaded]  # <= 1 passes
    worst = int(np.flatnonzero(loaded)[np.argmax(excess)])
    qmax_err = abs(static.max() - q_max) / q_max
    return {
        names[0]: check(
            excess.max(),
            1.0,
            excess.max() <= 1.0,
            f"largest error over tolerance of the {int(loaded.sum())} loaded rollers "
            f"(10 % of its force or {STATIC_EDGE_SHARE:.0%} of Q_max, whichever is larger): "
            f"roller {worst}: {static[worst]:.5g} N vs {what} {expected[worst]:.5g} N "
            f"({static[worst] - expected[worst]:+.4g} N, allowed +-{allowed[worst]:.4g} N)",
        ),
        names[1]: check(
            qmax_err,
            STATIC_QMAX_LIMIT,
            qmax_err <= STATIC_QMAX_LIMIT,
            f"FE {static.max():.5g} N vs {what} {q_max:.5g} N",
        ),
    }


def static_force_checks(
    static: np.ndarray, analytical: np.ndarray, outer_support: str = "housing"
) -> dict[str, dict]:
    """Each loaded roller against the analytical (rigid-ring) force, Q_max within 5 %.

    The rigid-ring model holds for an outer ring held all round (``housing``). Hung from
    the adapter the ring ovalises and fewer rollers carry the load (Q_max some 40-50 %
    above Harris's on the default bearing); there the comparison is reported with
    ``passed`` None and the flexible-ring checks are the ones that apply.
    """
    out = _force_checks(static, analytical, ("static_roller_forces", "static_q_max"), "analytical")
    if outer_support != "housing":
        for entry in out.values():
            entry["passed"] = None
            entry["note"] += (
                "; not applicable: the adapter-hung outer ring is not rigid (see static_*_flexible)"
            )
    return out


def flexible_reference_checks(static: np.ndarray, reference: np.ndarray) -> dict[str, dict]:
    """The same limits against the flexible-ring reference
    (:mod:`taichi_bearing.static_reference`: the rings' own mesh and supports, a
    Palmgren spring per roller), which holds the ring flexibility the rigid-ring model
    leaves out: on the adapter-supported default bearing the FE load zone is the
    reference's, not Harris's."""
    return _force_checks(
        static,
        reference,
        ("static_roller_forces_flexible", "static_q_max_flexible"),
        "flexible-ring reference",
    )


# ------------------------------------------------------------------ speeds


def startup_time(case: Case) -> float:
    """End of the start-up left out of the speed checks: a fifth of the run, s."""
    return 0.2 * case.run.duration


def _slope(t: np.ndarray, y: np.ndarray) -> float:
    if len(t) < 2:
        return math.nan
    return float(np.polyfit(t, y, 1)[0])


def speed_checks(
    case: Case, hist: pd.DataFrame, rates: Mapping[str, float]
) -> tuple[dict[str, dict], dict]:
    """Cage speed and the spin of the loaded rollers (relative to the cage) after the
    start-up, against ideal rolling.

    The cage speed of kinematics is the orbital speed of the roller set: measured as the
    slope of the rollers' mean centre angle (the rigid cage, which only follows them
    through its pockets, is reported beside it). ``rates``: the ideal rolling rates of
    ``preload.json`` (``cage``, ``roller_relative``, rad/s).
    """
    t = hist[TIME_COLUMN].to_numpy()
    after = t >= startup_time(case)
    n = case.bearing.n_rollers
    cage_col = CAGE_COLUMNS[0]
    cols = [roller_motion_column(j, "angle_rad") for j in range(n)]
    if all(c in hist for c in cols):
        orbit = hist[cols].to_numpy().mean(axis=1)
        source = "mean roller orbit"
    else:
        orbit = hist[cage_col].to_numpy()
        source = "cage angle"
    cage = _slope(t[after], orbit[after])
    rigid = _slope(t[after], hist[cage_col].to_numpy()[after])
    ideal_cage, ideal_spin = rates["cage"], rates["roller_relative"]
    cage_err = abs(cage - ideal_cage) / abs(ideal_cage)
    out = {
        "cage_speed": check(
            cage_err,
            SPEED_LIMIT,
            cage_err <= SPEED_LIMIT,
            f"{source} {cage:.5g} rad/s vs kinematics {ideal_cage:.5g} rad/s "
            f"(rigid cage {rigid:.5g} rad/s)",
        )
    }
    # spin relative to the cage, of rollers in the load zone (|angle| < 60 deg)
    spins = []
    for j in range(n):
        a = hist.get(roller_motion_column(j, "angle_rad"))
        s = hist.get(roller_motion_column(j, "spin_rad_s"))
        if a is None or s is None:
            continue
        a = np.asarray(a)
        zone = after & (np.abs((a + math.pi) % (2 * math.pi) - math.pi) < math.radians(60))
        if zone.sum() > 1:
            spins.append(np.asarray(s)[zone] - cage)
    if spins:
        rel_spin = float(np.median(np.concatenate(spins)))
        spin_err = abs(rel_spin - ideal_spin) / abs(ideal_spin)
        out["roller_spin"] = check(
            spin_err,
            SPEED_LIMIT,
            spin_err <= SPEED_LIMIT,
            f"median spin relative to the cage of the loaded rollers {rel_spin:.5g} rad/s "
            f"vs kinematics {ideal_spin:.5g} rad/s",
        )
    return out, {
        "cage_speed_rad_s": cage,
        "rigid_cage_speed_rad_s": rigid,
        "cage_speed_rel_error": cage_err,
    }


# ------------------------------------------------------------------ energy


def energy_balance_check(hist: pd.DataFrame) -> tuple[dict, float]:
    """Largest |energy balance error| of the run (relative to the largest energy)."""
    err = float(np.max(np.abs(hist[BALANCE_COLUMN].to_numpy())))
    return check(err, ENERGY_LIMIT, err <= ENERGY_LIMIT, "max over the run"), err


# ------------------------------------------------------------------ spall passages


def exit_burst_check(signatures: list[dict]) -> dict:
    """Exit acceleration burst against entry and floor impact: the median passage.

    Each passage gives the ratio of its exit acceleration peak to the larger of its entry
    and traverse (floor impact) peaks; the check takes the median over the passages. One
    passage is one sample of a chaotic bounce: the size of the burst depends on where the
    roller is in its radial flight across the spall when the exit edge meets it (struck
    with a gap to the inner raceway it rattles between the two; arriving on the inner
    raceway it is squeezed up smoothly), and that phase is set by rounding-level
    differences after the first floor impact. The median states what a typical passage
    does; every passage's ratio is listed in the note.
    """
    if not signatures:
        return check(None, EXIT_BURST_LIMIT, None, "no complete passage")
    ratios = [
        s["exit_accel_peak"] / max(s["entry_accel_peak"], s["floor_accel_peak"], 1e-30)
        for s in signatures
    ]
    typical = float(np.median(ratios))
    n_pass = sum(r >= EXIT_BURST_LIMIT for r in ratios)
    return check(
        typical,
        EXIT_BURST_LIMIT,
        typical >= EXIT_BURST_LIMIT,
        "median over the passages of the ratio of the exit acceleration peak to the larger "
        "of the entry and traverse (floor impact) peaks; must be at least the limit; "
        f"{n_pass} of {len(ratios)} passages reach it; per passage: "
        + ", ".join(f"{r:.3g}" for r in ratios),
    )


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


def inner_restress_check(events: list, bpfi_hz: float) -> dict:
    """Time between the re-stressings of consecutive passages in the load zone against
    1/BPFI (inner-race spall).

    Passages in the load zone: the roller carried at least :data:`LOAD_ZONE_SHARE` of
    the most loaded passing roller's force (towards the zone's edges a lightly loaded
    roller's force, a few kN against the facets' rattle, gives no sharp event);
    consecutive: one BPFI period apart (the spall passes unloaded rollers between two
    visits to the load zone without an event). The re-stressing time is the first touch
    of the exit edge: the exit time (the 0.1 ms mean force regaining half of F0) needs
    more of the burst's impulses the larger F0, so it shifts with each passage's load,
    which the spall's turning changes from passage to passage (the exits' intervals are
    in the note).
    """
    loads = np.array([e["force_before_N"] for e in events])
    zone = [e for e in events if e["force_before_N"] >= LOAD_ZONE_SHARE * loads.max()]
    first = np.array([e["first_impact_time_s"] for e in zone])
    exits = np.array([e["exit_time_s"] for e in zone])
    keep = np.round(np.diff(first) * bpfi_hz) == 1
    gaps, exit_gaps = np.diff(first)[keep], np.diff(exits)[keep]
    left = f"{len(events) - len(zone)} passage(s) below {LOAD_ZONE_SHARE:.0%} of the largest load"
    if (~keep).any():
        left += f", {int((~keep).sum())} interval(s) over passages without an event"
    if not len(gaps):
        return check(
            None,
            RESTRESS_LIMIT,
            None,
            f"{len(zone)} re-stressing event(s) in the load zone: needs two one period "
            f"apart; left out: {left}",
        )
    err = float(np.max(np.abs(gaps * bpfi_hz - 1.0)))
    listing = ", ".join(f"{g * 1e3:.4g}" for g in gaps)
    return check(
        err,
        RESTRESS_LIMIT,
        err <= RESTRESS_LIMIT,
        f"first touches of the exit edge: intervals {listing} ms vs 1/BPFI "
        f"{1e3 / bpfi_hz:.4g} ms (exits: {', '.join(f'{g * 1e3:.4g}' for g in exit_gaps)} "
        f"ms); left out: {left}",
    )


# ------------------------------------------------------------------ numerical noise


def predicted_noise_frequencies(info: Mapping, rates: Mapping[str, float]) -> dict[str, float]:
    """Rolling-contact noise of the faceted (polygonal) surfaces, Hz: each contact crosses
    the facets of a surface at (edges) x (the surface's rotation rate relative to the
    contact): outer raceway N_o f_cage, inner N_i (f_shaft - f_cage), roller N_r f_spin
    relative to the cage. ``info``: the mesh info (``polygon_edges``); ``rates``: the ideal
    rolling rates (``shaft``, ``cage``, ``roller_relative``, rad/s)."""
    edges = info["polygon_edges"]
    two_pi = 2 * math.pi
    return {
        "outer_raceway": edges["outer_raceway"] * abs(rates["cage"]) / two_pi,
        "inner_raceway": edges["inner_raceway"] * abs(rates["shaft"] - rates["cage"]) / two_pi,
        "roller": edges["roller0"] * abs(rates["roller_relative"]) / two_pi,
    }


def noise_frequencies(
    signal: np.ndarray, fs: float, predicted: Mapping[str, float], band: float = 0.1
) -> tuple[dict[str, float | None], float, dict[str, float | None]]:
    """The highest spectral peak within +-``band`` of each prediction.

    Returns its frequency (None above Nyquist), the spectral resolution (Hz) and the
    peak's prominence: its PSD over the median PSD of the band, in dB (a tone stands
    well above the broadband response; noise alone gives a few dB).
    """
    from diagnostics import psd

    x = np.asarray(signal, dtype=float)
    x = x - x.mean()
    if len(x) < 64:
        return dict.fromkeys(predicted), math.inf, dict.fromkeys(predicted)
    nperseg = min(4096, len(x))
    f, p = psd(x, fs, nperseg=nperseg)
    df = fs / nperseg
    out: dict[str, float | None] = {}
    prominence: dict[str, float | None] = {}
    for name, f0 in predicted.items():
        # at least the neighbouring bins, however coarse the resolution
        half = max(band * f0, 1.5 * df)
        sel = (f >= f0 - half) & (f <= f0 + half)
        if not sel.any() or f0 >= fs / 2:
            out[name] = prominence[name] = None
            continue
        k = int(np.argmax(p[sel]))
        out[name] = float(f[sel][k])
        background = float(np.median(p[sel]))
        prominence[name] = float(10 * np.log10(p[sel][k] / background)) if background > 0 else None
    return out, df, prominence


def noise_check(
    predicted: Mapping[str, float],
    measured: Mapping[str, float | None],
    resolution: float,
    prominence_db: Mapping[str, float | None] | None = None,
    faceted: bool = True,
) -> dict:
    """Distance of each tonal peak from its prediction, relative to the prediction; the
    limit is 5 % or the spectral resolution, whichever is larger.

    Only peaks at least :data:`TONE_DB` above the band's median count as tones (all of
    them when no prominence is given). With none, the facet noise is below the broadband
    response: ``passed`` None, the levels in the note. Where the contact is not
    ``faceted`` (``contact.smoothing``: each segment's arc) only a weak residue of the
    facet noise is left, and a tone off the prediction is taken for what it then most
    likely is, a lightly damped structural mode that stands as high as a tone (a default
    run put one at 4.6 kHz, 10.4 dB over the roller's band, where the facet frequency's
    own peak stood 9.5 dB): ``passed`` None; a tone within the limit still passes.
    """
    prominence_db = prominence_db or {}
    names = [k for k in predicted if measured.get(k) is not None]
    if not names:
        return check(None, NOISE_LIMIT, None, "no prediction below Nyquist")
    # without a prominence every peak counts as a tone (a 0 dB peak does not)
    level = {k: prominence_db.get(k) for k in names}
    tones = [k for k in names if level[k] is None or level[k] >= TONE_DB]
    limit = max(NOISE_LIMIT, resolution / min(predicted[k] for k in names))

    def describe(k):
        level = prominence_db.get(k)
        db = "" if level is None else f" ({level:.3g} dB over the band)"
        return f"{k} {predicted[k]:.5g} -> {measured[k]:.5g} Hz{db}"

    listing = ", ".join(describe(k) for k in names)
    if not tones:
        return check(
            None,
            limit,
            None,
            f"no tonal peak {TONE_DB:g} dB above the band within 10 % of the predicted "
            f"facet frequencies: the facet noise is below the broadband response; {listing}",
        )
    err = max(abs(measured[k] - predicted[k]) / predicted[k] for k in tones)
    if err > limit and not faceted:
        return check(
            None,
            limit,
            None,
            "smooth contact (contact.smoothing): a tone off the facet frequencies is taken "
            f"for a structural mode, not placed (resolution {resolution:.4g} Hz): {listing}",
        )
    return check(
        err,
        limit,
        err <= limit,
        f"tonal peak next to each predicted frequency (resolution {resolution:.4g} Hz): " + listing,
    )


# ------------------------------------------------------------------ defect size


def defect_size_check(case: Case, signal: np.ndarray, fs: float) -> tuple[dict, float | None]:
    """The spall length from the acceleration's entry and exit events
    (:func:`diagnostics.estimate_defect_size`, on the race of the spall) against the
    case's. Not applied to an extended spall: the estimate pairs each exit with the
    entry before it, which is another roller's when two are inside at once."""
    from diagnostics import estimate_defect_size

    true = case.defect.length
    spacing = case.bearing.roller_spacing * (
        case.bearing.outer_raceway_radius
        if case.defect.race == "outer"
        else case.bearing.inner_raceway_radius
    )
    if case.defect.present and true >= spacing:
        return check(
            None,
            DEFECT_SIZE_LIMIT,
            None,
            f"not applied: the {true * 1e3:.4g} mm spall is longer than the roller spacing "
            f"({spacing * 1e3:.4g} mm), so the next roller enters before one leaves and the "
            "acceleration's entry/exit pairs do not belong to one roller; each roller's own "
            "entry and exit are in the events",
        ), None
    try:
        est = estimate_defect_size(
            signal,
            fs,
            case.bearing.geometry,
            case.operating.shaft_hz,
            case.defect.race,
            depth_m=case.defect.depth,
            # the FE roller de-stresses gradually (over ~0.4 ms on the default case)
            entry_cutoff_share=DEFECT_ENTRY_CUTOFF_SHARE,
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
        (:data:`~taichi_bearing.run_folder.REFERENCE_KEY`,
        :data:`~taichi_bearing.run_folder.ROLLING_RATES_KEY`).

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
        from taichi_bearing.modulation import load_zone_check

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
