"""The simulation stage: a case and its mesh turned into set-up data (starter), the Taichi
model built and preloaded, the transient stepped sample by sample (engine) with its
recorders, and the flexible-ring static reference."""

from taichi_bearing.simulation.engine import RunConfig, RunResult, run_transient

__all__ = ["RunConfig", "RunResult", "run_transient"]
