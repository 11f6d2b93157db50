"""Backend selection: an unavailable GPU backend is an error, never a silent CPU run."""

from __future__ import annotations

import subprocess
import sys

import pytest

from taichi_bearing.errors import InputError
from taichi_bearing.solver.backend import current_arch, init_taichi


def test_cuda_request_without_gpu_raises_clear_error():
    # In a child process: a failed init resets Taichi, which must not hit this process.
    code = (
        "from taichi_bearing.solver.backend import init_taichi\n"
        "from taichi_bearing.errors import InputError\n"
        "try:\n"
        "    init_taichi('cuda')\n"
        "except InputError as e:\n"
        "    print('ERR', e)\n"
        "else:\n"
        "    import taichi as ti\n"
        "    print('OK', ti.lang.impl.current_cfg().arch.name)\n"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120
    ).stdout
    line = [s for s in out.splitlines() if s.startswith(("ERR", "OK"))][-1]
    if line.startswith("OK"):
        # A CUDA machine: the arch obtained must really be cuda.
        assert line == "OK cuda"
    else:
        assert "cuda" in line and "--arch cpu" in line
        assert "\n" not in line.strip()


def test_unknown_arch_is_input_error_and_cpu_init_is_idempotent():
    with pytest.raises(InputError, match="arch"):
        init_taichi("gpu")
    assert init_taichi("cpu") == "cpu"
    assert init_taichi("cpu") == "cpu"
    assert current_arch() == "cpu"


@pytest.mark.parametrize("variable", ["launch", "graph"])
@pytest.mark.parametrize(
    "value, expected", [(None, "default"), ("4", 4), ("1", 1), ("0", None), ("x", None)]
)
def test_steps_per_launch_from_the_environment(monkeypatch, variable, value, expected):
    """Parallel stepping's steps per launch (unrolled; default 1) and per compute graph
    (default 16): the default unless the variable says otherwise, and a value that is not
    a whole number >= 1 is an input error naming the variable."""
    from taichi_bearing.solver import stepping

    name, read = {
        "launch": (stepping.STEPS_PER_LAUNCH_ENV, stepping.parallel_steps),
        "graph": (stepping.STEPS_PER_GRAPH_ENV, stepping.graph_steps),
    }[variable]
    if value is None:
        monkeypatch.delenv(name, raising=False)
    else:
        monkeypatch.setenv(name, value)
    if expected is None:
        with pytest.raises(InputError, match=name):
            read()
    else:
        default = {"launch": 1, "graph": 16}[variable]
        assert read() == (default if expected == "default" else expected)
