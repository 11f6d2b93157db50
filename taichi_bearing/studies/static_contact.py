r"""The preloaded contact against Hertz as the mesh is refined at a fixed pressure penalty,
then as the penalty stiffens (issue 43, item 3's static part).

For each penalty :math:`\alpha` (``contact.penalty_method: pressure``,
:math:`p_s = \alpha E^* / b_\mathrm{ref}`) and each mesh level of one case key (or keys
joined by ``+``), the case is meshed and preloaded only, by dynamic relaxation with the
contact nodes made heavier (``preload.mass_scaling``: the static state at a step the
elements set, not the penalty), and the preload's static quantities are read: the most
loaded roller's force :math:`Q_\max` and its outer contact patch (half-width and peak
pressure from the contact's nodal forces, the shape functions' spread taken off, beside
Hertz's for the same force). Per :math:`\alpha`: the change between levels, the observed
order and Richardson's estimate (:mod:`taichi_bearing.studies.convergence`), the verdict
(:data:`~taichi_bearing.studies.convergence.STATIC_LIMIT` between the two finest levels)
and the error against Hertz.

    python -m taichi_bearing.studies.static_contact cases/single_passage.yaml \
        --vary mesh.spall_size_mm+mesh.roller_surface_size_mm=0.25,0.125,0.0625 \
        --also mesh.surface_size_mm=0.5,0.5,0.25 \
        --alpha 10,30,100 --set mesh.fine_rollers=1 --set mesh.spall_zone_mm=6 --out OUT

Writes ``levels.csv`` and ``table.md`` to ``--out`` (temporary names, renamed), a row as
each level finishes.
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Sequence
from pathlib import Path

from taichi_bearing.errors import SimulationError
from taichi_bearing.studies.convergence import STATIC_LIMIT, assess

__all__ = ["QUANTITIES", "failed_row", "level_row", "main", "markdown_tables", "run_level"]

QUANTITIES = (
    ("q_max_N", "Q_max (N)"),
    ("half_width_mm", "patch half-width (mm)"),
    ("peak_pressure_GPa", "peak pressure (GPa)"),
    ("half_width_error", "half-width / Hertz - 1"),
    ("peak_pressure_error", "peak pressure / Hertz - 1"),
)
"""(column, label) of what each level reports; the first three are judged over the levels."""


def pressure_sets(alpha: float) -> list[str]:
    """The case overrides of a preload with the pressure law at ``alpha``."""
    return [
        "contact.penalty_method=pressure",
        f"contact.penalty_scale={alpha:g}",
        "contact.penalty_pressure_GPa_mm=0",
        "run.time_step=global",
        "preload.mass_scaling=true",
    ]


def run_level(case_path: str, sets: Sequence[str], threads: int) -> tuple[dict, dict]:
    """Mesh and preload one case; its ``preload`` dict and the mesh's figures."""
    from taichi_bearing.case.load import load_case
    from taichi_bearing.simulation.simulate import build_model, preload, stage_mesh

    t0 = time.perf_counter()
    case = load_case(case_path, list(sets))
    mesh, _ = stage_mesh(case)
    bm = build_model(case, mesh, "cpu", threads)
    pre = preload(bm)
    return pre, {
        "elements": mesh.n_elements,
        "transient_dt_ns": bm.model.dt * 1e9,
        "wall_s": time.perf_counter() - t0,
    }


def level_row(alpha: float, level: float, pre: dict, info: dict) -> dict:
    """One row: the level, its cost and its static quantities."""
    patch = pre["contact_patch"]
    return {
        "alpha": alpha,
        "level": level,
        **info,
        "relax_steps": pre["steps"],
        "relax_dt_ns": pre["mass_scaling"]["dt_s"] * 1e9,
        "q_max_N": max(pre["outer_force_N"]),
        "half_width_mm": patch["half_width_m"] * 1e3,
        "peak_pressure_GPa": patch["peak_pressure_Pa"] * 1e-9,
        "hertz_half_width_mm": patch["hertz_half_width_m"] * 1e3,
        "hertz_peak_pressure_GPa": patch["hertz_peak_pressure_Pa"] * 1e-9,
        "half_width_error": patch["half_width_m"] / patch["hertz_half_width_m"] - 1.0,
        "peak_pressure_error": patch["peak_pressure_Pa"] / patch["hertz_peak_pressure_Pa"] - 1.0,
    }


def failed_row(alpha: float, level: float, error: str) -> dict:
    """The row of a level whose preload failed: no values, the error."""
    row = {"alpha": alpha, "level": level, "elements": 0, "relax_steps": 0}
    row.update({c: math.nan for c, _ in QUANTITIES})
    row.update(relax_dt_ns=math.nan, transient_dt_ns=math.nan, error=error)
    return row


def _cell(v: float) -> str:
    return "-" if not math.isfinite(v) else f"{v:.4g}"


def _pct(v: float, digits: int = 1) -> str:
    return "-" if not math.isfinite(v) else f"{100 * v:+.{digits}f} %"


