"""What a :class:`~taichi_bearing.solver.contact.PenaltyContact` reads back: the pairs'
resultants and sample means, stored and dissipated energies (per ensemble member too),
nodal forces and the query states (a base class: plain Python over its fields)."""

import numpy as np

from taichi_bearing.solver import transfer
from taichi_bearing.solver.contributor import FORCE_QUANTUM

__all__ = ["ContactReadout"]


class ContactReadout:
    """The read-out half of :class:`~taichi_bearing.solver.contact.PenaltyContact`."""

    # ------------------------------------------------------------------ read-out

    def current_resultants(self) -> np.ndarray:
        """Per pair (fx, fy, fn, ft) of the last step, shape (n_pairs, 4), N.

        ``fx, fy``: force BY the slave body ON the master body (global axes). ``fn``: sum
        of the normal contact forces, positive in compression. ``ft``: tangential force on
        the master along the master surface's direction (body on its left), i.e. the
        outward normal turned +90 degrees.
        """
        return self.cur.to_numpy()[: self.n_pairs] * FORCE_QUANTUM

    def pop_sample_means(self) -> np.ndarray:
        """Mean of :meth:`current_resultants` over the steps since the last call (zeros
        if none), shape (n_pairs, 4); restarts the sums."""
        (acc,) = transfer.download((self.acc,), zero=True)
        s = acc[: self.n_pairs] / max(self.n_samples, 1)
        self.n_samples = 0
        return s

    def energy(self) -> float:
        """Elastic energy stored in the penalty springs (normal + tangential), J."""
        return self.energies()["elastic"]

    def member_energies(self) -> np.ndarray:
        """:meth:`energy` of each ensemble member: the sums over its own queries, in the
        order its model alone sums them."""
        en, et = transfer.download((self.q_en, self.q_et))
        owner = self.q_node_np // self._member_nodes
        bounds = np.searchsorted(owner, np.arange(self._members + 1))
        pairs = zip(bounds[:-1], bounds[1:], strict=True)
        return np.array([float(en[a:b].sum() + et[a:b].sum()) for a, b in pairs])

    def energies(self) -> dict[str, float]:
        """``elastic`` (stored penalty energy), ``friction`` and ``damping`` (dissipated
        since construction or :meth:`reset_dissipation`), J for the model's thickness."""
        n = self.n_query
        en, et, diss, q_diss = transfer.download((self.q_en, self.q_et, self.diss, self.q_diss))
        d = diss + q_diss[:n].sum(axis=0)
        elastic = float(en[:n].sum() + et[:n].sum())
        return {"elastic": elastic, "friction": float(d[0]), "damping": float(d[1])}

    def reset_dissipation(self) -> None:
        """Zero the dissipation sums (e.g. after the preload)."""
        transfer.fill((self.diss, self.q_diss))

    def nodal_forces(self) -> np.ndarray:
        """Contact force on every node in the last step, shape (n_nodes, 2), N."""
        return self.node_force.to_numpy() * FORCE_QUANTUM

    def contact_state(self) -> dict[str, np.ndarray]:
        """Per query node: ``node``, ``segment`` (-1 open), ``gap`` (m, negative inside),
        ``fn`` and ``ft`` (N) of the last step."""
        n = self.n_query
        return {
            "node": self.q_node_np.copy(),
            "segment": self.q_seg.to_numpy()[:n],
            "gap": self.q_gap.to_numpy()[:n],
            "fn": self.q_fn.to_numpy()[:n],
            "ft": self.q_ft.to_numpy()[:n],
        }
