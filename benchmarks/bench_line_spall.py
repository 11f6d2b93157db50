"""Speed of the bearing run: wall time, steps, element-steps/s and where the time goes.

Runs the case (default ``cases/line_spall.yaml``) through mesh and preload, then a SHORT
transient of ``--duration-ms`` (default 0.3 ms) with contact and every recorder, as the run
does it (contact and cage fused into the model's step kernels; on several CPU threads many
steps per launch by team stepping), and extrapolates it to the case's full duration
(labelled as such). In the same process, from the same state: the transient again with
one launch of parallel loops per step (the path before team stepping), with each
contributor's own kernel, timed (where the time goes: element
and node kernels, contact, cage), and the baseline, the model stepped without contact
(element forces, nodes, loads only). Recording: sensor sums read-out, energies, recorders,
history writing (everything in the time loop outside the steps).

Usage::

    python benchmarks/bench_line_spall.py [CASE] [--duration-ms 0.3] [--threads 2]
        [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from taichi_bearing.case import load_case
from taichi_bearing.simulate import build_model, preload, stage_mesh


class _Timed:
    """Wraps a force contributor and adds up the wall time of its ``add_forces``."""

    def __init__(self, inner) -> None:
        self.inner = inner
        self.seconds = 0.0

    def add_forces(self, model, t) -> None:
        t0 = time.perf_counter()
        self.inner.add_forces(model, t)
        self.seconds += time.perf_counter() - t0

    def energy(self, model=None) -> float:
        return self.inner.energy(model)


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("case", nargs="?", default="cases/line_spall.yaml")
    p.add_argument("--duration-ms", type=float, default=0.3)
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--set", dest="overrides", action="append", default=[])
    args = p.parse_args()

    from taichi_bearing.solver import RunConfig, run_transient
    from taichi_bearing.solver.engine import steps_per_sample

    case = load_case(args.case, args.overrides)
    rows = []
    t0 = time.perf_counter()
    mesh, _ = stage_mesh(case)
    rows.append(("mesh", time.perf_counter() - t0, 0))
    t0 = time.perf_counter()
    bm = build_model(case, mesh, "cpu", args.threads or None)
    model = bm.model
    rows.append(("model build (fields)", time.perf_counter() - t0, 0))
    t0 = time.perf_counter()
    pre = preload(bm)
    rows.append(("preload (dynamic relaxation)", time.perf_counter() - t0, pre["steps"]))
    model.set_initial_velocities()
    state = model.state_arrays()
    ne = mesh.n_elements

    duration = args.duration_ms * 1e-3
    cfg = RunConfig(duration=duration, sample_rate=case.run.sample_rate, progress=False)
    originals = list(model.contributors)
    advance = model.advance
    step_s = [0.0]

    def timed_advance(*a, **k):
        t = time.perf_counter()
        advance(*a, **k)
        step_s[0] += time.perf_counter() - t

    def transient(timed: list | None):
        """The short transient from the preloaded state: wall time, steps, time in steps.
        ``timed``: contributors wrapped to time their ``add_forces`` (which also takes
        them out of the model's fused step kernels)."""
        model.contributors[:] = timed if timed is not None else originals
        model.advance = timed_advance
        with tempfile.TemporaryDirectory() as tmp:
            # compile outside the timing: one short run first
            run_transient(
                model,
                RunConfig(duration=2 / case.run.sample_rate, sample_rate=case.run.sample_rate,
                          progress=False),
                Path(tmp), recorders=bm.recorders,
            )  # fmt: skip
            model.load_state_arrays(state)
            for c in timed or ():
                c.seconds = 0.0
            step_s[0] = 0.0
            t0 = time.perf_counter()
            res = run_transient(model, cfg, Path(tmp), recorders=bm.recorders)
            wall = time.perf_counter() - t0
        model.advance = advance
        model.contributors[:] = originals
        model.load_state_arrays(state)
        return res, wall, step_s[0]

    # --- the run's own path: contact and cage fused into the step kernels
    res, total, step_fused = transient(None)
    steps = res.steps
    # --- the same with one launch of parallel loops per step (no team stepping)
    model._team_size = lambda fused: 0  # shadows the method on this instance
    _, total_per_step, _ = transient(None)
    del model._team_size
    # --- the same with each contributor's own kernel, timed
    timed = [_Timed(c) for c in originals]
    _, total_unfused, step_unfused = transient(timed)
    contact_s = sum(c.seconds for c in timed)

    # --- baseline: the same model and state without contact
    model.contributors[:] = []
    model.load_state_arrays(state)
    s, dt = steps_per_sample(model.dt_stable, case.run.sample_rate)
    model.set_dt(dt)
    model.advance(10)  # compile
    t0 = time.perf_counter()
    model.advance(steps)  # as the run would step it
    base = time.perf_counter() - t0

    full_steps = round(case.run.duration / res.dt)
    scale = full_steps / steps
    print(f"case {case.name}: {ne} elements, {mesh.n_nodes} nodes, dt {res.dt:.4g} s, "
          f"threads {args.threads or 'all'}")  # fmt: skip
    print(f"measured transient {args.duration_ms:g} ms = {steps} steps; EXTRAPOLATED to the "
          f"case's {case.run.duration * 1e3:g} ms = {full_steps} steps")  # fmt: skip
    print()
    print(f"{'stage':40s} {'wall s':>10s} {'steps':>9s} {'elem-steps/s':>13s}")
    for name, wall, n in rows:
        rate = f"{ne * n / wall:13.3g}" if n else f"{'':13s}"
        print(f"{name:40s} {wall:10.2f} {n:9d} {rate}")
    print(f"{'transient, measured':40s} {total:10.2f} {steps:9d} {ne * steps / total:13.3g}")
    print(f"{'transient, extrapolated (full duration)':40s} {total * scale:10.1f} "
          f"{full_steps:9d} {ne * steps / total:13.3g}")  # fmt: skip
    print(f"{'transient, one launch per step':40s} {total_per_step:10.2f} {steps:9d} "
          f"{ne * steps / total_per_step:13.3g}")  # fmt: skip
    print(f"{'baseline: no contact, same steps':40s} {base:10.2f} {steps:9d} "
          f"{ne * steps / base:13.3g}")  # fmt: skip
    print(f"{'transient, contributors unfused (timed)':40s} {total_unfused:10.2f} {steps:9d} "
          f"{ne * steps / total_unfused:13.3g}")  # fmt: skip
    print()
    print(f"fused / unfused wall time: {total / total_unfused:.2f}")
    print(f"run's path / one launch per step: {total / total_per_step:.2f}")
    print(f"recording (samples, files): {100 * (total - step_fused) / total:.1f} % of the "
          "fused transient")  # fmt: skip
    elem = step_unfused - contact_s
    print("share of the unfused transient (each contributor's kernel timed):")
    print(f"  element forces + node update  {elem:8.2f} s  {100 * elem / total_unfused:5.1f} %")
    for c in timed:
        name = type(c.inner).__name__
        print(f"  {name:28s}  {c.seconds:8.2f} s  {100 * c.seconds / total_unfused:5.1f} %")
    print(f"contact run (fused) / baseline per step: {total / base:.2f}x")


if __name__ == "__main__":
    main()
