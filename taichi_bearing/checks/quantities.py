"""The quantities a run's preload and passages are judged by, as the reports and the
studies show them: each one's column name (SI), label, display unit and scale, whether it
is static (the preload's) or dynamic (the transient's), and one value per run or per
passage (:data:`QUANTITIES`)."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["QUANTITIES", "QUANTITY", "Quantity"]


@dataclass(frozen=True)
class Quantity:
    """A quantity a study compares.

    Attributes
    ----------
    name : str
        Its column in the study's tables, SI (``*_s``, ``*_m``, ``*_N``, ``*_Pa``).
    label : str
        What it is, in words.
    unit : str
        The unit it is shown in; ``scale`` converts: shown = SI value * scale.
    scale : float
    kind : str
        ``static`` (the preload's) or ``dynamic`` (the transient's).
    per : str
        ``run`` (one value per run) or ``passage``.
    reference : str or None
        The run table's column of the value it is compared with (Hertz's), if any.
    """

    name: str
    label: str
    unit: str
    scale: float
    kind: str
    per: str
    reference: str | None = None


QUANTITIES: tuple[Quantity, ...] = (
    Quantity("q_max_N", "Q_max, the largest roller force after the preload", "kN", 1e-3,
             "static", "run"),
    Quantity("zone_edge_share", "zone-edge share: smallest loaded roller force / Q_max", "-",
             1.0, "static", "run"),
    Quantity("contact_half_width_m", "contact half-width at the most loaded roller (outer)",
             "mm", 1e3, "static", "run", "hertz_half_width_m"),
    Quantity("contact_peak_pressure_Pa", "peak contact pressure at the most loaded roller",
             "MPa", 1e-6, "static", "run", "hertz_peak_pressure_Pa"),
    Quantity("entry_destress_time_s", "de-stressing time at entry (0.9 to 0.1 F0)", "ms",
             1e3, "dynamic", "passage"),
    Quantity("exit_force_peak_ratio", "exit force peak / F0", "-", 1.0, "dynamic", "passage"),
    Quantity("exit_impulses", "impulses at exit", "count", 1.0, "dynamic", "passage"),
    Quantity("exit_impulse_width_s", "exit impulse width at half height", "us", 1e6,
             "dynamic", "passage"),
    Quantity("exit_reload_time_s", "first touch of the exit edge to full load (0.9 F0)", "ms",
             1e3, "dynamic", "passage"),
    Quantity("exit_entry_accel_ratio", "exit / entry acceleration peak", "-", 1.0, "dynamic",
             "passage"),
    Quantity("exit_peak_frequency_hz", "frequency the re-stressing excites (exit burst peak)",
             "kHz", 1e-3, "dynamic", "passage"),
    Quantity("defect_size_estimate_m", "spall length estimated from the acceleration", "mm",
             1e3, "dynamic", "run"),
)  # fmt: skip
QUANTITY = {q.name: q for q in QUANTITIES}
