"""
Build and look at the mesh
==========================

The ``mesh`` command (``python -m taichi_bearing mesh CASE.yaml``) in Python: read a case,
turn it into a mesh specification, build the graded quadrilateral mesh of the outer ring
with its adapter, the inner ring and every roller, and look at it. The coarse validation
case (1 mm elements on the surfaces) builds in a few seconds; the default case has about
28,000 elements.
"""

# %%
# Read the case and build the mesh
# --------------------------------
# ``--set`` overrides are strings ``KEY.PATH=VALUE``, exactly as on the command line.
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PolyCollection

from taichi_bearing.case import load_case
from taichi_bearing.mesh.bearing_mesh import build_bearing_mesh
from taichi_bearing.mesh.quality import mesh_statistics
from taichi_bearing.mesh.spec import spec_from_case


def repository_root() -> Path:
    """The checkout this example belongs to (the gallery runs it from examples/)."""
    here = Path(globals().get("__file__", "examples/plot_mesh.py")).resolve().parent
    return next(p for p in (here, *here.parents) if (p / "cases").is_dir())


case = load_case(repository_root() / "cases/validation/coarse_spall.yaml")
mesh = build_bearing_mesh(spec_from_case(case))
print(f"{mesh.n_elements} elements, {len(mesh.nodes)} nodes, parts: {len(mesh.part_names)}")

# %%
# Mesh statistics
# ---------------
# Sizes, element quality, the smallest element's critical time step and the highest
# frequency each part resolves: what ``mesh_statistics.json`` holds.
m = case.material
stats = mesh_statistics(mesh, m.youngs_modulus, m.poissons_ratio, m.density)
print(stats.summary())

# %%
# The whole bearing, coloured by part
# -----------------------------------
# Each element is a quadrilateral of four node indices, counter-clockwise.
polygons = mesh.nodes[mesh.elements] * 1e3  # mm
part_kind = np.array(
    [0 if n.startswith("outer") else 1 if n.startswith("inner") else 2 for n in mesh.part_names]
)
colours = np.array(["#9ecae1", "#fdae6b", "#a1d99b"])[part_kind[mesh.element_part]]

fig, ax = plt.subplots(figsize=(7, 7))
ax.add_collection(PolyCollection(polygons, facecolors=colours, edgecolors="k", linewidths=0.1))
ax.autoscale()
ax.set_aspect("equal")
ax.set(xlabel="x (mm)", ylabel="y (mm)", title=f"{case.name}: {mesh.n_elements} elements")
plt.show()

# %%
# The spall under the load line
# -----------------------------
# The spall is an exact rectangular notch in the outer raceway at 12 o'clock; the elements
# are graded from the surface size at the raceways to the largest size inside the bodies.
spall = mesh.info["spall"]
print({k: spall[k] for k in ("race", "length", "depth")})

centre = np.array([0.0, 1e3 * case.bearing.pitch_diameter / 2])
near = np.abs(polygons - centre).max(axis=(1, 2)) < 25.0
fig, ax = plt.subplots(figsize=(8, 5))
ax.add_collection(
    PolyCollection(polygons[near], facecolors=colours[near], edgecolors="k", linewidths=0.3)
)
ax.autoscale()
ax.set_aspect("equal")
ax.set(xlabel="x (mm)", ylabel="y (mm)", title="outer raceway, spall and the roller below it")
plt.show()
