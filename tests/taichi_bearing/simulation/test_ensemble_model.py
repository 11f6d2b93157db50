"""An ensemble's members step exactly as their cases alone: four members of the coarse
case (rollers at another start angle, another load, both) stepped as one model give, in
every stepping mode, the positions, velocities, energies, contact resultants and cage
states of the four cases' own models, bit for bit; and a member held still does not
move while the others relax on."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from taichi_bearing.case import load_case
from taichi_bearing.errors import InputError
from taichi_bearing.mesh.stack import stack_meshes
from taichi_bearing.simulation.ensemble import build_ensemble_model, check_members
from taichi_bearing.simulation.simulate import build_model, stage_mesh
from taichi_bearing.solver.backend import current_threads, init_taichi

COARSE = "cases/validation/coarse_spall.yaml"
RELAX_C = 2000.0  # 1/s: a fixed relaxation damping (the members' own are tested apart)


def member_cases():
    base = load_case(COARSE)

    def vary(angle_deg: float = 0.0, load: float = 1.0):
        run = dataclasses.replace(
            base.run, first_roller_angle=base.run.first_roller_angle + math.radians(angle_deg)
        )
        op = dataclasses.replace(base.operating, load=base.operating.load * load)
        return dataclasses.replace(base, run=run, operating=op)

    return [vary(), vary(angle_deg=0.7), vary(load=1.3), vary(angle_deg=-0.4, load=0.8)]


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


def step_all(singles, ens, mode: str, relax: bool, chunks: int, steps: int) -> None:
    for b in singles:
        for _ in range(chunks):
            b.model.advance(steps, record_last=True, mode=mode,
                            relax_damping=RELAX_C if relax else None)  # fmt: skip
    for _ in range(chunks):
        ens.model.advance(steps, record_last=True, mode=mode,
                          relax_damping=RELAX_C if relax else None)  # fmt: skip


def assert_members_match(singles, ens) -> None:
    nn = ens.model.member_nodes
    x, v = ens.model.positions(), ens.model.velocities()
    energies = ens.model.member_energies()
    pairs = ens.contact.current_resultants()
    n_pairs = len(singles[0].contact.pairs)
    cage = ens.cage.state.to_numpy()
    contact_e = ens.contact.member_energies()
    for k, b in enumerate(singles):
        part = slice(k * nn, (k + 1) * nn)
        np.testing.assert_array_equal(x[part], b.model.positions())
        np.testing.assert_array_equal(v[part], b.model.velocities())
        assert energies[k] == b.model.energies()
        np.testing.assert_array_equal(
            pairs[k * n_pairs : (k + 1) * n_pairs], b.contact.current_resultants()
        )
        np.testing.assert_array_equal(cage[2 * k : 2 * k + 2], b.cage.state.to_numpy())
        assert contact_e[k] == b.contact.energy()


MODES = ["serial", "team", "parallel"]


@pytest.mark.parametrize("mode", MODES)
def test_members_relax_and_roll_as_their_cases_alone(models, mode):
    singles, ens = models
    if mode == "team" and current_threads() < 2:
        pytest.skip("team stepping needs two CPU threads")
    for m in [b.model for b in singles] + [ens.model]:
        m.restart_accounting()
        m.set_state(x=np.asarray(m.mesh.nodes, dtype=float), v=m.velocities() * 0.0)
    step_all(singles, ens, mode, relax=True, chunks=3, steps=40)
    assert_members_match(singles, ens)
    for m in [b.model for b in singles] + [ens.model]:
        m.set_initial_velocities()
    step_all(singles, ens, mode, relax=False, chunks=3, steps=60)
    assert_members_match(singles, ens)
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
    coarser = dataclasses.replace(cases[0], mesh=dataclasses.replace(cases[0].mesh, max_size=0.008))
    with pytest.raises(ValueError, match="share one mesh topology"):
        stack_meshes([meshes[0], stage_mesh(coarser)[0]])
