"""How a case key is declared, checked and converted: the vocabulary of the case schema.

A section of the case file is a frozen dataclass whose fields are declared with
:func:`key`::

    @dataclass(frozen=True)
    class Operating:
        load: float = key("kN", gt=0.0, doc="radial load on the adapter top")

That one line is the whole declaration of ``operating.load_kN``: the attribute ``load``
(SI, N), its file name (attribute + ``_`` + unit), its type (the annotation: ``int``,
``float``, ``bool``, ``str``, ``str | None``, or ``Literal[...]`` for a choice), its
range, its default (none: required) and its comment. :func:`section_keys` reads them back
as :class:`Key` objects, from which the loader validates and converts, the ``--set``
parser finds its way, and :mod:`taichi_bearing.case.reference` writes the docs.
"""

from __future__ import annotations

import dataclasses
import math
import re
import types
import typing
from dataclasses import dataclass
from typing import Any, Literal

from taichi_bearing.errors import CaseError

__all__ = [
    "REQUIRED",
    "UNITS",
    "Key",
    "Section",
    "Unit",
    "key",
    "section_keys",
    "sections_of",
    "type_name",
]


@dataclass(frozen=True)
class Unit:
    """A unit a case key may be given in: its key suffix, its factor to SI, the SI unit."""

    suffix: str  # as written after the attribute name, e.g. "mm" in pitch_diameter_mm
    factor: float  # file value * factor = SI value
    si: str  # unit of the loaded attribute
    text: str = ""  # how the file unit is printed, when not the suffix itself

    @property
    def label(self) -> str:
        return self.text or self.suffix


# The factors are the exact expressions the loaded values have always been computed with
# (value * factor): changing one (e.g. 1e-3 to 1 / 1000) would change results by a bit.
UNITS: dict[str, Unit] = {
    u.suffix: u
    for u in (
        Unit("mm", 1e-3, "m"),
        Unit("kN", 1e3, "N"),
        Unit("GPa", 1e9, "Pa"),
        Unit("GPa_mm", 1e12, "Pa/m", "GPa/mm"),
        Unit("ms", 1e-3, "s"),
        Unit("deg", math.pi / 180.0, "rad"),
        Unit("rpm", 2.0 * math.pi / 60.0, "rad/s"),
        Unit("Hz", 1.0, "Hz"),
        Unit("kg", 1.0, "kg"),
        Unit("kg_m3", 1.0, "kg/m^3", "kg/m^3"),
        Unit("s_m", 1.0, "s/m", "s/m"),
    )
}


class _Required:
    def __repr__(self) -> str:
        return "REQUIRED"


REQUIRED: Any = _Required()
"""The default of a key that the case file must give."""

_META = "taichi_bearing.case.key"
# YAML 1.1 reads exponents without a dot (1e-5) as strings
_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)[eE][-+]?\d+")


@dataclass(frozen=True)
class _Declared:
    """What :func:`key` stores in a dataclass field's metadata."""

    unit: str
    doc: str
    lo: float | None
    hi: float | None
    lo_open: bool
    hi_open: bool


def key(
    unit: str = "",
    *,
    doc: str,
    gt: float | None = None,
    ge: float | None = None,
    lt: float | None = None,
    le: float | None = None,
    default: Any = REQUIRED,
) -> Any:
    """Declare a section field as a case key.

    Parameters
    ----------
    unit : str
        The unit the file gives the value in, one of :data:`UNITS` (the key is named
        ``<attribute>_<unit>``); empty for a dimensionless key or a choice.
    doc : str
        What the key means (one line; the unit is added by the reference).
    gt, ge, lt, le : float, optional
        Range of the value as written in the file (before the SI conversion): greater
        than, at least, less than, at most.
    default : optional
        The loaded (SI) value when the key is left out; without it the key is required.

    Returns
    -------
    dataclasses.Field
        To be assigned to the annotated field in the class body.
    """
    if unit and unit not in UNITS:
        raise ValueError(f"unknown unit {unit!r}; known: {', '.join(UNITS)}")
    if gt is not None and ge is not None or lt is not None and le is not None:
        raise ValueError("give at most one lower (gt/ge) and one upper (lt/le) bound")
    declared = _Declared(
        unit=unit,
        doc=doc,
        lo=gt if gt is not None else ge,
        hi=lt if lt is not None else le,
        lo_open=gt is not None,
        hi_open=lt is not None,
    )
    if default is REQUIRED:
        return dataclasses.field(metadata={_META: declared})
    return dataclasses.field(default=default, metadata={_META: declared})


