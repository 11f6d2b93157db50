"""The recorder interface: extra history columns sampled from the model once per output
sample (no Taichi here)."""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

__all__ = ["Recorder"]


class Recorder:
    """Base class of the extra history columns (e.g. roller contact forces, cage angle).

    :meth:`sample` is called by :func:`taichi_bearing.simulation.engine.run_transient` once
    per output sample, after the steps of the interval, and returns one value per name
    in ``columns`` (means over the interval where that makes sense: see each recorder).
    A recorder that keeps state between samples saves it in checkpoints through
    :meth:`state_arrays` and :meth:`load_state_arrays`.
    """

    columns: list[str] = []

    def sample(self, model) -> np.ndarray:
        """The values of :attr:`columns` for the interval just stepped."""
        raise NotImplementedError

    def state_arrays(self) -> dict[str, np.ndarray]:
        """What the recorder needs to continue bit for bit after a resume (default: none)."""
        return {}

    def load_state_arrays(self, arrays: Mapping[str, np.ndarray]) -> None:
        """Restore :meth:`state_arrays`."""
