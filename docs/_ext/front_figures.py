"""The documentation's own pictures of the bearing, drawn from the default case's mesh.

Run from the repository root when the mesh or the default case changes, and commit the
PNGs it writes (the site does not draw them at build time, so a build without the gallery
still has them)::

    python docs/_ext/front_figures.py            # writes docs/_static/figures/*.png

* ``bearing_mesh.png``: the default bearing's mesh, whole and round the spall (front page).
* ``bearing_geometry.png`` and ``spall_geometry.png``: the bearing and the spall's profile
  with the case keys that set each dimension (the case reference).
"""

from __future__ import annotations

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402
from matplotlib.patches import Circle, FancyArrowPatch, Polygon, Rectangle, Wedge  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "docs" / "_static" / "figures"
CASE = ROOT / "cases" / "line_spall.yaml"

# One colour per kind of body, the same on every picture of the site.
OUTER, INNER, ROLLER = "#9ecae1", "#fdae6b", "#a1d99b"
SPALL = "#d62728"


def default_mesh():
    """The default case and its mesh (about 2 s)."""
    sys.path.insert(0, str(ROOT))
    from taichi_bearing.case import load_case
    from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
    from taichi_bearing.mesh.spec import spec_from_case

    case = load_case(CASE)
    return case, build_bearing_mesh(spec_from_case(case))


def part_colours(mesh) -> np.ndarray:
    kind = np.array(
        [0 if n.startswith("outer") else 1 if n.startswith("inner") else 2 for n in mesh.part_names]
    )
    return np.array([OUTER, INNER, ROLLER])[kind[mesh.element_part]]


def mesh_figure(case, mesh, path: Path) -> None:
    """The whole mesh beside a close view of the spall and the roller about to enter it."""
    polygons = mesh.nodes[mesh.elements] * 1e3  # mm
    colours = part_colours(mesh)
    fig, (whole, close) = plt.subplots(
        1, 2, figsize=(10, 4.6), gridspec_kw={"width_ratios": [1, 1.25]}, layout="constrained"
    )
    whole.add_collection(
        PolyCollection(polygons, facecolors=colours, edgecolors="k", linewidths=0.05)
    )
    whole.autoscale()
    whole.set_aspect("equal")
    whole.set_axis_off()
    whole.set_title(f"{mesh.n_elements:,} quadrilaterals, 22 bodies", fontsize=11)

    # the close view: the spall's edges, roller 0 below its entry edge
    x0, x1, y0, y1 = -10.0, 10.0, 102.5, 117.0
    box = Rectangle((x0, y0), x1 - x0, y1 - y0, fill=False, edgecolor=SPALL, linewidth=1.2)
    whole.add_patch(box)
    centre = polygons.mean(axis=1)
    near = (centre[:, 0] > x0 - 3) & (centre[:, 0] < x1 + 3) & (centre[:, 1] > y0 - 3)
    near &= centre[:, 1] < y1 + 3
    close.add_collection(
        PolyCollection(polygons[near], facecolors=colours[near], edgecolors="k", linewidths=0.25)
    )
    close.set_xlim(x0, x1)
    close.set_ylim(y0, y1)
    close.set_aspect("equal")
    close.set_xticks([])
    close.set_yticks([])
    for side in close.spines.values():
        side.set_edgecolor(SPALL)
        side.set_linewidth(1.2)
    spall = mesh.info["spall"]
    half = 1e3 * spall["length"] / 2
    raceway = 1e3 * spall["raceway_radius"]
    close.annotate(
        f"spall {1e3 * spall['length']:.0f} mm x {1e3 * spall['depth']:.1f} mm",
        xy=(0.0, raceway + 0.1),
        xytext=(0.0, raceway + 2.6),
        ha="center",
        fontsize=10,
        color=SPALL,
        bbox={"boxstyle": "round", "fc": "white", "ec": SPALL},
        arrowprops={"arrowstyle": "->", "color": SPALL},
    )
    close.annotate(
        "roller 0", xy=(3.0, 106.5), xytext=(-6.5, 104.0), fontsize=10, ha="center",
        bbox={"boxstyle": "round", "fc": "white", "ec": "0.3"},
        arrowprops={"arrowstyle": "->"},
    )  # fmt: skip
    close.annotate(
        "", xy=(-half - 3.5, 107.2), xytext=(-half + 1.0, 107.2),
        arrowprops={"arrowstyle": "-|>", "color": "0.1", "linewidth": 1.5},
    )  # fmt: skip
    close.text(-half - 1.2, 107.6, "rolling", ha="center", va="bottom", fontsize=10)
    close.set_title("round the spall: 0.5 mm on the raceways", fontsize=11)
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _dimension(ax, a, b, text, offset=(0.0, 0.0), **kw) -> None:
    ax.annotate(
        "", xy=a, xytext=b, arrowprops={"arrowstyle": "<->", "linewidth": 0.9, "color": "0.15"}
    )
    mid = (np.asarray(a) + np.asarray(b)) / 2 + np.asarray(offset)
    ax.text(*mid, text, fontsize=9, **kw)


