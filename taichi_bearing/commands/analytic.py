"""`python -m taichi_bearing analytic CASE.yaml [--out DIR]`: the quasi-static model.

Writes ``static_contacts.csv`` (healthy bearing at the case load), ``analytic_forces.csv``
(every roller at every cage angle while roller 0 passes the spall),
``analytic_summary.json`` and figures in ``figures/``.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

from taichi_bearing.commands.common import add_case_arguments, case_output_folder
from taichi_bearing.errors import InputError

if TYPE_CHECKING:  # numpy, pandas and the model load when the command runs, not for --help
    import pandas as pd

    from taichi_bearing.case import Case
    from taichi_bearing.quasistatic import LoadDistribution, Spall

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
    from diagnostics.files import atomic_path

    with atomic_path(path) as tmp:
        frame.to_csv(tmp, index=False, float_format="%.10g")
    return path


def _check_angles(n_angles: int) -> None:
    if n_angles < 11:
        raise InputError(f"--angles: need at least 11 cage angles, got {n_angles}")


def _spall(case: Case) -> Spall | None:
    """The case's spall; a defect the model does not cover is refused (InputError)."""
    from taichi_bearing.quasistatic import spall_from_case

    try:
        return spall_from_case(case)
    except ValueError as exc:
        raise InputError(str(exc)) from None


def _edge_sweeps(case: Case, spall: Spall, window: float, n: int = 801):
    """Fine sweeps of roller 0 across the entry and the exit edge (patch and step)."""
    import numpy as np

    from taichi_bearing.quasistatic import solve_case

    out = []
    for edge in (spall.entry, spall.exit):
        angles = edge + np.linspace(-window, window, n)
        out.append((solve_case(case, angles, "patch"), solve_case(case, angles, "step")))
    return out


def run_analytic(case: Case, out: Path, n_angles: int = 2001) -> dict:
    """Compute the tables and figures of the quasi-static model into ``out``.

    Returns the summary written to ``analytic_summary.json``.
    """
    import numpy as np
    import pandas as pd

    from diagnostics.files import write_json
    from taichi_bearing.bearing import fault_frequencies
    from taichi_bearing.post.analytic_figures import (
        plot_defect_passage,
        plot_edge_zoom,
        plot_load_distribution,
    )
    from taichi_bearing.quasistatic import (
        defect_sweep,
        solve_case,
        static_contact_table,
        stribeck_ratio,
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

    patch = defect_sweep(case, n_angles, "patch")
    step = defect_sweep(case, n_angles, "step")
    _write_csv(forces_frame(patch), out / "analytic_forces.csv")

    centre = int(np.argmin(np.abs(patch.cage_angle - spall.centre)))
    plot_load_distribution(healthy, patch, centre, spall, figures / "load_distribution.png")
    plot_defect_passage(patch, step, spall, figures / "defect_passage.png")

    b = float(table["outer_half_width_m"][top])
    r = case.bearing.roller_radius
    reach = math.sqrt(2.0 * r * float(table["deflection_m"][top]))  # pivot length
    window = 1.4 * max(4.0 * b, reach + b) / case.bearing.outer_raceway_radius
    (entry_p, entry_s), (exit_p, exit_s) = _edge_sweeps(case, spall, window)
    plot_edge_zoom(
        entry_p,
        entry_s,
        exit_p,
        exit_s,
        spall,
        case.bearing.outer_raceway_radius,
        b,
        figures / "edge_zoom.png",
    )

    f0 = patch.outer_force[:, 0]
    inside = (patch.cage_angle > spall.entry) & (patch.cage_angle < spall.exit)
    summary.update(
        {
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
    write_json(out / "analytic_summary.json", summary)
    return summary


def main(args: argparse.Namespace) -> int:
    from taichi_bearing.case import load_case_for_cli

    _check_angles(args.angles)
    case = load_case_for_cli(args.case, args.overrides)
    _spall(case)  # refused before the folder is made
    out = case_output_folder(args.out, case)
    summary = run_analytic(case, out, args.angles)
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
    print(f"written to {out}/")
    return 0
