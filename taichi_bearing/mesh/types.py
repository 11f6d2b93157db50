r"""The mesh handed from the mesher to the solver: plain numpy arrays, SI units.

Conventions (every producer and consumer relies on them):

- ``nodes`` are reference coordinates in metres, bearing centre at the origin, +y up
  (12 o'clock), angles counter-clockwise from +x unless a name says otherwise.
- ``elements`` are 4-node quadrilaterals listed counter-clockwise.
- ``surfaces`` are ordered segment lists ``(n_segments, 2)`` of node indices, oriented so
  that the body lies on the LEFT of each segment (a->b). The outward normal of a segment
  is therefore :math:`(\Delta y, -\Delta x) / \mathrm{length}`. An outer boundary runs
  counter-clockwise, a hole's boundary (e.g. the outer raceway) clockwise.
- Parts are numbered from 0; ``part_names[p]`` names part ``p``; ``element_part[e]`` is the
  part of element ``e``. Bodies that may separate (rings, rollers) share no nodes.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Mesh:
    """A 2-D quadrilateral mesh with parts, node sets and contact surfaces.

    Attributes
    ----------
    nodes : ndarray, shape (n_nodes, 2)
        Reference coordinates, m.
    elements : ndarray of int, shape (n_elements, 4)
        Node indices, counter-clockwise.
    element_part : ndarray of int, shape (n_elements,)
        Part id of each element.
    part_names : list of str
        Name of each part id, e.g. ``["outer_ring", "inner_ring", "roller0", ...]``.
    node_sets : dict of str to ndarray of int
        Named node sets, e.g. ``"inner_bore"``, ``"adapter_top"``.
    surfaces : dict of str to ndarray of int, shape (n_segments, 2)
        Named contact surfaces, body on the left of each segment.
    sensor_nodes : dict of str to int
        Named sensor node indices.
    info : dict
        Free-form metadata from the mesher (e.g. polygon edge counts, spall geometry).
    """

    nodes: np.ndarray
    elements: np.ndarray
    element_part: np.ndarray
    part_names: list[str]
    node_sets: dict[str, np.ndarray] = field(default_factory=dict)
    surfaces: dict[str, np.ndarray] = field(default_factory=dict)
    sensor_nodes: dict[str, int] = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    @property
    def n_nodes(self) -> int:
        return int(self.nodes.shape[0])

    @property
    def n_elements(self) -> int:
        return int(self.elements.shape[0])

    def part_id(self, name: str) -> int:
        """Part id of the part called ``name``."""
        try:
            return self.part_names.index(name)
        except ValueError:
            raise KeyError(f"no part named {name!r}; parts are {self.part_names}") from None

    def segment_normals(self, surface: str) -> np.ndarray:
        """Unit outward normals of a surface's segments in the reference configuration."""
        seg = self.surfaces[surface]
        d = self.nodes[seg[:, 1]] - self.nodes[seg[:, 0]]
        n = np.stack([d[:, 1], -d[:, 0]], axis=1)
        return n / np.linalg.norm(n, axis=1, keepdims=True)
