"""Recorders of a run, numpy in, files out (no Taichi here).

- :mod:`.histories`: ``histories.parquet`` written in crash-safe chunks, with resume.
- :mod:`.checkpoint`: ``checkpoint_<step>.npz`` state files and the case/mesh fingerprint.
- :mod:`.vtk`: ``mesh.vtu``, ``frames/frame_*.vtu`` and the ``frames.pvd`` series.
- :mod:`.progress`: progress of the preload and the transient (a bar, or lines in a log).
- :mod:`.summary`: ``summary.json`` with the required keys checked.

Import from the submodules; this package imports nothing so that ``import
taichi_bearing.output`` stays cheap.
"""
