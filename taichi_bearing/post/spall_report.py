"""The report's paragraphs about the spall that depend on its kind: the passage interval
against 1/BPFO or 1/BPFI, every passage of an inner-race spall through and out of the
load zone with the shaft-rate sidebands, and the load the other rollers share while two
are inside an extended spall (for :mod:`taichi_bearing.post.report`)."""

from __future__ import annotations

import math
from pathlib import Path

from taichi_bearing.post.report import Para, Table, _figure, _pct, fmt
from taichi_bearing.post.spall_figures import OVERLAP_FIGURE, fault_rate, spall_race

__all__ = ["interval_blocks", "spall_blocks"]


def interval_blocks(summary: dict, exits: list[float]) -> list:
    """The time between consecutive re-stressing events against the fault period; for an
    inner-race spall what the restress_interval check took (consecutive passages in the
    load zone, first touches of the exit edge; see
    :func:`taichi_bearing.checks.inner_restress_check`)."""
    name, rate = fault_rate(summary)
    if spall_race(summary) == "inner":
        note = ((summary.get("checks") or {}).get("restress_interval") or {}).get("note")
        return [Para(f"Re-stressing against 1/BPFI (check restress_interval): {note}.")]
    if len(exits) < 2 or not rate:
        return []
    period = 1.0 / float(rate)
    gaps = [b - a for a, b in zip(exits[:-1], exits[1:], strict=True)]
    return [
        Para(
            "Time between consecutive re-stressing events: "
            + ", ".join(f"{fmt(1e3 * g)} ms ({_pct(g, period)})" for g in gaps)
            + f" against 1/{name} = {fmt(1e3 * period)} ms ({name} {fmt(rate)} Hz)."
        )
    ]


def spall_blocks(summary: dict, figs: dict, run_dir: Path) -> list:
    """Every passage of an inner-race spall, and the load sharing of an extended one."""
    out: list = []
    if spall_race(summary) == "inner":
        out += _inner_passages(summary)
    entry = figs.get(OVERLAP_FIGURE)
    if entry and "values" in entry:
        out += _sharing(entry["values"], summary)
        out += _figure(figs, run_dir, OVERLAP_FIGURE)
    return out


def _inner_passages(summary: dict) -> list:
    passages = summary.get("passages") or []
    if not passages:
        return []
    events = summary.get("events") or []
    found = {(int(e["roller"]), round(e["entry_time_s"], 6)) for e in events}

    def has_event(p: dict) -> bool:
        # an event of this roller whose entry lies within a period before the passage
        period = 1.0 / float(summary.get("bpfi_hz") or math.inf)
        return any(r == p["roller"] and 0.0 <= p["time_s"] - te < period for r, te in found)

    rows = [
        [
            fmt(p["roller"]),
            fmt(1e3 * p["time_s"]),
            fmt(p["spall_angle_deg"], 3),
            fmt(None if not math.isfinite(p["force_before_N"]) else p["force_before_N"] / 1e3),
            "yes" if has_event(p) else "no",
        ]
        for p in passages
    ]
    sidebands = (summary.get("checks") or {}).get("load_zone_sidebands") or {}
    text = (
        "The spall turns with the inner ring at the shaft speed and passes a roller once "
        f"every 1/BPFI ({fmt(1e3 / float(summary['bpfi_hz']))} ms), "
        f"{fmt(360.0 * float(summary['shaft_hz']) / float(summary['bpfi_hz']), 3)} degrees "
        "further round each time. Every passage in the record, with the spall's angle "
        "(fixed frame, from 12 o'clock) when its centre was on the roller and the load the "
        "roller carried before it: under the load the roller de-stresses and re-stresses "
        "(an event); outside the load zone it carries nothing and the passage leaves no "
        "event."
    )
    out = [Para(text), Table(["roller", "time (ms)", "spall angle (deg)",
                               "roller load before (kN)", "event"], rows)]  # fmt: skip
    if sidebands:
        out.append(
            Para("Load-zone modulation (check load_zone_sidebands): " + str(sidebands.get("note")))
        )
    return out


def _sharing(values: dict, summary: dict) -> list:
    t0, t1 = values["window_s"]
    a, b = values["rollers_inside"]
    rows = [
        [
            fmt(r["roller"]),
            fmt(r["angle_deg"], 3),
            fmt(r["fe_N"] / 1e3),
            fmt(r["quasi_static_spall_N"] / 1e3),
            fmt(r["quasi_static_healthy_N"] / 1e3),
        ]
        for r in values["rollers"]
    ]
    checks = summary.get("checks") or {}
    verdict = {True: "pass", False: "FAIL", None: "not applied"}
    said = "; ".join(
        f"{name}: {verdict[c.get('passed')]}"
        for name, c in checks.items()
        if name in ("restress_interval", "exit_burst", "defect_size")
    )
    text = (
        f"Extended spall: rollers {a} and {b} were both inside it, neither touching its "
        f"exit edge, from {fmt(1e3 * t0)} ms (roller {b}'s entry) to {fmt(1e3 * t1)} ms "
        f"(roller {a}'s first touch of the exit edge). Each roller's force over the middle "
        "half of that window, "
        "beside the rigid-ring quasi-static model at the same cage angle with the spall "
        "(both rollers in it unloaded, the rest sharing the load) and healthy. Each "
        "roller's own entry and exit are in the passage table above; the checks on the "
        f"passages say {said}."
    )
    head = ["roller", "angle (deg)", "FE (kN)", "quasi-static, spall (kN)",
            "quasi-static, healthy (kN)"]  # fmt: skip
    return [Para(text), Table(head, rows)]
