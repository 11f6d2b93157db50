"""The impact validation study: for each contact size and penalty scale, the explicit model's
impact (:mod:`taichi_bearing.validation.impact_model`) against the Hertz reference, as the
table of ``docs/results/impact/README.md`` and a figure of the force histories.

Run ``python -m taichi_bearing.validation.impact``.
"""

from __future__ import annotations

import argparse
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from taichi_bearing.validation.hertz_impact import (
    LineContactLaw,
    ReferenceImpact,
    half_space_size,
    reference_impact,
    speed_for_peak,
)
from taichi_bearing.validation.impact_model import (
    FEImpact,
    ImpactBodies,
    calibrate_size,
    lowest_period,
    run_impact,
)

__all__ = [
    "Reference",
    "level_row",
    "main",
    "make_reference",
    "markdown_table",
    "run_level",
]


# --------------------------------------------------------------------------- study


@dataclass(frozen=True)
class Reference:
    """The reference of one set of bodies: the calibrated law, the throw speed that
    peaks at ``bodies.peak_load``, the impact, and the quasi-static check."""

    bodies: ImpactBodies
    law: LineContactLaw
    v0: float
    impact: ReferenceImpact
    half_space: ReferenceImpact  # the same throw with the half-space size term
    period_block: float
    period_cap: float


def make_reference(
    bodies: ImpactBodies, calibration_size: float = 5e-6, threshold_fraction: float = 0.01
) -> Reference:
    """Calibrate the size term at the peak load on a mesh of surface size
    ``calibration_size`` (m), choose ``v0`` for that peak and integrate the impact.
    Durations are measured above ``threshold_fraction`` of the peak load."""
    load = bodies.peak_load
    size = calibrate_size(bodies, load, calibration_size)[0]
    law = LineContactLaw(bodies.e_star, bodies.radius, size)
    v0 = speed_for_peak(law, bodies.mass, load)
    threshold = threshold_fraction * load
    nu = bodies.material.poissons_ratio
    hs = replace(law, size=half_space_size(bodies.cap_height, bodies.block_height, nu))
    block, cap = bodies.block(4 * calibration_size), bodies.cap(4 * calibration_size)
    return Reference(
        bodies=bodies,
        law=law,
        v0=v0,
        impact=reference_impact(law, bodies.mass, v0, threshold),
        half_space=reference_impact(hs, bodies.mass, v0, threshold),
        period_block=lowest_period(block, bodies.material, block.node_sets["bottom"]),
        period_cap=lowest_period(cap, bodies.material, cap.node_sets["top"]),
    )


def run_level(
    ref: Reference,
    fine: float,
    penalty_scale: float,
    damping_ratio: float = 0.0,
    samples: int = 1000,
) -> FEImpact:
    """The finite element impact at one level, thrown as the reference, recorded at
    ``samples`` samples per reference contact duration, for up to four times that
    time (a run stops earlier once the roller has left)."""
    imp = ref.impact
    return run_impact(
        ref.bodies,
        fine,
        penalty_scale,
        ref.v0,
        t_end=4.0 * imp.duration,
        threshold=imp.threshold,
        sample_interval=imp.duration / samples,
        damping_ratio=damping_ratio,
    )


def level_row(ref: Reference, fe: FEImpact, damping_ratio: float = 0.0) -> dict[str, float]:
    """One table row: the level, its results and errors against the reference."""
    imp = ref.impact
    at_peak = int(np.argmax(fe.force))
    return {
        "size_mm": fe.size * 1e3,
        "size_over_b": fe.size / ref.bodies.peak_half_width,
        "penalty_scale": fe.penalty_scale,
        "damping_ratio": damping_ratio,
        "peak_N_per_mm": fe.peak * 1e-3,
        "peak_error": fe.peak / imp.peak - 1.0,
        "duration_us": fe.duration_above * 1e6,
        "duration_error": fe.duration_above / imp.duration_above - 1.0,
        # What the contact yields beyond the law at the peak: the penalty's compliance.
        "extra_approach_um": (fe.approach[at_peak] - float(ref.law.approach(fe.peak))) * 1e6,
        "restitution": fe.restitution,
        "steps": fe.steps,
        "dt_ns": fe.dt * 1e9,
        "wall_s": fe.wall,
        "step_wall_s": fe.step_wall,
        "elements": fe.n_elements,
    }


def markdown_table(rows: Sequence[dict[str, float]]) -> str:
    """The rows as a Markdown table."""
    head = (
        "| size (mm) | size / b | penalty scale | damping | peak (N/mm) | peak error "
        "| duration (us) | duration error | extra approach (um) | restitution | steps "
        "| dt (ns) | wall (s) | of which steps (s) |"
    )
    lines = [head, "|" + "---:|" * head.count(" | ") + "---:|"]
    for r in rows:
        lines.append(
            f"| {r['size_mm']:.2f} | {r['size_over_b']:.2f} | {r['penalty_scale']:g} "
            f"| {r['damping_ratio']:g} | {r['peak_N_per_mm']:.1f} | {100 * r['peak_error']:+.1f} % "
            f"| {r['duration_us']:.2f} | {100 * r['duration_error']:+.1f} % "
            f"| {r['extra_approach_um']:+.2f} | {r['restitution']:.4f} | {r['steps']} "
            f"| {r['dt_ns']:.2f} | {r['wall_s']:.1f} | {r['step_wall_s']:.1f} |"
        )
    return "\n".join(lines)


