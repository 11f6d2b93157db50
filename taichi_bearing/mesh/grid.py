"""Quad-grid building blocks shared by every mesher: structured grids, Coons patches,
boundary extraction and orientation.

A structured grid of ``n_u x n_v`` cells has ``(n_u + 1) x (n_v + 1)`` nodes numbered
row by row (``v`` major); with ``periodic=True`` the ``u`` direction wraps and a row holds
``n_u`` nodes.
"""

from __future__ import annotations

import numpy as np


def quad_grid(n_u: int, n_v: int, periodic: bool = False) -> np.ndarray:
    """Connectivity of a structured ``n_u x n_v`` quad grid, counter-clockwise in (u, v).

    Parameters
    ----------
    n_u, n_v : int
        Cells along ``u`` (fast index) and ``v``.
    periodic : bool
        Whether ``u`` wraps: a row then has ``n_u`` nodes and the last cell joins the first.

    Returns
    -------
    ndarray of int, shape (n_u * n_v, 4)
        Node indices ``(u, v), (u+1, v), (u+1, v+1), (u, v+1)`` with node index
        ``v * row + u``.
    """
    if n_u < 1 or n_v < 1:
        raise ValueError(f"a grid needs at least one cell each way, got {n_u} x {n_v}")
    row = n_u if periodic else n_u + 1
    i = np.arange(n_u)
    j = np.arange(n_v)
    ii, jj = np.meshgrid(i, j)
    ii = ii.ravel()
    jj = jj.ravel()
    i1 = (ii + 1) % row if periodic else ii + 1
    return np.stack(
        [jj * row + ii, jj * row + i1, (jj + 1) * row + i1, (jj + 1) * row + ii], axis=1
    ).astype(np.int64)


def coons_patch(
    bottom: np.ndarray, right: np.ndarray, top: np.ndarray, left: np.ndarray
) -> np.ndarray:
    """Node grid of a transfinite (Coons) patch between four boundary polylines.

    Parameters
    ----------
    bottom, top : ndarray, shape (n_u + 1, 2)
        Bottom and top edges, both from the left side to the right side.
    left, right : ndarray, shape (n_v + 1, 2)
        Left and right edges, both from the bottom to the top.

    Returns
    -------
    ndarray, shape ((n_v + 1) * (n_u + 1), 2)
        Node coordinates, row by row from the bottom, matching :func:`quad_grid`.

    Notes
    -----
    The parameter along each edge is its normalised arc length, so graded edge nodes
    carry their grading into the interior.
    """
    bottom, right, top, left = (np.asarray(a, dtype=float) for a in (bottom, right, top, left))
    if len(bottom) != len(top) or len(left) != len(right):
        raise ValueError("opposite sides of a Coons patch need the same number of nodes")
    corners_ok = (
        np.allclose(bottom[0], left[0])
        and np.allclose(bottom[-1], right[0])
        and np.allclose(top[0], left[-1])
        and np.allclose(top[-1], right[-1])
    )
    if not corners_ok:
        raise ValueError("the four sides of a Coons patch must meet at their corners")
    s_b, s_t = _arc_parameter(bottom), _arc_parameter(top)
    t_l, t_r = _arc_parameter(left), _arc_parameter(right)
    n_v, n_u = len(left), len(bottom)
    # Where the line joining matching bottom/top nodes crosses the line joining matching
    # left/right nodes: exact for opposite sides graded differently.
    sb, st = s_b[None, :], s_t[None, :]
    tl, tr = t_l[:, None], t_r[:, None]
    den = 1.0 - (st - sb) * (tr - tl)
    s = (sb + tl * (st - sb)) / den
    t = (tl + sb * (tr - tl)) / den
    pts = (
        (1 - t)[..., None] * bottom[None, :, :]
        + t[..., None] * top[None, :, :]
        + (1 - s)[..., None] * left[:, None, :]
        + s[..., None] * right[:, None, :]
        - (1 - s)[..., None] * (1 - t)[..., None] * bottom[0]
        - s[..., None] * (1 - t)[..., None] * bottom[-1]
        - (1 - s)[..., None] * t[..., None] * top[0]
        - s[..., None] * t[..., None] * top[-1]
    )
    # Boundary nodes exactly as given (the blend reproduces them only to round-off).
    pts[0, :] = bottom
    pts[-1, :] = top
    pts[:, 0] = left
    pts[:, -1] = right
    return pts.reshape(n_v * n_u, 2)


def _arc_parameter(points: np.ndarray) -> np.ndarray:
    """Normalised cumulative arc length along a polyline, 0 at the start and 1 at the end."""
    d = np.linalg.norm(np.diff(points, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(d)])
    return s / s[-1]


