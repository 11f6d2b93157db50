"""Checks on the analysed acceleration: the numerical noise lines the polygonal mesh
predicts, and the spall's size estimated from the entry/exit timing."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from taichi_bearing.case import Case
from taichi_bearing.checks.common import (
    DEFECT_ENTRY_CUTOFF_SHARE,
    DEFECT_SIZE_LIMIT,
    NOISE_LIMIT,
    TONE_DB,
    check,
)


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
    facet noise is left, at about the tone threshold: default runs 0.005 deg apart read it
    11 and 9.3 dB over the band, so whether it counts as a tone is a draw of the chaotic
    exit, and a tone off the prediction there is most likely a lightly damped structural
    mode (one default run put one at 4.6 kHz, 10.4 dB over the roller's band). So with a
    smooth contact the check reports the peaks and their distances and does not judge
    (``passed`` None): it decides only what every run of a correct model would decide the
    same way (issue 43 item 6).
    """
    prominence_db = prominence_db or {}
    names = [k for k in predicted if measured.get(k) is not None]
    if not names:
        return check(None, NOISE_LIMIT, None, "no prediction below Nyquist")
    limit = max(NOISE_LIMIT, resolution / min(predicted[k] for k in names))

    def distance(k):
        return abs(measured[k] - predicted[k]) / predicted[k]

    def describe(k):
        level = prominence_db.get(k)
        db = "" if level is None else f" ({level:.3g} dB over the band)"
        return f"{k} {predicted[k]:.5g} -> {measured[k]:.5g} Hz{db}"

    listing = ", ".join(describe(k) for k in names)
    if not faceted:
        nearest = max(distance(k) for k in names)
        return check(
            nearest,
            limit,
            None,
            "smooth contact (contact.smoothing): the facet noise's residue stands at about "
            f"the {TONE_DB:g} dB tone threshold, a draw of the chaotic exit from run to run, "
            "so its peaks are reported, not judged (the faceted contact's check); largest "
            f"distance {nearest:.2%} (resolution {resolution:.4g} Hz): {listing}",
        )
    # without a prominence every peak counts as a tone (a 0 dB peak does not)
    level = {k: prominence_db.get(k) for k in names}
    tones = [k for k in names if level[k] is None or level[k] >= TONE_DB]
    if not tones:
        return check(
            None,
            limit,
            None,
            f"no tonal peak {TONE_DB:g} dB above the band within 10 % of the predicted "
            f"facet frequencies: the facet noise is below the broadband response; {listing}",
        )
    err = max(distance(k) for k in tones)
    return check(
        err,
        limit,
        err <= limit,
        f"tonal peak next to each predicted frequency (resolution {resolution:.4g} Hz): " + listing,
    )


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
