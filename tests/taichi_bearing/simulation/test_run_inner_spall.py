"""The bearing run with an inner-race spall (cases/validation/inner_spall.yaml, about a
minute on one thread): the notch is in the inner ring and turns with it, the spall passes
rollers 0 and 1 in the load zone one BPFI period apart, and the checks use BPFI.

One run is shared by the tests of this module.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from taichi_bearing.analytic.bearing import cage_speed, fault_frequencies
from taichi_bearing.analytic.inner_race import passage_spall_angles
from taichi_bearing.analytic.quasistatic import analytical_roller_forces
from taichi_bearing.case import load_case
from taichi_bearing.output.histories import read_histories

INNER = "cases/validation/inner_spall.yaml"


@pytest.fixture(scope="module")
def case():
    return load_case(INNER)


@pytest.fixture(scope="module")
def inner_run(case, tmp_path_factory):
    from taichi_bearing.pipeline import run_case

    out = tmp_path_factory.mktemp("inner_run")
    summary = run_case(case, out, threads=1, quiet=True, post=False)
    return out, summary, read_histories(out)


def test_the_notch_is_cut_in_the_inner_ring_and_turns_with_it(case, inner_run):
    """The spall's corner nodes belong to the inner ring, at defect.angle_deg at t = 0,
    and in each frame they have turned by the shaft's angle (the ring's elastic
    deflection is microns: 0.01 deg is 15 um on the raceway)."""
    import meshio

    from taichi_bearing.output.vtk import read_pvd
    from taichi_bearing.simulation.simulate import stage_mesh

    out, _, _ = inner_run
    mesh, _ = stage_mesh(case)
    info = json.loads((out / "mesh_info.json").read_text())
    spall = info["spall"]
    assert spall["race"] == "inner"
    corners = np.asarray(spall["corner_nodes"])
    inner = mesh.part_id("inner_ring")
    for k in corners:
        parts = mesh.element_part[np.any(mesh.elements == k, axis=1)]
        assert set(parts.tolist()) == {inner}
    start = np.degrees(np.arctan2(-mesh.nodes[corners, 0], mesh.nodes[corners, 1]))
    half = math.degrees(0.5 * case.defect.length / case.bearing.inner_raceway_radius)
    expected0 = math.degrees(case.defect.angle) + np.array([-half, -half, half, half])
    np.testing.assert_allclose(start, expected0, atol=1e-9)
    frames = read_pvd(out / "frames" / "frames.pvd")
    assert len(frames) >= 2
    for time, name in frames[-2:]:
        m = meshio.read(out / "frames" / name)
        x = m.points[corners, :2] + m.point_data["displacement"][corners, :2]
        turned = np.degrees(np.arctan2(-x[:, 0], x[:, 1]))
        shaft = math.degrees(case.operating.speed * time)
        np.testing.assert_allclose(turned, start + shaft, atol=0.01)


def test_events_one_bpfi_period_apart_when_the_spall_reaches_each_roller(case, inner_run):
    """Rollers 0 and 1 each lose their load as the spall reaches them, 1/BPFI apart
    (bearing.py's BPFI), at the times the kinematics give, one each side of the load
    line."""
    _, summary, hist = inner_run
    events = summary["events"]
    assert [e["roller"] for e in events] == [0, 1]
    bpfi = fault_frequencies(case.bearing, case.operating.shaft_hz).bpfi
    assert summary["bpfi_hz"] == pytest.approx(bpfi, rel=1e-12)
    for key in ("entry_time_s", "exit_time_s"):
        gap = events[1][key] - events[0][key]
        assert gap * bpfi == pytest.approx(1.0, abs=0.02)
    check = summary["checks"]["restress_interval"]
    assert check["passed"] and "1/BPFI" in check["note"]
    # the entry edge reaches roller j half the spall's travel before its centre does
    _, centre = passage_spall_angles(
        case, case.run.first_roller_angle, case.defect.angle, len(events)
    )
    shaft, cage = case.operating.speed, cage_speed(case.bearing, case.operating.speed)
    lag = 0.5 * case.defect.length / case.bearing.inner_raceway_radius / (shaft - cage)
    entries = np.array([e["entry_time_s"] for e in events])
    np.testing.assert_allclose(entries, centre - lag, atol=1e-4)
    angles = [p["spall_angle_deg"] for p in summary["passages"]]
    assert angles == pytest.approx([-16.07, 16.07], abs=0.2)
    # inside the spall the roller carries nothing on the inner raceway
    t = hist["time_s"].to_numpy()
    for e in events:
        inside = (t > e["entry_time_s"] + 5e-5) & (t < e["floor_window_s"][1])
        fn = hist[f"roller{e['roller']}_inner_fn"].to_numpy()
        assert np.median(fn[inside]) < 0.05 * e["force_before_N"]


def test_static_check_and_report_entries_for_the_inner_race(case, inner_run):
    _, summary, _ = inner_run
    assert summary["spall_race"] == "inner"
    # the quasi-static forces with the spall where it starts (no roller on it at t = 0)
    np.testing.assert_allclose(
        summary["analytical_roller_forces_N"], analytical_roller_forces(case)
    )
    sidebands = summary["checks"]["load_zone_sidebands"]
    assert sidebands["passed"] is None and "shorter than two shaft turns" in sidebands["note"]
    assert summary["checks"]["defect_size"]["passed"] is not False
