"""What a :class:`~taichi_bearing.solver.model.Model` reads back and restores: energies,
sensor means, stresses, the first inverted element, positions and velocities, which
ensemble members step, and the state a checkpoint holds (a base class of ``Model``: plain
Python over its fields, no kernel of its own)."""

from collections.abc import Mapping

import numpy as np

from taichi_bearing.solver import transfer
from taichi_bearing.solver.element_forces import store_von_mises
from taichi_bearing.solver.energy_sums import measure_energies

__all__ = ["ModelState"]


class ModelState:
    """The read-out and state half of :class:`~taichi_bearing.solver.model.Model`."""

    # ------------------------------------------------------------------ read-out

    def energies(self) -> dict[str, float]:
        """Energies at the last step run with ``record_last`` (J, for the thickness):
        kinetic, internal (strain), hourglass, damping (dissipated), external_work (done by
        loads, constraints and contributors), and ``mass_u2`` = sum m |u|^2. One model:
        an ensemble's are :meth:`member_energies`."""
        if self.ensemble_size != 1:
            raise ValueError("an ensemble's energies are per member: member_energies()")
        return self.member_energies()[0]

    def member_energies(self) -> list[dict[str, float]]:
        """:meth:`energies` of every ensemble member (one read-out for them all)."""
        measure_energies(self)
        s = self.sums.to_numpy().reshape(self.ensemble_size, 6)
        keys = ("kinetic", "internal", "hourglass", "damping", "external_work", "mass_u2")
        return [{key: float(v) for key, v in zip(keys, row, strict=True)} for row in s]

    def take_sensor_means(self, n_steps: int) -> np.ndarray:
        """Mean (ux, uy, vx, vy, ax, ay) of each sensor over the last ``n_steps`` steps
        (shape (n_sensors, 6)), and zero the sums."""
        if self.n_sensor == 0:
            return np.zeros((0, 6))
        (sums,) = transfer.download((self.sensor_sum,), zero=True)
        return sums[: self.n_sensor] / max(n_steps, 1)

    def von_mises_stress(self) -> np.ndarray:
        """Cauchy von Mises stress of each element at the current positions, Pa."""
        store_von_mises(self)
        return self.von_mises.to_numpy()[: self.n_elements]

    def bad_element_index(self, member: int | None = None) -> int | None:
        """First element found with det F <= 0 (or NaN) since the last reset, else None:
        of ``member``, or of the first member that has one (default)."""
        bad = self.bad_element.to_numpy()
        for k in range(self.ensemble_size) if member is None else (member,):
            if bad[k] < self.member_elements:
                return int(k * self.member_elements + bad[k])
        return None

    def reset_bad_elements(self) -> None:
        """Forget the elements found inverted (:meth:`bad_element_index`)."""
        self.bad_element.fill(self.member_elements)

    def set_members_active(self, active) -> None:
        """Which members the steps move (a sequence of bool, one per member): a member
        held still keeps its positions, velocities and contact and cage states, as if
        its steps had not been taken (an ensemble whose members stop relaxing at
        different steps). Every member is active after construction."""
        flags = np.asarray(active, dtype=np.int32).ravel()
        if flags.shape != (self.ensemble_size,):
            raise ValueError(f"set_members_active: one flag per member ({self.ensemble_size})")
        transfer.upload([(self.member_on, flags)])

    def positions(self) -> np.ndarray:
        return self.x.to_numpy()[: self.n_nodes]

    def velocities(self) -> np.ndarray:
        return self.v.to_numpy()[: self.n_nodes]

    def displacements(self) -> np.ndarray:
        return self.positions() - np.asarray(self.mesh.nodes, dtype=float)

    def set_state(self, x: np.ndarray | None = None, v: np.ndarray | None = None) -> None:
        """Overwrite positions and/or velocities (shape (n_nodes, 2))."""
        pairs = [(self.x, x), (self.v, v)]
        transfer.upload([(f, np.asarray(a, dtype=float)) for f, a in pairs if a is not None])
        self.history_stale = True

    # ------------------------------------------------------------------ checkpoint state

    _STATE_FIELDS = ("x", "v", "a", "f_other", "work", "e_damp", "sensor_sum", "v_int")
    # Checkpoints written before the strain history lack these: seeded again on resume.
    _HISTORY_FIELDS = ("e_prev", "q_prev")

    def state_arrays(self) -> dict[str, np.ndarray]:
        """Everything needed to continue bit for bit (see :meth:`load_state_arrays`)."""
        names = self._STATE_FIELDS + self._HISTORY_FIELDS
        saved = transfer.download([getattr(self, name) for name in names])
        out = dict(zip(names, saved, strict=True))
        out["history_stale"] = np.int64(self.history_stale)
        out["step_count"] = np.int64(self.step_count)
        out["first"] = np.int64(self.first)
        out["dt"] = np.float64(self.dt)
        return out

    def load_state_arrays(self, arrays: Mapping[str, np.ndarray]) -> None:
        """Restore a state from :meth:`state_arrays`."""
        history = all(name in arrays for name in self._HISTORY_FIELDS)
        pairs = []
        for name in self._STATE_FIELDS + (self._HISTORY_FIELDS if history else ()):
            field = getattr(self, name)
            a = np.asarray(arrays[name])
            if a.shape != transfer.array_shape(field):
                raise ValueError(f"checkpoint array {name!r} has shape {a.shape}, model differs")
            pairs.append((field, a))
        transfer.upload(pairs)
        self.step_count = int(arrays["step_count"])
        self.first = bool(arrays["first"])
        self._dt_set = float(arrays["dt"])
        self.history_stale = not history or bool(arrays.get("history_stale", 0))
        self.history_key = None  # whatever the resumed run steps with
