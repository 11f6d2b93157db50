"""The impact validation study: for each contact size and penalty, the explicit model's
impact (:mod:`taichi_bearing.validation.impact_model`) against the Hertz reference, as the
tables of ``docs/results/impact/README.md`` (a roller on a block, segment law) and
``docs/results/cylinder_impact/README.md`` (two cylinders; the pressure law, whose own
compliance the reference can include: :func:`with_penalty`), with a figure of the force
histories.

Run ``python -m taichi_bearing.validation.impact`` (``--target cap`` for two cylinders,
``--law pressure`` for the pressure law).
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from bearing_io.files import atomic_path
from taichi_bearing.validation.hertz_impact import (
    LineContactLaw,
    ReferenceImpact,
    half_space_size,
    reference_impact,
    speed_for_peak,
)
from taichi_bearing.validation.impact_model import (
    TARGETS,
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
    "penalty_label",
    "run_level",
    "with_penalty",
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
    law = LineContactLaw(bodies.e_star, bodies.effective_radius, size)
    v0 = speed_for_peak(law, bodies.mass, load)
    threshold = threshold_fraction * load
    nu = bodies.material.poissons_ratio
    hs = replace(law, size=half_space_size(bodies.cap_height, bodies.target_height, nu))
    block, cap = bodies.struck(4 * calibration_size), bodies.cap(4 * calibration_size)
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
    method: str = "segment",
) -> FEImpact:
    r"""The finite element impact at one level, thrown as the reference, recorded at
    ``samples`` samples per reference contact duration, for up to four times that
    time (a run stops earlier once the roller has left).

    ``method`` ``"segment"``: the segment penalty of scale ``penalty_scale``;
    ``"pressure"``: the pressure law with :math:`p_s = \alpha E^* / b` where
    :math:`\alpha` is ``penalty_scale`` and :math:`b` the Hertz half-width at the
    reference peak (as a bearing case reads ``contact.penalty_scale`` for that law)."""
    if method not in ("segment", "pressure"):
        raise ValueError(f"method must be 'segment' or 'pressure', got {method!r}")
    imp = ref.impact
    bodies = ref.bodies
    pressure = 0.0
    if method == "pressure":
        pressure = penalty_scale * bodies.e_star / bodies.peak_half_width
    return run_impact(
        bodies,
        fine,
        penalty_scale,
        ref.v0,
        t_end=4.0 * imp.duration,
        threshold=imp.threshold,
        sample_interval=imp.duration / samples,
        damping_ratio=damping_ratio,
        penalty_pressure=pressure,
    )


def penalty_label(fe: FEImpact) -> str:
    """The level's contact law in a few characters: ``f_s 0.1`` or ``alpha 30``."""
    return f"alpha {fe.penalty_scale:g}" if fe.penalty_pressure > 0 else f"f_s {fe.penalty_scale:g}"


def with_penalty(ref: Reference, alpha: float) -> ReferenceImpact:
    r"""The reference impact with the pressure law's own compliance added.

    A pressure law of :math:`p_s = \alpha E^* / b` under a Hertz pressure overlaps by
    :math:`p_0 / p_s = 2 P / (\pi \alpha E^*)` at the centre (:math:`p_0 = 2 P / (\pi b)`),
    so to first order in :math:`1 / \alpha` the approach is
    :math:`(2 P / (\pi E^*)) (\ln(\Lambda / b) + 1 / \alpha)`: the law with its size term
    times :math:`e^{1 / \alpha}`. What a converged mesh at that :math:`\alpha` should give.
    """
    law = replace(ref.law, size=ref.law.size * math.exp(1.0 / alpha))
    return reference_impact(law, ref.bodies.mass, ref.v0, ref.impact.threshold)


