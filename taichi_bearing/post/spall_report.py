"""The report's paragraphs about the spall: the verdict that opens a report (what the
rollers did at entry and exit, over every passage, and which checks failed), and those that
depend on the spall's kind: the passage interval against 1/BPFO or 1/BPFI, every passage
of an inner-race spall through and out of the load zone with the shaft-rate sidebands,
and the load the other rollers share while two are inside an extended spall (for
:mod:`taichi_bearing.post.report` and the passages study's report).

Every number in the verdict is computed from ``summary.json`` (its events, passages and
checks) and ``figures.json``; what the run does not hold is said to be unknown.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

from taichi_bearing.checks.passages import passage_statistics
from taichi_bearing.checks.quantities import QUANTITY
from taichi_bearing.output.run_folder import passage_events
from taichi_bearing.post.document import Para, Table, figure_block, fmt, pct
from taichi_bearing.post.spall_figures import OVERLAP_FIGURE, fault_rate, spall_race

__all__ = [
    "checks_sentence",
    "distribution_blocks",
    "distribution_cells",
    "interval_blocks",
    "passage_sentences",
    "sharing_sentence",
    "spall_blocks",
    "spread",
    "statistics_table",
    "verdict_blocks",
]


# --------------------------------------------------------------------------- the verdict


def _finite(value) -> float | None:
    """``value`` as a finite float; None for None, NaN, infinity or not a number."""
    try:
        x = float(value)
    except (TypeError, ValueError):
        return None
    return x if math.isfinite(x) else None


def spread(events: Sequence[Mapping], name: str) -> dict:
    """Median (:func:`~taichi_bearing.checks.passages.passage_statistics`, as in summary.json),
    smallest and largest value of ``name`` over the passages that measured it, and
    their number ``n`` (0: unknown)."""
    values = [x for e in events if (x := _finite(e.get(name))) is not None]
    if not values:
        return {"n": 0}
    median = passage_statistics([{name: v} for v in values], [name])[name]["median"]
    return {"median": median, "lo": min(values), "hi": max(values), "n": len(values)}


def _amount(s: Mapping, scale: float = 1.0, unit: str = "") -> str | None:
    """``0.34 ms`` for one passage, ``a median 0.1 ms (range 0.05 to 0.2 ms)`` for
    several; None when no passage measured it."""
    if not s.get("n"):
        return None
    u = f" {unit}" if unit else ""
    med = f"{fmt(scale * s['median'], 3)}{u}"
    if s["n"] == 1:
        return med
    return f"a median {med} (range {fmt(scale * s['lo'], 3)} to {fmt(scale * s['hi'], 3)}{u})"


def _complete(events: Sequence[Mapping]) -> list[Mapping]:
    return [
        e
        for e in events
        if _finite(e.get("entry_time_s")) is not None and _finite(e.get("exit_time_s")) is not None
    ]


def _rollers(events: Sequence[Mapping]) -> str:
    named = list(dict.fromkeys(int(e["roller"]) for e in events if e.get("roller") is not None))
    if not named:
        return "Rollers"
    if len(named) == 1:
        return f"Roller {named[0]}"
    if len(named) > 8:
        return f"{len(named)} rollers"
    return "Rollers " + ", ".join(str(j) for j in named[:-1]) + f" and {named[-1]}"


def passage_sentences(events: Sequence[Mapping], record: str = "the record") -> list[str]:
    """What the rollers did at the spall's entry and exit, in words with the numbers: the
    de-stressing time, the exit impulses, the exit force peak over F0 and the exit/entry
    acceleration ratio, as a median with the range over the complete passages of
    ``events`` (summary.json events, or one row per passage of a study); ``record``
    names the time recorded (for a run without a passage)."""
    done = _complete(events)
    open_ = [e for e in events if e not in done]
    out = []
    if not done:
        out.append(
            f"No roller passed through the spall in {record}, so what the rollers do at "
            "its entry and exit is unknown."
        )
    else:
        n = len(done)
        head = _rollers(done) + (" passed through the spall once" if n == 1 else
                                 f" passed through the spall: {n} passages")  # fmt: skip
        if n == 1:
            e = done[0]
            head += (f" (entry at {fmt(1e3 * e['entry_time_s'], 4)} ms, exit at "
                     f"{fmt(1e3 * e['exit_time_s'], 4)} ms)")  # fmt: skip
        out.append(head + ".")
        who = "the roller" if n == 1 else "the rollers"
        destress = _amount(spread(done, "entry_destress_time_s"), 1e3, "ms")
        out.append(
            f"At entry {who} de-stressed (the force falling from 0.9 to 0.1 of F0, the "
            f"force before the spall) in {destress or 'a time not measured'}."
        )
        impulses = _amount(spread(done, "exit_impulses"), unit="impulses")
        peak = _amount(spread(done, "exit_force_peak_ratio"), unit="F0")
        ratio = _amount(spread(done, "exit_entry_accel_ratio"))
        out.append(
            f"At exit {who} re-stressed with a burst of "
            f"{impulses or 'impulses (their number not measured)'}, the force peaking at "
            f"{peak or 'a value not measured'}; the sensor's acceleration peak at exit was "
            + (f"{ratio} times that at entry." if ratio else "not compared with entry's.")
        )
        if n == 1:
            out.append(
                "One passage is one sample of a chaotic bounce, not yet a distribution "
                "(`python -m taichi_bearing passages` runs more)."
            )
    for e in open_:
        who = f"roller {e['roller']}" if e.get("roller") is not None else "a roller"
        t_in, t_out = _finite(e.get("entry_time_s")), _finite(e.get("exit_time_s"))
        if t_in is not None:
            out.append(f"{who.capitalize()} entered the spall at {fmt(1e3 * t_in, 4)} ms and "
                       "had not left it when the record ends.")  # fmt: skip
        elif t_out is not None:
            out.append(f"{who.capitalize()} left the spall at {fmt(1e3 * t_out, 4)} ms, "
                       "its entry before the record starts.")  # fmt: skip
    return out


def _inner_sentence(summary: Mapping) -> str | None:
    """How many of an inner-race spall's passages gave an event (in the load zone)."""
    passages = summary.get("passages") or []
    if spall_race(summary) != "inner" or not passages:
        return None
    flags = [_has_event(p, summary) for p in passages]
    k = sum(flags)
    rate = _finite(summary.get("bpfi_hz"))
    every = f", once every 1/BPFI = {fmt(1e3 / rate, 3)} ms" if rate else ""
    text = (
        f"The spall, on the inner raceway, turned with the shaft and met a roller "
        f"{len(passages)} times{every}: {k} of these passages gave an event"
    )
    loads = [x for p, f in zip(passages, flags, strict=True)
             if f and (x := _finite(p.get("force_before_N"))) is not None]  # fmt: skip
    if loads:
        text += (f", the roller carrying {fmt(min(loads) / 1e3, 3)} to "
                 f"{fmt(max(loads) / 1e3, 3)} kN before it (the load zone)")  # fmt: skip
    rest = [_finite(p.get("force_before_N")) for p, f in zip(passages, flags, strict=True) if not f]
    if rest:
        known = [x for x in rest if x is not None]
        where = ("the roller carrying no load (outside the load zone)" if known and not max(known)
                 else f"the roller carrying at most {fmt(max(known) / 1e3, 3)} kN" if known
                 else "the roller's load unknown")  # fmt: skip
        text += f"; the other {len(rest)}, {where}, none"
    return text + "."


