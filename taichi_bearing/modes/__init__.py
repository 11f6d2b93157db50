"""Natural frequencies and mode shapes of the finite element model (numpy/scipy only;
no Taichi): ``python -m taichi_bearing modes CASE``.

:func:`~taichi_bearing.modes.model.bearing_modal_model` builds a part of a case's mesh
with the solver's own lumped masses and small-strain stiffness, free or held as in the
run; :func:`~taichi_bearing.modes.solve.solve_modes` finds its lowest modes (or those
nearest a frequency) and describes each; :mod:`~taichi_bearing.modes.output` writes
``modes.csv``, a ``.pvd`` series of the shapes and a figure; :func:`modes_near_band`
(:mod:`~taichi_bearing.modes.band`) gives the outer ring's modes around a frequency band
for the run report. Names are imported on first use, so the command line's start-up
stays light.
"""

from __future__ import annotations

import importlib

_WHERE = {
    "PARTS": "model",
    "SUPPORTS": "model",
    "ModalModel": "model",
    "bearing_modal_model": "model",
    "modal_model": "model",
    "ModalResult": "solve",
    "Mode": "solve",
    "solve_modes": "solve",
    "write_modes": "output",
    "modes_near_band": "band",
}

__all__ = sorted(_WHERE)


def __getattr__(name: str):
    if name in _WHERE:
        return getattr(importlib.import_module(f"taichi_bearing.modes.{_WHERE[name]}"), name)
    raise AttributeError(f"module 'taichi_bearing.modes' has no attribute {name!r}")
