"""Explicit dynamics core in Taichi: plane-strain quadrilaterals, central differences,
force contributors (penalty contact, a rigid cage), dynamic relaxation, the transient run.

Typical use::

    from taichi_bearing.solver import (
        init_taichi, Material, Model, StiffnessDamping, HeldDirection, PrescribedRotation,
        RigidVelocity, PenaltyContact, ContactPair, ContactParameters, line_load, relax,
        RunConfig, run_transient,
    )

    init_taichi("cpu")                              # explicit arch, f64, checked
    model = Model(mesh, Material(210e9, 0.3, 7850.0), thickness=0.05,
                  constraints=[PrescribedRotation(bore, (0, 0), omega=52.4),
                               HeldDirection(top, (1.0, 0.0))],
                  loads=[line_load(mesh.nodes, top, (0.0, -50e3))],
                  initial_velocities=[RigidVelocity("roller0", omega=..., center=...)],
                  damping=StiffnessDamping(0.02, 20e3))
    model.add_contributor(PenaltyContact(model, pairs, ContactParameters()))
    relax(model, ke_ratio_tol=1e-5)                 # static preload
    model.set_initial_velocities()                  # rigid rolling velocities, t = 0
    result = run_transient(model, RunConfig(duration=0.03, sample_rate=1e5,
                                            frame_interval=1e-3,
                                            checkpoint_interval=5e-3), out_dir="runs/x")

Taichi must be initialised before :class:`Model` is built (its fields live in the runtime).
Where things are: one step, :mod:`~taichi_bearing.solver.step`; how steps are launched,
:mod:`~taichi_bearing.solver.stepping`; the element law,
:mod:`~taichi_bearing.solver.element_law`; force contributors,
:mod:`~taichi_bearing.solver.contributor`.
"""

from taichi_bearing.solver.backend import current_arch, init_taichi
from taichi_bearing.solver.cage import RigidCage
from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
from taichi_bearing.solver.contributor import FORCE_QUANTUM, ForceContributor, add_force
from taichi_bearing.solver.damping import StiffnessDamping
from taichi_bearing.solver.engine import RunConfig, RunResult, run_transient
from taichi_bearing.solver.loads import (
    FixedNodes,
    HeldDirection,
    NodalForces,
    PrescribedRotation,
    RigidVelocity,
    line_load,
    rotation_angle,
    uniform_load,
)
from taichi_bearing.solver.materials import Material
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.relaxation import RelaxResult, relax

__all__ = [
    "FORCE_QUANTUM",
    "ContactPair",
    "ContactParameters",
    "FixedNodes",
    "ForceContributor",
    "HeldDirection",
    "Material",
    "Model",
    "NodalForces",
    "PenaltyContact",
    "PrescribedRotation",
    "RelaxResult",
    "RigidCage",
    "RigidVelocity",
    "RunConfig",
    "RunResult",
    "StiffnessDamping",
    "add_force",
    "current_arch",
    "init_taichi",
    "line_load",
    "relax",
    "rotation_angle",
    "run_transient",
    "uniform_load",
]
