"""`python -m taichi_bearing analytic CASE.yaml [--out DIR]`: the quasi-static model.

Writes ``static_contacts.csv`` (healthy bearing at the case load), ``analytic_forces.csv``
(every roller at every cage angle while roller 0 passes the spall),
``analytic_summary.json`` and figures in ``figures/``.

An inner-race spall turns with the shaft, so where roller 0 passes it matters: each of
``--spall-angles`` (default the case's ``defect.angle_deg``) is the spall's angle when
roller 0 is on it, and ``analytic_forces.csv`` gains a ``spall_angle_deg`` column (the
spall's angle at each row's instant); ``inner_load_zone.png`` shows the load the spall
meets over a shaft turn and the passages at those angles.
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from pathlib import Path
from typing import TYPE_CHECKING

from taichi_bearing.commands.common import add_case_arguments, case_output_folder
from taichi_bearing.errors import InputError

if TYPE_CHECKING:  # numpy, pandas and the model load when the command runs, not for --help
    import pandas as pd

    from taichi_bearing.analytic.quasistatic import LoadDistribution, Spall
    from taichi_bearing.case import Case

FORCE_COLUMNS = (
    "cage_angle_deg",
    "roller",
    "outer_fx_N",
    "outer_fy_N",
    "outer_force_N",
    "inner_force_N",
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument(
        "--angles",
        type=int,
        default=2001,
        metavar="N",
        help="cage angles over one roller pitch centred on the spall (default 2001)",
    )
    parser.add_argument(
        "--spall-angles",
        default=None,
        metavar="DEG[,DEG...]",
        help="inner-race spall only: its angle(s) from 12 o'clock when roller 0 passes "
        "over it (default defect.angle_deg); with a leading minus write "
        "--spall-angles=-35,0,35",
    )


def forces_frame(dist: LoadDistribution) -> pd.DataFrame:
    """Long table: one row per cage angle and roller, columns :data:`FORCE_COLUMNS`."""
    import numpy as np
    import pandas as pd

    n_angles, z = dist.outer_fx.shape
    return pd.DataFrame(
        {
            "cage_angle_deg": np.repeat(np.degrees(dist.cage_angle), z),
            "roller": np.tile(np.arange(z), n_angles),
            "outer_fx_N": dist.outer_fx.ravel(),
            "outer_fy_N": dist.outer_fy.ravel(),
            "outer_force_N": dist.outer_force.ravel(),
            "inner_force_N": dist.inner_force.ravel(),
        },
        columns=list(FORCE_COLUMNS),
    )


def _write_csv(frame: pd.DataFrame, path: Path) -> Path:
    from bearing_io.files import atomic_path

    with atomic_path(path) as tmp:
        frame.to_csv(tmp, index=False, float_format="%.10g")
    return path


def _check_angles(n_angles: int) -> None:
    if n_angles < 11:
        raise InputError(f"--angles: need at least 11 cage angles, got {n_angles}")


def _spall(case: Case) -> Spall | None:
    """The case's spall; a defect the model does not cover is refused (InputError)."""
    from taichi_bearing.analytic.quasistatic import spall_from_case

    try:
        return spall_from_case(case)
    except ValueError as exc:
        raise InputError(str(exc)) from None


def spall_angles(text: str | None, case: Case) -> list[float]:
    """``--spall-angles`` in rad: only for an inner-race spall (one line naming the option
    otherwise), each within [-180, 180] degrees; default ``defect.angle``."""
    inner = case.defect.present and case.defect.race == "inner"
    if text is None:
        return [case.defect.angle] if inner else []
    if not inner:
        raise InputError(
            "--spall-angles: only an inner-race spall turns (set defect.angle_deg to move "
            "an outer-race one)"
        )
    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        raise InputError(f"--spall-angles: numbers in degrees, got {text!r}") from None
    if not values or any(not -180.0 <= v <= 180.0 for v in values):
        raise InputError(f"--spall-angles: each in [-180, 180] degrees, got {text!r}")
    return [math.radians(v) for v in values]


def _edge_sweeps(
    case: Case, spall: Spall, window: float, n: int = 801, at: float | None = None
) -> tuple[list, tuple | None]:
    """Fine sweeps of roller 0 across the entry and the exit edge (patch and step); for
    an inner-race spall, roller 0 passing it with the spall at ``at``, and its travel."""
    import numpy as np

    from taichi_bearing.analytic.inner_race import passage_angles
    from taichi_bearing.analytic.quasistatic import solve_case

    out, travels = [], []
    if spall.race == "inner":
        for edge in (-spall.half_angle, spall.half_angle):
            cage, spall_at, travel = passage_angles(case, at, n, 2 * window, edge)
            out.append(
                tuple(solve_case(case, cage, m, spall_angles=spall_at) for m in ("patch", "step"))
            )
            travels.append(travel)
        return out, tuple(travels)
    for edge in (spall.entry, spall.exit):
        angles = edge + np.linspace(-window, window, n)
        out.append((solve_case(case, angles, "patch"), solve_case(case, angles, "step")))
    return out, None


