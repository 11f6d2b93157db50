"""Benchmarks of the ``diagnostics`` package: synthetic scenarios (another impact source,
impacts at random times, varying speed, fault-free noise), scans over the development
records, the fast kurtogram against its reference and ``compare_diagnoses`` (two revisions'
diagnoses compared bit for bit). Each runs as ``python benchmarks/diagnostics/NAME.py``
from the repository root; the tests import their generators as
``benchmarks.diagnostics.NAME``. The numbers they print are in
docs/results/diagnostics/README.md."""
