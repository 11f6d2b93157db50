"""taichi-bearing: 2-D explicit dynamics of a roller bearing with a spall.

The Python API is three calls (:mod:`taichi_bearing.api`)::

    import taichi_bearing as tb

    case = tb.load_case("cases/line_spall.yaml", ["run.duration_ms=10"])
    run = tb.run(case, "runs/line_spall")     # mesh, preload, transient, checks
    run.summary["checks"]["exit_burst"], run.histories["roller0_outer_fn"]
    run = tb.load_run("runs/line_spall")      # any run folder, later, without Taichi

The packages follow the pipeline, each importing only those before it: ``geometry``,
``case``, ``analytic``, ``mesh``, ``solver``, ``output``, ``modes``, ``simulation``,
``checks``, ``post``, ``studies``, ``validation``; ``pipeline`` runs them in turn and
``commands`` is the command line (``python -m taichi_bearing``).
"""

from taichi_bearing.api import load_case, load_run, run
from taichi_bearing.errors import CaseError, InputError, SimulationError

__version__ = "0.1.0"
__all__ = [
    "CaseError",
    "InputError",
    "SimulationError",
    "__version__",
    "load_case",
    "load_run",
    "run",
]
