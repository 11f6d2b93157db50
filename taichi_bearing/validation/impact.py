"""Impact of an elastic cylinder on an elastic block in plane strain: the explicit model
with penalty contact against the quasi-static Hertz impact solution.

The 2-D counterpart of a sphere-on-plate impact check (issue 18, item 5). A cylinder cap
of radius R, under a rigid layer that carries most of the moving mass, is thrown at
``v0`` onto a block held at its bottom face. Friction and contact damping are off.

Reference (what is analytic and what is calibrated)
---------------------------------------------------
A line contact has no force-approach law of its own: the approach of two bodies under a
line load P (per unit length) depends on where it is measured. Here it is the motion of
the rigid layer towards the block's held bottom face, i.e. the sum of each body's
compression from its contact point to its far face. For two bodies of one material,
contact modulus ``E* = E / (2 (1 - nu^2))`` and Hertz half-width
``b = sqrt(4 P R / (pi E*))``::

    delta(P) = (2 P / (pi E*)) ln(Lambda / b(P))

- Analytic: the form. A body compressed by the Hertz (elliptic) pressure moves, relative
  to a point far below the contact, by ``(P (1 - nu^2) / (pi E)) (2 ln(2 d / b) + c)``
  with the ``ln b`` coming from the pressure's own near field (Johnson, Contact
  Mechanics, 1985, sections 2.2 and 5.6: Flamant's line-load solution integrated over the
  Hertz pressure). For a half-space measured to depth d on the axis,
  ``c = -nu / (1 - nu)``; two such bodies give :func:`half_space_size`.
- Calibrated: the size term Lambda. The bodies are finite (a block clamped at its bottom,
  a cap clamped to a rigid layer, both of finite width), so the constant is theirs:
  :func:`calibrate_size` solves each body's linear static problem under the Hertz
  pressure (prescribed, no contact algorithm) with the solver's own element stiffness on
  a fine mesh, and reads the centre compressions.

The impact is then the rigid-body ODE ``M delta'' = -P(delta)`` (:func:`reference_impact`),
valid while the contact lasts much longer than the bodies' lowest mode periods
(:func:`lowest_period`): the ratio is reported.

Run ``python -m taichi_bearing.validation.impact`` for the table of
``docs/results/impact/README.md``.
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh

from taichi_bearing.analytic.bearing import hertz_half_width
from taichi_bearing.blas import one_blas_thread
from taichi_bearing.case.material import Material
from taichi_bearing.mesh.bodies import (
    cylinder_cap_mesh,
    graded_block_mesh,
    merge_meshes,
)
from taichi_bearing.mesh.types import Mesh
from taichi_bearing.solver.element import element_geometry
from taichi_bearing.solver.linear_reference import assemble_stiffness, linear_static
from taichi_bearing.validation.hertz_impact import (
    LineContactLaw,
    ReferenceImpact,
    half_space_size,
    hertz_nodal_forces,
    peak_load,
    reference_impact,
    speed_for_peak,
)

__all__ = [
    "FEImpact",
    "ImpactBodies",
    "LineContactLaw",
    "Reference",
    "ReferenceImpact",
    "calibrate_size",
    "half_space_size",
    "hertz_nodal_forces",
    "impact_materials",
    "impact_mesh",
    "level_row",
    "lowest_period",
    "main",
    "make_reference",
    "markdown_table",
    "peak_load",
    "reference_impact",
    "run_impact",
    "run_level",
    "speed_for_peak",
    "with_rigid_layer",
]

STEEL = Material(210e9, 0.3, 7850.0)


# --------------------------------------------------------------------------- bodies


@dataclass(frozen=True)
class ImpactBodies:
    """The two bodies, the thrown mass and the target load (SI units, per metre of
    thickness: the models have thickness 1 m, so forces are N/m).

    Attributes
    ----------
    radius : float
        Cylinder radius R, m (about a bearing roller's).
    half_width : float
        Half width of the block and of the cylinder cap, m.
    cap_height : float
        Elastic height of the cap above its lowest point, m.
    block_height : float
        Depth of the block below the contact, m.
    layer_height : float
        Rigid layer on top of the cap (one row of elements), m.
    mass : float
        Moving mass (cap and layer), kg per metre of thickness. Heavy, so that the
        contact lasts many periods of the bodies' lowest modes (quasi-static impact).
    peak_half_width : float
        Hertz half-width b at the reference peak force, m; it sets ``v0``. 0.2 mm: the
        default bearing case's most loaded roller (2b = 0.38 mm).
    fine_half_width : float
        Half width of the fine zone along both contact surfaces, m (3 b at the peak).
    growth : float
        Growth of the elements away from the fine zone.
    material : Material
        Both bodies.
    """

    radius: float = 10e-3
    half_width: float = 4e-3
    cap_height: float = 4e-3
    block_height: float = 4e-3
    layer_height: float = 1e-3
    mass: float = 8.0
    peak_half_width: float = 0.2e-3
    fine_half_width: float = 0.6e-3
    growth: float = 1.3
    material: Material = field(default=STEEL)

    @property
    def e_star(self) -> float:
        """Contact modulus ``E / (2 (1 - nu^2))`` of two bodies of this material, Pa."""
        m = self.material
        return m.youngs_modulus / (2.0 * (1.0 - m.poissons_ratio**2))

    @property
    def peak_load(self) -> float:
        """Line load whose Hertz half-width is ``peak_half_width``, N/m."""
        return math.pi * self.e_star * self.peak_half_width**2 / (4.0 * self.radius)

    def fine_zone(self, fine: float) -> float:
        """Half width of the fine zone for surface size ``fine``: at least two elements."""
        return max(self.fine_half_width, 2.0 * fine)

    def block(self, fine: float) -> Mesh:
        """The block, fine ``fine`` along its top around x = 0 (top at y = 0)."""
        return graded_block_mesh(
            self.half_width, self.block_height, fine, self.fine_zone(fine), self.growth
        )

    def cap(self, fine: float) -> Mesh:
        """The cylinder cap, lowest point at the origin, graded like :meth:`block`."""
        return cylinder_cap_mesh(
            self.radius,
            self.half_width,
            self.cap_height,
            fine,
            self.fine_zone(fine),
            self.growth,
        )


def with_rigid_layer(cap: Mesh, height: float) -> Mesh:
    """The cap with one row of elements (part ``mass``) on its flat top.

    Node set ``rigid``: the cap's top nodes and the layer's, which the model moves as one
    rigid plate; surface ``bottom``: the cap's curved face.
    """
    top = np.asarray(cap.node_sets["top"])
    top = top[np.argsort(cap.nodes[top, 0])]
    new = cap.n_nodes + np.arange(len(top))
    nodes = np.concatenate([cap.nodes, cap.nodes[top] + np.array([0.0, height])])
    # counter-clockwise: bottom left, bottom right, top right, top left
    layer = np.stack([top[:-1], top[1:], new[1:], new[:-1]], axis=1)
    return Mesh(
        nodes=nodes,
        elements=np.concatenate([cap.elements, layer]).astype(np.int64),
        element_part=np.concatenate(
            [np.zeros(cap.n_elements, dtype=np.int64), np.ones(len(layer), dtype=np.int64)]
        ),
        part_names=["cap", "mass"],
        node_sets={"bottom": cap.node_sets["bottom"], "rigid": np.concatenate([top, new])},
        surfaces={"bottom": cap.surfaces["bottom"]},
    )


def impact_mesh(bodies: ImpactBodies, fine: float, offset: float = 0.5) -> Mesh:
    """Block and roller (cap with its rigid layer), the roller's lowest point touching
    the block's top at ``x = offset * fine``: mid-segment by default, so the nodes of the
    two surfaces do not face each other (as between a roller and a raceway).

    Parts ``block``, ``roller.cap``, ``roller.mass``; surfaces ``block.top`` and
    ``roller.bottom``; node sets ``block.bottom`` (held) and ``roller.rigid``.
    """
    roller = with_rigid_layer(bodies.cap(fine), bodies.layer_height)
    roller.nodes = roller.nodes + np.array([offset * fine, 0.0])
    return merge_meshes({"block": bodies.block(fine), "roller": roller})


def impact_materials(bodies: ImpactBodies, mesh: Mesh) -> dict[str, Material]:
    """Materials by part: the layer's density makes the roller's mass ``bodies.mass``."""
    geo_area = element_geometry(np.asarray(mesh.nodes), np.asarray(mesh.elements)).area
    part = np.asarray(mesh.element_part)
    cap_area = geo_area[part == mesh.part_names.index("roller.cap")].sum()
    layer_area = geo_area[part == mesh.part_names.index("roller.mass")].sum()
    m = bodies.material
    rho_layer = (bodies.mass - m.density * cap_area) / layer_area
    if rho_layer <= 0:
        raise ValueError("the roller's mass must exceed its elastic cap's")
    layer = Material(m.youngs_modulus, m.poissons_ratio, rho_layer)
    return {"block": m, "roller.cap": m, "roller.mass": layer}


# --------------------------------------------------------------------------- reference
# The analytic impact is in hertz_impact.py; the size term is calibrated here.


def _centre_compression(
    mesh: Mesh, material: Material, surface: str, fixed: str, load: float, b: float, sign: float
) -> float:
    """Compression (m) of a body from its surface node at x = 0 to its held face, under
    the Hertz pressure pushing along ``sign`` y."""
    ids = np.asarray(mesh.node_sets[surface])
    ids = ids[np.argsort(mesh.nodes[ids, 0])]
    forces = np.zeros((mesh.n_nodes, 2))
    forces[ids, 1] = sign * hertz_nodal_forces(mesh.nodes[ids, 0], load, b)
    held = np.asarray(mesh.node_sets[fixed])
    u = linear_static(
        assemble_stiffness(mesh, material), forces, np.concatenate([2 * held, 2 * held + 1])
    )
    centre = ids[np.argmin(np.abs(mesh.nodes[ids, 0]))]
    return sign * float(u[centre, 1])


def calibrate_size(bodies: ImpactBodies, load: float, fine: float) -> tuple[float, float, float]:
    """Size term of the bodies' approach law from linear static solves.

    Each body, held at its far face (the block's bottom, the cap's top where the rigid
    layer holds it), takes the Hertz pressure of ``load`` (N/m) on its contact face,
    with the solver's element stiffness (:func:`assemble_stiffness`) on a mesh of
    surface size ``fine``. The sum of the two centre compressions is the approach.

    Returns
    -------
    size, compression_cap, compression_block : float
        Lambda with ``delta = (2 P / (pi E*)) ln(Lambda / b)``, and the two parts of
        delta, m.
    """
    b = float(hertz_half_width(load, 1.0, bodies.radius, bodies.e_star))
    mat = bodies.material
    w_block = _centre_compression(bodies.block(fine), mat, "top", "bottom", load, b, -1.0)
    w_cap = _centre_compression(bodies.cap(fine), mat, "bottom", "top", load, b, 1.0)
    size = b * math.exp(math.pi * bodies.e_star * (w_cap + w_block) / (2.0 * load))
    return size, w_cap, w_block


def lowest_period(mesh: Mesh, material: Material, held: np.ndarray) -> float:
    """Period (s) of the lowest mode of a body held (all directions) at nodes ``held``,
    with the model's lumped masses."""
    nodes, elements = np.asarray(mesh.nodes), np.asarray(mesh.elements)
    mass = np.zeros(mesh.n_nodes)
    np.add.at(mass, elements, element_geometry(nodes, elements).shape_integrals * material.density)
    held = np.asarray(held)
    free = np.setdiff1d(np.arange(2 * mesh.n_nodes), np.concatenate([2 * held, 2 * held + 1]))
    k = assemble_stiffness(mesh, material).tocsr()[free][:, free]
    m = sp.diags(np.repeat(mass, 2)[free])
    with one_blas_thread():  # the same period on any BLAS thread count
        lam = eigsh(k.tocsc(), k=1, M=m.tocsc(), sigma=0.0, which="LM")[0][0]
    return 2.0 * math.pi / math.sqrt(lam)


# --------------------------------------------------------------------------- finite elements


@dataclass(frozen=True)
class FEImpact:
    """One finite element impact: histories and summary (forces N/m, times s).

    ``force`` is the vertical resultant of the contact pair (the roller's push on the
    block) at every step, ``approach`` the rigid layer's motion towards the block's held
    face; ``duration_above`` runs from the first to the last step above ``threshold``.
    """

    size: float
    penalty_scale: float
    time: np.ndarray
    force: np.ndarray
    approach: np.ndarray
    peak: float
    duration_above: float
    threshold: float
    restitution: float
    steps: int
    dt: float
    wall: float  # the whole level: mesh, model, Taichi compilation, steps
    step_wall: float  # the time loop alone
    n_elements: int


def run_impact(
    bodies: ImpactBodies,
    fine: float,
    penalty_scale: float,
    v0: float,
    t_end: float,
    threshold: float,
    sample_interval: float,
    damping_ratio: float = 0.0,
) -> FEImpact:
    """Throw the roller at ``v0`` onto the block and record the contact force.

    The model is built as the bearing's: the global (assembled) critical time step at
    0.9, segment penalty of ``penalty_scale``, two passes, arc smoothing; no friction,
    contact damping ``damping_ratio``. The force is the pair resultant's mean over each
    ``sample_interval`` (as the bearing's recorders take it). The run stops at ``t_end``
    or once the roller has left the block for good (no force for a tenth of the time so
    far). Taichi must be started first (:func:`taichi_bearing.solver.backend.init_taichi`).
    """
    from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
    from taichi_bearing.solver.loads import FixedNodes, RigidPlate
    from taichi_bearing.solver.model import Model

    t0 = time.perf_counter()
    mesh = impact_mesh(bodies, fine)
    rigid = np.asarray(mesh.node_sets["roller.rigid"])
    model = Model(
        mesh,
        impact_materials(bodies, mesh),
        constraints=[FixedNodes(mesh.node_sets["block.bottom"]), RigidPlate(rigid, (0.0, 1.0))],
        time_step="global",
        dt_factor=0.9,
    )
    params = ContactParameters(penalty_scale=penalty_scale, damping_ratio=damping_ratio)
    pair = ContactPair("roller_block", "roller.bottom", "block.top", two_pass=True)
    contact = PenaltyContact(model, [pair], params)
    model.add_contributor(contact)
    roller = np.unique(np.concatenate([model.part_nodes("roller.cap"), rigid]))
    v = np.zeros((model.n_nodes, 2))
    v[roller, 1] = -v0
    model.set_state(v=v)
    model.restart_accounting()
    dt = model.dt
    every = max(1, round(sample_interval / dt))
    y0 = float(mesh.nodes[rigid[0], 1])
    times, forces, approach = [], [], []
    last_touch = 0.0
    contact.pop_sample_means()
    t_loop = time.perf_counter()
    while model.time < t_end:
        model.advance(every)
        # A step's force acts at the positions it starts from: the window's mid-time.
        t = model.time - 0.5 * (every + 1) * dt
        p = -float(contact.pop_sample_means()[0][1])
        times.append(t)
        forces.append(p)
        approach.append(y0 - float(model.positions()[rigid[0], 1]))
        if p > 0.0:
            last_touch = t
        elif last_touch > 0.0 and t - last_touch > 0.1 * t:
            break
    wall = time.perf_counter() - t0
    step_wall = time.perf_counter() - t_loop
    f = np.asarray(forces)
    t = np.asarray(times)
    above = np.flatnonzero(f > threshold)
    duration = float(t[above[-1]] - t[above[0]]) if above.size else 0.0
    v_out = float(model.velocities()[rigid[0], 1])
    return FEImpact(
        size=fine,
        penalty_scale=penalty_scale,
        time=t,
        force=f,
        approach=np.asarray(approach),
        peak=float(f.max()),
        duration_above=duration,
        threshold=threshold,
        restitution=v_out / v0,
        steps=model.step_count,
        dt=dt,
        wall=wall,
        step_wall=step_wall,
        n_elements=mesh.n_elements,
    )


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
