"""Where a step's wall time goes on a backend launching one kernel per step (a GPU).

Builds the case (default ``cases/line_spall.yaml``) on ``--arch``, preloads it, and times
``--steps`` transient steps three ways: the wall time per step (synchronised); the same
under cProfile (the host's Python share: argument packing and launching); and, with
``TI_KERNEL_PROFILER=1`` in the environment, Taichi's per-task device times (the
device's share). Wall per step well above the device's share means the run is bound by
the host's launches, not by the device.

    TI_KERNEL_PROFILER=1 python benchmarks/taichi_bearing/profile_gpu.py --arch cuda --steps 2000
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import cProfile
import os
import pstats
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))


def main() -> int:
    from benchmarks.taichi_bearing.preloaded import case_parser

    p = case_parser(__doc__, arch="cuda", threads=0)
    p.add_argument("--steps", type=int, default=2000)
    args = p.parse_args()

    import taichi as ti

    from benchmarks.taichi_bearing.preloaded import preloaded_model

    case, mesh, bm, pre = preloaded_model(args.case, args.overrides, args.arch, args.threads)
    model = bm.model
    print(f"preload: {pre['steps']} steps in {pre['wall_s']:.1f} s", flush=True)
    model.advance(50)
    ti.sync()

    n = args.steps
    t0 = time.perf_counter()
    model.advance(n)
    ti.sync()
    wall = (time.perf_counter() - t0) / n
    rate = mesh.n_elements / wall
    print(f"{mesh.n_elements} elements, stepping {sorted(model.steps_by_mode)}: "
          f"{wall * 1e6:.1f} us per step wall, {rate:.3g} element-steps/s")  # fmt: skip

    prof = cProfile.Profile()
    prof.enable()
    model.advance(n)
    ti.sync()
    prof.disable()
    stats = pstats.Stats(prof)
    total = sum(v[2] for v in stats.stats.values())  # tottime over every function
    # Taichi's C++ launch (on a GPU: the tasks' launches, not their run) against the rest
    launch = sum(v[2] for k, v in stats.stats.items() if "taichi_python.launch_kernel" in k[2])
    us = 1e6 / n
    print(f"host under cProfile: {total * us:.1f} us per step, of which in Taichi's C++ "
          f"launch {launch * us:.1f} us, Python {(total - launch) * us:.1f} us")  # fmt: skip
    stats.sort_stats("tottime").print_stats(8)

    if os.environ.get("TI_KERNEL_PROFILER") == "1":
        ti.profiler.clear_kernel_profiler_info()
        model.advance(n)
        ti.sync()
        device = ti.profiler.get_kernel_profiler_total_time()
        print(f"device tasks: {device / n * 1e6:.1f} us per step")
        ti.profiler.print_kernel_profiler_info("count")
    return 0


if __name__ == "__main__":
    sys.exit(main())
