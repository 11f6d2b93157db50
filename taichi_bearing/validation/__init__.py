"""Validation cases of the solver against analytic contact mechanics (no bearing here).

- :mod:`taichi_bearing.validation.impact`: a cylinder dropped onto a block, peak force and
  contact duration against the plane-strain Hertz impact solution.
- :mod:`taichi_bearing.validation.hertz_impact`: that solution (the line contact's
  force-approach law and the rigid-body impact ODE), numpy and scipy only.
- :mod:`taichi_bearing.validation.bar_impact`: an elastic bar striking a rigid wall, its
  contact pressure plateau and duration against the one-dimensional wave solution.
- :mod:`taichi_bearing.validation.hertz_static`: a cylinder pressed onto a block, the
  contact patch against Hertz as the mesh is refined at a fixed penalty.
"""
