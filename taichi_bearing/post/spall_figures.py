"""Figures of a run about its spall: each roller's contact force through it, the load
the others take while two rollers are inside an extended spall, and the deformed mesh
around it (for :mod:`taichi_bearing.post.run_figures`).

The spall is on the outer raceway or on the inner one, which turns with the shaft:
``summary["spall_race"]`` says which (absent: outer), and the fault frequency the
passages repeat at is BPFO or BPFI (:func:`fault_rate`).
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from taichi_bearing.output.layout import (
    FRAMES_DIR,
    PVD_FILE,
    RACES,
    TIME_COLUMN,
    roller_force_column,
    roller_motion_column,
)
from taichi_bearing.output.run_folder import RunData, passage_events

__all__ = [
    "OVERLAP_FIGURE",
    "contact_forces",
    "deformed",
    "fault_rate",
    "load_sharing",
    "overlaps",
    "spall_race",
]

OVERLAP_FIGURE = "load_sharing"  # drawn only when two rollers are inside the spall at once
_ROLLER_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:pink")
LOADED_SHARE = 0.05  # rollers shown in the load-sharing figure: this share of the largest


def _run_case(run: RunData):
    """The run's case, without the warnings it gave when the run was set up (an
    extended spall's: the run and ``post`` have said it already)."""
    from taichi_bearing.case import CaseWarning, parse_case

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", CaseWarning)
        return parse_case(run.case)


def spall_race(summary: dict) -> str:
    """The raceway with the spall: ``outer`` unless the summary says ``inner``."""
    return "inner" if summary.get("spall_race") == "inner" else "outer"


def fault_rate(summary: dict) -> tuple[str, float | None]:
    """The frequency the spall passages repeat at: ``("BPFO", bpfo_hz)`` for an
    outer-race spall, ``("BPFI", bpfi_hz)`` for an inner-race one."""
    if spall_race(summary) == "inner":
        return "BPFI", summary.get("bpfi_hz")
    return "BPFO", summary.get("bpfo_hz")


def overlaps(events: list[dict]) -> list[tuple[dict, dict]]:
    """Pairs of passages with both rollers inside the spall at once, both unloaded: a
    later roller's entry before an earlier one's first touch of the exit edge (an
    extended spall, longer than the roller spacing)."""
    ev = sorted(
        (e for e in events if math.isfinite(e["entry_time_s"]) and math.isfinite(e["exit_time_s"])),
        key=lambda e: e["entry_time_s"],
    )
    return [
        (a, b)
        for i, a in enumerate(ev)
        for b in ev[i + 1 :]
        if b["roller"] != a["roller"] and b["entry_time_s"] < _touch(a)
    ]


def contact_forces(run: RunData) -> tuple[Figure, str, dict]:
    """Normal force on both raceways of each roller that crossed the spall."""
    ev = passage_events(run.summary)
    race_of_spall = spall_race(run.summary)
    rollers = [e["roller"] for e in ev if e["roller"] is not None]
    rollers = list(dict.fromkeys(int(r) for r in rollers))
    hist = run.histories
    t_ms = 1e3 * hist[TIME_COLUMN].to_numpy(dtype=float)
    named = bool(rollers)
    if not named:
        # No passage recorded: show the rollers whose force varies most.
        ranges = []
        for j in range(run.rollers):
            col = roller_force_column(j, race_of_spall, "fn")
            if col in hist:
                ranges.append((float(np.ptp(hist[col].to_numpy())), j))
        rollers = sorted(j for _, j in sorted(ranges, reverse=True)[:3])
    fig = Figure(figsize=(9.0, 6.5), layout="constrained")
    axes = fig.subplots(2, 1, sharex=True)
    values: dict = {}
    for ax, race in zip(axes, RACES, strict=True):
        for i, j in enumerate(rollers):
            col = roller_force_column(j, race, "fn")
            if col not in hist:
                continue
            colour = _ROLLER_COLOURS[i % len(_ROLLER_COLOURS)]
            fn = hist[col].to_numpy(dtype=float) / 1e3
            ax.plot(t_ms, fn, lw=0.8, color=colour, label=f"roller {j}")
            for e in ev:
                if e["roller"] is not None and int(e["roller"]) != j:
                    continue
                if math.isfinite(e["entry_time_s"]):
                    ax.axvline(1e3 * e["entry_time_s"], color=colour, ls="--", lw=0.8)
                if math.isfinite(e["exit_time_s"]):
                    ax.axvline(1e3 * e["exit_time_s"], color=colour, ls="-", lw=0.8)
                if e["roller"] is not None and race == race_of_spall:
                    values[f"roller{j}"] = _passage_numbers(t_ms / 1e3, fn * 1e3, e)
        ax.set_ylabel(f"normal force on {race} raceway (kN)")
        ax.set_title(f"{race} raceway")
        ax.legend(loc="upper right", fontsize="small", ncol=2)
    axes[-1].set_xlabel("time (ms)")
    if named:
        fig.suptitle("Contact force of each roller through the spall (dashed: entry, solid: exit)")
    else:
        fig.suptitle("No spall passage recorded: the rollers whose contact force varies most")
    parts = []
    for name, v in values.items():
        parts.append(
            f"{name}: {v['before_kN']:.3g} kN before entry, minimum {v['min_kN']:.3g} kN in "
            f"the spall, peak {v['peak_after_exit_kN']:.3g} kN in the 1 ms after exit"
        )
    if named:
        where = "" if race_of_spall == "outer" else " inner-race"
        caption = (
            f"Normal contact force of each roller that crossed the{where} spall. "
            + "; ".join(parts)
        )
    else:
        caption = (
            "No spall passage was recorded; normal contact forces of rollers "
            + ", ".join(map(str, rollers))
            + ", whose forces vary most."
        )
    return fig, caption, values


