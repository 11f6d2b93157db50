"""Figures of the quasi-static model: load distribution, defect passage, edge zooms."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from bearing_io.files import atomic_path  # noqa: E402
from taichi_bearing.analytic.quasistatic import LoadDistribution, Spall  # noqa: E402

__all__ = [
    "plot_defect_passage",
    "plot_edge_zoom",
    "plot_inner_load_zone",
    "plot_load_distribution",
]

SPALL_COLOUR = "#f4c7a1"
PATCH_COLOUR = "#1f5fa8"
STEP_COLOUR = "#c0392b"


def _save(fig, path: Path) -> Path:
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=130, format="png")
    plt.close(fig)
    return Path(path)


def _profile_text(spall: Spall) -> str:
    """The walls and edges of a spall that is not the rectangular notch, for titles."""
    if spall.rectangular:
        return ""
    text = f", walls {np.degrees(spall.entry_slope):.3g}/{np.degrees(spall.exit_slope):.3g} deg"
    if spall.edge_radius > 0:
        text += f", edges rounded {spall.edge_radius * 1e3:.3g} mm"
    return text


def _bars(ax, dist: LoadDistribution, index: int, title: str) -> None:
    angles = np.degrees(dist.roller_angle[index])
    order = np.argsort(angles)
    angles = angles[order]
    fy = dist.outer_fy[index, order] / 1e3
    fx = dist.outer_fx[index, order] / 1e3
    width = 0.36 * 360.0 / dist.n_rollers
    ax.bar(angles - width / 2, fy, width, label="vertical (y)", color=PATCH_COLOUR)
    ax.bar(angles + width / 2, fx, width, label="horizontal (x)", color="#7fb3d5")
    ax.axhline(0.0, color="k", lw=0.6)
    total = dist.outer_fy[index].sum() / 1e3
    ax.set_title(f"{title}  (sum of vertical components {total:.3f} kN)", fontsize=10)
    ax.set_ylabel("force on outer ring, kN")
    ax.set_xticks(np.arange(-120, 121, 30))
    ax.grid(alpha=0.3)


def plot_load_distribution(
    healthy: LoadDistribution,
    defective: LoadDistribution,
    defect_index: int,
    spall: Spall | None,
    path: Path,
) -> Path:
    """Per-roller vertical and horizontal force components: healthy bearing (top) and with
    roller 0 in the spall (bottom)."""
    fig, axes = plt.subplots(2, 1, figsize=(9, 6.5), sharex=True, sharey=True)
    _bars(axes[0], healthy, 0, "healthy bearing, roller 0 at 12 o'clock")
    cage = np.degrees(defective.cage_angle[defect_index])
    _bars(axes[1], defective, defect_index, f"roller 0 in the spall (cage angle {cage:.2f} deg)")
    if spall is not None:
        axes[1].axvspan(
            np.degrees(spall.start),
            np.degrees(spall.end),
            color=SPALL_COLOUR,
            label="spall",
            zorder=0,
        )
    for ax in axes:
        ax.set_xlim(120, -120)  # as seen from the front: counter-clockwise (+) is left
        ax.legend(loc="upper right", fontsize=8)
    axes[1].set_xlabel("roller angle from 12 o'clock, deg (+ counter-clockwise, to the left)")
    fig.suptitle(
        f"Quasi-static load distribution, W = {healthy.load / 1e3:g} kN "
        "(forces of the rollers on the outer ring)",
        fontsize=11,
    )
    fig.tight_layout()
    return _save(fig, path)


def plot_defect_passage(
    patch: LoadDistribution,
    step: LoadDistribution,
    spall: Spall,
    path: Path,
    travel: np.ndarray | None = None,
) -> Path:
    """Contact force of roller 0 through the spall (patch model vs step model), with its
    neighbours (load compensation), and roller 0's force components.

    Against the cage angle; for an inner-race spall, which turns while roller 0 crosses
    it, against ``travel`` (rad: the spall's angle less roller 0's, -half at entry).
    """
    z = patch.n_rollers
    if travel is None:
        angle = np.degrees(patch.cage_angle)
        entry, exit_ = np.degrees(spall.entry), np.degrees(spall.exit)
        xlabel = "cage angle (angle of roller 0 from 12 o'clock), deg"
        force = "outer contact force, kN"
    else:
        angle = np.degrees(travel)
        entry, exit_ = -np.degrees(spall.half_angle), np.degrees(spall.half_angle)
        xlabel = (
            "travel of roller 0 over the inner-ring spall (spall angle - roller angle), deg; "
            f"spall centre at {np.degrees(patch.spall_angle[len(travel) // 2]):.3g} deg "
            "when roller 0 is on it"
        )
        force = "contact force (outer = inner), kN"
    fig, (ax, ax2) = plt.subplots(
        2, 1, figsize=(9, 7), sharex=True, gridspec_kw={"height_ratios": [2.2, 1]}
    )
    for a in (ax, ax2):
        a.axvspan(
            entry,
            exit_,
            color=SPALL_COLOUR,
            zorder=0,
            label="spall" if a is ax else None,
        )
        a.grid(alpha=0.3)
    ax.plot(
        angle,
        step.outer_force[:, 0] / 1e3,
        color=STEP_COLOUR,
        lw=1.2,
        ls="--",
        label="roller 0, step model (no contact width)",
    )
    ax.plot(
        angle,
        patch.outer_force[:, 0] / 1e3,
        color=PATCH_COLOUR,
        lw=2.0,
        label="roller 0, finite roller and contact width",
    )
    ax.plot(angle, patch.outer_force[:, 1] / 1e3, color="#27ae60", lw=1.0, label="roller 1 (ahead)")
    ax.plot(
        angle,
        patch.outer_force[:, z - 1] / 1e3,
        color="#8e44ad",
        lw=1.0,
        label=f"roller {z - 1} (behind)",
    )
    peak = patch.outer_force[:, 0].max() / 1e3
    y_text = 0.55 * peak
    for x, text, ha in (
        (entry, "1 de-stressing\n(entry)", "right"),
        (0.5 * (entry + exit_), "2 traverse\n3 load compensation", "center"),
        (exit_, "4 re-stressing\n(exit)", "left"),
    ):
        ax.annotate(
            text,
            (x, y_text),
            ha=ha,
            fontsize=8,
            xytext=(-6 if ha == "right" else 6 if ha == "left" else 0, 0),
            textcoords="offset points",
        )
    ax.set_ylabel(force)
    ax.set_ylim(bottom=0.0, top=1.35 * max(peak, patch.outer_force[:, 1].max() / 1e3))
    ax.legend(loc="upper left", fontsize=8, ncol=2)
    ax.set_title(
        f"Roller 0 through the {spall.race}-race spall "
        f"({2 * np.degrees(spall.half_angle):.2f} deg, "
        f"{spall.depth * 1e3:g} mm deep{_profile_text(spall)}), W = {patch.load / 1e3:g} kN",
        fontsize=11,
    )
    ax2.plot(angle, patch.outer_fy[:, 0] / 1e3, color=PATCH_COLOUR, label="roller 0, y")
    ax2.plot(angle, patch.outer_fx[:, 0] / 1e3, color="#7fb3d5", label="roller 0, x")
    ax2.plot(
        angle,
        patch.outer_fy.sum(axis=1) / 1e3 - patch.load / 1e3,
        color="k",
        lw=0.8,
        ls=":",
        label=f"sum of y over rollers - W (largest |.|: {patch.balance_error().max():.0e} W)",
    )
    ax2.set_ylabel("component, kN")
    ax2.set_xlabel(xlabel)
    ax2.legend(loc="upper left", fontsize=8, ncol=3)
    fig.tight_layout()
    return _save(fig, path)


def plot_edge_zoom(
    entry_patch: LoadDistribution,
    entry_step: LoadDistribution,
    exit_patch: LoadDistribution,
    exit_step: LoadDistribution,
    spall: Spall,
    outer_raceway_radius: float,
    half_width: float,
    path: Path,
    travels: tuple[np.ndarray, np.ndarray] | None = None,
) -> Path:
    """Force of roller 0 against its position relative to each spall edge (mm of arc).

    ``outer_raceway_radius``: the radius of the raceway with the spall. ``travels``: for
    an inner-race spall, roller 0's travel over it in each sweep (rad, see
    :func:`plot_defect_passage`), instead of the cage angle.
    """
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    if travels is None:
        at = (entry_patch.cage_angle, exit_patch.cage_angle)
        edges, lo, hi = (spall.entry, spall.exit), spall.entry, spall.exit
    else:
        at, half = travels, spall.half_angle
        edges, lo, hi = (-half, half), -half, half
    panels = (
        (axes[0], entry_patch, entry_step, edges[0], at[0], "entry edge: de-stressing"),
        (axes[1], exit_patch, exit_step, edges[1], at[1], "exit edge: re-stressing"),
    )
    for ax, patch, step, edge, x, title in panels:
        s = (x - edge) * outer_raceway_radius * 1e3
        inside = (x > lo) & (x < hi)
        ax.fill_between(
            s,
            0,
            1,
            where=inside,
            color=SPALL_COLOUR,
            alpha=0.9,
            transform=ax.get_xaxis_transform(),
            label="spall",
            step="mid",
        )
        ax.axvspan(
            -half_width * 1e3,
            half_width * 1e3,
            color="0.85",
            zorder=0,
            label="edge within the patch (+-b)",
        )
        ax.plot(
            s, step.outer_force[:, 0] / 1e3, color=STEP_COLOUR, ls="--", lw=1.2, label="step model"
        )
        ax.plot(
            s,
            patch.outer_force[:, 0] / 1e3,
            color=PATCH_COLOUR,
            lw=2.0,
            label="finite roller + contact width",
        )
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("contact point position relative to the edge, mm of arc")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("roller 0 outer contact force, kN")
    axes[0].set_ylim(bottom=0.0)
    axes[0].legend(loc="lower left", fontsize=8)
    fig.suptitle(
        f"Edges of the spall (healthy half-width b = {half_width * 1e3:.3f} mm)", fontsize=11
    )
    fig.tight_layout()
    return _save(fig, path)


def plot_inner_load_zone(
    angles: np.ndarray,
    load: np.ndarray,
    passages: list[tuple[float, np.ndarray, np.ndarray]],
    spall: Spall,
    path: Path,
) -> Path:
    """The load an inner-race spall meets as it turns (top), and roller 0 passing over
    it at given spall angles (bottom).

    ``passages``: (spall angle at mid-passage, rad; travel, rad; roller 0's inner force,
    N) for each.
    """
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 7))
    top.plot(np.degrees(angles), load / 1e3, color=PATCH_COLOUR, lw=1.5)
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, max(len(passages), 1)))
    for (at, _, _), colour in zip(passages, colours, strict=False):
        top.axvline(np.degrees(at), color=colour, ls="--", lw=1.0)
    top.set_xlim(180, -180)  # as seen from the front: counter-clockwise (+) is left
    top.set_xlabel("spall angle from 12 o'clock, deg (+ counter-clockwise, to the left)")
    top.set_ylabel("load of the roller at it, kN")
    top.set_title(
        "Load an inner-race spall meets as it turns with the shaft (healthy rigid-ring "
        "load zone; dashed: the passages below)",
        fontsize=10,
    )
    top.grid(alpha=0.3)
    half = np.degrees(spall.half_angle)
    bottom.axvspan(-half, half, color=SPALL_COLOUR, zorder=0, label="spall")
    for (at, travel, force), colour in zip(passages, colours, strict=False):
        bottom.plot(
            np.degrees(travel), force / 1e3, color=colour, lw=1.5,
            label=f"spall at {np.degrees(at):.3g} deg",
        )  # fmt: skip
    bottom.set_xlabel("travel of roller 0 over the spall (spall angle - roller angle), deg")
    bottom.set_ylabel("roller 0 inner contact force, kN")
    bottom.set_ylim(bottom=0.0)
    bottom.legend(fontsize=8)
    bottom.grid(alpha=0.3)
    fig.tight_layout()
    return _save(fig, path)
