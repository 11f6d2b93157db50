"""What multi-rate (subcycled) stepping could save on a case's mesh, before building it.

Each node's stable step is the smallest of its elements' own steps and of the step its
contact springs and dashpots allow (as to ground, as the model bounds them); nodes step at
the run's step times 2**c, c the largest power that keeps them stable (capped at
``--max-level``), and an element steps with its fastest node (a node partition: the
elements of slower nodes are evaluated less often, the ones on an interface at the fast
rate). Prints, per case and level cap, the share of elements and nodes in each class and
the element and node work against single-rate stepping: the best any multi-rate scheme can
do on that mesh, before the interface's own cost. Builds the model (Taichi on the CPU) but
runs no step.

    python benchmarks/multirate_potential.py cases/line_spall.yaml
    python benchmarks/multirate_potential.py cases/single_passage.yaml \
        --set mesh.spall_size_mm=0.125 --set mesh.roller_surface_size_mm=0.125
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def node_steps(element_dt: np.ndarray, elements: np.ndarray, n_nodes: int) -> np.ndarray:
    """Each node's stable step: the smallest of its elements' steps."""
    dt = np.full(n_nodes, np.inf)
    for k in range(elements.shape[1]):
        np.minimum.at(dt, elements[:, k], element_dt)
    return dt


def spring_steps(stiffness, damping, mass, dt_factor: float) -> np.ndarray:
    """Stable step of a node on a spring and dashpot to ground (inf where it has none)."""
    out = np.full(len(mass), np.inf)
    has = stiffness > 0
    omega = np.sqrt(stiffness[has] / mass[has])
    zeta = damping[has] / (2.0 * np.sqrt(stiffness[has] * mass[has]))
    out[has] = dt_factor * (2.0 / omega) * (np.sqrt(1.0 + zeta**2) - zeta)
    return out


def work_by_class(node_dt: np.ndarray, elements: np.ndarray, dt: float, max_level: int):
    """Node and element classes (step ``dt 2**c``) and the work against single rate.

    Returns ``(element_class, element_share, node_share, element_work, node_work)``: each
    element's class, the share of elements and nodes in each class 0..max_level and the
    evaluations per unit time relative to stepping everything at ``dt``.
    """
    ratio = np.maximum(node_dt / dt, 1.0)
    node_class = np.minimum(np.floor(np.log2(ratio)).astype(int), max_level)
    element_class = node_class[elements].min(axis=1)
    element_share = np.bincount(element_class, minlength=max_level + 1) / len(elements)
    node_share = np.bincount(node_class, minlength=max_level + 1) / len(node_class)
    element_work = float(np.mean(0.5**element_class))
    node_work = float(np.mean(0.5**node_class))
    return element_class, element_share, node_share, element_work, node_work


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
    from taichi_bearing.simulate import build_model, stage_mesh

    case = load_case(args.case, args.sets)
    mesh, _ = stage_mesh(case)
    model = build_model(case, mesh, "cpu", 1).model
    model.freeze_contributors()  # the contributors flag the nodes they act on
    crit = model.critical
    dt = model.dt
    elements = np.asarray(mesh.elements)
    element_dt = crit.element_dt * crit.dt_factor
    springs = spring_steps(crit.node_stiffness, crit.node_damping, crit.mass, crit.dt_factor)
    node_dt = np.minimum(node_steps(element_dt, elements, model.n_nodes), springs)
    if args.acted_on_fast:
        from taichi_bearing.solver.step import ACTED_ON, SENSOR

        flags = model.bc.to_numpy()
        node_dt[(flags & (ACTED_ON | SENSOR)) != 0] = 0.0
    print(
        f"{Path(args.case).name} {' '.join(args.sets)}: {len(elements)} elements, "
        f"{model.n_nodes} nodes, run step {dt * 1e9:.2f} ns; smallest element step "
        f"{element_dt.min() * 1e9:.2f} ns, smallest contact-node step {springs.min() * 1e9:.2f} "
        f"ns ({int(np.isfinite(springs).sum())} nodes)"
    )
    print("levels  element share per class      node share per class         element work"
          "  node work")  # fmt: skip
    for level in args.max_level:
        _, e_share, n_share, e_work, n_work = work_by_class(node_dt, elements, dt, level)
        print(
            f"{level:>6}  {np.array2string(e_share, precision=3):<28} "
            f"{np.array2string(n_share, precision=3):<28} {e_work:.3f} (x{1 / e_work:.2f})"
            f"  {n_work:.3f}"
        )
    part = np.asarray(mesh.element_part)
    cls = work_by_class(node_dt, elements, dt, max(args.max_level))[0]
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
