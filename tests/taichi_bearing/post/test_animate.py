"""``python -m taichi_bearing animate RUN_DIR`` on a tiny real run (the coarse case, 0.1 ms,
a frame every 0.025 ms): the GIF's frame count and size, the colour range against the
frames' von Mises stresses read with meshio, the default window around the spall, the
drawn geometry at scale 1, and one-line refusals (exit status 2) of bad input."""

from __future__ import annotations

import math
import os
import shutil
import subprocess
import sys
from pathlib import Path

import meshio
import numpy as np
import pytest
from PIL import Image
from scipy.spatial import cKDTree

from taichi_bearing.__main__ import main
from taichi_bearing.output.layout import FRAMES_DIR, PVD_FILE
from taichi_bearing.output.vtk import read_pvd
from taichi_bearing.post import animation

ROOT = Path(__file__).resolve().parents[3]
COARSE = ROOT / "cases" / "validation" / "coarse_spall.yaml"
# The coarse case: roller diameter 24 mm, outer raceway radius 112 mm, spall 6 mm at 12 o'clock.
ROLLER_D, RACEWAY_R, SPALL_L = 24e-3, 112e-3, 6e-3


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("animate") / "run"
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    args = [COARSE, "--set", "run.duration_ms=0.1", "--set", "run.frame_interval_ms=0.025",
            "--set", "preload.ke_ratio_tol=0.01", "--set", "run.threads=1",
            "--out", out, "--quiet", "--no-post"]  # fmt: skip
    proc = subprocess.run(
        [sys.executable, "-m", "taichi_bearing", *map(str, args)],
        capture_output=True, text=True, timeout=600, env=env, cwd=ROOT,
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr[-2000:]
    return out


def _frames(run_dir: Path) -> list[tuple[float, str]]:
    return read_pvd(run_dir / FRAMES_DIR / PVD_FILE)


def _cli(capsys, *args: str) -> tuple[int, str, str]:
    try:
        rc = main(["animate", *map(str, args)])
    except SystemExit as exc:  # argparse's refusals
        rc = exc.code
    captured = capsys.readouterr()
    return rc, captured.out, captured.err


def _gif(path: Path) -> tuple[int, tuple[int, int], list[np.ndarray]]:
    with Image.open(path) as im:
        pictures = []
        for i in range(im.n_frames):
            im.seek(i)
            pictures.append(np.asarray(im.convert("RGB")))
        return im.n_frames, im.size, pictures


def test_default_gif_has_every_frame_at_960x540(run_dir, capsys):
    rc, out, err = _cli(capsys, run_dir)
    assert rc == 0, err
    frames = _frames(run_dir)
    assert len(frames) >= 4
    n, size, pictures = _gif(run_dir / animation.ANIMATION_FILES["gif"])
    assert n == len(frames)
    assert size == (960, 540)
    assert f"{n} frames" in out and "displacement x" in out
    # Each frame is a different picture (the time at least), drawn in many colours.
    assert all(np.any(a != b) for a, b in zip(pictures, pictures[1:], strict=False))
    assert len(np.unique(pictures[0].reshape(-1, 3), axis=0)) > 16


def test_picked_frames_size_and_scale(run_dir, tmp_path, capsys):
    frames = _frames(run_dir)
    t = [1e3 * time for time, _ in frames]
    out = tmp_path / "sub" / "picked.gif"
    rc, _, err = _cli(capsys, run_dir, "--from-ms", t[1], "--to-ms", t[-1], "--every", 2,
                      "--width-px", 480, "--scale", 1, "--fps", 5, "--out", out)  # fmt: skip
    assert rc == 0, err
    n, size, _ = _gif(out)
    assert n == len(t[1::2])
    assert size == (480, 270)


def test_colour_range_is_the_frames_von_mises_min_max_in_the_window(run_dir, tmp_path):
    # A fixed window (no following): x in [-30, 30] mm, y in [91, 121] mm.
    info = animation.animate_run(
        run_dir, tmp_path / "a.gif", centre=(0.0, 0.106), width=0.060, height=0.030
    )
    lo, hi = math.inf, -math.inf
    for _, name in _frames(run_dir):
        m = meshio.read(run_dir / FRAMES_DIR / name)
        xy = (m.points + m.point_data["displacement"])[:, :2][m.cells[0].data].mean(axis=1)
        inside = (np.abs(xy[:, 0]) <= 0.030) & (xy[:, 1] >= 0.091) & (xy[:, 1] <= 0.121)
        vm = m.cell_data["von_mises"][0][inside]
        lo, hi = min(lo, vm.min()), max(hi, vm.max())
    assert info["von_mises_range_Pa"] == pytest.approx((lo, hi), rel=1e-12)
    assert hi > 10 * lo and hi > 1e6  # the loaded contacts are in view


def test_default_window_holds_the_spall_and_a_few_rollers(run_dir, tmp_path):
    info = animation.animate_run(run_dir, tmp_path / "a.gif", to_s=0.05e-3)
    view = info["view"]
    half = 0.5 * SPALL_L / RACEWAY_R
    spall = [(RACEWAY_R * math.sin(a), RACEWAY_R * math.cos(a)) for a in (-half, 0.0, half)]
    assert view.contains(view.local(np.array(spall))).all()
    assert 2 * ROLLER_D <= view.width <= 5 * ROLLER_D
    # A whole roller below the spall (outer raceway): from the raceway to one diameter in.
    assert view.y0 < -ROLLER_D and view.y1 > 0
    assert info["n_frames"] == sum(t <= 0.05e-3 for t, _ in _frames(run_dir)) >= 2
    assert info["scale"] >= 1
    mantissa = info["scale"] / 10 ** math.floor(math.log10(info["scale"]))
    assert min(abs(mantissa - m) for m in (1, 2, 5)) < 1e-9  # a 1-2-5 factor


def test_scale_one_draws_the_true_deformed_geometry(run_dir):
    from taichi_bearing.case import parse_case
    from taichi_bearing.output.run_folder import read_case_dict

    time, name = _frames(run_dir)[-1]
    frame = animation.read_frame(run_dir / FRAMES_DIR / name, time)
    node_part = animation.node_parts(len(frame.points), frame.cells, frame.part)
    view = animation.spall_view(parse_case(read_case_dict(run_dir)))
    rollers = [p for p in np.unique(frame.part) if p >= 2]  # outer ring, inner ring, rollers
    fiv = animation.frame_in_view(frame, view, node_part, contact=(0, rollers, 1.0))
    true = view.local(frame.points + frame.displacement)[frame.cells].reshape(-1, 8)
    drawn = fiv.shown(1.0).reshape(-1, 8)
    assert len(drawn) > 1000
    # every drawn cell is a cell of the frame at its true position (to rounding)
    distance, _ = cKDTree(true).query(drawn)
    assert distance.max() < 1e-12
    assert fiv.peak_elastic > 0  # the contacts deform
    assert np.any(fiv.shown(50.0).reshape(-1, 8) != drawn)  # magnified: not the truth


def _one_line_error(rc: int, err: str, *words: str) -> None:
    assert rc == 2
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert "Traceback" not in err
    for w in words:
        assert w in lines[0], lines[0]


def test_bad_inputs_are_one_line_with_exit_2(run_dir, tmp_path, capsys, monkeypatch):
    _one_line_error(*_cli(capsys, tmp_path / "missing")[::2], "RUN_DIR")
    no_frames = tmp_path / "no_frames"
    shutil.copytree(run_dir, no_frames, ignore=shutil.ignore_patterns(FRAMES_DIR, "*.gif"))
    _one_line_error(*_cli(capsys, no_frames)[::2], "RUN_DIR", FRAMES_DIR)
    t = 1e3 * _frames(run_dir)[1][0]
    rc, _, err = _cli(capsys, run_dir, "--from-ms", t, "--to-ms", t)
    _one_line_error(rc, err, "--from-ms", "run.frame_interval_ms=0.02")
    _one_line_error(*_cli(capsys, run_dir, "--format", "bad")[::2], "--format")
    _one_line_error(*_cli(capsys, run_dir, "--scale", "-1")[::2], "--scale")
    _one_line_error(*_cli(capsys, run_dir, "--fps", "0")[::2], "--fps")
    from matplotlib.animation import FFMpegWriter

    monkeypatch.setattr(FFMpegWriter, "isAvailable", classmethod(lambda cls: False))
    out = tmp_path / "a.mp4"
    _one_line_error(*_cli(capsys, run_dir, "--format", "mp4", "--out", out)[::2], "--format")
    assert not out.exists()


def test_mp4_with_ffmpeg(run_dir, tmp_path, capsys):
    from matplotlib.animation import FFMpegWriter

    if not FFMpegWriter.isAvailable():
        pytest.skip("ffmpeg not found")
    rc, _, err = _cli(capsys, run_dir, "--format", "mp4", "--out", tmp_path / "a.mp4")
    assert rc == 0, err
    assert (tmp_path / "a.mp4").stat().st_size > 1000
