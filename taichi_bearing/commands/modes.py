"""`python -m taichi_bearing modes CASE.yaml [--part P] [--support S] [--count N]`:
natural frequencies and mode shapes of the finite element model (no Taichi).

Writes ``modes.csv``, ``modes.pvd`` with ``modes/mode_*.vtu`` (open the ``.pvd`` in
ParaView and warp by ``displacement``) and ``modes.png`` into ``--out``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from taichi_bearing.commands.common import add_case_arguments
from taichi_bearing.errors import InputError
from taichi_bearing.modes.model import PARTS, SUPPORTS

MAX_COUNT = 500


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument(
        "--part",
        default="outer_ring",
        help="outer_ring (with its adapter), inner_ring or bearing (rings and rollers, "
        "the loaded rollers tied to the raceways by their contact stiffness); default "
        "outer_ring",
    )
    parser.add_argument(
        "--support",
        default="case",
        help="free (nothing holds it: rigid-body modes at 0 Hz) or case (held as in the "
        "run: loading plate on the adapter top or the housing, inner bore held); "
        "default case",
    )
    parser.add_argument(
        "--count",
        default="20",
        metavar="N",
        help="how many elastic modes (the lowest N; the rigid-body modes below them are "
        "listed too); default 20",
    )


def _count(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise InputError(f"--count: expected a whole number, got {text!r}") from None
    if not 1 <= n <= MAX_COUNT:
        raise InputError(f"--count: expected 1 to {MAX_COUNT}, got {n}")
    return n


def main(args: argparse.Namespace) -> int:
    if args.part not in PARTS:
        raise InputError(f"--part: expected one of {', '.join(PARTS)}, got {args.part!r}")
    if args.support not in SUPPORTS:
        raise InputError(f"--support: expected one of {', '.join(SUPPORTS)}, got {args.support!r}")
    count = _count(args.count)
    from taichi_bearing.case import load_case_for_cli
    from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
    from taichi_bearing.mesh.spec import spec_from_case
    from taichi_bearing.modes import bearing_modal_model, solve_modes
    from taichi_bearing.modes.output import write_modes

    case = load_case_for_cli(args.case, args.overrides)
    out = Path(args.out) if args.out else case.out_dir
    t0 = time.perf_counter()
    try:
        mesh = build_bearing_mesh(spec_from_case(case))
    except ValueError as exc:  # geometry the mesher cannot build
        raise InputError(f"{args.case}: cannot mesh this case: {exc}") from None
    model = bearing_modal_model(case, mesh, args.part, args.support)
    try:
        result = solve_modes(model, count)
    except ValueError as exc:
        raise InputError(f"--{exc}") from None
    seconds = time.perf_counter() - t0
    files = write_modes(result, out, f"{case.name}: {args.part}, support {args.support}")
    print(
        f"{args.part} ({args.support}): {model.mesh.n_elements} elements, "
        f"{model.matrix.shape[0]} degrees of freedom; " + "; ".join(model.notes)
    )
    n_rigid = sum(m.rigid for m in result.modes)
    print(
        f"{len(result.modes)} modes ({n_rigid} rigid-body, below "
        f"{result.rigid_threshold:.3g} Hz) in {seconds:.1f} s"
    )
    for m in result.modes:
        print(f"{m.number:4d} {m.frequency:12.6g} Hz  {m.description}")
    for f in files:
        print(f"wrote {f}")
    return 0
