"""An ensemble's members step exactly as their cases alone: four members of the coarse
case (rollers at another start angle, another load, both; on a 2 mm mesh) stepped as one
model give, in every stepping mode, the positions, velocities, energies, contact
resultants and cage states of the four cases' own models, bit for bit; and a member held
still does not move while the others relax on. The cases alone step in serial mode only:
a model's modes give it the same bits (test_solver_team), and each model compiles its
kernels anew for each mode it steps in, the cost of this module."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from ensemble_cases import base_case, vary

from taichi_bearing.errors import InputError
from taichi_bearing.mesh.stack import stack_meshes
from taichi_bearing.simulation.ensemble import build_ensemble_model, check_members
from taichi_bearing.simulation.simulate import build_model, stage_mesh
from taichi_bearing.solver.backend import current_threads, init_taichi

RELAX_C = 2000.0  # 1/s: a fixed relaxation damping (the members' own are tested apart)


def member_cases():
    base = base_case()
    return [
        vary(base), vary(base, angle_deg=0.7), vary(base, load=1.3),
        vary(base, angle_deg=-0.4, load=0.8),
    ]  # fmt: skip


@pytest.fixture(scope="module")
def models():
    init_taichi("cpu")
    cases = member_cases()
    meshes = [stage_mesh(c)[0] for c in cases]
    singles = [build_model(c, m, "cpu") for c, m in zip(cases, meshes, strict=True)]
    ens = build_ensemble_model(cases, meshes, "cpu")
    # one step for all (the run fits it to the sample interval, the same for all)
    dt = min([b.model.dt_stable for b in singles] + [ens.model.dt_stable])
    for m in [b.model for b in singles] + [ens.model]:
        m.set_dt(dt)
    return singles, ens


def saved(model) -> list[dict]:
    """The model's and its contributors' (contact, cage, ...) state, to start again from."""
    return [model.state_arrays()] + [c.state_arrays() for c in model.contributors]


def restore(model, state: list[dict]) -> None:
    model.load_state_arrays(state[0])
    for c, arrays in zip(model.contributors, state[1:], strict=True):
        c.load_state_arrays(arrays)


def relax_then_roll(built, mode: str):
    """Relax from the mesh at rest (3 x 40 steps at a fixed damping), then roll (3 x 60
    steps from the rigid-body velocities); yields after each phase."""
    model = built.model
    model.restart_accounting()
    model.set_state(x=np.asarray(model.mesh.nodes, dtype=float), v=model.velocities() * 0.0)
    for relax in (True, False):
        if not relax:
            model.set_initial_velocities()
        for _ in range(3):
            model.advance(40 if relax else 60, record_last=True, mode=mode,
                          relax_damping=RELAX_C if relax else None)  # fmt: skip
        yield


def snapshot(built) -> dict:
    return {
        "x": built.model.positions(),
        "v": built.model.velocities(),
        "energies": built.model.energies(),
        "pairs": built.contact.current_resultants(),
        "cage": built.cage.state.to_numpy(),
        "contact_energy": built.contact.energy(),
    }


@pytest.fixture(scope="module")
def alone(models):
    """Each case's own model relaxed and rolled in serial stepping (one launch a phase
    item; the other modes give a model the same bits, test_solver_team): a snapshot after
    each phase. The ensemble starts every mode from its state before this."""
    singles, ens = models
    start = saved(ens.model)
    per_phase = [[snapshot(b) for _ in relax_then_roll(b, "serial")] for b in singles]
    return start, list(zip(*per_phase, strict=True))


def assert_members_match(ens, singles: list[dict]) -> None:
    nn = ens.model.member_nodes
    x, v = ens.model.positions(), ens.model.velocities()
    energies = ens.model.member_energies()
    pairs = ens.contact.current_resultants()
    n_pairs = len(singles[0]["pairs"])
    cage = ens.cage.state.to_numpy()
    contact_e = ens.contact.member_energies()
    for k, single in enumerate(singles):
        part = slice(k * nn, (k + 1) * nn)
        np.testing.assert_array_equal(x[part], single["x"])
        np.testing.assert_array_equal(v[part], single["v"])
        assert energies[k] == single["energies"]
        np.testing.assert_array_equal(pairs[k * n_pairs : (k + 1) * n_pairs], single["pairs"])
        np.testing.assert_array_equal(cage[2 * k : 2 * k + 2], single["cage"])
        assert contact_e[k] == single["contact_energy"]


MODES = ["serial", "team", "parallel"]


@pytest.mark.parametrize("mode", MODES)
def test_members_relax_and_roll_as_their_cases_alone(models, alone, mode):
    _, ens = models
    if mode == "team" and current_threads() < 2:
        pytest.skip("team stepping needs two CPU threads")
    start, phases = alone
    restore(ens.model, start)
    for _, singles in zip(relax_then_roll(ens, mode), phases, strict=True):
        assert_members_match(ens, singles)
    assert np.abs(ens.contact.current_resultants()).max() > 0  # the rollers touch
    # the members do differ: the cases are not the same
    nn = ens.model.member_nodes
    x = ens.model.positions()
    assert not np.array_equal(x[:nn], x[2 * nn : 3 * nn])


def test_a_member_held_still_does_not_move(models):
    _, ens = models
    model = ens.model
    model.restart_accounting()
    model.set_initial_velocities()
    model.set_members_active([True, False, True, True])
    nn = model.member_nodes
    x0, v0 = model.positions()[nn : 2 * nn], model.velocities()[nn : 2 * nn]
    cage0 = ens.cage.state.to_numpy()[2:4]
    model.advance(50, record_last=True)
    np.testing.assert_array_equal(model.positions()[nn : 2 * nn], x0)
    np.testing.assert_array_equal(model.velocities()[nn : 2 * nn], v0)
    np.testing.assert_array_equal(ens.cage.state.to_numpy()[2:4], cage0)
    assert not np.array_equal(model.positions()[:nn], model.positions()[nn : 2 * nn])
    model.set_members_active([True] * 4)


def test_members_that_cannot_share_a_model_are_refused():
    cases = member_cases()
    other = dataclasses.replace(
        cases[1], material=dataclasses.replace(cases[1].material, density=7000.0)
    )
    with pytest.raises(InputError, match="material.*members 0 and 1 differ"):
        check_members([cases[0], other])
    meshes = [stage_mesh(c)[0] for c in cases[:1]]
    coarser = dataclasses.replace(cases[0], mesh=dataclasses.replace(cases[0].mesh, max_size=0.012))
    with pytest.raises(ValueError, match="share one mesh topology"):
        stack_meshes([meshes[0], stage_mesh(coarser)[0]])