def markdown_tables(rows: Sequence[dict], key: str) -> str:
    """Per alpha: the levels' values and costs, then per quantity the changes, the finest
    three levels' order and Richardson's estimate, and the verdict."""
    out = []
    for alpha in sorted({r["alpha"] for r in rows}):
        rs = [r for r in rows if r["alpha"] == alpha]
        out.append(f"### alpha {alpha:g}\n")
        head = "| " + key + " | elements | relax steps | relax dt (ns) | transient dt (ns) | "
        head += " | ".join(label for _, label in QUANTITIES) + " |"
        out += [head, "|" + "---:|" * (head.count("|") - 1)]
        for r in rs:
            vals = " | ".join(
                _pct(r[c]) if c.endswith("error") else _cell(r[c]) for c, _ in QUANTITIES
            )
            out.append(
                f"| {r['level']:g} | {r['elements'] or '-'} | {r['relax_steps'] or '-'} "
                f"| {_cell(r['relax_dt_ns'])} | {_cell(r['transient_dt_ns'])} | {vals} |"
            )
        out.append("")
        if len(rs) >= 2:
            levels = [r["level"] for r in rs]
            out += [
                "| quantity | changes | order (finest three) | Richardson | verdict |",
                "|---|---|---:|---:|---|",
            ]
            for c, label in QUANTITIES[:3]:
                a = assess(levels, [r[c] for r in rs], STATIC_LIMIT)
                changes = ", ".join(_pct(x, 2) for x in a.changes)
                last = a.orders[-1] if a.orders else None
                order = _cell(last.order) if last else "-"
                rich = _cell(last.extrapolated) if last and last.meaningful else "-"
                why = f" ({last.reason})" if last and not last.meaningful else ""
                out.append(
                    f"| {label} | {changes} | {order} | {rich}{why} | {a.verdict.status}: "
                    f"{a.verdict.reason} |"
                )
            out.append("")
    return "\n".join(out)


def _write(out: Path, rows: list[dict], key: str) -> None:
    import pandas as pd

    from bearing_io.files import atomic_path
    from taichi_bearing.studies.report import write_csv

    out.mkdir(parents=True, exist_ok=True)
    write_csv(out / "levels.csv", pd.DataFrame(rows), float_format="%.8g")
    with atomic_path(out / "table.md") as tmp:
        Path(tmp).write_text(markdown_tables(rows, key) + "\n")


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: the levels of each alpha, one preload each, tables as they finish."""
    ap = argparse.ArgumentParser(
        prog="python -m taichi_bearing.studies.static_contact",
        description="The preloaded contact patch and Q_max against Hertz over mesh levels "
        "at fixed pressure penalties.",
    )
    ap.add_argument("case", help="case file (YAML)")
    ap.add_argument("--vary", required=True, metavar="KEY=L1,L2,...", help="levels, coarse to fine")
    ap.add_argument(
        "--also",
        action="append",
        default=[],
        metavar="KEY=V1,V2,...",
        help="another key set with each level, one value per level (e.g. the surface size "
        "that keeps a coarse surface within four elements of the refined one facing it)",
    )
    ap.add_argument("--alpha", default="10,30,100", help="pressure penalties alpha E* / b_ref")
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--out", type=Path, default=None)
    args = ap.parse_args(argv)
    key, _, text = args.vary.partition("=")
    try:
        levels = [float(v) for v in text.split(",") if v.strip()]
        alphas = [float(v) for v in args.alpha.split(",") if v.strip()]
    except ValueError as exc:
        ap.error(f"--vary and --alpha take numbers separated by commas: {exc}")
    if not key or len(levels) < 2 or not alphas or min(levels + alphas) <= 0:
        ap.error("--vary needs KEY=L1,L2,... with two or more positive levels; --alpha > 0")
    also = []
    for item in args.also:
        k, _, vals = item.partition("=")
        values = [v.strip() for v in vals.split(",") if v.strip()]
        if not k or len(values) != len(levels):
            ap.error(f"--also {item}: one value per level of --vary ({len(levels)})")
        also.append((k, values))
    rows: list[dict] = []
    for alpha in alphas:
        for i, level in enumerate(levels):
            sets = [*args.sets, *pressure_sets(alpha)]
            sets += [f"{k}={level:g}" for k in key.split("+")]
            sets += [f"{k}={values[i]}" for k, values in also]
            try:
                pre, info = run_level(args.case, sets, args.threads)
            except SimulationError as exc:
                # a level that does not come to rest is a result too: kept, with why
                rows.append(failed_row(alpha, level, str(exc)))
                print(f"alpha {alpha:g}, {key}={level:g}: {exc}", flush=True)
                if args.out is not None:
                    _write(args.out, rows, key)
                continue
            rows.append(level_row(alpha, level, pre, info))
            r = rows[-1]
            print(
                f"alpha {alpha:g}, {key}={level:g}: {r['elements']} elements, "
                f"{r['relax_steps']} steps at {r['relax_dt_ns']:.3g} ns ({r['wall_s']:.0f} s); "
                f"Q_max {r['q_max_N']:.5g} N, b {r['half_width_mm']:.4f} mm "
                f"({100 * r['half_width_error']:+.1f} %), p0 {r['peak_pressure_GPa']:.4g} GPa "
                f"({100 * r['peak_pressure_error']:+.1f} %)",
                flush=True,
            )
            if args.out is not None:
                _write(args.out, rows, key)
    print(markdown_tables(rows, key))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