def sharing_sentence(values: Mapping) -> str:
    """An extended spall's load sharing in words, from the ``load_sharing`` figure's
    values (:func:`taichi_bearing.post.spall_figures.load_sharing`)."""
    t0, t1 = values["window_s"]
    inside = [int(j) for j in values["rollers_inside"]]
    rows = {int(r["roller"]): r for r in values["rollers"]}
    mine = [rows[j] for j in inside if j in rows]
    carried = " and ".join(fmt(r["fe_N"] / 1e3, 3) for r in mine)
    healthy = " and ".join(fmt(r["quasi_static_healthy_N"] / 1e3, 3) for r in mine)
    rest = [r for j, r in rows.items() if j not in inside]
    took = sorted(rest, key=lambda r: r["fe_N"] - r["quasi_static_healthy_N"], reverse=True)[:2]
    text = (
        f"The spall is longer than the roller spacing: rollers {inside[0]} and {inside[1]} "
        f"were both inside it from {fmt(1e3 * t0, 4)} to {fmt(1e3 * t1, 4)} ms"
        + (f", carrying {carried} kN ({healthy} kN in a healthy bearing)" if mine else "")
    )
    if took:
        text += "; the others shared the load, most of all " + ", ".join(
            f"roller {int(r['roller'])} with {fmt(r['fe_N'] / 1e3, 3)} kN (quasi-static "
            f"{fmt(r['quasi_static_spall_N'] / 1e3, 3)} kN with the spall, "
            f"{fmt(r['quasi_static_healthy_N'] / 1e3, 3)} kN healthy)"
            for r in took
        )
    return text + "."


