"""How long each team member waits at each barrier of a step: the team's idle time.

Team stepping (:mod:`taichi_bearing.solver.team`) splits every phase of a step among its
members and makes them meet at a spin barrier after each shared phase. A member that
finishes its share first spins until the others arrive, so the spins it counts measure the
imbalance of the shares (plus anything that delayed the last member: an interrupt, a
descheduled thread). This script swaps the barrier for one that counts each member's
spins at each phase (the team's own wait, plus a counter), runs the case as a run steps it
(``--samples`` output samples), and converts spins to time with the cost of one spin
measured in the same process (one thread spinning alone on the counter, as a waiting
member does). The dynamics are untouched: only the waiting is counted.

Prints, per member and phase, the spins a step and the microseconds a step they stand
for, beside the whole step's time. Nothing else should run on the machine meanwhile.

    python benchmarks/taichi_bearing/profile_barriers.py [CASE] [--threads 2] [--samples 20] \
        [--repeats 3]
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import sys
import tempfile
import time
from pathlib import Path

import taichi as ti

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

# Barriers a step passes when it runs every phase: after CLEAR, FORCES, GATHER and NODES.
PHASES = ("CLEAR", "FORCES", "GATHER", "NODES")
N_BARRIERS = len(PHASES)


def counting_barrier(spins_field):
    """A barrier with :func:`taichi_bearing.solver.team.barrier`'s signature (its own wait,
    :func:`~taichi_bearing.solver.team.barrier_spins`) that adds each member's spins to
    ``spins_field[member, phase]``; the phase is the count of barriers passed in this launch
    modulo 4, since every step passes four."""
    from taichi_bearing.solver.team import barrier_spins

    @ti.func
    def barrier(team: ti.template(), passed, n_members):
        out, spins = barrier_spins(team, passed, n_members)
        spins_field[ti.global_thread_idx(), passed % N_BARRIERS] += spins
        return out

    return barrier


def spin_cost_ns(flag, n: int = 2_000_000) -> float:
    """Nanoseconds of one spin (an atomic read of a counter no other thread touches), on one
    worker of a parallel loop of two, the way a waiting member spins."""

    @ti.kernel
    def spin(n: ti.i64) -> ti.i64:
        total = ti.i64(0)
        for j in range(2):
            if j == 0:
                seen = ti.i64(0)
                spins = ti.i64(0)
                while seen < 1:  # the counter stays 0: spins until the cap
                    seen = ti.atomic_add(flag[None], 0)
                    spins += 1
                    if spins >= n:
                        break
                total += spins
        return total

    spin(10)
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        count = spin(n)
        best = min(best, (time.perf_counter() - t0) / count)
    return best * 1e9


def main() -> int:
    from benchmarks.taichi_bearing.preloaded import case_parser

    p = case_parser(__doc__, threads=2)
    p.add_argument("--samples", type=int, default=20, help="output samples a repeat")
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    if args.threads < 2:
        p.error("--threads: a team needs 2 or more")

    from benchmarks.taichi_bearing.preloaded import preloaded_model
    from taichi_bearing.simulation.engine import steps_per_sample
    from taichi_bearing.solver import stepping
    from taichi_bearing.solver.backend import init_taichi
    from taichi_bearing.solver.team import TEAM_MAX_THREADS

    # Started here first (preloaded_model's own start is then a no-op) so that the counter
    # field exists before the stepping kernel is compiled; a cache of its own, since the
    # kernel differs from a run's.
    init_taichi("cpu", args.threads, cache_dir=tempfile.mkdtemp(prefix="profile_barriers_"))
    spins = ti.field(ti.i64, shape=(TEAM_MAX_THREADS, N_BARRIERS))
    flag = ti.field(ti.i64, shape=())
    stepping.barrier = counting_barrier(spins)

    case, _, bm, _ = preloaded_model(args.case, args.overrides, "cpu", args.threads)
    model = bm.model
    if stepping.choose_mode(model) != "team":
        p.error("this case does not step as a team here (too small, or the machine is busy)")
    s_steps, _ = steps_per_sample(model.dt_stable, case.run.sample_rate, model.cycle_steps)
    model.advance(s_steps, record_last=True)
    ns = spin_cost_ns(flag)
    members = args.threads
    n = args.samples * s_steps

    print(f"{case.name}: {model.n_elements} elements, {members} threads, team stepping; "
          f"{n} steps a repeat; one spin {ns:.1f} ns")  # fmt: skip
    head = "repeat  us/step  " + "  ".join(f"m{j} {ph:>6}" for j in range(members) for ph in PHASES)
    print(head + "  idle us/step by member")
    for r in range(args.repeats):
        spins.fill(0)
        t0 = time.perf_counter()
        for _ in range(args.samples):
            model.advance(s_steps, record_last=True)
        step_us = (time.perf_counter() - t0) / n * 1e6
        per_step = spins.to_numpy()[:members] / n
        cells = "  ".join(f"{v:9.0f}" for v in per_step.ravel())
        idle = per_step.sum(axis=1) * ns * 1e-3
        idle_text = ", ".join(f"{v:.1f}" for v in idle)
        print(f"{r:6d}  {step_us:7.1f}  {cells}  {idle_text} ({idle.max() / step_us:.1%})")
    print("cells: spins a step (member m, waiting after the phase); idle: spins x spin cost")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