def geometry_figure(case, mesh, path: Path) -> None:
    """The bearing with its dimensions and loads named by case key, and the spall's profile."""
    info = mesh.info
    r_out, r_in = 1e3 * info["raceway_radii"]["outer"], 1e3 * info["raceway_radii"]["inner"]
    r_ring = 1e3 * info["outer_ring_outer_radius"]
    r_bore = 1e3 * info["inner_bore_radius"]
    r_roll, r_pitch = 1e3 * info["roller_radius"], 1e3 * info["pitch_radius"]
    adapter = info["adapter"]
    a_w, a_h, a_top = 1e3 * adapter["width"], 1e3 * adapter["height"], 1e3 * adapter["top_y"]

    fig, ax = plt.subplots(figsize=(6.6, 6.9), layout="constrained")
    fig_s, sx = plt.subplots(figsize=(6.6, 3.4), layout="constrained")
    # outer ring and adapter (one body), inner ring, rollers
    ax.add_patch(Wedge((0, 0), r_ring, 0, 360, width=r_ring - r_out, fc=OUTER, ec="k", lw=0.8))
    ax.add_patch(Rectangle((-a_w / 2, a_top - a_h), a_w, a_h, fc=OUTER, ec="k", lw=0.8))
    ax.add_patch(Wedge((0, 0), r_in, 0, 360, width=r_in - r_bore, fc=INNER, ec="k", lw=0.8))
    centres = 1e3 * np.asarray(info["roller_centres"])
    for k, (x, y) in enumerate(centres):
        ax.add_patch(Circle((x, y), r_roll, fc=ROLLER, ec="k", lw=0.6))
        if k in (0, 1, 19):
            ax.text(x, y, str(k), ha="center", va="center", fontsize=7.5)
    ax.add_patch(Circle((0, 0), r_pitch, fill=False, ls="--", lw=0.7, ec="0.35"))
    ax.add_patch(Wedge((0, 0), r_out + 1.5, 86.5, 93.5, width=1.5, fc=SPALL, ec=SPALL))

    # dimensions, by case key
    def label(text, xy, xytext, **kw):
        ax.annotate(text, xy=xy, xytext=xytext, fontsize=9,
                    arrowprops={"arrowstyle": "->", "lw": 0.8, "color": kw.pop("ac", "0.15")},
                    **kw)  # fmt: skip

    t = np.radians(200)
    label("bearing.pitch_diameter_mm\n(dashed: the roller centres)",
          (r_pitch * np.cos(t), r_pitch * np.sin(t)), (-165, -150))  # fmt: skip
    c = centres[4]
    label("bearing.roller_diameter_mm", (c[0] - r_roll * 0.9, c[1] + r_roll * 0.4), (-165, 80))
    t = np.radians(-35)
    r = (r_out + r_ring) / 2
    label("bearing.outer_ring_thickness_mm", (r * np.cos(t), r * np.sin(t)), (40, -160))
    label("bearing.inner_ring_thickness_mm", (0, (r_in + r_bore) / 2), (0, 14), ha="center")
    _dimension(ax, (-a_w / 2, a_top - 18), (a_w / 2, a_top - 18), "bearing.adapter_width_mm",
               offset=(0, 1.5), ha="center", va="bottom")  # fmt: skip
    _dimension(ax, (a_w / 2 + 5, a_top - a_h), (a_w / 2 + 5, a_top),
               "bearing.adapter_height_mm", offset=(3, 0), va="center")  # fmt: skip
    # load on the adapter's top, the shaft's speed, the sensor
    ax.add_patch(FancyArrowPatch((-30, a_top + 36), (-30, a_top + 2), arrowstyle="-|>",
                                 mutation_scale=14, color="k", lw=1.4))  # fmt: skip
    ax.text(-34, a_top + 22, "operating.load_kN", ha="right", fontsize=9)
    theta = np.radians(np.linspace(215, 318, 60))
    ax.plot(34 * np.cos(theta), 34 * np.sin(theta), color="k", lw=1.2)
    end = np.radians([318, 326])
    ax.annotate("", xy=(34 * np.cos(end[1]), 34 * np.sin(end[1])),
                xytext=(34 * np.cos(end[0]), 34 * np.sin(end[0])),
                arrowprops={"arrowstyle": "-|>", "color": "k", "lw": 1.2})  # fmt: skip
    ax.text(0, -8, "operating.speed_rpm\n(inner ring)", ha="center", va="top", fontsize=9)
    ax.plot([0], [a_top], marker="v", color="#6a3d9a", ms=7)
    label("sensors.adapter_top", (1, a_top), (14, a_top + 18), color="#6a3d9a", ac="#6a3d9a")
    label("defect: race outer,\nangle_deg 0 (12 o'clock)", (-1, r_out + 0.7), (-165, 140),
          color=SPALL, ac=SPALL)  # fmt: skip
    ax.set_xlim(-170, 170)
    ax.set_ylim(-170, 200)
    ax.set_aspect("equal")
    ax.set_axis_off()
    ax.set_title(f"The default case ({CASE.name}), to scale", fontsize=11)

    # the spall's profile, not to scale: the outer ring above its raceway (12 o'clock), the
    # notch cut up into it, the roller below; depth drawn 15 times its length's scale
    spall = info["spall"]
    length, depth = 1e3 * spall["length"], 1e3 * spall["depth"]
    exaggerate = 15.0
    h = depth * exaggerate
    slope = 3.0  # a sloped exit wall, to show what exit_slope_deg sets
    half = length / 2
    ring = [(-12, 0), (-half, 0), (-half + slope, h), (half, h), (half, 0), (12, 0), (12, 6),
            (-12, 6)]  # fmt: skip
    sx.add_patch(Polygon(ring, closed=True, fc=OUTER, ec="k", lw=0.9))
    sx.add_patch(Circle((7.5, -1.6), 1.6, fc=ROLLER, ec="k", lw=0.8))
    sx.text(7.5, -1.6, "0", ha="center", va="center", fontsize=9)
    sx.annotate("", xy=(3.0, -1.6), xytext=(5.6, -1.6), arrowprops={"arrowstyle": "-|>"})
    sx.text(4.3, -2.0, "rolling", ha="center", va="top", fontsize=9)
    for x in (-half, half):
        sx.plot([x, x], [-0.1, -3.9], color="0.5", lw=0.6, ls=":")
    _dimension(sx, (-half, -3.9), (half, -3.9), "defect.length_mm (arc length)",
               offset=(0, -0.3), ha="center", va="top")  # fmt: skip
    _dimension(sx, (-1.0, 0), (-1.0, h), "defect.depth_mm", offset=(0.25, 0), va="center")
    sx.text(2.2, h - 0.3, "spall floor", ha="center", va="top", fontsize=9)
    sx.text(-11.6, -0.3, "outer raceway", va="top", fontsize=9)
    arrow = {"arrowstyle": "->", "lw": 0.8}
    sx.annotate("exit edge: defect.exit_slope_deg\n(here sloped)",
                xy=(-half + slope / 2, h / 2), xytext=(-11.6, 4.2), fontsize=9,
                arrowprops=arrow)  # fmt: skip
    sx.annotate("entry edge: defect.entry_slope_deg\n(here 90: radial)", xy=(half, h / 2),
                xytext=(2.6, 6.6), fontsize=9, arrowprops=arrow)  # fmt: skip
    sx.annotate("defect.edge_radius_mm\nrounds both edges", xy=(half + 0.05, 0.05),
                xytext=(8.0, 2.6), fontsize=9, arrowprops=arrow)  # fmt: skip
    sx.set_xlim(-12.2, 12.2)
    sx.set_ylim(-5.4, 8.2)
    sx.set_aspect("equal")
    sx.set_axis_off()
    sx.set_title(f"The spall, depth drawn {exaggerate:.0f} times", fontsize=11)
    fig.savefig(path, dpi=110)
    fig_s.savefig(path.with_name("spall_geometry.png"), dpi=110)
    plt.close(fig)
    plt.close(fig_s)


def main() -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    case, mesh = default_mesh()
    mesh_figure(case, mesh, OUT / "bearing_mesh.png")
    geometry_figure(case, mesh, OUT / "bearing_geometry.png")
    print(f"wrote bearing_mesh.png, bearing_geometry.png and spall_geometry.png in {OUT}")


if __name__ == "__main__":
    main()
