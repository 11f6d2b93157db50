"""Penalty contact against Hertz: a cylinder pressed onto a flat block in plane strain."""

# No `from __future__ import annotations`: Taichi reads kernel annotations at definition.

import numpy as np
import pytest

from taichi_bearing.solver.backend import init_taichi
from taichi_bearing.solver.contact import ContactParameters
from taichi_bearing.validation.hertz_static import (
    B_TARGET,
    E_STAR,
    P,
    R,
    pressed_cylinder,
    pressure_profile,
)


@pytest.fixture(scope="module", autouse=True)
def taichi_cpu():
    init_taichi("cpu")


def test_cylinder_on_block_matches_hertz():
    # The penalty adds stiffness of the order of the elements': a shorter step keeps it
    # stable (the element step does not count the contact's springs).
    params = ContactParameters(penalty_scale=1.0)
    mesh, model, contact, _ = pressed_cylinder(B_TARGET / 10, params, dt_factor=0.5)
    x, fy, p, _ = pressure_profile(mesh, contact)
    # The elliptic Hertz pressure has second moment b^2 / 4 about its centre.
    b = 2.0 * np.sqrt((x**2 * fy).sum() / fy.sum())
    b_hertz = np.sqrt(4 * P * R / (np.pi * E_STAR))
    p_hertz = 2 * P / (np.pi * b_hertz)
    err_b = b / b_hertz - 1
    err_p = p.max() / p_hertz - 1
    print(f"half-width error {err_b:+.4f}, peak pressure error {err_p:+.4f}")
    assert abs(err_b) < 0.05
    assert abs(err_p) < 0.05
    # Force balance: the contact carries the load, on the block and as the pair resultant.
    fx, fy_pair, fn, _ = contact.current_resultants()[0]
    print(f"force balance error {fy.sum() / P - 1:+.2e}, resultant {-fy_pair / P - 1:+.2e}")
    assert fy.sum() == pytest.approx(P, rel=0.01)
    assert -fy_pair == pytest.approx(P, rel=0.01)  # by the cap on the block: downwards
    assert fn == pytest.approx(P, rel=0.01)
    assert abs(fx) < 1e-3 * P
    # No penetration beyond the penalty estimate: peak nodal force over the two-pass
    # stiffness (both passes push; the smaller segment stiffness bounds the gap).
    gap = contact.contact_state()["gap"]
    k_min = contact.seg_k.to_numpy()[: contact.n_seg].min()
    assert -gap.min() <= fy.max() / k_min
