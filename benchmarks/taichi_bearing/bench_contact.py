"""Cost of penalty contact per step on the default bearing mesh, next to the element forces.

Usage::

    python benchmarks/taichi_bearing/bench_contact.py [--case cases/line_spall.yaml] [--steps 200]
                                       [--threads 0] [--arch cpu]

Pairs: every roller against the outer and the inner raceway (2 Z pairs, two-pass). The
bodies are given the rigid velocities of ideal rolling so that the grid is rebuilt as it
would be in a run. Columns: ms per step for the element/node phases alone (the baseline,
a model without contributors, one launch per step), for the contact alone (its own
launches, ``add_forces``), for the rigid cage alone, and for a full step with both (as a
run steps it); their share of
the full step; grid rebuilds. A row with ``smoothing`` off (contact against the chords,
the polygon: the baseline of the smooth arc contact, which is the case's default). A last
row forces a grid rebuild every step (the worst case of the search). Best of 5 repeats
each.
"""

from __future__ import annotations

import argparse
import dataclasses
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from taichi_bearing.case import load_case  # noqa: E402
from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh  # noqa: E402
from taichi_bearing.mesh.spec import spec_from_case  # noqa: E402
from taichi_bearing.solver.backend import init_taichi  # noqa: E402


def _time(fn, steps: int, repeats: int = 5) -> float:
    """Best ms per step over ``repeats`` runs (the machine may be shared)."""
    fn(2)  # compile
    best = float("inf")
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn(steps)
        best = min(best, (time.perf_counter() - t0) / steps * 1e3)
    return best


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--case", default=str(ROOT / "cases" / "line_spall.yaml"))
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--arch", default="cpu")
    args = ap.parse_args()
    init_taichi(args.arch, threads=args.threads or None)
    from taichi_bearing.solver.cage import RigidCage
    from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
    from taichi_bearing.solver.loads import RigidVelocity
    from taichi_bearing.solver.model import Model

    case = load_case(args.case)
    mesh = build_bearing_mesh(spec_from_case(case))
    info = mesh.info
    z = len(info["roller_centres"])
    # Rolling-like motion: rings turn, rollers orbit and spin (exact kinematics are not
    # needed for the cost, only realistic motion of the surfaces).
    w = 50.0
    vel = [RigidVelocity("inner_ring", omega=w)]
    for j, c in enumerate(info["roller_centres"]):
        v = 0.4 * w * np.array([-c[1], c[0]])
        vel.append(RigidVelocity(f"roller{j}", omega=-3.0 * w, center=tuple(c), velocity=tuple(v)))

    def bearing_model() -> Model:
        return Model(
            mesh, case.material, thickness=case.bearing.roller_length, initial_velocities=vel
        )

    model = bearing_model()
    pairs = []
    for j in range(z):
        pairs.append(ContactPair(f"roller{j}_outer", f"roller{j}", "outer_raceway"))
        pairs.append(ContactPair(f"roller{j}_inner", f"roller{j}", "inner_raceway"))
    params = ContactParameters.from_case(case.contact)
    contact = PenaltyContact(model, pairs, params)
    n_surf_nodes = contact.n_query
    print(
        f"mesh: {mesh.n_elements} elements, {mesh.n_nodes} nodes; contact: {len(pairs)} pairs, "
        f"{n_surf_nodes} query nodes, {contact.n_seg} segments, grid "
        f"{contact.grid.nx} x {contact.grid.ny} cells of {contact.grid.cell * 1e3:.2f} mm; "
        f"dt {model.dt:.3g} s"
    )

    bare = bearing_model()  # no contributors: the element and node phases alone
    base = _time(lambda n: bare.advance(n, mode="parallel"), args.steps)
    contact_only = _time(lambda n: [contact.add_forces(model, 0.0) for _ in range(n)], args.steps)
    flip = dataclasses.replace(params, smoothing=not params.smoothing)
    other = PenaltyContact(model, pairs, flip)
    other_only = _time(lambda n: [other.add_forces(model, 0.0) for _ in range(n)], args.steps)
    model.f_extra.fill(0)
    cage = RigidCage.from_mesh(model, params, case.cage.mass, case.cage.pocket_clearance)
    cage_only = _time(lambda n: [cage.add_forces(model, 0.0) for _ in range(n)], args.steps)
    model.add_contributor(contact)
    model.add_contributor(cage)
    r0 = contact.rebuilds
    full = _time(lambda n: model.advance(n), args.steps)
    rebuilds = contact.rebuilds - r0

    def rebuild_every_step(n: int) -> None:
        for _ in range(n):
            contact._rebuild(model)
            contact.add_forces(model, 0.0)

    worst = _time(rebuild_every_step, args.steps)

    # baseline of the active-query list: every query visited (the list made the identity)
    def visit_all(x):
        contact.q_active.from_numpy(np.arange(contact.n_query, dtype=np.int32))
        contact.status[1] = contact.n_query

    active = contact.n_active
    contact._k_activate = visit_all
    contact.after_state_load()  # rebuild (with every query listed) at the next call
    all_queries = _time(lambda n: [contact.add_forces(model, 0.0) for _ in range(n)], args.steps)
    print(f"{'':34s}{'ms/step':>10s}{'share of full step':>20s}")
    print(f"{'elements + nodes (baseline)':34s}{base:10.3f}")
    label = f"contact alone, smoothing {'on' if params.smoothing else 'off'}"
    print(f"{label:34s}{contact_only:10.3f}{contact_only / full:20.1%}")
    label = f"contact, smoothing {'off' if params.smoothing else 'on'}"
    print(f"{label:34s}{other_only:10.3f}{other_only / full:20.1%}")
    print(f"{'rigid cage alone':34s}{cage_only:10.3f}{cage_only / full:20.1%}")
    print(f"{'full step with contact and cage':34s}{full:10.3f}")
    print(f"{'contact with a rebuild every step':34s}{worst:10.3f}{worst / (base + worst):20.1%}")
    print(f"grid rebuilds in {5 * args.steps + 2} full steps: {rebuilds}")
    print(
        f"queries visited: {active} of {contact.n_query} (active list); contact with every "
        f"query visited {all_queries:.3f} ms/step: the list saves "
        f"{all_queries / contact_only:.2f}x on the contact"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