def run_analytic(
    case: Case, out: Path, n_angles: int = 2001, at: list[float] | None = None
) -> dict:
    """Compute the tables and figures of the quasi-static model into ``out``.

    ``at``: for an inner-race spall, its angles (rad) when roller 0 passes over it
    (default ``defect.angle``); the first is the one of ``analytic_forces.csv``'s plain
    columns and of the passage figures. Returns the summary written to
    ``analytic_summary.json``.
    """
    import numpy as np
    import pandas as pd

    from bearing_io.files import write_json
    from taichi_bearing.analytic.bearing import fault_frequencies
    from taichi_bearing.analytic.quasistatic import (
        defect_sweep,
        solve_case,
        static_contact_table,
        stribeck_ratio,
    )
    from taichi_bearing.post.analytic_figures import (
        plot_defect_passage,
        plot_edge_zoom,
        plot_load_distribution,
    )

    _check_angles(n_angles)
    spall = _spall(case)
    out = Path(out)
    figures = out / "figures"

    table = static_contact_table(case)
    _write_csv(pd.DataFrame(table), out / "static_contacts.csv")
    healthy = solve_case(case, 0.0, healthy=True)
    top = int(np.argmax(table["outer_force_N"]))
    summary = {
        "case": case.name,
        "load_N": case.operating.load,
        "stribeck_ratio_qmax_z_over_w": float(stribeck_ratio(healthy)[0]),
        "most_loaded_roller": {k: float(v[top]) for k, v in table.items()},
        **{
            k: v
            for k, v in fault_frequencies(case.bearing, case.operating.shaft_hz).as_dict().items()
        },
    }

    if spall is None:
        sweep = defect_sweep(case, n_angles)
        _write_csv(forces_frame(sweep), out / "analytic_forces.csv")
        plot_load_distribution(healthy, healthy, 0, None, figures / "load_distribution.png")
        summary["max_balance_error"] = float(sweep.balance_error().max())
        write_json(out / "analytic_summary.json", summary)
        return summary

    inner = spall.race == "inner"
    angles_at = (at or [spall.centre]) if inner else [None]
    patch = defect_sweep(case, n_angles, "patch", spall_angle=angles_at[0])
    step = defect_sweep(case, n_angles, "step", spall_angle=angles_at[0])
    if inner:
        centre = n_angles // 2  # roller 0 on the spall's centre
        travel = patch.spall_angle - patch.cage_angle
        shown = dataclasses.replace(
            spall,
            entry=spall.entry + patch.spall_angle[centre] - spall.centre,
            exit=spall.exit + patch.spall_angle[centre] - spall.centre,
        )
        inside = np.abs(travel) < spall.half_angle
        f0 = patch.inner_force[:, 0]
        width, radius = table["inner_half_width_m"], case.bearing.inner_raceway_radius
    else:
        centre = int(np.argmin(np.abs(patch.cage_angle - spall.centre)))
        travel, shown = None, spall
        inside = (patch.cage_angle > spall.entry) & (patch.cage_angle < spall.exit)
        f0 = patch.outer_force[:, 0]
        width, radius = table["outer_half_width_m"], case.bearing.outer_raceway_radius
    _write_csv(_passages_frame(case, patch, angles_at, n_angles), out / "analytic_forces.csv")
    plot_load_distribution(healthy, patch, centre, shown, figures / "load_distribution.png")
    plot_defect_passage(patch, step, spall, figures / "defect_passage.png", travel)

    b = float(width[top])
    r = case.bearing.roller_radius
    reach = math.sqrt(2.0 * r * float(table["deflection_m"][top]))  # pivot length
    window = 1.4 * max(4.0 * b, reach + b) / radius
    ((entry_p, entry_s), (exit_p, exit_s)), travels = _edge_sweeps(
        case, spall, window, at=angles_at[0]
    )
    plot_edge_zoom(
        entry_p, entry_s, exit_p, exit_s, spall, radius, b, figures / "edge_zoom.png", travels
    )  # fmt: skip

    summary.update(
        {
            "spall_race": spall.race,
            "spall_entry_deg": math.degrees(spall.entry),
            "spall_exit_deg": math.degrees(spall.exit),
            "max_balance_error": float(
                max(patch.balance_error().max(), step.balance_error().max())
            ),
            "roller0_force_before_entry_N": float(f0[0]),
            "roller0_min_force_in_spall_N": float(f0[inside].min()),
            "neighbour_max_force_N": float(patch.outer_force[:, 1:].max()),
            "healthy_max_force_N": float(healthy.outer_force.max()),
            "largest_force_jump_patch_N": float(np.abs(np.diff(f0)).max()),
            "largest_force_jump_step_N": float(np.abs(np.diff(step.outer_force[:, 0])).max()),
        }
    )
    if inner:
        summary.update(_inner_summary(case, spall, angles_at, n_angles, figures))
    write_json(out / "analytic_summary.json", summary)
    return summary


