r"""Dynamic relaxation: damped explicit steps until the structure is at rest under its loads.

Mass-proportional viscous damping :math:`c` is set adaptively to critical damping of the
current deflection shape (Underwood):
:math:`\omega^2 \approx 2 (U_\mathrm{int} + U_\mathrm{hg}) / \sum m |u|^2`, the
Rayleigh quotient of the displacement, which under a static load is close to the lowest
loaded mode. Loads act at full value and prescribed rotations are held at angle zero.
"""

from __future__ import annotations

import contextlib
import math
from collections.abc import Callable
from dataclasses import dataclass

from taichi_bearing.errors import SimulationError
from taichi_bearing.solver.model import Model

__all__ = ["RelaxResult", "relax", "relax_members"]


@dataclass
class RelaxResult:
    """Outcome of :func:`relax`: steps taken, final KE / peak KE, and whether it converged;
    ``error``: why the member stopped (an ensemble's member that went unstable), else
    empty; ``dt`` the step it relaxed with (s) and ``scaled_nodes`` the nodes whose mass
    it raised (``scale_masses``)."""

    steps: int
    ke_ratio: float
    converged: bool
    damping: float
    error: str = ""
    dt: float = 0.0
    scaled_nodes: int = 0


def relax(
    model: Model,
    ke_ratio_tol: float = 1e-5,
    max_steps: int = 200_000,
    check_every: int = 50,
    min_steps: int = 200,
    progress: Callable[[int, float], None] | None = None,
    scale_masses: bool = False,
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
    scale_masses : bool
        Relax with the nodes that contributors' springs act on made heavier, so that a
        stiff contact does not set the step (:meth:`Model.contributor_masses`): the same
        static state in fewer steps. The transient then steps with the real masses.

    Returns
    -------
    RelaxResult

    Raises
    ------
    SimulationError
        If the energies stop being finite or an element inverts.
    """
    (res,) = relax_members(
        model, ke_ratio_tol, max_steps, check_every, min_steps, progress, scale_masses
    )
    if res.error:
        raise SimulationError(res.error)
    return res


def relax_members(
    model: Model,
    ke_ratio_tol: float = 1e-5,
    max_steps: int = 200_000,
    check_every: int = 50,
    min_steps: int = 200,
    progress: Callable[[int, float], None] | None = None,
    scale_masses: bool = False,
) -> list[RelaxResult]:
    """:func:`relax` for every member of an ensemble (one model: one member).

    Each member relaxes as it would alone: its own damping from its own energies, its own
    stop; a member that has stopped (converged, or gone unstable: ``error``) is held still
    (:meth:`Model.set_members_active`) while the others go on. ``progress`` gets the
    largest KE ratio of the members still relaxing. Afterwards every member is active,
    at rest, its accounting restarted.
    """
    masses = model.contributor_masses() if scale_masses else contextlib.nullcontext(0)
    with masses as scaled:
        results = _relax(model, ke_ratio_tol, max_steps, check_every, min_steps, progress)
        for r in results:
            r.dt, r.scaled_nodes = model.dt, scaled
    model.set_state(v=model.velocities() * 0.0)
    model.restart_accounting()
    return results


def _relax(model, ke_ratio_tol, max_steps, check_every, min_steps, progress) -> list[RelaxResult]:
    """The relaxation's loop (:func:`relax_members`), at the model's masses and step."""
    nm = model.ensemble_size
    model.restart_accounting()
    model.set_state(v=model.velocities() * 0.0)
    ke_peak = [0.0] * nm
    ratio = [math.inf] * nm
    c = [0.0] * nm
    done = [0] * nm  # steps at the member's stop, 0 while it relaxes
    errors = [""] * nm
    c_max = 1.0 / model.dt  # keeps (1 - c dt / 2) > 0
    steps = 0
    while steps < max_steps and not all(done):
        n = min(check_every, max_steps - steps)
        model.advance(n, record_last=True, relax_damping=c if nm > 1 else c[0])
        steps += n
        energies = model.member_energies()
        for k, e in enumerate(energies):
            if done[k]:
                continue
            ke = e["kinetic"]
            bad = model.bad_element_index(k)
            if not math.isfinite(ke) or bad is not None:
                errors[k] = (
                    f"dynamic relaxation step {steps}: "
                    + (f"element {bad} inverted" if bad is not None else "energy not finite")
                    + "; likely cause: load too large for the mesh or too few constraints"
                )
                done[k] = steps
                continue
            ke_peak[k] = max(ke_peak[k], ke)
            if e["mass_u2"] > 0:
                omega2 = 2.0 * (e["internal"] + e["hourglass"]) / e["mass_u2"]
                c[k] = min(2.0 * math.sqrt(max(omega2, 0.0)), c_max)
            ratio[k] = ke / ke_peak[k] if ke_peak[k] > 0 else math.inf
            if steps >= min_steps and ratio[k] < ke_ratio_tol:
                done[k] = steps
        if progress is not None:
            progress(steps, max(r for r, d in zip(ratio, done, strict=True) if not d)
                     if not all(done) else max(ratio))  # fmt: skip
        if nm > 1 and any(done) and not all(done):
            model.set_members_active([not d for d in done])
    if nm > 1:
        model.set_members_active([True] * nm)
    return [
        RelaxResult(
            done[k] or steps, ratio[k], ratio[k] < ke_ratio_tol and not errors[k], c[k], errors[k]
        )  # fmt: skip
        for k in range(nm)
    ]
