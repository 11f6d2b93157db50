"""Layer thicknesses that grow away from a contact surface, and where to coarsen.

A body is meshed as layers parallel to its contact surface: the first layer is the
surface size thick, each next one ``growth`` times thicker (capped at the maximum size),
scaled so that the stack fills the thickness exactly. Whenever a layer becomes much
thicker than its elements are wide, the row becomes a coarsening row (ratio 2) so that the
elements stay close to square.
"""

from __future__ import annotations

import math

import numpy as np

# Coarsen when a layer is this much thicker than its elements are wide: the coarsening row
# is then about two fine cells tall, so the templates' sub-quads are close to square.
COARSEN_ASPECT = 1.8


def graded_layers(thickness: float, first: float, growth: float, max_size: float) -> np.ndarray:
    r"""Thicknesses of layers filling ``thickness``, starting at ``first``.

    The raw sequence :math:`\mathrm{first} \cdot \mathrm{growth}^k` (capped at ``max_size``)
    is cut at the layer count whose stretch factor is closest to 1; layers after the first
    are then scaled so the sum is exact.

    Returns
    -------
    ndarray
        Layer thicknesses, first (surface) layer first.
    """
    if thickness <= first * (1 + 1e-9):
        return np.array([thickness])
    raw = [first]
    while sum(raw) < thickness:
        raw.append(min(raw[-1] * growth, max_size))
    best = None
    for n in (len(raw) - 1, len(raw)):
        rest = sum(raw[1:n])
        if n < 2 or rest <= 0:
            continue
        alpha = (thickness - first) / rest
        if best is None or abs(math.log(alpha)) < abs(math.log(best[1])):
            best = (n, alpha)
    n, alpha = best
    return np.array([first] + [alpha * t for t in raw[1:n]])


def coarsening_rows(
    thicknesses: np.ndarray,
    widths: np.ndarray,
    max_size: float,
    frozen: int = 1,
    max_rows: int = 4,
    min_width: float = 0.0,
) -> list[float]:
    """The coarsening ratio (1 or 2) of every layer.

    Parameters
    ----------
    thicknesses : ndarray
        Layer thicknesses from the surface.
    widths : ndarray
        Element width each layer would have without any coarsening (the surface size
        scaled by the layer's radius over the surface radius).
    max_size : float
        Elements are not coarsened beyond this width.
    frozen : int
        Rows next to the surface that stay plain (surface elements stay regular).
    max_rows : int
        At most this many coarsening rows.
    min_width : float
        Also coarsen a row whose elements would be narrower than this (a shrinking
        circumference, as inside a roller), as long as the row is at least as thick as
        its elements are wide: narrow elements would cut the time step.

    Returns
    -------
    list of float
        Ratio of each row; the elements above a row with ratio 2 are twice as wide.
    """
    ratios = []
    factor = 1.0
    for k, (t, w) in enumerate(zip(thicknesses, widths, strict=True)):
        width = w * factor
        needed = t >= COARSEN_ASPECT * width or (width < min_width and t >= width)
        coarsen = (
            k >= frozen and needed and 2 * width <= 1.2 * max_size and ratios.count(2.0) < max_rows
        )
        ratios.append(2.0 if coarsen else 1.0)
        factor *= ratios[-1]
    return ratios


def notch_depths(far: np.ndarray, depth: float) -> tuple[np.ndarray, int]:
    """Level depths at a notch, and the number of layers across the notch depth.

    The notch takes ``n_thin`` equal layers, ``n_thin`` being the first far-field level at
    or below the notch depth; from level ``n_thin + 1`` on the far-field levels ``far``
    (cumulative depths, level 0 = 0) are kept. So a shallow notch is one thin layer, a deep
    one several, and the layer under the floor is never thinner than the ones around it.
    """
    far = np.asarray(far, dtype=float)
    below = np.flatnonzero(far >= depth * (1 - 1e-12))
    n_thin = int(below[0]) if len(below) else len(far)
    if n_thin >= len(far) - 1:
        raise ValueError(
            f"the notch depth {depth} m reaches the back of the ring's layer stack ({far[-1]} m)"
        )
    near = far.copy()
    near[: n_thin + 1] = depth * np.arange(n_thin + 1) / n_thin
    return near, n_thin
