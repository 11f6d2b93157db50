"""Benchmark scripts: each prints a table and runs as ``python benchmarks/NAME.py`` from the
repository root; never part of the test suite. A package so that tests and scripts import
one another by name (``benchmarks.versions``, ``benchmarks.diagnostics.other_source_scenarios``)
instead of putting folders on ``sys.path``."""
