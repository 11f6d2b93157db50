"""The laws the solver is built from, each behind a small interface so that a new one is
one class: contact laws (:mod:`~taichi_bearing.solver.laws.contact`), friction
(:mod:`~taichi_bearing.solver.laws.friction`) and the element's constitutive law
(:mod:`~taichi_bearing.solver.laws.material`)."""

from taichi_bearing.solver.laws.contact import (
    CONTACT_LAWS,
    ContactLaw,
    PressurePenalty,
    SegmentPenalty,
    SoftPenalty,
    contact_law,
)
from taichi_bearing.solver.laws.friction import friction_force

__all__ = [
    "CONTACT_LAWS",
    "ContactLaw",
    "PressurePenalty",
    "SegmentPenalty",
    "SoftPenalty",
    "contact_law",
    "friction_force",
]
