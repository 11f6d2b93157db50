"""Explicit dynamics core in Taichi: plane-strain quadrilaterals, central differences,
force contributors (penalty contact, a rigid cage), dynamic relaxation. The transient run,
sample by sample with its output, is :func:`taichi_bearing.simulation.run_transient`.

Typical use::

    from taichi_bearing.solver import (
        init_taichi, Material, Model, StiffnessDamping, HeldDirection, PrescribedRotation,
        RigidVelocity, PenaltyContact, ContactPair, ContactParameters, line_load, relax,
    )
    from taichi_bearing.simulation import RunConfig, run_transient

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
The names below load their modules on first use, so that the numpy-only modules
(:mod:`~taichi_bearing.solver.element`, :mod:`~taichi_bearing.solver.contact_setup`,
:mod:`~taichi_bearing.solver.loads`, ...) are imported without starting Taichi (the modal
analysis and the reports use them).
Where things are: one step, :mod:`~taichi_bearing.solver.step_phases`; how steps are launched,
:mod:`~taichi_bearing.solver.stepping`; the element law,
:mod:`~taichi_bearing.solver.element_forces`; force contributors,
:mod:`~taichi_bearing.solver.contributor`.
"""

import importlib

# Public name -> the module that defines it (PEP 562: loaded on first use).
_EXPORTS = {
    "backend": ("current_arch", "init_taichi"),
    "cage": ("RigidCage",),
    "contact": ("PenaltyContact",),
    "contact_setup": ("ContactPair", "ContactParameters"),
    "contributor": ("FORCE_QUANTUM", "ForceContributor", "add_force"),
    "damping": ("StiffnessDamping",),
    "loads": ("FixedNodes", "HeldDirection", "NodalForces", "PrescribedRotation",
              "RigidVelocity", "line_load", "rotation_angle", "uniform_load"),
    "model": ("Model",),
    "relaxation": ("RelaxResult", "relax", "relax_members"),
}  # fmt: skip
_MODULE_OF = {name: module for module, names in _EXPORTS.items() for name in names}
_MODULE_OF["Material"] = None  # the case's material (taichi_bearing.case.material)

__all__ = sorted(_MODULE_OF)


def __getattr__(name: str):
    if name not in _MODULE_OF:
        raise AttributeError(f"module 'taichi_bearing.solver' has no attribute {name!r}")
    module = _MODULE_OF[name]
    where = "taichi_bearing.case.material" if module is None else f"taichi_bearing.solver.{module}"
    value = getattr(importlib.import_module(where), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))
