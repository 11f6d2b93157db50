"""A disk on a block: resultants and passes, and friction against rigid-body answers (a
pushed disk rolls without slip when friction suffices and slides when it does not; a
spinning disk set down slides, then rolls at the speed angular momentum gives)."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np
import pytest
import taichi as ti

from taichi_bearing.case.material import Material
from taichi_bearing.mesh.bodies import merge_meshes
from taichi_bearing.mesh.primitives import disk_mesh, rectangle_mesh
from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.contact import ContactPair, ContactParameters, PenaltyContact
from taichi_bearing.solver.contact_search import SCAN_BLOCK
from taichi_bearing.solver.contributor import ForceContributor, add_force
from taichi_bearing.solver.loads import FixedNodes, uniform_load
from taichi_bearing.solver.model import Model
from taichi_bearing.solver.model_setup import rigid_velocity_field
from taichi_bearing.solver.relaxation import relax

STEEL = Material(210e9, 0.3, 7850.0)
R = 0.01
G = 5000.0  # normal load per unit mass, m/s^2 (short runs), spinning disk
G_PUSH = 1000.0  # the same for the pushed disk (it turns less in the run)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


@ti.data_oriented
class Push(ForceContributor):
    """Test contributor: a constant force split equally over some nodes (from Python)."""

    in_kernel = False

    def __init__(self, nodes: np.ndarray, force: tuple[float, float]) -> None:
        self.nodes = ti.field(ti.i32, shape=len(nodes))
        self.nodes.from_numpy(nodes.astype(np.int32))
        self.f = np.asarray(force) / len(nodes)

    @ti.kernel
    def _add(self, f: ti.template(), fx: ti.f64, fy: ti.f64):
        for k in self.nodes:
            add_force(f, self.nodes[k], ti.Vector([fx, fy]))

    def add_forces(self, model: Model, t: float) -> None:
        self._add(model.f_extra, self.f[0], self.f[1])


def disk_on_block(
    params: ContactParameters, g: float = G, swap: bool = False, two_pass: bool = True
):
    """A disk resting on a fixed block under a normal load m G (equal nodal shares, so
    the resultant passes through the centre), relaxed to rest."""
    disk = disk_mesh(R, 48)
    disk.nodes = disk.nodes + np.array([0.0005, R])  # its lowest vertex mid-segment
    block = rectangle_mesh(0.06, 0.01, 60, 10, origin=(-0.03, -0.01))
    mesh = merge_meshes({"disk": disk, "block": block})
    disk_ids = np.unique(mesh.elements[mesh.element_part == mesh.part_id("disk")])
    mass = Model(mesh, STEEL).mass_np  # lumped masses (a throwaway model)
    m = mass[disk_ids].sum()
    model = Model(
        mesh,
        STEEL,
        constraints=[FixedNodes(mesh.node_sets["block.bottom"])],
        loads=[uniform_load(disk_ids, (0.0, -m * g))],
    )
    pair = (
        ContactPair("disk_block", "block.top", "disk.outer", two_pass)
        if swap
        else ContactPair("disk_block", "disk.outer", "block.top", two_pass)
    )
    contact = PenaltyContact(model, [pair], params)
    model.add_contributor(contact)
    assert relax(model, ke_ratio_tol=1e-8, max_steps=60_000).converged
    contact.reset_dissipation()
    return model, contact, disk_ids


def rigid_motion(model: Model, ids: np.ndarray) -> tuple[np.ndarray, float, float, float]:
    """Centre velocity, spin, mass and polar inertia of a body from its nodes."""
    m = model.mass_np[ids]
    x, v = model.positions()[ids], model.velocities()[ids]
    c = (m[:, None] * x).sum(0) / m.sum()
    vc = (m[:, None] * v).sum(0) / m.sum()
    r, w = x - c, v - vc
    inertia = (m * (r**2).sum(1)).sum()
    omega = (m * (r[:, 0] * w[:, 1] - r[:, 1] * w[:, 0])).sum() / inertia
    return vc, omega, m.sum(), inertia


def trace(model: Model, ids: np.ndarray, n_steps: int, every: int = 25) -> np.ndarray:
    """Run and record (t, centre x, rotation angle) of a body every ``every`` steps.

    Positions (not the leapfrog velocities) average out the body's vibration on the
    contact springs, which a rigid-body answer does not have.
    """
    m = model.mass_np[ids]
    x0 = model.positions()[ids]
    c0 = (m[:, None] * x0).sum(0) / m.sum()
    r0 = x0 - c0
    rows = []
    for _ in range(n_steps // every):
        model.advance(every)
        x = model.positions()[ids]
        c = (m[:, None] * x).sum(0) / m.sum()
        r = x - c
        cross = (m * (r0[:, 0] * r[:, 1] - r0[:, 1] * r[:, 0])).sum()
        dot = (m * (r0 * r).sum(1)).sum()
        rows.append((model.time, c[0] - c0[0], np.arctan2(cross, dot)))
    return np.array(rows)


@pytest.mark.slow  # ~40 s; friction's stick-slip is also checked by the spinning disk
def test_pushed_disk_rolls_when_friction_suffices_and_slides_when_not():
    mu_s, mu_d = 0.3, 0.2
    params = ContactParameters(
        friction_static=mu_s, friction_dynamic=mu_d, friction_decay=100.0, damping_ratio=0.2
    )
    for fraction, rolls in ((0.5, True), (2.0, False)):
        model, contact, ids = disk_on_block(params, G_PUSH)
        _, _, m, inertia = rigid_motion(model, ids)
        n_load = m * G_PUSH
        # Rolling needs friction F I / (I + m R^2); it is available up to mu_s N.
        f_crit = mu_s * n_load * (1.0 + m * R**2 / inertia)
        force = fraction * f_crit
        model.add_contributor(Push(ids, (force, 0.0)))
        # Short: the polygonal disk must turn by much less than mu radians, or the normal
        # force, off-centre under a vertex rocking off the bottom, adds a moment.
        t, xc, theta = trace(model, ids, 2400).T
        # Constant accelerations after the start, where the tangential spring loads up
        # (a rigid body would see the friction force at once): quadratic fits.
        late = t > t[-1] / 4
        a = 2.0 * np.polyfit(t[late], xc[late], 2)[0]
        alpha = 2.0 * np.polyfit(t[late], theta[late], 2)[0]
        if rolls:
            a_expected = force / (m + inertia / R**2)
            alpha_expected = -a_expected / R
        else:
            a_expected = (force - mu_d * n_load) / m
            alpha_expected = -mu_d * n_load * R / inertia
        # Slip: distance the contact point slid over the block, against the distance rolled.
        # Rolling leaves only the elastic (stick) shear of the contact, which stays bounded.
        slip = (xc[-1] + theta[-1] * R) / xc[-1]
        print(
            f"F/F_crit={fraction}: a {a / a_expected - 1:+.4f}, "
            f"alpha {alpha / alpha_expected - 1:+.4f}, slip {slip:+.4f}"
        )
        assert a == pytest.approx(a_expected, rel=0.03)
        assert alpha == pytest.approx(alpha_expected, rel=0.03)
        if rolls:
            assert abs(slip) < 0.02
        else:
            assert slip > 0.3
        e = contact.energies()
        assert e["friction"] >= 0.0 and e["damping"] >= 0.0


def test_spinning_disk_slides_then_rolls_at_the_rigid_body_speed():
    mu = 0.3
    params = ContactParameters(friction_static=mu, friction_dynamic=mu, damping_ratio=0.2)
    model, contact, ids = disk_on_block(params)
    _, _, m, inertia = rigid_motion(model, ids)
    # Counter-clockwise: it will roll towards -x. Slow enough that the polygonal disk
    # turns by far less than a facet while it slides (a vertex rocking off the bottom
    # would add a moment of the normal force).
    omega0 = 30.0
    x = model.positions()
    c = x[ids].mean(0)
    v = np.zeros_like(x)
    r = x[ids] - c
    v[ids] = omega0 * np.stack([-r[:, 1], r[:, 0]], axis=1)
    model.set_state(v=v)
    # Angular momentum about the contact point is conserved: I w0 = m v R + I w, v = -w R.
    v_final = -inertia * omega0 * R / (inertia + m * R**2)
    t_roll = abs(v_final) / (mu * G)
    t, xc, theta = trace(model, ids, int(5.0 * t_roll / model.dt)).T
    slide = t < 0.8 * t_roll
    a = 2.0 * (xc[slide] @ t[slide] ** 2) / (t[slide] ** 2 @ t[slide] ** 2)
    roll = t > 1.5 * t_roll
    v_end = np.polyfit(t[roll], xc[roll], 1)[0]
    # Slip speed over rolling speed while rolling: the slid distance (see the test above)
    # only oscillates with the elastic shear of the contact.
    slip = np.polyfit(t[roll], (xc + theta * R)[roll], 1)[0] / v_end
    print(
        f"sliding: a {a / (-mu * G) - 1:+.4f}; "
        f"rolling: v {v_end / v_final - 1:+.4f}, slip {slip:+.4f}"
    )
    assert a == pytest.approx(-mu * G, rel=0.03)
    assert v_end == pytest.approx(v_final, rel=0.03)
    assert abs(slip) < 0.02
    # Friction dissipated the rigid-body kinetic energy lost (elastic waves take a little).
    lost = 0.5 * inertia * omega0**2 - 0.5 * (m + inertia / R**2) * v_final**2
    e = contact.energies()
    print(f"friction dissipation / rigid KE lost {e['friction'] / lost:.4f}")
    assert e["friction"] == pytest.approx(lost, rel=0.1)


def test_resting_disk_resultants_obey_newton_and_both_passes_agree():
    frictionless = ContactParameters()
    results = {}
    soft = ContactParameters(penalty_method="soft")
    cases = ((False, True, frictionless), (True, True, frictionless), (False, False, soft))
    for swap, two_pass, params in cases:
        model, contact, ids = disk_on_block(params, swap=swap, two_pass=two_pass)
        model.advance(1)
        m = model.mass_np[ids].sum()
        f = contact.nodal_forces()
        block = np.setdiff1d(np.arange(model.n_nodes), ids)
        fx, fy, fn, ft = contact.current_resultants()[0]
        # Third law: contact forces sum to zero; the resultant is the force on the master.
        assert np.abs(f.sum(0)).max() < 1e-9 * m * G
        on_master = f[ids].sum(0) if swap else f[block].sum(0)
        assert np.allclose([fx, fy], on_master, rtol=1e-9, atol=1e-9 * m * G)
        # At rest the contact carries the load, normal to the block.
        down = -1.0 if not swap else 1.0  # by the disk on the block: downwards
        assert down * fy == pytest.approx(m * G, rel=0.01)
        assert fn == pytest.approx(m * G, rel=0.01)
        assert abs(fx) < 1e-3 * m * G and abs(ft) < 1e-3 * m * G
        # Penetration no deeper than the largest nodal force over the smallest stiffness.
        state = contact.contact_state()
        k_min = contact.seg_k.to_numpy()[: contact.n_seg].min()
        if params.penalty_method == "soft":  # f_s m_eff / dt^2, m_eff >= half the lightest
            k_min = params.penalty_scale * 0.5 * model.mass_np.min() / model.dt**2
        assert 0 < -state["gap"].min() <= np.abs(f).max() / k_min
        results[(swap, two_pass)] = (fx, fy, fn)
    # Slave and master swapped: the same contact seen from the other body.
    one, other = results[(False, True)], results[(True, True)]
    assert -other[1] == pytest.approx(one[1], rel=1e-3)
    assert other[2] == pytest.approx(one[2], rel=1e-3)


def thrown_disk(
    params: ContactParameters, velocity: tuple[float, float], omega: float = 0.0
) -> tuple[Model, PenaltyContact, np.ndarray]:
    """A disk just above the block (its lowest vertex mid-segment), moving at
    ``velocity`` and spinning at ``omega`` about its centre; the block's bottom fixed."""
    disk = disk_mesh(R, 48)
    disk.nodes = disk.nodes + np.array([0.0005, R + 1e-6])
    block = rectangle_mesh(0.06, 0.01, 60, 10, origin=(-0.03, -0.01))
    mesh = merge_meshes({"disk": disk, "block": block})
    ids = np.unique(mesh.elements[mesh.element_part == mesh.part_id("disk")])
    model = Model(mesh, STEEL, constraints=[FixedNodes(mesh.node_sets["block.bottom"])])
    contact = PenaltyContact(model, [ContactPair("c", "disk.outer", "block.top")], params)
    model.add_contributor(contact)
    X = model.positions()
    v = np.zeros((model.n_nodes, 2))
    v[ids] = rigid_velocity_field(X[ids], omega, X[ids].mean(0), velocity)
    model.set_state(v=v)
    model.restart_accounting()
    return model, contact, ids