def level_row(ref: Reference, fe: FEImpact, damping_ratio: float = 0.0) -> dict[str, float]:
    """One table row: the level, its results and errors against the reference (and, for
    the pressure law, against the reference with the penalty's compliance,
    :func:`with_penalty`)."""
    imp = ref.impact
    at_peak = int(np.argmax(fe.force))
    # a pressure-law level's penalty_scale is its alpha (run_level)
    penalised = with_penalty(ref, fe.penalty_scale) if fe.penalty_pressure > 0 else None
    return {
        "size_mm": fe.size * 1e3,
        "size_over_b": fe.size / ref.bodies.peak_half_width,
        "penalty": penalty_label(fe),
        "penalty_scale": fe.penalty_scale,
        "penalty_pressure_GPa_per_mm": fe.penalty_pressure * 1e-12,
        "damping_ratio": damping_ratio,
        "peak_N_per_mm": fe.peak * 1e-3,
        "peak_error": fe.peak / imp.peak - 1.0,
        "duration_us": fe.duration_above * 1e6,
        "duration_error": fe.duration_above / imp.duration_above - 1.0,
        "peak_error_with_penalty": (
            fe.peak / penalised.peak - 1.0 if penalised is not None else math.nan
        ),
        "duration_error_with_penalty": (
            fe.duration_above / penalised.duration_above - 1.0
            if penalised is not None
            else math.nan
        ),
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
        "| size (mm) | size / b | penalty | damping | peak (N/mm) | peak error "
        "| duration (us) | duration error | peak error, Hertz + penalty "
        "| duration error, Hertz + penalty | extra approach (um) | restitution | steps "
        "| dt (ns) | wall (s) | of which steps (s) |"
    )
    lines = [head, "|" + "---:|" * head.count(" | ") + "---:|"]

    def pct(value: float) -> str:
        return "" if math.isnan(value) else f"{100 * value:+.1f} %"

    for r in rows:
        lines.append(
            f"| {r['size_mm']:.2f} | {r['size_over_b']:.2f} | {r['penalty']} "
            f"| {r['damping_ratio']:g} | {r['peak_N_per_mm']:.1f} | {pct(r['peak_error'])} "
            f"| {r['duration_us']:.2f} | {pct(r['duration_error'])} "
            f"| {pct(r['peak_error_with_penalty'])} | {pct(r['duration_error_with_penalty'])} "
            f"| {r['extra_approach_um']:+.2f} | {r['restitution']:.4f} | {r['steps']} "
            f"| {r['dt_ns']:.2f} | {r['wall_s']:.1f} | {r['step_wall_s']:.1f} |"
        )
    return "\n".join(lines)


def reference_summary(ref: Reference) -> str:
    """The reference's numbers, as Markdown bullet lines."""
    b, law, imp, hs = ref.bodies, ref.law, ref.impact, ref.half_space
    nu = b.material.poissons_ratio
    t_mode = max(ref.period_block, ref.period_cap)
    struck = "block" if b.target == "block" else "struck cap"
    lines = [
        f"- R = {b.radius * 1e3:g} mm, E* = {b.e_star / 1e9:.2f} GPa, moving mass "
        f"{b.mass:g} kg/m, v0 = {ref.v0:.4f} m/s",
        f"- size term: calibrated {law.size * 1e3:.3f} mm, half-space estimate "
        f"{half_space_size(b.cap_height, b.target_height, nu) * 1e3:.3f} mm",
    ]
    if b.target == "cap":
        # Johnson's two whole cylinders, each loaded along a diameter, centre to centre:
        # (2 P / (pi E*)) (ln(4 R / b) - 1/2) for like cylinders; context, not the reference.
        lines[0] += f", two like cylinders (effective radius {b.effective_radius * 1e3:g} mm)"
        lines.append(
            f"- whole cylinders centre to centre (Johnson 5.6) would have "
            f"{4 * b.radius / math.sqrt(math.e) * 1e3:.2f} mm"
        )
    return "\n".join(
        lines
        + [
            f"- peak {imp.peak * 1e-3:.1f} N/mm (b = {float(law.half_width(imp.peak)) * 1e3:.3f}"
            f" mm), approach {float(law.approach(imp.peak)) * 1e6:.3f} um",
            f"- contact duration {imp.duration * 1e6:.2f} us (above "
            f"{imp.threshold * 1e-3:.1f} N/mm: {imp.duration_above * 1e6:.2f} us)",
            f"- lowest mode periods: {struck} {ref.period_block * 1e6:.2f} us, cap "
            f"{ref.period_cap * 1e6:.2f} us; duration / period {imp.duration / t_mode:.1f}",
            f"- with the half-space size term instead: peak {hs.peak / imp.peak - 1:+.1%}, "
            f"duration {hs.duration_above / imp.duration_above - 1:+.1%}",
        ]
    )