def checks_sentence(checks: Mapping) -> str:
    """How many checks pass, each failed one named with its value and limit, and those
    not applied."""
    if not checks:
        return "summary.json holds no checks, so whether the run passes them is unknown."
    result = {name: (c or {}).get("passed") for name, c in checks.items()}
    failed = [name for name, r in result.items() if r is False]
    skipped = [name for name, r in result.items() if r is None]
    text = f"{sum(r is True for r in result.values())} of {len(checks)} checks pass."
    if failed:
        text += (
            " Failed: "
            + "; ".join(
                f"{name} {fmt(checks[name].get('value'))} (limit {fmt(checks[name].get('limit'))})"
                for name in failed
            )
            + "."
        )
    else:
        text += " None failed."
    if skipped:
        text += " Not applied or not computable: " + ", ".join(skipped) + " (notes in Checks)."
    return text


def verdict_blocks(summary: Mapping, figs: Mapping, record: str = "the record") -> list:
    """The verdict: what the rollers did at the spall (every passage; for an inner-race
    spall which passages gave an event, for an extended one the load sharing), then the
    checks."""
    inner = _inner_sentence(summary)
    out = [Para(inner)] if inner else []
    out.append(Para(" ".join(passage_sentences(passage_events(summary), record))))
    entry = figs.get(OVERLAP_FIGURE) or {}
    if entry.get("values"):
        out.append(Para(sharing_sentence(entry["values"])))
    return [*out, Para(checks_sentence(summary.get("checks") or {}))]


# --------------------------------------------------------------------------- the analyses


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
            + ", ".join(f"{fmt(1e3 * g)} ms ({pct(g, period)})" for g in gaps)
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
        out += figure_block(figs, run_dir, OVERLAP_FIGURE)
    return out


def _inner_passages(summary: dict) -> list:
    passages = summary.get("passages") or []
    if not passages:
        return []
    rows = [
        [
            fmt(p["roller"]),
            fmt(1e3 * p["time_s"]),
            fmt(p["spall_angle_deg"], 3),
            fmt(None if not math.isfinite(p["force_before_N"]) else p["force_before_N"] / 1e3),
            "yes" if _has_event(p, summary) else "no",
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


def _has_event(passage: Mapping, summary: Mapping) -> bool:
    """Whether an event of the passage's roller has its entry within one 1/BPFI before
    the passage (the spall's centre on the roller)."""
    period = 1.0 / float(summary.get("bpfi_hz") or math.inf)
    return any(
        e.get("roller") is not None
        and int(e["roller"]) == passage["roller"]
        and 0.0 <= passage["time_s"] - round(float(e["entry_time_s"]), 6) < period
        for e in summary.get("events") or []
        if _finite(e.get("entry_time_s")) is not None
    )


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


def distribution_cells(stats: Mapping[str, float], scale: float = 1.0) -> list[str]:
    """``median``, ``q25 to q75`` and ``n`` of
    :func:`~taichi_bearing.checks.passages.passage_statistics` as table cells, each value
    times ``scale``."""
    n = int(stats.get("n") or 0)
    if n == 0:
        return ["-", "-", "0"]
    med, q25, q75 = (scale * float(stats[k]) for k in ("median", "q25", "q75"))
    iqr = f"{fmt(q25)} to {fmt(q75)}" if math.isfinite(q25) else "-"
    return [fmt(med), iqr, str(n)]


def statistics_table(stats: dict, names: Sequence[str]) -> Table:
    """Median, interquartile range and count of each quantity, in its display unit (a
    name :data:`~taichi_bearing.checks.quantities.QUANTITY` does not know: as it is, SI)."""
    rows = []
    for n in names:
        q = QUANTITY.get(n)
        label, unit, scale = (q.label, q.unit, q.scale) if q else (n, "SI", 1.0)
        rows.append([label, unit, *distribution_cells(stats[n], scale)])
    return Table(["quantity", "unit", "median", "interquartile range", "n"], rows)


def distribution_blocks(summary: dict, n_passages: int) -> list:
    """The run report's blocks for ``passage_statistics`` of summary.json: each passage
    quantity's median and interquartile range over the run's ``n_passages`` passages, set
    beside the per-passage table so that no single passage reads as the finding."""
    stats = summary.get("passage_statistics")
    if not stats:
        return []
    more = "`python -m taichi_bearing passages` runs more"
    if n_passages == 1:
        text = (
            "The one passage's quantities (summary.json passage_statistics): one sample of "
            f"a chaotic bounce, not yet a distribution ({more})."
        )
    else:
        text = (
            f"Each passage quantity over the {n_passages} passages: median and "
            "interquartile range (summary.json passage_statistics). One passage is one "
            "sample of a chaotic bounce, so these, not one passage's value, are the run's "
            f"finding; few passages give a wide range ({more})."
        )
    return [Para(text), statistics_table(stats, list(stats))]
