"""The static contact study's rows and tables (no model is built here: the preload it
reads is tested in the solver and simulation tests, the study's numbers are in
docs/results/contact_convergence/)."""

import math

import pytest

from taichi_bearing.studies.static_contact import failed_row, level_row, main, markdown_tables


def preload_of(q_max: float, b: float, p0: float, b_hertz: float, p_hertz: float) -> dict:
    return {
        "steps": 1000,
        "outer_force_N": [0.5 * q_max, q_max, 0.2 * q_max],
        "mass_scaling": {"nodes": 10, "dt_s": 2e-8},
        "contact_patch": {
            "half_width_m": b,
            "peak_pressure_Pa": p0,
            "hertz_half_width_m": b_hertz,
            "hertz_peak_pressure_Pa": p_hertz,
        },
    }


def test_a_row_holds_the_largest_force_and_the_errors_against_hertz():
    row = level_row(30.0, 0.125, preload_of(15e3, 0.21e-3, 0.9e9, 0.2e-3, 1.0e9), {"elements": 5})
    assert row["q_max_N"] == 15e3
    assert row["half_width_mm"] == pytest.approx(0.21)
    assert row["half_width_error"] == pytest.approx(0.05)
    assert row["peak_pressure_error"] == pytest.approx(-0.1)
    assert row["relax_dt_ns"] == pytest.approx(20.0)


def test_the_table_gives_order_and_richardson_of_a_second_order_sequence():
    """Values 1 + 3 h^2 at h = 0.4, 0.2, 0.1: order 2, Richardson's estimate 1; the
    change between the two finest levels (-8.3 %) is over the 2 % static limit."""
    rows = []
    for h in (0.4, 0.2, 0.1):
        f = 1.0 + 3.0 * h**2
        pre = preload_of(1e4 * f, 0.2e-3 * f, 1e9 / f, 0.2e-3, 1e9)
        rows.append(level_row(10.0, h, pre, {"elements": 1, "transient_dt_ns": 1.0}))
    table = markdown_tables(rows, "mesh.surface_size_mm")
    q_line = next(line for line in table.splitlines() if line.startswith("| Q_max"))
    cells = [c.strip() for c in q_line.split("|")]
    assert float(cells[3]) == pytest.approx(2.0, rel=1e-3)
    assert float(cells[4]) == pytest.approx(1e4, rel=1e-3)
    assert "not converged" in cells[5]
    assert math.isclose(rows[-1]["half_width_error"], 0.03, rel_tol=1e-9)


def test_levels_that_are_not_numbers_are_one_line_and_status_2(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["case.yaml", "--vary", "mesh.surface_size_mm=0.5,a"])
    assert exc.value.code == 2
    assert "--vary" in capsys.readouterr().err.strip().splitlines()[-1]


def test_a_level_that_did_not_come_to_rest_stays_in_the_table_without_values():
    rows = [
        level_row(30.0, 0.25, preload_of(1e4, 0.2e-3, 1e9, 0.2e-3, 1e9), {"elements": 1}),
        failed_row(30.0, 0.125, "element 7 inverted"),
    ]
    rows[0]["transient_dt_ns"] = 1.0
    table = markdown_tables(rows, "mesh.spall_size_mm")
    failed = next(line for line in table.splitlines() if line.startswith("| 0.125 |"))
    assert failed.count("| - ") >= 5
    assert "not judged" in table
