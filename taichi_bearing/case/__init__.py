"""Case files: the YAML description of a simulation, loaded into frozen dataclasses in SI.

A case file holds ``name``, one mapping per section (``bearing``, ``material``, ``defect``,
``operating``, ``mesh``, ``contact``, ``cage``, ``damping``, ``preload``, ``run``,
``output``) and ``sensors``. Every dimensional key carries its unit as a suffix; the loaded
attribute is the key without the suffix and holds the SI value (``pitch_diameter_mm: 200``
-> ``case.bearing.pitch_diameter == 0.2``). Angles are measured from 12 o'clock (the load
line), positive counter-clockwise seen from the front; the shaft turns counter-clockwise.

The package:

- :mod:`.schema`: how a key is declared (:func:`~.schema.key`), checked and converted;
- :mod:`.sections` and :mod:`.material`: every section and key, declared once;
- :mod:`.load`: reading the file, ``--set`` overrides, :func:`parse_case`;
- :mod:`.validate`: checks across keys (geometry, operating point, defect, time step,
  sensors);
- :mod:`.reference`: the case-file reference, ``docs/case_reference.md``.

Errors are raised as :class:`CaseError` naming the dotted key path (e.g.
``bearing.roller_diameter_mm``) and what was expected.
"""

from __future__ import annotations

from taichi_bearing.case.load import (
    apply_overrides,
    case_to_dict,
    load_case,
    load_case_for_cli,
    parse_case,
    read_case_file,
    schema_attributes,
)
from taichi_bearing.case.material import Material
from taichi_bearing.case.sections import (
    SECTIONS,
    Bearing,
    Cage,
    Case,
    Contact,
    Damping,
    Defect,
    MeshControls,
    Operating,
    Output,
    Preload,
    Run,
    Sensor,
)
from taichi_bearing.case.validate import (
    ContactPressureWarning,
    ExtendedDefectWarning,
    SpallReachWarning,
    stable_step_estimate,
)
from taichi_bearing.errors import CaseError, CaseWarning

__all__ = [
    "SECTIONS",
    "Bearing",
    "Cage",
    "Case",
    "CaseError",
    "CaseWarning",
    "Contact",
    "ContactPressureWarning",
    "Damping",
    "Defect",
    "ExtendedDefectWarning",
    "Material",
    "MeshControls",
    "Operating",
    "Output",
    "Preload",
    "Run",
    "Sensor",
    "SpallReachWarning",
    "apply_overrides",
    "case_to_dict",
    "load_case",
    "load_case_for_cli",
    "parse_case",
    "read_case_file",
    "schema_attributes",
    "stable_step_estimate",
]
