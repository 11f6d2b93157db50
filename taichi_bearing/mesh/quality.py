r"""Element quality and the explicit time step a mesh allows.

Definitions (the solver relies on the same ones):

- element size: the shortest edge; aspect ratio: longest / shortest edge;
- Jacobian ratio: smallest / largest determinant of the bilinear map over the four corners
  (1 for a parallelogram, <= 0 for an inverted or degenerate quad);
- characteristic length :math:`L = A / d_\mathrm{max}` (area over the longer diagonal, as
  LS-DYNA does for 2-D solids); critical step :math:`\Delta t = L / c` with the
  plane-strain dilatational wave speed :math:`c = \sqrt{(\lambda + 2 \mu) / \rho}`.

Resolution: a wave is resolved where an element is at most :math:`1 / N` of its
wavelength, so a part resolves frequencies up to :math:`f = c_R / (N h)`, :math:`h` its
longest element edge. :math:`c_R` is the Rayleigh wave speed, the slowest wave in the
bodies (0.93 of the shear wave speed for steel, half the dilatational one), so its
wavelength is the shortest at a given frequency: it is the wave that carries a contact
impulse along a raceway, and bending of the rings is slower still only where the ring is
thin against the wavelength. :math:`N` is 10 by default (``mesh.elements_per_wavelength``):
the usual rule for linear elements (Kuhlemeyer and Lysmer's :math:`h \le \lambda / 10` for
wave propagation), at which a lumped-mass linear element's wave speed is low by about
1.6 % (:math:`(k h)^2 / 24`); 20 halves the element size for a quarter of that error.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from taichi_bearing.mesh.grid import signed_areas
from taichi_bearing.mesh.types import Mesh

ELEMENTS_PER_WAVELENGTH = 10.0
"""Default elements per wavelength of the resolution criterion (see the module notes)."""

GAUSS_2X2 = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float) / np.sqrt(3.0)
CORNERS = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]], dtype=float)


def jacobian_determinants(
    nodes: np.ndarray, elements: np.ndarray, points: np.ndarray = GAUSS_2X2
) -> np.ndarray:
    """Determinant of the bilinear map of every quad at the given (xi, eta) points.

    Returns
    -------
    ndarray, shape (n_elements, n_points)
    """
    x = nodes[elements]  # (ne, 4, 2)
    xi = points[:, 0][:, None]
    eta = points[:, 1][:, None]
    sx = np.array([-1.0, 1.0, 1.0, -1.0])
    sy = np.array([-1.0, -1.0, 1.0, 1.0])
    dn_dxi = 0.25 * sx[None, :] * (1 + sy[None, :] * eta)  # (np, 4)
    dn_deta = 0.25 * sy[None, :] * (1 + sx[None, :] * xi)
    j11 = np.einsum("pa,ea->ep", dn_dxi, x[..., 0])
    j12 = np.einsum("pa,ea->ep", dn_dxi, x[..., 1])
    j21 = np.einsum("pa,ea->ep", dn_deta, x[..., 0])
    j22 = np.einsum("pa,ea->ep", dn_deta, x[..., 1])
    return j11 * j22 - j12 * j21


def wave_speed(youngs_modulus: float, poissons_ratio: float, density: float) -> float:
    r"""Plane-strain dilatational wave speed :math:`\sqrt{(\lambda + 2 \mu) / \rho}`, m/s."""
    e, nu = youngs_modulus, poissons_ratio
    if e <= 0 or density <= 0 or not -1 < nu < 0.5:
        raise ValueError(f"need E > 0, rho > 0 and -1 < nu < 0.5, got {e}, {density}, {nu}")
    return float(np.sqrt(e * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) / density))


def shear_wave_speed(youngs_modulus: float, poissons_ratio: float, density: float) -> float:
    r"""Shear wave speed :math:`\sqrt{\mu / \rho}`, m/s."""
    return float(np.sqrt(youngs_modulus / (2.0 * (1.0 + poissons_ratio)) / density))


def rayleigh_wave_speed(youngs_modulus: float, poissons_ratio: float, density: float) -> float:
    r"""Rayleigh (surface) wave speed, m/s: the root :math:`\xi = (c_R / c_s)^2` in (0, 1) of
    :math:`\xi^3 - 8 \xi^2 + (24 - 16 k) \xi - 16 (1 - k) = 0`, :math:`k = (c_s / c_p)^2`
    (plane strain, so :math:`c_p` is the dilatational speed)."""
    cs = shear_wave_speed(youngs_modulus, poissons_ratio, density)
    k = (cs / wave_speed(youngs_modulus, poissons_ratio, density)) ** 2
    roots = np.roots([1.0, -8.0, 24.0 - 16.0 * k, -16.0 * (1.0 - k)])
    xi = [r.real for r in roots if abs(r.imag) < 1e-12 and 0.0 < r.real < 1.0]
    return float(cs * math.sqrt(min(xi)))


def element_geometry(nodes: np.ndarray, elements: np.ndarray) -> dict[str, np.ndarray]:
    """Per-element area, shortest/longest edge, characteristic length and Jacobian ratio."""
    x = nodes[elements]
    edges = np.linalg.norm(np.roll(x, -1, axis=1) - x, axis=2)
    diag = np.maximum(
        np.linalg.norm(x[:, 2] - x[:, 0], axis=1), np.linalg.norm(x[:, 3] - x[:, 1], axis=1)
    )
    area = signed_areas(nodes, elements)
    det = jacobian_determinants(nodes, elements, CORNERS)
    return {
        "area": area,
        "min_edge": edges.min(axis=1),
        "max_edge": edges.max(axis=1),
        "char_length": area / diag,
        "jacobian_ratio": det.min(axis=1) / det.max(axis=1),
    }


@dataclass
class MeshStatistics:
    """Counts, sizes and quality of a mesh; see the module notes for the definitions."""

    n_nodes: int
    n_elements: int
    part_elements: dict[str, int]
    part_nodes: dict[str, int]
    min_size: float
    max_size: float
    worst_aspect: float
    worst_jacobian_ratio: float
    min_char_length: float
    wave_speed: float
    critical_dt: float
    worst_element: int
    polygon_edges: dict[str, int] = field(default_factory=dict)
    part_max_size: dict[str, float] = field(default_factory=dict)
    part_min_char_length: dict[str, float] = field(default_factory=dict)
    resolved_frequency: dict[str, float] = field(default_factory=dict)
    elements_per_wavelength: float = ELEMENTS_PER_WAVELENGTH
    resolution_wave_speed: float = 0.0

    def summary(self) -> str:
        """A one-screen text summary."""
        lines = [
            f"mesh: {self.n_elements} elements, {self.n_nodes} nodes",
            f"{'part':<14}{'elements':>10}{'nodes':>10}",
        ]
        for label, names in _group_rollers(self.part_elements):
            ne = [self.part_elements[n] for n in names]
            nn = [self.part_nodes[n] for n in names]
            each = " each" if len(names) > 1 else ""
            lines.append(f"{label:<14}{_span(ne):>10}{_span(nn):>10}{each}")
        lines += [
            f"element size   {1e3 * self.min_size:.4g} .. {1e3 * self.max_size:.4g} mm "
            "(shortest edge .. longest edge)",
            f"worst aspect ratio {self.worst_aspect:.3g}, "
            f"worst Jacobian ratio {self.worst_jacobian_ratio:.3g}",
            f"smallest characteristic length {1e3 * self.min_char_length:.4g} mm "
            f"(element {self.worst_element}); wave speed {self.wave_speed:.5g} m/s",
            f"critical time step {1e9 * self.critical_dt:.4g} ns (solver uses 0.9 x)",
        ]
        if self.part_min_char_length:
            smallest = _per_part(self.part_min_char_length, 1e3)
            lines.append(f"smallest characteristic length per part (mm): {smallest}")
        if self.resolved_frequency:
            parts = _per_part(self.resolved_frequency, 1e-3)
            lines.append(
                f"resolves up to (kHz, {self.elements_per_wavelength:g} elements per "
                f"Rayleigh wavelength, c_R {self.resolution_wave_speed:.5g} m/s, longest "
                f"edge of each part): {parts}"
            )
        if self.polygon_edges:
            groups = _group_rollers(self.polygon_edges)
            edges = ", ".join(
                f"{label} {_span([self.polygon_edges[n] for n in names])}"
                for label, names in groups
            )
            lines.append(f"polygon edges per turn: {edges}")
        return "\n".join(lines)


def _group_rollers(per_part: dict[str, int]) -> list[tuple[str, list[str]]]:
    """Parts in order, with all ``roller<j>`` gathered into one ``rollers (Z)`` entry."""
    rollers = [k for k in per_part if k.startswith("roller") and k[6:].isdigit()]
    out = []
    for name in per_part:
        if name in rollers:
            if name == rollers[0]:
                out.append((f"rollers ({len(rollers)})", rollers))
        else:
            out.append((name, [name]))
    return out


def _per_part(per_part: dict[str, float], scale: float) -> str:
    """One value (or span of values, the rollers grouped) per part, times ``scale``."""
    return ", ".join(
        f"{label} {_span_scaled([per_part[n] for n in names], scale)}"
        for label, names in _group_rollers(per_part)
    )


def _span_scaled(values: list[float], scale: float) -> str:
    lo, hi = scale * min(values), scale * max(values)
    return f"{lo:.3g}" if f"{lo:.3g}" == f"{hi:.3g}" else f"{lo:.3g}-{hi:.3g}"


def _span(values: list[int]) -> str:
    lo, hi = min(values), max(values)
    return f"{lo}" if lo == hi else f"{lo}-{hi}"


def mesh_statistics(
    mesh: Mesh,
    youngs_modulus: float = 210e9,
    poissons_ratio: float = 0.3,
    density: float = 7850.0,
    wave_speed_m_s: float | None = None,
    elements_per_wavelength: float | None = None,
) -> MeshStatistics:
    """Counts per part, element sizes (the smallest characteristic length per part too),
    worst quality, the critical time step and the highest frequency each part resolves.

    Parameters
    ----------
    mesh : Mesh
    youngs_modulus, poissons_ratio, density : float
        Material, SI; used when ``wave_speed_m_s`` is not given.
    wave_speed_m_s : float, optional
        Dilatational wave speed to use directly.
    elements_per_wavelength : float, optional
        ``N`` of the resolution criterion (module notes); default the mesh's own
        (``mesh.info["sizes"]["elements_per_wavelength"]``, from the case) or
        :data:`ELEMENTS_PER_WAVELENGTH`.
    """
    c = wave_speed_m_s or wave_speed(youngs_modulus, poissons_ratio, density)
    if elements_per_wavelength is None:
        sizes = mesh.info.get("sizes", {})
        elements_per_wavelength = sizes.get("elements_per_wavelength", ELEMENTS_PER_WAVELENGTH)
    c_r = rayleigh_wave_speed(youngs_modulus, poissons_ratio, density)
    g = element_geometry(mesh.nodes, mesh.elements)
    worst = int(np.argmin(g["char_length"]))
    part_elements, part_nodes, part_size, part_length, resolved = {}, {}, {}, {}, {}
    for p, name in enumerate(mesh.part_names):
        in_part = mesh.element_part == p
        sel = mesh.elements[in_part]
        part_elements[name] = int(len(sel))
        part_nodes[name] = int(len(np.unique(sel)))
        if in_part.any():
            part_size[name] = float(g["max_edge"][in_part].max())
            part_length[name] = float(g["char_length"][in_part].min())
            resolved[name] = c_r / (elements_per_wavelength * part_size[name])
    polygon = {k: int(v) for k, v in mesh.info.get("polygon_edges", {}).items()}
    return MeshStatistics(
        n_nodes=mesh.n_nodes,
        n_elements=mesh.n_elements,
        part_elements=part_elements,
        part_nodes=part_nodes,
        min_size=float(g["min_edge"].min()),
        max_size=float(g["max_edge"].max()),
        worst_aspect=float((g["max_edge"] / g["min_edge"]).max()),
        worst_jacobian_ratio=float(g["jacobian_ratio"].min()),
        min_char_length=float(g["char_length"][worst]),
        wave_speed=float(c),
        critical_dt=float(g["char_length"][worst] / c),
        worst_element=worst,
        polygon_edges=polygon,
        part_max_size=part_size,
        part_min_char_length=part_length,
        resolved_frequency=resolved,
        elements_per_wavelength=float(elements_per_wavelength),
        resolution_wave_speed=c_r,
    )


def resolution_warning(statistics: Mapping, band_hz: float, what: str) -> str | None:
    """One line when ``band_hz`` lies above the highest frequency some part of the mesh
    resolves (``statistics``: :class:`MeshStatistics` as a dict, e.g. a run's
    ``mesh_statistics.json``); None when every part resolves it or the statistics say
    nothing of resolution. ``what`` names the band, e.g. ``"run.sample_rate_Hz / 2"``."""
    resolved = statistics.get("resolved_frequency") or {}
    below = {k: v for k, v in resolved.items() if v is not None and v < band_hz}
    if not below:
        return None
    part = min(below, key=below.get)
    size = (statistics.get("part_max_size") or {}).get(part)
    edge = f", its longest element {1e3 * size:.3g} mm" if size else ""
    others = f" (and {len(below) - 1} more parts)" if len(below) > 1 else ""
    return (
        f"mesh: the analysed band reaches {1e-3 * band_hz:.4g} kHz ({what}) but "
        f"{part}{others} resolves only {1e-3 * below[part]:.3g} kHz with "
        f"{statistics.get('elements_per_wavelength', ELEMENTS_PER_WAVELENGTH):g} elements "
        f"per Rayleigh wavelength{edge}: waves above it are too short for its elements "
        "(lower mesh.max_size_mm, or accept fewer mesh.elements_per_wavelength)"
    )
