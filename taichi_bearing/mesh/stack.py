"""Meshes stacked into one: the members of an ensemble, stepped by one model.

An ensemble steps several independent copies of a study (the same mesh topology; the
rollers at other start angles, other loads) in the same kernel launches. Its mesh holds
the members one after another, each with its own nodes and elements, and renames every
part, node set, surface and sensor ``m<k>:<name>`` (:func:`member_name`). Nothing joins
the members: they may overlap in space.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from taichi_bearing.mesh.types import Mesh

__all__ = ["member_layout", "member_name", "stack_meshes"]


def member_name(name: str, member: int) -> str:
    """The name of member ``member``'s part, node set, surface or sensor ``name``."""
    return f"m{member}:{name}"


def stack_meshes(meshes: Sequence[Mesh]) -> Mesh:
    """One mesh of the members ``meshes``, one after another.

    Parameters
    ----------
    meshes : sequence of Mesh
        The members: the same numbers of nodes and elements and the same parts, node
        sets, surfaces and sensors (their coordinates may differ).

    Returns
    -------
    Mesh
        Member ``k``'s nodes are ``k nn .. (k+1) nn - 1``, its elements likewise, in its
        own order; names as :func:`member_name` gives them; ``info`` is the first
        member's with ``"members"`` (the count) and ``"member_info"`` (each one's).

    Raises
    ------
    ValueError
        If the members differ in their counts or names.
    """
    if not meshes:
        raise ValueError("stack_meshes: no member")
    first = meshes[0]
    for k, m in enumerate(meshes[1:], 1):
        same = (
            m.n_nodes == first.n_nodes
            and m.n_elements == first.n_elements
            and m.part_names == first.part_names
            and m.node_sets.keys() == first.node_sets.keys()
            and m.surfaces.keys() == first.surfaces.keys()
            and m.sensor_nodes.keys() == first.sensor_nodes.keys()
        )
        if not same:
            raise ValueError(
                f"stack_meshes: member {k}'s mesh differs from member 0's in its node or "
                "element count or its names; an ensemble's members must share one mesh "
                "topology"
            )
    nn, n_parts = first.n_nodes, len(first.part_names)
    return Mesh(
        nodes=np.concatenate([np.asarray(m.nodes, dtype=float) for m in meshes]),
        elements=np.concatenate(
            [np.asarray(m.elements, dtype=np.int64) + k * nn for k, m in enumerate(meshes)]
        ),
        element_part=np.concatenate(
            [np.asarray(m.element_part, dtype=np.int64) + k * n_parts for k, m in enumerate(meshes)]
        ),
        part_names=[member_name(p, k) for k in range(len(meshes)) for p in first.part_names],
        node_sets={
            member_name(name, k): np.asarray(ids) + k * nn
            for k, m in enumerate(meshes)
            for name, ids in m.node_sets.items()
        },
        surfaces={
            member_name(name, k): np.asarray(seg) + k * nn
            for k, m in enumerate(meshes)
            for name, seg in m.surfaces.items()
        },
        sensor_nodes={
            member_name(name, k): int(i) + k * nn
            for k, m in enumerate(meshes)
            for name, i in m.sensor_nodes.items()
        },
        info={**first.info, "members": len(meshes), "member_info": [m.info for m in meshes]},
    )


def member_layout(mesh: Mesh, members: int) -> tuple[int, int, int]:
    """``(members, nodes per member, elements per member)`` of a stacked mesh.

    Raises
    ------
    ValueError
        If the counts do not divide, or an element joins two members.
    """
    members = int(members)
    if members < 1:
        raise ValueError(f"members must be at least 1, got {members!r}")
    nn, ne = mesh.n_nodes, mesh.n_elements
    if nn % members or ne % members:
        raise ValueError(f"{nn} nodes and {ne} elements do not split into {members} members")
    nn, ne = nn // members, ne // members
    if members > 1:
        own = np.repeat(np.arange(members), ne)[:, None]
        if np.any(np.asarray(mesh.elements) // nn != own):
            raise ValueError("an element joins nodes of two ensemble members")
    return members, nn, ne
