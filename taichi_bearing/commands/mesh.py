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
    from bearing_io.files import write_json
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
        "refinement": _refinement(mesh.info),
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
    refined = summary["refinement"]
    if refined["zone"] or refined["fine_rollers"]:
        print(_refinement_text(refined))
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


def _refinement(info: dict) -> dict:
    """Where the mesh is finer than ``mesh.surface_size_mm``: the raceway round the spall
    (its extent in mm of arc from the spall's centre) and the fine rollers."""
    sizes = info["sizes"]
    rollers = [float(v) for v in sizes["roller_surface_size"]]
    fine = [j for j, v in enumerate(rollers) if v < sizes["surface_size"]]
    zone = info.get("fine_zone")
    if zone:
        spall = info["spall"]
        radius, centre = spall["raceway_radius"], spall["centre_angle"]
        zone = {
            "size_mm": 1e3 * zone["fine_size"],
            "from_centre_mm": [1e3 * radius * (a - centre) for a in zone["zone_angles"]],
            "transitions_to_mm": [1e3 * radius * (a - centre) for a in zone["transition_angles"]],
            "band_depth_mm": 1e3 * zone["band_depth"],
        }
    return {
        "zone": zone,
        "fine_rollers": fine,
        "roller_surface_size_mm": 1e3 * min(rollers),
    }


def _refinement_text(refined: dict) -> str:
    parts = []
    zone = refined["zone"]
    if zone:
        lo, hi = zone["from_centre_mm"]
        t_lo, t_hi = zone["transitions_to_mm"]
        parts.append(
            f"raceway {zone['size_mm']:.4g} mm from {lo:.4g} to {hi:.4g} mm of the spall's "
            f"centre (graded to the surface size by {t_lo:.4g} and {t_hi:.4g} mm, "
            f"{zone['band_depth_mm']:.3g} mm deep)"
        )
    if refined["fine_rollers"]:
        names = ", ".join(str(j) for j in refined["fine_rollers"])
        parts.append(f"rollers {names} at {refined['roller_surface_size_mm']:.4g} mm")
    return "refined: " + "; ".join(parts)
