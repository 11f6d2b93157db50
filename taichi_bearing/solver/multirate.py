r"""Multi-rate (subcycled) stepping: which nodes and elements step less often (numpy).

A node of class :math:`c` changes its velocity once every :math:`2^c` steps, by
:math:`2^c \Delta t` times its acceleration then; its position moves every step with the
velocity it has, which is the linear interpolation of its leapfrog path between its own
steps (the nodal partition of Belytschko, Yen and Mullen 1979, with linear interpolation
at the interface). An element
belongs to the fastest class among its nodes and is evaluated only at the steps where that
class moves: every node then finds the forces of all its elements at its own steps, and an
element on the interface between two classes runs at the faster one.

Classes come from the stable step: a node takes the largest :math:`c` with
:math:`2^c \Delta t` within
``dt_factor`` times the critical step of every element it belongs to (the same margin the
single-rate step keeps), and class 0 wherever anything but its elements acts on it (a
contact, the cage, a load, a constraint) or a sensor reads it: force contributors and the
outputs then see every step as before. Every class moves at the steps that are multiples
of :math:`2^\mathrm{levels}`, so outputs recorded there see one consistent state.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["MAX_LEVELS", "StepClasses", "step_classes"]

# Classes 0..MAX_LEVELS (at most 16 steps between a slow node's velocity updates).
MAX_LEVELS = 4


@dataclass(frozen=True)
class StepClasses:
    r"""Step class of every node and element (step :math:`2^\mathrm{class}` times the run's
    step).

    Attributes
    ----------
    levels : int
        Highest class allowed.
    node_class, element_class : ndarray of int
    element_order : ndarray of int
        Elements by class, then by index: the elements moving at a step whose highest
        moving class is ``c`` are the first ``element_count[c]``.
    element_count : ndarray of int (levels + 1,)
        Elements of class ``c`` or faster.
    """

    levels: int
    node_class: np.ndarray
    element_class: np.ndarray
    element_order: np.ndarray
    element_count: np.ndarray

    @property
    def element_work(self) -> float:
        """Element evaluations per step against single-rate stepping (1 = no saving)."""
        return float(np.mean(0.5**self.element_class))

    def summary(self) -> dict:
        """Levels, the share of elements and nodes per class, the element work."""
        n = self.levels + 1

        def share(c: np.ndarray) -> list[float]:
            return (np.bincount(c, minlength=n) / c.size).tolist()

        return {
            "levels": self.levels,
            "element_share": share(self.element_class),
            "node_share": share(self.node_class),
            "element_work": self.element_work,
        }


def step_classes(
    element_dt: np.ndarray,
    elements: np.ndarray,
    dt: float,
    levels: int,
    fast_nodes: np.ndarray,
) -> StepClasses:
    """Step classes of a mesh for a run at step ``dt``.

    Parameters
    ----------
    element_dt : ndarray (n_elements,)
        Each element's stable step (its critical step times the run's margin), s.
    elements : ndarray of int (n_elements, 4)
    dt : float
        The run's step, s.
    levels : int
        Highest class (0: every node every step).
    fast_nodes : ndarray of bool (n_nodes,)
        Nodes held at class 0 (acted on by more than their elements, or read by a sensor).

    Returns
    -------
    StepClasses

    Examples
    --------
    Four elements in a row, the third one four times smaller (its stable step 1, the others'
    4), at a run step of 1 with up to two levels: only the first element is clear of it.

    >>> elements = np.array([[0, 1, 6, 5], [1, 2, 7, 6], [2, 3, 8, 7], [3, 4, 9, 8]])
    >>> element_dt = np.array([4.0, 4.0, 1.0, 4.0])
    >>> c = step_classes(element_dt, elements, 1.0, 2, np.zeros(10, dtype=bool))
    >>> c.node_class.tolist()
    [2, 2, 0, 0, 2, 2, 2, 0, 0, 2]
    >>> c.element_class.tolist(), c.element_order.tolist(), c.element_count.tolist()
    ([2, 0, 0, 0], [1, 2, 3, 0], [3, 3, 4])
    >>> c.element_work
    0.8125

    A node held fast (say a load on node 5) brings its elements to class 0:

    >>> step_classes(element_dt, elements, 1.0, 2, np.arange(10) == 5).element_class.tolist()
    [0, 0, 0, 0]
    """
    if not 0 <= levels <= MAX_LEVELS:
        raise ValueError(f"levels must lie in [0, {MAX_LEVELS}], got {levels!r}")
    if not dt > 0:
        raise ValueError(f"dt must be positive, got {dt!r}")
    elements = np.asarray(elements, dtype=np.int64)
    n_nodes = len(fast_nodes)
    node_dt = np.full(n_nodes, np.inf)
    for k in range(elements.shape[1]):
        np.minimum.at(node_dt, elements[:, k], np.asarray(element_dt, dtype=float))
    # The 1e-12 keeps a node whose step is exactly 2**c dt in class c despite rounding.
    ratio = np.maximum(node_dt / dt * (1.0 + 1e-12), 1.0)
    node_class = np.minimum(np.floor(np.log2(ratio)).astype(np.int64), levels)
    node_class[np.asarray(fast_nodes, dtype=bool)] = 0
    element_class = node_class[elements].min(axis=1)
    order = np.argsort(element_class, kind="stable")
    count = np.cumsum(np.bincount(element_class, minlength=levels + 1))
    return StepClasses(levels, node_class, element_class, order, count)
