"""The application around the ``diagnostics`` library: what reads files by name, writes
results or shows progress.

- :mod:`diagnostics.app.cli`: ``python -m diagnostics analyze|benchmark|compare``
  (``bearing-diagnostics``), its parsers and the option checks;
- :mod:`diagnostics.app.benchmark`: ``diagnose`` over a folder of public records,
  tabulated against the faults their names give;
- :mod:`diagnostics.app.report`: ``analyze``'s ``report.html`` and ``benchmark --html``,
  one self-contained page each;
- :mod:`diagnostics.app.datasets`: what a CWRU or MFPT record's name says, its bearing,
  and how to read it;
- :mod:`diagnostics.app.compare`: records side by side through one analysis, figures and
  ``summary.json`` (``python -m taichi_bearing compare`` calls it).

The signal code (the :mod:`diagnostics` namespace and :mod:`diagnostics.plots`) never
imports this package; files are written atomically and progress is shown through
:mod:`bearing_io`.
"""
