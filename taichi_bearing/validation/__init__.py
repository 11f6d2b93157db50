"""Validation cases of the solver against analytic contact mechanics (no bearing here).

- :mod:`taichi_bearing.validation.impact`: a cylinder dropped onto a block, peak force and
  contact duration against the plane-strain Hertz impact solution (issue 18, item 5).
"""