def _passages_frame(case: Case, first, angles_at: list, n_angles: int) -> pd.DataFrame:
    """analytic_forces.csv: the first passage's rows; for an inner-race spall every
    passage in ``angles_at`` with the spall's angle at each row (``spall_angle_deg``)."""
    import numpy as np
    import pandas as pd

    from taichi_bearing.analytic.quasistatic import defect_sweep

    if angles_at[0] is None:
        return forces_frame(first)
    frames = []
    for k, at in enumerate(angles_at):
        dist = first if k == 0 else defect_sweep(case, n_angles, "patch", spall_angle=at)
        frame = forces_frame(dist)
        frame.insert(1, "spall_angle_deg", np.repeat(np.degrees(dist.spall_angle), dist.n_rollers))
        frames.append(frame)
    return pd.concat(frames, ignore_index=True)


def _inner_summary(case: Case, spall: Spall, angles_at: list, n_angles: int, figures) -> dict:
    """The inner-race spall's passages at ``angles_at`` and the load zone it turns
    through (figure ``inner_load_zone.png``)."""
    import numpy as np

    from taichi_bearing.analytic.inner_race import sideband_ratio
    from taichi_bearing.analytic.quasistatic import defect_sweep, load_zone
    from taichi_bearing.post.analytic_figures import plot_inner_load_zone

    angles, load = load_zone(case)
    rows, curves = [], []
    for at in angles_at:
        dist = defect_sweep(case, n_angles, "patch", spall_angle=at)
        travel = dist.spall_angle - dist.cage_angle
        force = dist.inner_force[:, 0]
        inside = np.abs(travel) < spall.half_angle
        curves.append((at, travel, force))
        rows.append(
            {
                "spall_angle_deg": math.degrees(at),
                "roller0_force_before_entry_N": float(force[0]),
                "roller0_min_force_in_spall_N": float(force[inside].min()),
                "neighbour_max_force_N": float(dist.outer_force[:, 1:].max()),
            }
        )
    plot_inner_load_zone(angles, load, curves, spall, figures / "inner_load_zone.png")
    zone = angles[load > 1e-9 * load.max()]
    return {
        "spall_angles_deg": [math.degrees(a) for a in angles_at],
        "passages": rows,
        "load_zone_deg": [math.degrees(float(zone.min())), math.degrees(float(zone.max()))],
        # impacts growing with the load: the line at BPFI and its shaft-rate sidebands
        "shaft_sideband_ratio_squared_envelope": sideband_ratio(angles, load**2),
        "shaft_sideband_ratio_envelope": sideband_ratio(angles, load),
    }


def main(args: argparse.Namespace) -> int:
    from taichi_bearing.case import load_case_for_cli

    _check_angles(args.angles)
    case = load_case_for_cli(args.case, args.overrides)
    _spall(case)  # refused before the folder is made
    at = spall_angles(args.spall_angles, case)
    out = case_output_folder(args.out, case)
    summary = run_analytic(case, out, args.angles, at)
    top = summary["most_loaded_roller"]
    print(
        f"case '{case.name}': W = {case.operating.load / 1e3:g} kN, "
        f"Q_max Z / W = {summary['stribeck_ratio_qmax_z_over_w']:.4f} "
        "(Stribeck, zero clearance: 4.08)"
    )
    print(
        f"most loaded roller: Q = {top['outer_force_N']:.1f} N, "
        f"deflection {top['deflection_m'] * 1e6:.2f} um, "
        f"b outer/inner {top['outer_half_width_m'] * 1e3:.4f}/"
        f"{top['inner_half_width_m'] * 1e3:.4f} mm, "
        f"p_max outer/inner {top['outer_pmax_Pa'] / 1e6:.0f}/{top['inner_pmax_Pa'] / 1e6:.0f} MPa"
    )
    if "roller0_min_force_in_spall_N" in summary:
        print(
            f"roller through the spall: {summary['roller0_force_before_entry_N']:.0f} N before, "
            f"{summary['roller0_min_force_in_spall_N']:.1f} N inside; neighbours up to "
            f"{summary['neighbour_max_force_N']:.0f} N"
        )
    for p in summary.get("passages", []):
        print(
            f"inner-race spall at {p['spall_angle_deg']:.3g} deg: roller "
            f"{p['roller0_force_before_entry_N']:.0f} N before, "
            f"{p['roller0_min_force_in_spall_N']:.1f} N inside"
        )
    if "shaft_sideband_ratio_squared_envelope" in summary:
        lo, hi = summary["load_zone_deg"]
        print(
            f"load zone {lo:.3g} to {hi:.3g} deg: shaft-rate sidebands of the squared "
            f"envelope at {summary['shaft_sideband_ratio_squared_envelope']:.2f} of the BPFI "
            "line (impacts growing with the load)"
        )
    print(f"written to {out}/")
    return 0