def _passage_numbers(t: np.ndarray, fn: np.ndarray, e: dict) -> dict:
    te, tx = e["entry_time_s"], e["exit_time_s"]
    before = fn[(t < te) & (t >= te - 5e-4)]
    inside = fn[(t >= te) & (t < tx)]
    after = fn[(t >= tx) & (t < tx + 1e-3)]
    pick = lambda a, f: float(f(a)) / 1e3 if a.size else math.nan  # noqa: E731
    return {
        "before_kN": pick(before, np.mean),
        "min_kN": pick(inside, np.min),
        "peak_after_exit_kN": pick(after, np.max),
    }


def _touch(event: dict) -> float:
    """When a passage's roller first touches the exit edge, s (its exit if not known)."""
    touch = event.get("first_impact_time_s")
    touch = math.nan if touch is None else float(touch)
    return touch if math.isfinite(touch) else float(event["exit_time_s"])


def load_sharing(run: RunData) -> tuple[Figure, str, dict]:
    """The rollers' forces while two are inside an extended spall.

    Top: the outer-raceway force of every roller that carries load, with the windows in
    which two rollers are inside the spall shaded (from the later one's entry to the
    earlier one's first touch of the exit edge: both unloaded). Bottom, over the middle
    half of the first such window: each roller's force against the rigid-ring
    quasi-static model at the same cage angle, with the spall (the two rollers in it
    unloaded, the rest sharing the load) and without it.
    """
    from taichi_bearing.analytic.quasistatic import solve_case

    pairs = overlaps(passage_events(run.summary))
    if not pairs:
        raise ValueError("no two rollers were inside the spall at once")
    hist = run.histories
    t = hist[TIME_COLUMN].to_numpy(dtype=float)
    race = spall_race(run.summary)
    forces = np.stack(
        [hist[roller_force_column(j, race, "fn")].to_numpy(dtype=float) for j in range(run.rollers)]
    )
    peak = float(np.max(np.median(forces, axis=1)))
    # the rollers in the load zone and those in the spall (outside the zone a roller's
    # rattle against the raceways reaches a few kN at moments: its median is nil)
    inside_any = {int(e["roller"]) for pair in pairs for e in pair}
    shown = [
        j
        for j in range(run.rollers)
        if np.median(forces[j]) > LOADED_SHARE * peak or j in inside_any
    ]
    fig = Figure(figsize=(9.0, 7.5), layout="constrained")
    top, bottom = fig.subplots(2, 1)
    for i, j in enumerate(shown):
        # ten distinct colours: the load zone and the rollers in the spall, told apart
        top.plot(1e3 * t, forces[j] / 1e3, lw=0.8, color=f"C{i % 10}", label=f"roller {j}")
    for a, b in pairs:
        top.axvspan(1e3 * b["entry_time_s"], 1e3 * _touch(a), color="0.85", zorder=0)
    top.set_xlabel("time (ms)")
    top.set_ylabel(f"normal force on {race} raceway (kN)")
    top.set_title("Rollers carrying load; shaded: two rollers inside the spall")
    top.legend(loc="upper right", fontsize="x-small", ncol=4)

    a, b = pairs[0]
    # from the first touch of the exit edge the earlier roller takes load again
    t0, t1 = b["entry_time_s"], _touch(a)
    mid = (t >= t0 + 0.25 * (t1 - t0)) & (t <= t1 - 0.25 * (t1 - t0))
    if not mid.any():
        mid = (t >= t0) & (t <= t1)
    fe = forces[:, mid].mean(axis=1)
    k = int(np.flatnonzero(mid)[mid.sum() // 2])
    angles = np.array(
        [float(hist[roller_motion_column(j, "angle_rad")].iloc[k]) for j in range(run.rollers)]
    )
    case = _run_case(run)
    cage = float(angles[0])
    spalled = solve_case(case, cage).outer_force[0]
    healthy = solve_case(case, cage, healthy=True).outer_force[0]
    deg = (np.degrees(angles) + 180.0) % 360.0 - 180.0
    order = [j for j in np.argsort(deg) if healthy[j] > 0 or fe[j] > LOADED_SHARE * peak]
    x = np.arange(len(order))
    w = 0.28
    bottom.bar(x - w, fe[order] / 1e3, w, label="finite elements (mean over the window)")
    bottom.bar(x, spalled[order] / 1e3, w, label="quasi-static, rigid ring, with the spall")
    bottom.bar(x + w, healthy[order] / 1e3, w, label="quasi-static, rigid ring, healthy")
    bottom.set_xticks(x, [f"{j}\n{deg[j]:.0f}" for j in order], fontsize="small")
    bottom.set_xlabel("roller and its angle from 12 o'clock (deg)")
    bottom.set_ylabel("roller force (kN)")
    bottom.set_title(
        f"Rollers {a['roller']} and {b['roller']} inside, {1e3 * t0:.3g}-{1e3 * t1:.3g} ms"
    )
    bottom.legend(fontsize="x-small")
    rows = [
        {
            "roller": int(j),
            "angle_deg": float(deg[j]),
            "fe_N": float(fe[j]),
            "quasi_static_spall_N": float(spalled[j]),
            "quasi_static_healthy_N": float(healthy[j]),
        }
        for j in order
    ]
    inside = (a["roller"], b["roller"])
    rest = [r for r in rows if r["roller"] not in inside]
    caption = (
        f"While rollers {inside[0]} and {inside[1]} were both inside the spall "
        f"({1e3 * t0:.3g}-{1e3 * t1:.3g} ms, {len(pairs)} such window(s)) they carried "
        f"{fe[inside[0]] / 1e3:.3g} and {fe[inside[1]] / 1e3:.3g} kN; the other "
        f"{len(rest)} loaded rollers took the load: "
        + ", ".join(f"roller {r['roller']} {r['fe_N'] / 1e3:.3g} kN" for r in rest)
        + ". Beside them the rigid-ring model at the same cage angle, with the spall and "
        "healthy (the adapter-hung ring concentrates the load on fewer rollers than the "
        "rigid ring; see the static checks)."
    )
    values = {"window_s": [t0, t1], "rollers_inside": list(inside), "rollers": rows}
    return fig, caption, values


def deformed(run: RunData, path: Path) -> tuple[str, dict]:
    """Render the deformed mesh around the spall at the last frame into ``path``."""
    from taichi_bearing.output.vtk import read_pvd
    from taichi_bearing.post.deformed_render import render_spall_frame

    pvd = run.run_dir / FRAMES_DIR / PVD_FILE
    if not pvd.is_file():
        raise FileNotFoundError(f"no {FRAMES_DIR}/{PVD_FILE} (output.frames off?)")
    frames = read_pvd(pvd)
    if not frames:
        raise FileNotFoundError(f"{FRAMES_DIR}/{PVD_FILE} lists no frame")
    time, name = frames[-1]
    point, edges, half, text = _spall_view(run)
    title = f"t = {1e3 * time:.3g} ms, {text}"
    values = render_spall_frame(pvd.parent / name, path, point, half, edges, title=title)
    values["time_s"] = time
    caption = (
        f"Deformed mesh around the spall at the last frame (t = {1e3 * time:.3g} ms), elastic "
        f"displacement x{values['magnification']:g}, coloured by von Mises stress "
        f"(max {values['max_von_mises_Pa'] / 1e6:.4g} MPa in view)."
    )
    return caption, values


def _spall_view(run: RunData):
    """Reference points of the spall centre and edges on the raceway (the render follows
    them with their ring: an inner-race spall turns with the shaft), view half-height,
    label."""
    case = _run_case(run)
    b, d = case.bearing, case.defect
    if not d.present:
        angle, race, length = 0.0, "outer", 0.0
    else:
        angle, race, length = d.angle, d.race, d.length
    radius = b.outer_raceway_radius if race == "outer" else b.inner_raceway_radius
    theta = 0.5 * math.pi + angle  # angles from 12 o'clock, counter-clockwise
    half_span = 0.5 * length / radius

    def at(a: float) -> tuple[float, float]:
        return (radius * math.cos(a), radius * math.sin(a))

    edges = (at(theta - half_span), at(theta + half_span)) if d.present else None
    half = 0.5 * length + 1.2 * b.roller_radius
    text = (
        f"{race} raceway spall {1e3 * length:.3g} mm"
        if d.present
        else "healthy bearing: view at 12 o'clock"
    )
    return at(theta), edges, half, text
