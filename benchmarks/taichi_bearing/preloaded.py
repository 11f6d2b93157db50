"""A case built, preloaded and ready to step: the start every profiling script shares."""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable, Sequence


def case_parser(
    doc: str, case: str = "cases/line_spall.yaml", arch: str | None = None,
    threads: int | None = None,
) -> argparse.ArgumentParser:  # fmt: skip
    """The arguments every profiling script shares: the case file (``case`` by default),
    ``--set KEY=VALUE`` overrides (``overrides``), and ``--arch`` and ``--threads`` where
    a default is given; the description is the first paragraph of ``doc``."""
    p = argparse.ArgumentParser(description=doc.split("\n\n")[0])
    p.add_argument("case", nargs="?", default=case)
    if arch is not None:
        p.add_argument("--arch", default=arch)
    if threads is not None:
        p.add_argument("--threads", type=int, default=threads)
    p.add_argument("--set", dest="overrides", action="append", default=[])
    return p


def preloaded_model(
    case_path: str,
    overrides: Sequence[str] = (),
    arch: str = "cpu",
    threads: int = 1,
    mesh_transform: Callable | None = None,
):
    """Load the case, mesh it (then ``mesh_transform(mesh)`` if given, e.g. a renumbering),
    build the model on ``arch`` with ``threads``, preload it, and set the transient's
    initial velocities and time step (the run's own, from the sample rate). Returns
    ``(case, mesh, built, preloaded)``: ``built`` the
    :class:`taichi_bearing.simulation.simulate.BearingModel` (``.model``, ``.setup``, ``.contact``),
    ``preloaded`` the preload's result (:func:`taichi_bearing.simulation.simulate.preload`) with its
    wall time ``wall_s``."""
    from taichi_bearing.case import load_case
    from taichi_bearing.simulation.engine import steps_per_sample
    from taichi_bearing.simulation.simulate import build_model, preload, stage_mesh

    case = load_case(case_path, list(overrides))
    mesh, _ = stage_mesh(case)
    if mesh_transform is not None:
        mesh = mesh_transform(mesh)
    built = build_model(case, mesh, arch, threads)
    t0 = time.perf_counter()
    preloaded = preload(built)
    preloaded["wall_s"] = time.perf_counter() - t0
    model = built.model
    model.set_initial_velocities()
    model.set_dt(steps_per_sample(model.dt_stable, case.run.sample_rate, model.cycle_steps)[1])
    return case, mesh, built, preloaded
