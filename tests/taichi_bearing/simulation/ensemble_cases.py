"""Members for the ensemble tests: the coarse case on a mesh twice as coarse again (what
is compared is the arithmetic, bit for bit, which a coarser mesh tests as well at a
third of the cost), with the rollers at another start angle and another load."""

from __future__ import annotations

import dataclasses
import math

from taichi_bearing.case import load_case
from taichi_bearing.case.sections import Case

COARSE = "cases/validation/coarse_spall.yaml"


def base_case() -> Case:
    """The coarse case with 2 mm surface and 8 mm inner elements (5,709 elements)."""
    base = load_case(COARSE)
    mesh = dataclasses.replace(base.mesh, surface_size=0.002, max_size=0.008)
    return dataclasses.replace(base, mesh=mesh)


def vary(base: Case, angle_deg: float = 0.0, load: float = 1.0, **run) -> Case:
    """``base`` with the rollers turned by ``angle_deg``, the load scaled by ``load`` and
    any other ``run`` keys replaced."""
    run_section = dataclasses.replace(
        base.run, first_roller_angle=base.run.first_roller_angle + math.radians(angle_deg), **run
    )
    op = dataclasses.replace(base.operating, load=base.operating.load * load)
    return dataclasses.replace(base, run=run_section, operating=op)
