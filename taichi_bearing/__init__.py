"""taichi-bearing: 2-D explicit dynamics of a roller bearing with a line spall."""

from taichi_bearing.errors import CaseError, InputError, SimulationError

__version__ = "0.1.0"
__all__ = ["CaseError", "InputError", "SimulationError", "__version__"]