# ~30 s; every run's energy_balance check (test_run_coarse) covers the contact's work in CI
@pytest.mark.slow
def test_bouncing_disk_keeps_the_energy_balance():
    """A disk thrown onto the block: kinetic + strain + stored penalty energy + what the
    contact dissipated stays equal to the initial kinetic energy (elastic impact, and an
    impact with contact damping)."""
    for zeta in (0.0, 0.5):
        model, contact, ids = thrown_disk(ContactParameters(damping_ratio=zeta), (0.0, -1.0))
        model.restart_accounting()
        ke0 = 0.5 * model.mass_np[ids].sum()
        worst, touched = 0.0, False
        for _ in range(30):
            model.advance(50, record_last=True)
            e, c = model.energies(), contact.energies()
            total = e["kinetic"] + e["internal"] + e["hourglass"] + c["elastic"] + c["damping"]
            worst = max(worst, abs(total / ke0 - 1))
            touched |= c["elastic"] > 0
        print(
            f"zeta {zeta}: worst energy balance error {worst:.2e}, damped {c['damping'] / ke0:.3f}"
        )
        assert touched
        assert worst < 0.02
        if zeta > 0:
            assert c["damping"] > 0.01 * ke0


@pytest.mark.slow  # ~45 s; the runs' bit-identity across modes covers the active list too
def test_active_query_list_skips_far_nodes_and_changes_nothing():
    """A spinning disk thrown onto the block bounces and rolls. Listing only the queries
    within reach of a paired segment at each grid build (most of the disk's rim and of
    the block's top are far from the contact) must give the same motion and contact
    forces as visiting every query."""

    def throw(visit_all: bool):
        params = ContactParameters(friction_static=0.3, friction_dynamic=0.2)
        model, contact, _ = thrown_disk(params, (2.0, -1.0), omega=-300.0)
        if visit_all:

            def every_query(x):
                contact.q_active.from_numpy(np.arange(contact.n_query, dtype=np.int32))
                contact.status[1] = contact.n_query

            contact._k_activate = every_query
        listed, fn = [], []
        for _ in range(40):
            model.advance(50)
            listed.append(contact.n_active)
            fn.append(contact.contact_state()["fn"].sum())
        return model.positions(), np.array(fn), np.array(listed), contact.n_query, contact

    x_list, fn_list, listed, n_query, contact = throw(False)
    x_all, fn_all, _, _, _ = throw(True)
    print(f"queries listed {listed.min()}-{listed.max()} of {n_query}; rebuilds {contact.rebuilds}")
    assert fn_list.max() > 0  # it touched
    assert contact.rebuilds > 5  # the list was made again as the disk moved
    assert listed.max() < 0.3 * n_query
    scale = np.abs(fn_all).max()
    np.testing.assert_allclose(fn_list, fn_all, rtol=0, atol=1e-9 * scale)
    np.testing.assert_allclose(x_list, x_all, rtol=0, atol=1e-12)


def test_grid_starts_and_active_list_follow_their_counts():
    """The grid's cell starts (running totals of the cells' counts, by blocks of
    SCAN_BLOCK cells) end where the filling of each cell ended, and the active list holds
    exactly the queries flagged near, in query order, at every rebuild as the disk moves."""
    params = ContactParameters(friction_static=0.3, friction_dynamic=0.2)
    model, contact, _ = thrown_disk(params, (2.0, -1.0), omega=-300.0)
    assert contact._nx * contact._ny > SCAN_BLOCK  # several blocks of cells
    checked = set()
    for _ in range(40):
        model.advance(50)
        if contact.rebuilds in checked:
            continue
        checked.add(contact.rebuilds)
        start = contact.cell_start.to_numpy()
        assert start[0] == 0 and (np.diff(start) >= 0).all()
        np.testing.assert_array_equal(contact.cell_fill.to_numpy(), start[1:])
        near = contact.q_near.to_numpy()[: contact.n_query]
        n = contact.n_active
        assert n == near.sum()
        np.testing.assert_array_equal(contact.q_active.to_numpy()[:n], np.flatnonzero(near))
    assert len(checked) > 5
