"""Where an output sample's wall time goes: its steps, and the run's read-out after them.

Builds the case (default ``cases/line_spall.yaml``) on ``--arch``, preloads it and times
``--samples`` output samples the way ``run_transient`` takes them: the sample's steps
without a recorded step, the same with it (``record_last``: the element energies and the
last step launched apart), then each read-out piece (sensor means, each recorder, the
energy sums, the contributors' energies, the inverted-element flag), each synchronised.
Medians, in ms a sample and us a step of the sample. On a GPU, where a step costs tens of
microseconds, a read-out piece of a few milliseconds is a large share of the run.

    python benchmarks/taichi_bearing/profile_sample.py --arch cuda --samples 20
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def main() -> int:
    from benchmarks.taichi_bearing.preloaded import case_parser

    p = case_parser(__doc__, arch="cpu", threads=0)
    p.add_argument("--samples", type=int, default=20)
    args = p.parse_args()

    import taichi as ti

    from benchmarks.taichi_bearing.preloaded import preloaded_model
    from taichi_bearing.simulation.engine import steps_per_sample

    case, mesh, bm, pre = preloaded_model(args.case, args.overrides, args.arch, args.threads)
    model = bm.model
    s_steps = steps_per_sample(model.dt_stable, case.run.sample_rate, model.cycle_steps)[0]
    print(f"{args.case} on {args.arch}: {mesh.n_elements} elements, preload {pre['steps']} "
          f"steps in {pre['wall_s']:.1f} s, {s_steps} steps a sample", flush=True)  # fmt: skip

    pieces = {
        "sensor means": lambda: model.take_sensor_means(s_steps),
        **{type(r).__name__: (lambda r=r: r.sample(model)) for r in bm.recorders},
        "energy sums": model.energies,
        **{f"{type(c).__name__}.energy": c.energy for c in model.contributors},
        "inverted-element flag": model.bad_element_index,
    }
    times: dict[str, list[float]] = {k: [] for k in ("steps", "steps, last recorded", *pieces)}

    def timed(name: str, f) -> None:
        t0 = time.perf_counter()
        f()
        ti.sync()
        times[name].append(time.perf_counter() - t0)

    for k in range(args.samples + 1):  # the first compiles
        # alternate which of the two goes first: the first after the read-out can differ
        runs = [("steps", False), ("steps, last recorded", True)]
        for name, rec in runs if k % 2 else runs[::-1]:
            timed(name, lambda rec=rec: model.advance(s_steps, record_last=rec))
        for name, f in pieces.items():
            timed(name, f)
        if k == 0:
            for v in times.values():
                v.clear()

    med = {k: statistics.median(v) for k, v in times.items()}
    read_out = sum(med[k] for k in pieces)
    rows = [*med.items(), ("read-out, all pieces", read_out)]
    print(f"\n{'part of a sample':28s} {'ms':>8s} {'us a step':>10s}")
    for name, t in rows:
        print(f"{name:28s} {t * 1e3:8.3f} {t / s_steps * 1e6:10.2f}")
    whole = med["steps, last recorded"] + read_out
    extra = med["steps, last recorded"] - med["steps"]
    print(f"\na sample: {whole * 1e3:.2f} ms, of which read-out {read_out / whole:.1%} and the "
          f"recorded step's extra {extra / whole:.1%}")  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
