"""The stable time step of a model: from its elements or from the assembled mesh, with
what force contributors' springs and dashpots can add (numpy and scipy, no Taichi)."""

from __future__ import annotations

import copy

import numpy as np
import scipy.sparse as sp

from taichi_bearing.solver.element import (
    assembled_matrix,
    assembled_max_frequency,
    critical_time_steps,
)

__all__ = ["TIME_STEP_METHODS", "CriticalStep"]

TIME_STEP_METHODS = ("element", "global")


class CriticalStep:
    r"""The critical step of a model, found when first asked for and again after a
    contributor declares a bound (:meth:`add_bound`).

    Parameters
    ----------
    method : {"element", "global"}
        ``"element"``: the smallest element's own step (:math:`2 / \omega_e`, the element
        eigenvalue bound; for a square element, its characteristic length over the wave
        speed). ``"global"``: the assembled mesh's highest frequency
        (:func:`~taichi_bearing.solver.element.assembled_max_frequency`), never smaller,
        and larger where small elements border larger ones; contributors' springs and
        dashpots count (the element estimate ignores them).
    element_stiffness : ndarray (n_elements, 8, 8)
        Element stiffness matrices (for the global estimate).
    elements : ndarray of int (n_elements, 4)
    mass : ndarray (n_nodes,)
        Lumped nodal masses, kg.
    omega_e : ndarray (n_elements,)
        Highest frequency of each element alone, rad/s.
    beta_e : ndarray (n_elements,)
        Stiffness-proportional damping coefficient of each element, s.
    dt_factor : float
        The stable step as a fraction of the critical one.
    """

    def __init__(
        self,
        method: str,
        element_stiffness: np.ndarray,
        elements: np.ndarray,
        mass: np.ndarray,
        omega_e: np.ndarray,
        beta_e: np.ndarray,
        dt_factor: float,
    ) -> None:
        if method not in TIME_STEP_METHODS:
            raise ValueError(f"time_step must be one of {TIME_STEP_METHODS}, got {method!r}")
        self.method = method
        self.dt_factor = float(dt_factor)
        self.mass = mass
        self.element_dt = critical_time_steps(omega_e, beta_e)
        self._omega_e_max = float(omega_e.max())
        # contributors' springs and dashpots to ground, see add_bound
        self.node_stiffness = np.zeros(len(mass))
        self.node_damping = np.zeros(len(mass))
        self._global = None
        if method == "global":
            c = None
            if np.any(beta_e > 0):
                c = assembled_matrix(element_stiffness * beta_e[:, None, None], elements, mass)
            self._global = (assembled_matrix(element_stiffness, elements, mass), c)
        self._step: tuple[float, float, float] | None = None

    def add_bound(
        self, nodes: np.ndarray, stiffness: np.ndarray, damping: np.ndarray | float = 0.0
    ) -> None:
        """Springs (N/m) and dashpots (N s/m) a contributor can add at ``nodes``, each as if
        to ground in both directions (a spring ``k`` between two nodes is bounded by
        ``2 k`` on each)."""
        idx = np.asarray(nodes, dtype=np.int64)
        np.add.at(self.node_stiffness, idx, stiffness)
        np.add.at(self.node_damping, idx, damping)
        self._step = None

    def values(self) -> tuple[float, float, float]:
        """(critical step, damping step factor, stable step), s."""
        if self._step is None:
            if self._global is None:
                step, undamped = float(self.element_dt.min()), 2.0 / self._omega_e_max
            else:
                k, c = self._global
                omega, zeta = assembled_max_frequency(
                    k, self.mass, c, self.node_stiffness, self.node_damping
                )
                step = float(critical_time_steps(np.array([omega]), 2.0 * zeta / omega)[0])
                undamped = 2.0 / omega
            self._step = (step, step / undamped, self.dt_factor * step)
        return self._step

    def contributor_mass_scale(self) -> np.ndarray:
        r"""Nodal masses with which the contributors' springs no longer shorten the step:
        each node a spring :math:`k_n` acts on carries
        :math:`m_n (1 + k_n / K_{nn})`, :math:`K_{nn}` its larger diagonal stiffness from
        the elements, so that :math:`(K_{nn} + k_n) / m_n'` is the elements' own
        :math:`K_{nn} / m_n`. The static state under the loads does not depend on the
        masses, so a relaxation may step with these (kg, one per node; the masses
        themselves where no spring acts). Needs the global estimate (the element estimate
        ignores the springs, so they set no step to lift)."""
        if self._global is None:
            raise ValueError("contributor mass scaling needs the global time-step estimate")
        m = np.asarray(self.mass, dtype=float)
        k_diag = self._global[0].diagonal().reshape(-1, 2).max(axis=1) * m
        return m * (1.0 + self.node_stiffness / k_diag)

    def with_masses(self, mass: np.ndarray) -> CriticalStep:
        r"""The same estimate (elements, contributors' bounds, damping) with nodal masses
        ``mass`` in place of the model's. A contributor's dashpot bound
        :math:`2 \zeta \sqrt{k m}` follows its node's mass."""
        if self._global is None:
            raise ValueError("a step with other masses needs the global time-step estimate")
        mass = np.asarray(mass, dtype=float)
        ratio = mass / np.asarray(self.mass, dtype=float)
        d = sp.diags(1.0 / np.sqrt(np.repeat(ratio, 2)))
        k, c = self._global
        other = copy.copy(self)
        other.mass = mass
        other._global = (d @ k @ d, None if c is None else d @ c @ d)
        other.node_damping = self.node_damping * np.sqrt(ratio)
        other._step = None
        return other