def reference_summary(ref: Reference) -> str:
    """The reference's numbers, as Markdown bullet lines."""
    b, law, imp, hs = ref.bodies, ref.law, ref.impact, ref.half_space
    nu = b.material.poissons_ratio
    t_mode = max(ref.period_block, ref.period_cap)
    return "\n".join(
        [
            f"- R = {b.radius * 1e3:g} mm, E* = {b.e_star / 1e9:.2f} GPa, moving mass "
            f"{b.mass:g} kg/m, v0 = {ref.v0:.4f} m/s",
            f"- size term: calibrated {law.size * 1e3:.3f} mm, half-space estimate "
            f"{half_space_size(b.cap_height, b.block_height, nu) * 1e3:.3f} mm",
            f"- peak {imp.peak * 1e-3:.1f} N/mm (b = {float(law.half_width(imp.peak)) * 1e3:.3f}"
            f" mm), approach {float(law.approach(imp.peak)) * 1e6:.3f} um",
            f"- contact duration {imp.duration * 1e6:.2f} us (above "
            f"{imp.threshold * 1e-3:.1f} N/mm: {imp.duration_above * 1e6:.2f} us)",
            f"- lowest mode periods: block {ref.period_block * 1e6:.2f} us, cap "
            f"{ref.period_cap * 1e6:.2f} us; duration / period {imp.duration / t_mode:.1f}",
            f"- with the half-space size term instead: peak {hs.peak / imp.peak - 1:+.1%}, "
            f"duration {hs.duration_above / imp.duration_above - 1:+.1%}",
        ]
    )


def plot_histories(ref: Reference, runs: Sequence[FEImpact], path: Path) -> None:
    """Force against time, one panel per penalty scale, the reference dashed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    scales = sorted({r.penalty_scale for r in runs})
    fig, axes = plt.subplots(1, len(scales), figsize=(4.2 * len(scales), 3.6), sharey=True)
    for ax, scale in zip(np.atleast_1d(axes), scales, strict=True):
        for r in runs:
            if r.penalty_scale == scale:
                ax.plot(r.time * 1e6, r.force * 1e-3, lw=1.0, label=f"{r.size * 1e3:g} mm")
        ax.plot(ref.impact.time * 1e6, ref.impact.force * 1e-3, "k--", lw=1.2, label="reference")
        ax.set_title(f"penalty scale {scale:g}")
        ax.set_xlabel("time (us)")
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("contact force (N/mm)")
    np.atleast_1d(axes)[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _floats(text: str) -> list[float]:
    return [float(v) for v in text.split(",") if v.strip()]


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: run the levels, print the table, write it with a figure."""
    ap = argparse.ArgumentParser(
        prog="python -m taichi_bearing.validation.impact",
        description="Cylinder-on-block impact against the plane-strain Hertz impact solution.",
    )
    ap.add_argument("--sizes-mm", default="0.5,0.2,0.1,0.05", help="surface element sizes")
    ap.add_argument("--penalty-scales", default="0.03,0.1,1.0")
    ap.add_argument(
        "--damped",
        default="0.5,0.2",
        help="sizes (mm) also run at penalty scale 0.1 with the bearing's contact damping",
    )
    ap.add_argument("--damping-ratio", type=float, default=0.2)
    ap.add_argument("--mass", type=float, default=ImpactBodies.mass, help="kg per m")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", type=Path, default=None, help="folder for table.md, levels.csv")
    args = ap.parse_args(argv)

    from taichi_bearing.solver.backend import init_taichi

    init_taichi("cpu", args.threads)
    ref = make_reference(ImpactBodies(mass=args.mass))
    summary = reference_summary(ref)
    print(summary, flush=True)
    levels = [(s, f, 0.0) for s in _floats(args.sizes_mm) for f in _floats(args.penalty_scales)]
    levels += [(s, 0.1, args.damping_ratio) for s in _floats(args.damped)]
    rows, runs = [], []
    for size_mm, scale, zeta in levels:
        fe = run_level(ref, size_mm * 1e-3, scale, zeta)
        rows.append(level_row(ref, fe, zeta))
        if zeta == 0.0:
            runs.append(fe)
        print(markdown_table(rows[-1:]).splitlines()[-1], flush=True)
    table = markdown_table(rows)
    print(table)
    if args.out is not None:
        import pandas as pd

        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "table.md").write_text(summary + "\n\n" + table + "\n")
        pd.DataFrame(rows).to_csv(args.out / "levels.csv", index=False, float_format="%.6g")
        plot_histories(ref, runs, args.out / "force_time.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
