"""An ensemble member seen as a model of its own, for the recorders.

The history recorders (:mod:`taichi_bearing.simulation.recorders`) read a model's time and
rollers' motion, a contact's sample means and a cage's angle and speed. In an
ensemble those are read back once per output sample for every member together
(:class:`EnsembleSample`) and each member's recorders get views of its share, so that a
member records exactly what its case run alone records.
"""

from __future__ import annotations

import numpy as np

__all__ = ["EnsembleSample", "MemberCage", "MemberContact", "MemberModel"]


class EnsembleSample:
    """What one output sample reads back from an ensemble's model, once for all members:
    the contact's pair means, the cages' states and the rollers' centres and spins (a
    :class:`~taichi_bearing.simulation.roller_readout.RollerReadout` of every member's
    rollers) (each read on first use after :meth:`refresh`)."""

    def __init__(self, model, contact, cage, rollers=None) -> None:
        self.model, self.contact, self.cage, self.rollers = model, contact, cage, rollers
        self._cache: dict[str, np.ndarray] = {}

    def refresh(self) -> None:
        """Forget the last sample's values (before the members' recorders read)."""
        self._cache.clear()

    def get(self, what: str) -> np.ndarray:
        if what not in self._cache:
            read = {
                "pairs": self.contact.pop_sample_means,
                "cage": lambda: self.cage.state.to_numpy(),
                "rollers": lambda: self.rollers.measure(self.model),
            }[what]
            self._cache[what] = read()
        return self._cache[what]


class MemberModel:
    """What member ``k``'s recorders read of the model itself: the time."""

    def __init__(self, sample: EnsembleSample, k: int) -> None:
        self.sample, self.k = sample, k

    @property
    def time(self) -> float:
        return self.sample.model.time


class MemberContact:
    """Member ``k``'s contact pairs' sample means (its pair table counts from 0)."""

    def __init__(self, sample: EnsembleSample, k: int, n_pairs: int) -> None:
        self.sample = sample
        self._pairs = slice(k * n_pairs, (k + 1) * n_pairs)

    def pop_sample_means(self) -> np.ndarray:
        return self.sample.get("pairs")[self._pairs]


class MemberCage:
    """Member ``k``'s cage angle and speed."""

    def __init__(self, sample: EnsembleSample, k: int) -> None:
        self.sample, self.k = sample, k

    @property
    def angle(self) -> float:
        return float(self.sample.get("cage")[2 * self.k])

    @property
    def speed(self) -> float:
        return float(self.sample.get("cage")[2 * self.k + 1])
