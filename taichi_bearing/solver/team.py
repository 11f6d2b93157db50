"""Team stepping: many steps in one kernel launch on several CPU threads.

A Taichi CPU parallel loop ends in a thread-pool dispatch (~100 us on a 2-core VM), more
than one phase of a step of a 30k-element mesh takes. So on several CPU threads one launch
runs a chunk of steps: each worker thread runs one team *member* (its
``ti.global_thread_idx()``) through every step of the chunk, doing the member's fixed
share of each phase (:mod:`taichi_bearing.solver.step_phases`), and the members meet at a spin
barrier between phases (an atomic add, ~1 us) instead of ending a parallel loop.

Members join by claiming their thread's first item of an ``n_members * 1024``-item loop:
Taichi's CPU tasks are at least 512 items, so there are at least two tasks per thread and
every worker takes one; a member busy in its first item cannot take another task.
"""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.
import taichi as ti

__all__ = [
    "TEAM_MAX_THREADS",
    "TEAM_SPIN_LIMIT",
    "TeamState",
    "barrier",
    "barrier_spins",
    "join",
    "share",
]

# A barrier spin this long means a member never came (then the launch stops and the
# stepping raises): far beyond any one phase of a step.
TEAM_SPIN_LIMIT = 1 << 28
TEAM_MAX_THREADS = 256


@ti.func
def share(count, member, n_members):
    """Member's contiguous share ``[lo, hi)`` of ``count`` items split among
    ``n_members``."""
    # In 64 bits: a GPU's 65,536 members times 32,768 items passes the i32 range.
    m = ti.cast(member, ti.i64)
    return ti.cast(m * count // n_members, ti.i32), ti.cast((m + 1) * count // n_members, ti.i32)


@ti.data_oriented
class TeamState:
    """A team's barrier counter, which threads joined, and a failed-barrier flag."""

    def __init__(self) -> None:
        self.bar = ti.field(ti.i64, shape=())
        self.joined = ti.field(ti.i32, shape=TEAM_MAX_THREADS)
        self.failed = ti.field(ti.i32, shape=())

    @ti.func
    def reset(self):
        """Before a launch (serial code): counter, joins and flag to zero."""
        self.bar[None] = 0
        self.failed[None] = 0
        for j in range(TEAM_MAX_THREADS):
            self.joined[j] = 0


@ti.func
def join(team: ti.template(), member):
    """Whether this thread is the first to claim member ``member`` (then it runs it)."""
    return ti.atomic_add(team.joined[member], 1) == 0


@ti.func
def barrier(team: ti.template(), passed, n_members):
    """Spin until all ``n_members`` reached their ``passed + 1``-th barrier; returns
    ``passed + 1``, or -1 (and sets ``team.failed``) if one never comes. The atomic add is
    a full fence: what a member wrote before, the others read after."""
    out, _ = barrier_spins(team, passed, n_members)
    return out


@ti.func
def barrier_spins(team: ti.template(), passed, n_members):
    """:func:`barrier`, returning also how many times this member read the counter while
    it waited (``benchmarks/taichi_bearing/profile_barriers.py`` counts them)."""
    out = passed + 1
    target = ti.i64(n_members) * out
    seen = ti.atomic_add(team.bar[None], 1) + 1
    spins = 0
    while seen < target:
        seen = ti.atomic_add(team.bar[None], 0)  # an atomic read, never hoisted
        spins += 1
        if spins > TEAM_SPIN_LIMIT:
            team.failed[None] = 1
            out = -1
            break
    return out, spins