def plot_histories(ref: Reference, runs: Sequence[FEImpact]):
    """Force against time, one panel per penalty, the reference dashed; the figure."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    labels = list(dict.fromkeys(penalty_label(r) for r in runs))
    fig, axes = plt.subplots(1, len(labels), figsize=(4.2 * len(labels), 3.6), sharey=True)
    for ax, label in zip(np.atleast_1d(axes), labels, strict=True):
        for r in runs:
            if penalty_label(r) == label:
                ax.plot(r.time * 1e6, r.force * 1e-3, lw=1.0, label=f"{r.size * 1e3:g} mm")
        ax.plot(ref.impact.time * 1e6, ref.impact.force * 1e-3, "k--", lw=1.2, label="reference")
        ax.set_title(label.replace("f_s", "penalty scale"))
        ax.set_xlabel("time (us)")
        ax.grid(alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("contact force (N/mm)")
    np.atleast_1d(axes)[0].legend(fontsize=8)
    fig.tight_layout()
    return fig


def _floats(text: str) -> list[float]:
    return [float(v) for v in text.split(",") if v.strip()]


DEFAULT_PENALTIES = {"segment": "0.03,0.1,1.0", "pressure": "10,30,100"}


def main(argv: Sequence[str] | None = None) -> int:
    """Command line: run the levels, print the table, write it with a figure."""
    ap = argparse.ArgumentParser(
        prog="python -m taichi_bearing.validation.impact",
        description="A cylinder thrown onto a block (or onto a like cylinder) against the "
        "plane-strain Hertz impact solution.",
    )
    ap.add_argument("--sizes-mm", default="0.5,0.2,0.1,0.05", help="surface element sizes")
    ap.add_argument(
        "--law",
        choices=("segment", "pressure"),
        default="segment",
        help="contact law: the segment penalty (scales f_s) or the pressure law "
        "(p_s = alpha E* / b, b the Hertz half-width at the peak)",
    )
    ap.add_argument(
        "--penalty-scales",
        default=None,
        help="f_s (segment) or alpha (pressure); default "
        + ", ".join(f"{k}: {v}" for k, v in DEFAULT_PENALTIES.items()),
    )
    ap.add_argument(
        "--target",
        choices=TARGETS,
        default="block",
        help="what the roller strikes: the block, or a like cylinder cap (two cylinders)",
    )
    ap.add_argument(
        "--damped",
        default="0.5,0.2",
        help="sizes (mm) also run with the bearing's contact damping, at penalty scale 0.1 "
        "(segment) or the first alpha (pressure)",
    )
    ap.add_argument("--damping-ratio", type=float, default=0.2)
    ap.add_argument("--mass", type=float, default=ImpactBodies.mass, help="kg per m")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", type=Path, default=None, help="folder for table.md, levels.csv")
    args = ap.parse_args(argv)
    try:
        sizes = _floats(args.sizes_mm)
        scales = _floats(args.penalty_scales or DEFAULT_PENALTIES[args.law])
        damped = _floats(args.damped)
    except ValueError as exc:
        ap.error(f"--sizes-mm, --penalty-scales and --damped take numbers, comma-separated: {exc}")
    if not sizes or min(sizes + scales + damped, default=1.0) <= 0 or not scales:
        ap.error("--sizes-mm, --penalty-scales and --damped must be positive")
    if args.out is not None and args.out.exists() and not args.out.is_dir():
        ap.error(f"--out {args.out} is a file, not a folder")

    from taichi_bearing.solver.backend import init_taichi

    init_taichi("cpu", args.threads)
    ref = make_reference(ImpactBodies(mass=args.mass, target=args.target))
    summary = reference_summary(ref)
    print(summary, flush=True)
    damped_scale = 0.1 if args.law == "segment" else scales[0]
    levels = [(s, f, 0.0) for s in sizes for f in scales]
    levels += [(s, damped_scale, args.damping_ratio) for s in damped]
    rows, runs = [], []
    for size_mm, scale, zeta in levels:
        fe = run_level(ref, size_mm * 1e-3, scale, zeta, method=args.law)
        rows.append(level_row(ref, fe, zeta))
        if zeta == 0.0:
            runs.append(fe)
        print(markdown_table(rows[-1:]).splitlines()[-1], flush=True)
    table = markdown_table(rows)
    print(table)
    if args.out is not None:
        import pandas as pd

        from taichi_bearing.studies.report import save_figure, write_csv

        args.out.mkdir(parents=True, exist_ok=True)
        with atomic_path(args.out / "table.md") as tmp:
            Path(tmp).write_text(summary + "\n\n" + table + "\n")
        write_csv(args.out / "levels.csv", pd.DataFrame(rows), float_format="%.6g")
        save_figure(plot_histories(ref, runs), args.out / "force_time.png")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
