"""`python -m taichi_bearing mesh CASE.yaml`: build the mesh, write ``mesh.vtu``, pictures
and ``mesh_statistics.json``, and print a one-screen summary."""

from __future__ import annotations

import argparse
import math
import time

from taichi_bearing.commands.common import add_case_arguments, case_output_folder
from taichi_bearing.errors import InputError


def add_arguments(parser: argparse.ArgumentParser) -> None:
    add_case_arguments(parser)
    parser.add_argument(
        "--no-pictures",
        dest="pictures",
        action="store_false",
        help="skip the rendered pictures (mesh.vtu and the statistics only)",
    )


def main(args: argparse.Namespace) -> int:
    from diagnostics.files import write_json
    from taichi_bearing.case import load_case_for_cli
    from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
    from taichi_bearing.mesh.quality import mesh_statistics
    from taichi_bearing.mesh.spec import spec_from_case
    from taichi_bearing.post.mesh_render import render_mesh_pictures, write_mesh_vtu

    case = load_case_for_cli(args.case, args.overrides)
    try:
        spec = spec_from_case(case)
        t0 = time.perf_counter()
        mesh = build_bearing_mesh(spec)
        seconds = time.perf_counter() - t0
    except ValueError as exc:  # geometry the mesher cannot build, e.g. a too thin ring
        raise InputError(f"{args.case}: cannot mesh this case: {exc}") from None
    out = case_output_folder(args.out, case)  # after meshing: a refused case makes no folder
    m = case.material
    stats = mesh_statistics(mesh, m.youngs_modulus, m.poissons_ratio, m.density)
    files = [write_mesh_vtu(mesh, out / "mesh.vtu")]
    summary = {
        "case": case.name,
        "build_seconds": seconds,
        "statistics": stats.__dict__,
        "spall": mesh.info.get("spall"),
        "sensor_nodes": mesh.sensor_nodes,
    }
    files.append(out / "mesh_statistics.json")
    write_json(files[-1], summary)
    if args.pictures:
        files += render_mesh_pictures(mesh, out, title=f"{case.name}: {mesh.n_elements} elements")
    print(stats.summary())
    spall = mesh.info.get("spall")
    if spall:
        print(
            f"spall: {spall['race']} raceway, {1e3 * spall['length']:.4g} mm x "
            f"{1e3 * spall['depth']:.4g} mm at {math.degrees(spall['centre_angle_from_top']):.4g} "
            f"deg from 12 o'clock, {spall['wall_layers']} element layer(s) deep"
        )
    dt = 0.9 * stats.critical_dt
    print(
        f"solver step about {1e9 * dt:.4g} ns: {case.run.duration / dt:,.0f} steps for "
        f"{1e3 * case.run.duration:.4g} ms"
    )
    budget = "" if mesh.n_elements <= 40_000 else "  (over the 40,000 element budget)"
    print(f"built in {seconds:.2f} s{budget}")
    for f in files:
        print(f"wrote {f}")
    return 0
