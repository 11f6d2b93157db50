"""The simulator's benchmarks, profiles, probes and regression guards (run each as a
script from the repository's root: ``python benchmarks/taichi_bearing/NAME.py``)."""
