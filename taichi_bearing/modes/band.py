"""The outer ring's modes around a frequency band, for the run report: the band the
re-stressing excites is where the envelope analysis looks, and the ring's modes there
are what rings."""

from __future__ import annotations

import math

from taichi_bearing.case import Case
from taichi_bearing.modes.model import bearing_modal_model
from taichi_bearing.modes.solve import ModalResult, solve_modes

__all__ = ["modes_near_band"]

# how many modes nearest the band's centre are found (a wide band holds more)
NEAREST = 16


def modes_near_band(
    case: Case, band_hz: tuple[float, float], mesh=None, count: int = NEAREST
) -> ModalResult:
    """The ``count`` modes of the outer ring (with its adapter, held as in the run)
    nearest the geometric centre of ``band_hz``, lowest first.

    Parameters
    ----------
    case : Case
    band_hz : (float, float)
        Lower and upper edge, Hz.
    mesh : Mesh, optional
        The case's bearing mesh (meshed here when not given; about a second).
    count : int
        How many modes.
    """
    lo, hi = (float(b) for b in band_hz)
    if not 0 < lo < hi:
        raise ValueError(f"band_hz: need 0 < low < high, got {band_hz!r}")
    if mesh is None:
        from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
        from taichi_bearing.mesh.spec import spec_from_case

        mesh = build_bearing_mesh(spec_from_case(case))
    model = bearing_modal_model(case, mesh, "outer_ring", "case")
    return solve_modes(model, count, near_hz=math.sqrt(lo * hi))
