"""The case-file reference (Markdown), written from the schema.

``python -m taichi_bearing.case.reference docs/case_reference.md`` regenerates the
committed reference; a test fails when it is out of date.
"""

from __future__ import annotations

import sys
from pathlib import Path

from taichi_bearing.case.schema import UNITS, Key, Section, section_keys
from taichi_bearing.case.sections import SECTIONS, SENSOR_KEYS, Case, Sensor
from taichi_bearing.case.validate import (
    DEPTH_REACH_FACTOR,
    MAX_PRESSURE_RATIO,
    MAX_SURFACE_SPEED_RATIO,
    MAX_WAVE_SPEED,
    SENSOR_REACH,
    STATIC_CAPACITY_PRESSURE,
    STEP_FLOOR,
)

__all__ = ["render_reference", "main"]

COMMAND = "python -m taichi_bearing.case.reference docs/case_reference.md"

_INTRO = f"""\
# Case file reference

<!-- Generated from the schema in taichi_bearing/case/ by `{COMMAND}`;
     do not edit by hand: tests/test_case.py checks that it is current. -->

A case file is YAML (UTF-8) with the top-level keys `name`, the sections below and
`sensors`. A dimensional key ends with its unit; the loaded attribute is the key without
the unit and holds the SI value, e.g. `bearing.pitch_diameter_mm: 200` is
`case.bearing.pitch_diameter == 0.2` (m). Angles are measured from 12 o'clock (the load
line), positive counter-clockwise seen from the front; the shaft turns counter-clockwise.
Ranges apply to the value as written in the file. Override any key from the command line
with `--set KEY.PATH=VALUE` (the value is read as YAML), e.g.
`--set operating.load_kN=80` or `--set sensors.probe.x_mm=10`.

An unknown, missing or duplicated key, a value of the wrong type or out of range, or values
that do not fit together stop the case before meshing with one line naming the key (exit
status 2).
"""


def _text(text: str) -> str:
    """Plain text for a Markdown table cell: a pipe would end the cell, <name> is HTML."""
    return text.replace("|", "\\|").replace("<", "&lt;").replace(">", "&gt;")


def _units_table() -> list[str]:
    lines = ["| suffix | file unit | loaded as | factor |", "| --- | --- | --- | --- |"]
    for u in UNITS.values():
        lines.append(f"| `_{u.suffix}` | {u.label} | {u.si} | {u.factor:.10g} |")
    return lines


def _type_text(k: Key) -> str:
    if k.choices:
        return " / ".join(f"`{c}`" for c in k.choices)
    text = {bool: "boolean", int: "integer", float: "number", str: "string"}[k.kind]
    if k.unit:
        text += f" ({UNITS[k.unit].label})"
    return text + (" or `null`" if k.nullable else "")


def _default_text(k: Key) -> str:
    if k.required:
        return "required"
    value = k.dump(k.default)
    if value is None:
        return "`null`"
    if isinstance(value, bool):
        return f"`{str(value).lower()}`"
    return f"`{value:g}`" if isinstance(value, float) else f"`{value}`"


def _attribute_text(path: str, k: Key) -> str:
    unit = f" ({UNITS[k.unit].si})" if k.unit else ""
    return f"`{path}.{k.attr}`{unit}"


def _keys_table(path: str, keys: tuple[Key, ...]) -> list[str]:
    lines = [
        "| key | type | range | default | loaded as | meaning |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for k in keys:
        cells = (
            f"`{k.name}`",
            _type_text(k),
            _text(k.range_text()),
            _default_text(k),
            _attribute_text(path, k),
            _text(k.doc),
        )
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def _section(section: Section) -> list[str]:
    title = f"## `{section.name}`" + (" (optional)" if section.optional else "")
    return [title, "", _text(section.doc), "", *_keys_table(section.name, section.keys), ""]


def _checks() -> list[str]:
    return [
        "## Checks across keys",
        "",
        "Besides each key's range, a case is refused (naming the key) when:",
        "",
        "- the rollers do not fit: larger than the pitch diameter, overlapping on the pitch "
        "circle, an interference beyond 1 % or a clearance beyond 10 % of the roller "
        "diameter, no room for the inner ring's bore, an adapter wider than the outer ring;",
        "- the defect is not a line spall: zero length or depth with a race, half the ring "
        "thick or more, longer than half the raceway (longer than the roller spacing is "
        "accepted with a warning: an extended defect);",
        "- no bearing runs at its operating point: the inner raceway's surface speed "
        f"exceeds {100 * MAX_SURFACE_SPEED_RATIO:g} % of the material's shear wave speed "
        "(`operating.speed_rpm`), or the Hertz peak pressure of the most loaded roller "
        "(healthy bearing, rigid rings, Stribeck's load: exact at zero clearance, a lower "
        f"bound otherwise) exceeds E/{1 / MAX_PRESSURE_RATIO:g} (`operating.load_kN`). "
        f"Above {STATIC_CAPACITY_PRESSURE / 1e9:g} GPa, a roller bearing's static capacity "
        "(ISO 76), the case loads with a warning, as it does with a spall more than "
        f"{DEPTH_REACH_FACTOR:g} times deeper than a rigid roller drops into it (its floor "
        "never touched);",
        "- `contact.friction_dynamic` exceeds `contact.friction_static`; "
        "`mesh.surface_size_mm` exceeds `mesh.max_size_mm` or a quarter of the roller "
        "diameter; `run.frame_interval_ms` exceeds `run.duration_ms`; fewer than two "
        "samples would be recorded;",
        "- the time step, estimated before meshing as the critical step of a square surface "
        "element (`surface_size / (sqrt(2) c)`, `c` the plane-strain dilatational wave "
        f"speed), is below {STEP_FLOOR:g} s (a material faster than {MAX_WAVE_SPEED:g} m/s "
        "names its modulus or density, otherwise `mesh.surface_size_mm`);",
        "- the run would take more than `run.max_steps` steps. Each sample interval holds a "
        "whole number of steps, so a `run.sample_rate_Hz` near or above 1 / step lowers the "
        "step (a warning says by how much, when by more than 10 %);",
        f"- a sensor lies more than {SENSOR_REACH:g} x `mesh.max_size_mm` outside the outer "
        "ring and adapter, or inside the inner ring's bore: its nearest node would be "
        "somewhere else.",
        "",
    ]


def render_reference() -> str:
    """The case-file reference as Markdown."""
    name_key = next(k for k in section_keys(Case) if k.attr == "name")
    lines = [_INTRO, "## Units", "", *_units_table(), ""]
    lines += ["## `name`", "", f"String: {_text(name_key.doc)}; no `/` or `\\`.", ""]
    for section in SECTIONS.values():
        lines += _section(section)
    lines += [
        "## `sensors`",
        "",
        f"A mapping of names (identifiers) to points. {' '.join(Sensor.__doc__.split())}",
        "",
        *_keys_table("sensors.<name>", SENSOR_KEYS),
        "",
        *_checks(),
    ]
    return "\n".join(lines).rstrip("\n") + "\n"


def main(argv: list[str] | None = None) -> int:
    """Write the reference to the path given (or print it)."""
    argv = sys.argv[1:] if argv is None else argv
    text = render_reference()
    if argv:
        Path(argv[0]).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
