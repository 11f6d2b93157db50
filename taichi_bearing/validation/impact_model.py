r"""Impact of an elastic cylinder on an elastic block in plane strain: the explicit model
with penalty contact against the quasi-static Hertz impact solution.

The 2-D counterpart of a sphere-on-plate impact check. A cylinder cap
of radius :math:`R`, under a rigid layer that carries most of the moving mass, is thrown at
:math:`v_0` onto a block held at its bottom face. Friction and contact damping are off.

Reference (what is analytic and what is calibrated)
---------------------------------------------------
A line contact has no force-approach law of its own: the approach of two bodies under a
line load :math:`P` (per unit length) depends on where it is measured. Here it is the motion of
the rigid layer towards the block's held bottom face, i.e. the sum of each body's
compression from its contact point to its far face. For two bodies of one material,
contact modulus :math:`E^* = E / (2 (1 - \nu^2))` and Hertz half-width
:math:`b = \sqrt{4 P R / (\pi E^*)}`:

.. math::

    \delta(P) = \frac{2 P}{\pi E^*} \ln \frac{\Lambda}{b(P)}

- Analytic: the form. A body compressed by the Hertz (elliptic) pressure moves, relative
  to a point far below the contact, by
  :math:`(P (1 - \nu^2) / (\pi E)) (2 \ln(2 d / b) + c)` with the :math:`\ln b` coming
  from the pressure's own near field (Johnson, Contact Mechanics, 1985, sections 2.2 and
  5.6: Flamant's line-load solution integrated over the Hertz pressure). For a half-space
  measured to depth :math:`d` on the axis, :math:`c = -\nu / (1 - \nu)`; two such bodies
  give :func:`half_space_size`.
- Calibrated: the size term :math:`\Lambda`. The bodies are finite (a block clamped at its bottom,
  a cap clamped to a rigid layer, both of finite width), so the constant is theirs:
  :func:`calibrate_size` solves each body's linear static problem under the Hertz
  pressure (prescribed, no contact algorithm) with the solver's own element stiffness on
  a fine mesh, and reads the centre compressions.

The impact is then the rigid-body ODE :math:`M \ddot\delta = -P(\delta)` (:func:`reference_impact`),
valid while the contact lasts much longer than the bodies' lowest mode periods
(:func:`lowest_period`): the ratio is reported.

The study over sizes and penalties, its table and figure, and the command
(``python -m taichi_bearing.validation.impact``, the table of
``docs/results/impact/README.md``) are :mod:`taichi_bearing.validation.impact`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

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
    "ReferenceImpact",
    "calibrate_size",
    "half_space_size",
    "hertz_nodal_forces",
    "impact_materials",
    "impact_mesh",
    "lowest_period",
    "peak_load",
    "reference_impact",
    "run_impact",
    "speed_for_peak",
    "with_rigid_layer",
]

STEEL = Material(210e9, 0.3, 7850.0)
TARGETS = ("block", "cap")


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
    target : {"block", "cap"}
        What the roller strikes: the block, held at its bottom face, or a second cap like
        the roller's, turned over and held at its flat face (two cylinders in central
        impact, each under a rigid layer: the effective radius is then R / 2).
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
    target: str = "block"

    def __post_init__(self) -> None:
        if self.target not in TARGETS:
            raise ValueError(f"target must be one of {TARGETS}, got {self.target!r}")

    @property
    def effective_radius(self) -> float:
        """R of the pair: the roller's on the flat block, half of it on a like cap, m."""
        return self.radius if self.target == "block" else 0.5 * self.radius

    @property
    def target_height(self) -> float:
        """Depth of the struck body below the contact, m."""
        return self.block_height if self.target == "block" else self.cap_height

    @property
    def e_star(self) -> float:
        r"""Contact modulus :math:`E / (2 (1 - \nu^2))` of two bodies of this material, Pa."""
        m = self.material
        return m.youngs_modulus / (2.0 * (1.0 - m.poissons_ratio**2))

    @property
    def peak_load(self) -> float:
        """Line load whose Hertz half-width is ``peak_half_width``, N/m."""
        return math.pi * self.e_star * self.peak_half_width**2 / (4.0 * self.effective_radius)

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

    def struck(self, fine: float) -> Mesh:
        """The struck body, contact face up with its centre at the origin: surface and
        node set ``top`` (the contact face), node set ``bottom`` (held). The block, or
        the cap turned over (a half turn keeps elements counter-clockwise and surfaces
        with the body on their left)."""
        if self.target == "block":
            return self.block(fine)
        cap = self.cap(fine)
        return Mesh(
            nodes=-np.asarray(cap.nodes),
            elements=np.asarray(cap.elements),
            element_part=np.asarray(cap.element_part),
            part_names=list(cap.part_names),
            node_sets={"top": cap.node_sets["bottom"], "bottom": cap.node_sets["top"]},
            surfaces={"top": cap.surfaces["bottom"]},
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
    """The struck body (:meth:`ImpactBodies.struck`) and the roller (cap with its rigid
    layer), the roller's lowest point touching the struck body's top at
    ``x = offset * fine``: mid-segment by default, so the nodes of the two surfaces do not
    face each other (as between a roller and a raceway).

    Parts ``block`` (the struck body, block or cap), ``roller.cap``, ``roller.mass``;
    surfaces ``block.top`` and ``roller.bottom``; node sets ``block.bottom`` (held) and
    ``roller.rigid``.
    """
    roller = with_rigid_layer(bodies.cap(fine), bodies.layer_height)
    roller.nodes = roller.nodes + np.array([offset * fine, 0.0])
    return merge_meshes({"block": bodies.struck(fine), "roller": roller})


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
    r"""Size term of the bodies' approach law from linear static solves.

    Each body, held at its far face (the struck body's bottom, the roller cap's top where
    the rigid layer holds it), takes the Hertz pressure of ``load`` (N/m) on its contact face,
    with the solver's element stiffness (:func:`assemble_stiffness`) on a mesh of
    surface size ``fine``. The sum of the two centre compressions is the approach.

    Returns
    -------
    size, compression_cap, compression_block : float
        :math:`\Lambda` with :math:`\delta = (2 P / (\pi E^*)) \ln(\Lambda / b)`, and the
        two parts of :math:`\delta`, m.
    """
    b = float(hertz_half_width(load, 1.0, bodies.effective_radius, bodies.e_star))
    mat = bodies.material
    w_block = _centre_compression(bodies.struck(fine), mat, "top", "bottom", load, b, -1.0)
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
    penalty_pressure: float  # the pressure law's p_s, Pa/m; 0 for the segment law
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
    penalty_pressure: float = 0.0,
) -> FEImpact:
    """Throw the roller at ``v0`` onto the struck body and record the contact force.

    The model is built as the bearing's: the global (assembled) critical time step at
    0.9, segment penalty of ``penalty_scale`` (or, where ``penalty_pressure`` (Pa/m) is
    positive, the pressure law of that :math:`p_s`), two passes, arc smoothing; no
    friction, contact damping ``damping_ratio``. The force is the pair resultant's mean over each
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
    if penalty_pressure > 0:
        params = ContactParameters(
            penalty_method="pressure",
            penalty_pressure=penalty_pressure,
            damping_ratio=damping_ratio,
        )
    else:
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
        penalty_pressure=penalty_pressure,
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
