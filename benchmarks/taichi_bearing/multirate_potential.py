"""What multi-rate (subcycled) stepping could save on a case's mesh, before running it.

The step classes of :func:`taichi_bearing.solver.multirate.step_classes` for each level cap
(``--max-level``): nodes step at the run's step times 2**c, c the largest power within the
stable step of every element they belong to, and an element steps with its fastest node.
By default the elements alone set the classes; ``--acted-on-fast`` also holds every node a
contact, load, constraint or sensor acts on at class 0, as a run does. Prints, per level
cap, the share of elements and nodes in each class and the element and node work against
single-rate stepping (before any cost of the scheme itself), then each part's elements.
Builds the model (Taichi on the CPU) but runs no step.

    python benchmarks/taichi_bearing/multirate_potential.py cases/line_spall.yaml --acted-on-fast
    python benchmarks/taichi_bearing/multirate_potential.py cases/single_passage.yaml \
        --acted-on-fast \
        --set mesh.spall_size_mm=0.125 --set mesh.roller_surface_size_mm=0.125
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("case", nargs="?", default=str(ROOT / "cases" / "line_spall.yaml"))
    parser.add_argument("--set", dest="sets", action="append", default=[], metavar="KEY=VALUE")
    parser.add_argument("--max-level", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument(
        "--acted-on-fast",
        action="store_true",
        help="every node a contact, load, constraint or sensor acts on steps at the run's "
        "step (the contributors then need no change)",
    )
    args = parser.parse_args(argv)

    from taichi_bearing.case.load import load_case
    from taichi_bearing.simulation.simulate import build_model, stage_mesh
    from taichi_bearing.solver.multirate import step_classes
    from taichi_bearing.solver.step_phases import ACTED_ON, SENSOR

    case = load_case(args.case, args.sets)
    mesh, _ = stage_mesh(case)
    model = build_model(case, mesh, "cpu", 1).model
    model.freeze_contributors()  # the contributors flag the nodes they act on
    dt = model.dt
    elements = np.asarray(mesh.elements)
    element_dt = model.element_dt * model.critical.dt_factor
    fast = np.zeros(model.n_nodes, dtype=bool)
    if args.acted_on_fast:
        fast = (model.bc_np & (ACTED_ON | SENSOR)) != 0
    print(
        f"{Path(args.case).name} {' '.join(args.sets)}: {len(elements)} elements, "
        f"{model.n_nodes} nodes, run step {dt * 1e9:.2f} ns; smallest element step "
        f"{element_dt.min() * 1e9:.2f} ns; {int(fast.sum())} nodes held at class 0"
    )
    print("levels  element share per class      node share per class         element work"
          "  node work")  # fmt: skip
    for level in args.max_level:
        c = step_classes(element_dt, elements, dt, level, fast)
        info = c.summary()
        node_work = float(np.mean(0.5**c.node_class))
        print(
            f"{level:>6}  {np.array2string(np.array(info['element_share']), precision=3):<28} "
            f"{np.array2string(np.array(info['node_share']), precision=3):<28} "
            f"{c.element_work:.3f} (x{1 / c.element_work:.2f})  {node_work:.3f}"
        )
    part = np.asarray(mesh.element_part)
    cls = step_classes(element_dt, elements, dt, max(args.max_level), fast).element_class
    print("part          elements  in class 0  share of the multi-rate element work")
    total = float(np.sum(0.5**cls))
    for p, name in enumerate(mesh.part_names):
        sel = part == p
        if sel.any():
            share = float(np.sum(0.5 ** cls[sel])) / total
            print(f"{name:<12} {int(sel.sum()):>9}  {np.mean(cls[sel] == 0):>10.2f}  {share:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