def signed_areas(nodes: np.ndarray, elements: np.ndarray) -> np.ndarray:
    """Signed area of each quad (shoelace); positive when counter-clockwise."""
    x = nodes[elements, 0]
    y = nodes[elements, 1]
    return 0.5 * np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1)


def orient_ccw(nodes: np.ndarray, elements: np.ndarray) -> np.ndarray:
    """The elements, all reversed if they all run clockwise.

    A block is oriented as a whole, never element by element: flipping a single inverted
    quad would hide a tangled mesh.

    Raises
    ------
    ValueError
        If some quads run clockwise (or are degenerate) and others counter-clockwise.
    """
    elements = np.asarray(elements)
    area = signed_areas(nodes, elements)
    if np.all(area < 0):
        return elements[:, ::-1].copy()
    bad = np.flatnonzero(area <= 0)
    if len(bad):
        raise ValueError(
            f"{len(bad)} of {len(elements)} quads are inverted or degenerate (first: {bad[0]})"
        )
    return np.array(elements, copy=True)


def boundary_segments(elements: np.ndarray) -> np.ndarray:
    """Element edges used by exactly one element, oriented as in that element.

    With counter-clockwise elements the body lies on the left of every returned segment.
    """
    edges = np.stack([elements, np.roll(elements, -1, axis=1)], axis=2).reshape(-1, 2)
    key = np.sort(edges, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return edges[counts[inverse.ravel()] == 1]


def chain_segments(segments: np.ndarray) -> list[np.ndarray]:
    """Order segments head to tail into chains (open or closed).

    Parameters
    ----------
    segments : ndarray of int, shape (n, 2)
        Oriented segments; each node starts at most one segment and ends at most one.

    Returns
    -------
    list of ndarray, shape (n_k, 2)
        Each chain in order. A closed loop starts at its lowest node index, an open chain
        at its free end.
    """
    segments = np.asarray(segments, dtype=np.int64).reshape(-1, 2)
    nxt = {}
    for k, (a, _) in enumerate(segments):
        if int(a) in nxt:
            raise ValueError(f"node {int(a)} starts two boundary segments")
        nxt[int(a)] = k
    ends = {int(b) for b in segments[:, 1]}
    starts = [int(a) for a in segments[:, 0] if int(a) not in ends]
    used = np.zeros(len(segments), dtype=bool)
    chains = []
    for first in sorted(starts) + sorted(int(a) for a in segments[:, 0]):
        k = nxt.get(first)
        if k is None or used[k]:
            continue
        order = []
        while k is not None and not used[k]:
            used[k] = True
            order.append(k)
            k = nxt.get(int(segments[k, 1]))
        chains.append(segments[order])
    return chains


def merge_nodes(
    nodes: np.ndarray, elements: np.ndarray, tol: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Merge nodes closer than ``tol`` and drop nodes no element uses.

    Returns
    -------
    nodes : ndarray
        The kept nodes.
    elements : ndarray of int
        Connectivity renumbered onto the kept nodes.
    old_to_new : ndarray of int
        New index of every input node (-1 for a dropped, unused node).
    """
    from scipy.spatial import cKDTree

    n = len(nodes)
    rep = np.arange(n)
    for a, b in sorted(cKDTree(nodes).query_pairs(tol)):
        ra, rb = _root(rep, a), _root(rep, b)
        if ra != rb:
            rep[max(ra, rb)] = min(ra, rb)
    rep = np.array([_root(rep, i) for i in range(n)])
    elements = rep[elements]
    used = np.zeros(n, dtype=bool)
    used[elements.ravel()] = True
    new_index = np.full(n, -1, dtype=np.int64)
    new_index[used] = np.arange(int(used.sum()))
    return nodes[used], new_index[elements], new_index[rep]


def _root(rep: np.ndarray, i: int) -> int:
    while rep[i] != i:
        rep[i] = rep[rep[i]]
        i = int(rep[i])
    return int(i)


def surface_chain(nodes: np.ndarray, elements: np.ndarray, on_surface) -> np.ndarray:
    """The boundary segments whose two end nodes satisfy ``on_surface(points) -> bool
    array``, ordered head to tail (body on the left).

    Raises
    ------
    ValueError
        If the selected segments do not form one chain.
    """
    seg = boundary_segments(elements)
    on = np.asarray(on_surface(nodes), dtype=bool)
    chains = chain_segments(seg[on[seg[:, 0]] & on[seg[:, 1]]])
    if len(chains) != 1:
        raise ValueError(f"expected one chain of surface segments, found {len(chains)}")
    return chains[0]
