"""Dynamic relaxation: damped explicit steps until the structure is at rest under its loads.

Mass-proportional viscous damping ``c`` is set adaptively to critical damping of the
current deflection shape (Underwood): ``omega^2 ~ 2 (U_int + U_hg) / sum m |u|^2``, the
Rayleigh quotient of the displacement, which under a static load is close to the lowest
loaded mode. Loads act at full value and prescribed rotations are held at angle zero.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from taichi_bearing.errors import SimulationError
from taichi_bearing.solver.model import Model

__all__ = ["RelaxResult", "relax"]


@dataclass
class RelaxResult:
    """Outcome of :func:`relax`: steps taken, final KE / peak KE, and whether it converged."""

    steps: int
    ke_ratio: float
    converged: bool
    damping: float


def relax(
    model: Model,
    ke_ratio_tol: float = 1e-5,
    max_steps: int = 200_000,
    check_every: int = 50,
    min_steps: int = 200,
    progress: Callable[[int, float], None] | None = None,
) -> RelaxResult:
    """Bring ``model`` to static equilibrium under its loads by damped steps.

    Parameters
    ----------
    model : Model
        Modified in place; afterwards velocities are zero and the accounting restarts
        (time 0, next step a half step), ready for :meth:`Model.set_initial_velocities`.
    ke_ratio_tol : float
        Stop when kinetic energy / its peak so far drops below this.
    max_steps : int
        Give up after this many steps (``converged`` False).
    check_every : int
        Steps between energy read-outs (and damping updates).
    min_steps : int
        Do not stop before this many steps (the load must first set the body moving).
    progress : callable, optional
        Called after each energy read-out with the steps taken and the KE ratio (e.g.
        :meth:`taichi_bearing.output.progress.RelaxProgress.update`); it only reads them.

    Returns
    -------
    RelaxResult

    Raises
    ------
    SimulationError
        If the energies stop being finite or an element inverts.
    """
    model.restart_accounting()
    model.set_state(v=model.velocities() * 0.0)
    ke_peak, ratio, c, steps = 0.0, math.inf, 0.0, 0
    c_max = 1.0 / model.dt  # keeps (1 - c dt / 2) > 0
    while steps < max_steps:
        n = min(check_every, max_steps - steps)
        model.advance(n, record_last=True, relax_damping=c)
        steps += n
        e = model.energies()
        ke = e["kinetic"]
        if not math.isfinite(ke) or model.bad_element_index() is not None:
            bad = model.bad_element_index()
            raise SimulationError(
                f"dynamic relaxation step {steps}: "
                + (f"element {bad} inverted" if bad is not None else "energy not finite")
                + "; likely cause: load too large for the mesh or too few constraints"
            )
        ke_peak = max(ke_peak, ke)
        if e["mass_u2"] > 0:
            omega2 = 2.0 * (e["internal"] + e["hourglass"]) / e["mass_u2"]
            c = min(2.0 * math.sqrt(max(omega2, 0.0)), c_max)
        ratio = ke / ke_peak if ke_peak > 0 else math.inf
        if progress is not None:
            progress(steps, ratio)
        if steps >= min_steps and ratio < ke_ratio_tol:
            break
    model.set_state(v=model.velocities() * 0.0)
    model.restart_accounting()
    return RelaxResult(steps, ratio, ratio < ke_ratio_tol, c)
