"""Speed of the bearing run: wall time, steps, element-steps/s and where the time goes.

Runs the case (default ``cases/line_spall.yaml``) through mesh and preload, then a SHORT
transient of ``--duration-ms`` (default 0.3 ms) with contact and every recorder, as the run
does it (contact and cage inside the model's step kernels; on several CPU threads many
steps per launch by team stepping), and extrapolates it to the case's full duration
(labelled as such). In the same process, from the same state: the transient again with
one launch of parallel loops per step (``mode="parallel"``), and the baseline, a model of
the same mesh without contact stepped as many steps (element forces, nodes, loads only).
Recording: sensor sums read-out, energies, recorders, history writing (everything in the
time loop outside the steps). To compare with another version of the code, side by side,
see ``bench_versions.py``.

Usage::

    python benchmarks/taichi_bearing/bench_line_spall.py [CASE] [--duration-ms 0.3] [--threads 2]
        [--set KEY=VALUE ...]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

from taichi_bearing.case import load_case
from taichi_bearing.simulation.simulate import build_model, preload, stage_mesh


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("case", nargs="?", default="cases/line_spall.yaml")
    p.add_argument("--duration-ms", type=float, default=0.3)
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--set", dest="overrides", action="append", default=[])
    args = p.parse_args()

    from taichi_bearing.simulation import RunConfig, run_transient
    from taichi_bearing.solver import Model

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
    advance = model.advance
    step_s = [0.0]

    def transient(mode: str | None):
        """The short transient from the preloaded state: wall time, steps, time in steps."""

        def timed_advance(*a, **k):
            t = time.perf_counter()
            advance(*a, **{**k, "mode": mode})
            step_s[0] += time.perf_counter() - t

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
            step_s[0] = 0.0
            t0 = time.perf_counter()
            res = run_transient(model, cfg, Path(tmp), recorders=bm.recorders)
            wall = time.perf_counter() - t0
        model.advance = advance
        model.load_state_arrays(state)
        return res, wall, step_s[0]

    # --- the run's own path, then one launch of parallel loops per step
    res, total, step_run = transient(None)
    steps = res.steps
    _, total_per_step, _ = transient("parallel")

    # --- baseline: the same mesh, set-up and preloaded state, no contributors
    bare = Model(
        mesh,
        bm.setup.material,
        thickness=bm.setup.thickness,
        constraints=bm.setup.constraints,
        loads=bm.setup.loads,
        damping=bm.setup.damping,
        max_added_mass=case.run.max_added_mass,
        time_step=case.run.time_step,
    )
    bare.load_state_arrays(state)
    bare.set_dt(res.dt)
    bare.advance(10)  # compile
    t0 = time.perf_counter()
    bare.advance(steps)  # as the run would step it
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
    print()
    print(f"run's path / one launch per step: {total / total_per_step:.2f}")
    print(f"recording (samples, files): {100 * (total - step_run) / total:.1f} % of the "
          "transient")  # fmt: skip
    print(f"contact run / baseline per step: {total / base:.2f}x")


if __name__ == "__main__":
    main()