@dataclass(frozen=True)
class Key:
    """One key of a section: its file name, loaded attribute, type, unit, range, default.

    Built by :func:`section_keys` from a field declared with :func:`key`.
    """

    attr: str
    kind: type  # bool, int, float or str
    doc: str
    unit: str = ""
    nullable: bool = False
    choices: tuple[str, ...] | None = None
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    default: Any = REQUIRED

    @property
    def name(self) -> str:
        """The key as written in the case file, e.g. ``pitch_diameter_mm``."""
        return f"{self.attr}_{self.unit}" if self.unit else self.attr

    @property
    def factor(self) -> float:
        """File value * factor = SI value."""
        return UNITS[self.unit].factor if self.unit else 1.0

    @property
    def required(self) -> bool:
        return self.default is REQUIRED

    def range_text(self) -> str:
        """The range as ``lo <= value < hi`` (empty without bounds)."""
        if self.lo is None and self.hi is None:
            return ""
        lo = "" if self.lo is None else f"{self.lo:g} {'<' if self.lo_open else '<='} "
        hi = "" if self.hi is None else f" {'<' if self.hi_open else '<='} {self.hi:g}"
        return f"{lo}value{hi}"

    def expected(self) -> str:
        """What the file must give, e.g. ``a number in mm`` or ``one of 'cpu', 'cuda'``."""
        if self.choices:
            return "one of " + ", ".join(repr(c) for c in self.choices)
        if self.kind is bool:
            return "true or false"
        if self.kind is int:
            return "an integer"
        if self.kind is float:
            return f"a number in {UNITS[self.unit].label}" if self.unit else "a number"
        return "a string or null" if self.nullable else "a string"

    def load(self, value: Any, path: str, source: str | None = None) -> Any:
        """Check a value as read from the file and return it in SI units.

        Raises
        ------
        CaseError
            Naming ``path`` when the value has the wrong type, is not one of the choices
            or is out of range.
        """

        def wrong() -> CaseError:
            return CaseError(path, f"expected {self.expected()}, got {type_name(value)}", source)

        if self.kind in (int, float):
            if isinstance(value, str) and _NUMBER.fullmatch(value.strip()):
                value = float(value)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise wrong()
            if self.kind is float:
                value = float(value)
                if not math.isfinite(value):
                    raise CaseError(path, f"expected a finite number, got {value!r}", source)
            elif isinstance(value, float):
                # 1e8 or 2.0e5 for a count: take it when it is a whole number
                if not value.is_integer():
                    raise wrong()
                value = int(value)
            too_low = self.lo is not None and (
                value <= self.lo if self.lo_open else value < self.lo
            )
            too_high = self.hi is not None and (
                value >= self.hi if self.hi_open else value > self.hi
            )
            if too_low or too_high:
                raise CaseError(
                    path, f"out of range: expected {self.range_text()}, got {value:g}", source
                )
            return value * self.factor if self.kind is float else value
        if self.kind is bool:
            if not isinstance(value, bool):
                raise wrong()
            return value
        if not (isinstance(value, str) or self.nullable and value is None):
            raise wrong()
        if self.choices is not None and value not in self.choices:
            raise CaseError(path, f"expected {self.expected()}, got {value!r}", source)
        return value

    def dump(self, value: Any) -> Any:
        """The loaded (SI) value in the file's unit (the inverse of :meth:`load`)."""
        return float(value) / self.factor if self.kind is float else value


def type_name(value: Any) -> str:
    """How a value read from YAML is named in messages: ``a mapping``, ``str 'big'``."""
    return {dict: "a mapping", list: "a list", type(None): "null"}.get(
        type(value), f"{type(value).__name__} {value!r}"
    )


def _kind_of(hint: Any, where: str) -> tuple[type, bool, tuple[str, ...] | None]:
    """(kind, nullable, choices) of a field's type annotation."""
    if hint in (bool, int, float, str):
        return hint, False, None
    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if origin is Literal and all(isinstance(a, str) for a in args):
        return str, False, tuple(args)
    if origin in (typing.Union, types.UnionType) and set(args) == {str, type(None)}:
        return str, True, None
    raise TypeError(f"{where}: a case key must be bool, int, float, str, str | None or Literal")


def section_keys(cls: type) -> tuple[Key, ...]:
    """The keys of a section class, in field order (the fields declared with :func:`key`)."""
    hints = typing.get_type_hints(cls)
    keys = []
    for f in dataclasses.fields(cls):
        declared = f.metadata.get(_META)
        if declared is None:
            continue
        kind, nullable, choices = _kind_of(hints[f.name], f"{cls.__name__}.{f.name}")
        keys.append(
            Key(
                attr=f.name,
                kind=kind,
                doc=declared.doc,
                unit=declared.unit,
                nullable=nullable,
                choices=choices,
                lo=declared.lo,
                hi=declared.hi,
                lo_open=declared.lo_open,
                hi_open=declared.hi_open,
                default=REQUIRED if f.default is dataclasses.MISSING else f.default,
            )
        )
    return tuple(keys)


@dataclass(frozen=True)
class Section:
    """A section of the case file: its name, the class it loads into and its keys."""

    name: str
    cls: type
    keys: tuple[Key, ...]

    @property
    def doc(self) -> str:
        """The first paragraph of the class docstring."""
        text = (self.cls.__doc__ or "").strip().split("\n\n")[0]
        return " ".join(text.split())

    @property
    def optional(self) -> bool:
        """Every key has a default, so the section may be left out."""
        return not any(k.required for k in self.keys)

    def find(self, name: str) -> Key | None:
        """The key written ``name`` in the file, if any."""
        return next((k for k in self.keys if k.name == name), None)

    def load(self, raw: dict[str, Any], source: str | None = None) -> Any:
        """Build the section object from its checked mapping (unknown keys refused before).

        Raises
        ------
        CaseError
            On a missing required key or a bad value.
        """
        values = {}
        for k in self.keys:
            path = f"{self.name}.{k.name}"
            if k.name not in raw:
                if k.required:
                    raise CaseError(path, f"missing key (expected {k.expected()})", source)
                values[k.attr] = k.default
            else:
                values[k.attr] = k.load(raw[k.name], path, source)
        return self.cls(**values)

    def dump(self, obj: Any) -> dict[str, Any]:
        """The section object as a file mapping (unit-suffixed keys, file units)."""
        return {k.name: k.dump(getattr(obj, k.attr)) for k in self.keys}


def sections_of(case_cls: type) -> dict[str, Section]:
    """The sections of a case class: its fields whose class declares keys, in order."""
    hints = typing.get_type_hints(case_cls)
    out = {}
    for f in dataclasses.fields(case_cls):
        cls = hints[f.name]
        if dataclasses.is_dataclass(cls) and isinstance(cls, type):
            keys = section_keys(cls)
            if keys:
                out[f.name] = Section(f.name, cls, keys)
    return out
