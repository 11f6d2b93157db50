"""Reading a case: the YAML file, ``--set`` overrides, validation into a :class:`Case`.

Every problem is a :class:`CaseError` (one line) naming the file or the ``--set`` argument
it came from and the key path, e.g. ``cases/x.yaml: bearing.n_roler: unknown key; did you
mean 'bearing.n_rollers'?``.
"""

from __future__ import annotations

import copy
import difflib
import sys
import warnings
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import yaml

from taichi_bearing.case.schema import type_name
from taichi_bearing.case.sections import SECTIONS, SENSOR_KEYS, Case, Sensor
from taichi_bearing.case.validate import check_case
from taichi_bearing.errors import CaseError, CaseWarning, InputError

__all__ = [
    "TOP_KEYS",
    "apply_overrides",
    "case_to_dict",
    "load_case",
    "load_case_for_cli",
    "parse_case",
    "read_case_file",
    "schema_attributes",
]

TOP_KEYS: tuple[str, ...] = ("name", *SECTIONS, "sensors")


# --------------------------------------------------------------------------------------
# The file
# --------------------------------------------------------------------------------------


def read_case_file(path: str | Path) -> Any:
    """The YAML content of a case file, refusing what a case file cannot be.

    Raises
    ------
    InputError
        When the file cannot be read.
    CaseError
        On binary content, text that is not UTF-8, invalid YAML or a key given twice in
        one mapping (naming the line).
    """
    source = str(path)
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise InputError(f"{source}: cannot read the case file ({exc.strerror})") from None
    if b"\0" in data:
        line = data[: data.index(b"\0")].count(b"\n") + 1
        raise CaseError(f"line {line}", "binary content (a NUL byte), not a YAML case file", source)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        raise CaseError(
            f"line {line}",
            f"not UTF-8 text (byte 0x{data[exc.start]:02x}); save the case file as UTF-8",
            source,
        ) from None
    loader = yaml.SafeLoader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        _refuse_duplicate_keys(node, "", source)
        return loader.construct_document(node)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark is not None else "(top)"
        problem = getattr(exc, "problem", None) or "invalid YAML"
        raise CaseError(where, f"not valid YAML ({problem})", source) from None
    finally:
        loader.dispose()


def _refuse_duplicate_keys(node: yaml.Node, path: str, source: str) -> None:
    """PyYAML keeps the last of two equal keys silently; a case file must not have any."""
    if isinstance(node, yaml.SequenceNode):
        for item in node.value:
            _refuse_duplicate_keys(item, path, source)
    if not isinstance(node, yaml.MappingNode):
        return
    seen: dict[str, int] = {}
    for key_node, value_node in node.value:
        if not isinstance(key_node, yaml.ScalarNode):
            continue
        name = key_node.value
        key_path = f"{path}.{name}" if path else name
        line = key_node.start_mark.line + 1
        if name in seen and key_node.tag != "tag:yaml.org,2002:merge":
            raise CaseError(
                key_path, f"given twice (lines {seen[name]} and {line}); keep one", source
            )
        seen[name] = line
        _refuse_duplicate_keys(value_node, key_path, source)


def load_case(path: str | Path, overrides: Iterable[str] = ()) -> Case:
    """Read, override and validate a case file.

    Parameters
    ----------
    path : str or Path
        YAML case file (UTF-8).
    overrides : iterable of str
        ``"key.path=value"`` strings (values parsed as YAML), applied before validation,
        e.g. ``"operating.load_kN=80"``. An error in a value given this way names the
        ``--set`` argument, not the file.

    Returns
    -------
    Case
        The validated case in SI units.

    Raises
    ------
    CaseError
        On an unreadable or malformed file or any invalid value (the message names the key).

    Warns
    -----
    CaseWarning
        E.g. :class:`~taichi_bearing.case.validate.ExtendedDefectWarning` when the defect is
        longer than the spacing between rollers.
    """
    source = str(path)
    raw = read_case_file(path)
    if not isinstance(raw, dict):
        raise CaseError("(top)", "expected a mapping of sections at the top level", source)
    raw, origins = _apply(raw, list(overrides))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CaseWarning)
        try:
            case = parse_case(raw, source=path)
        except CaseError as exc:
            raise _from_set(exc, origins) from None
    for w in caught:
        if isinstance(w.message, CaseWarning):
            warnings.warn(_from_set(w.message, origins), stacklevel=2)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return case


def _from_set(exc: CaseError | CaseWarning, origins: dict[str, str]) -> Any:
    """The error or warning, named by the ``--set`` argument its key came from, if any
    (rather than blaming the file)."""
    item = _origin(exc.key, origins)
    return exc if item is None else type(exc)(exc.key, exc.message, f"--set {item}")


def load_case_for_cli(path: str | Path, overrides: Iterable[str] = ()) -> Case:
    """:func:`load_case`, with its case warnings printed as one line each on stderr."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", CaseWarning)
        case = load_case(path, overrides)
    for w in caught:
        if issubclass(w.category, CaseWarning):
            print(f"warning: {w.message}", file=sys.stderr)
        else:
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    return case


# --------------------------------------------------------------------------------------
# --set overrides
# --------------------------------------------------------------------------------------


def apply_overrides(raw: dict, overrides: Iterable[str]) -> dict:
    """Return a copy of ``raw`` with ``key.path=value`` overrides applied (values as YAML).

    Raises
    ------
    CaseError
        On an argument that is not ``KEY.PATH=VALUE``, a value that is not YAML or a path
        through an unknown section, named by its ``--set`` argument.
    """
    return _apply(raw, list(overrides))[0]


def _apply(raw: dict, overrides: list[str]) -> tuple[dict, dict[str, str]]:
    """The overridden copy, and the ``--set`` argument behind each key path it wrote or
    created (a new sensor's path ends with ``.``: everything under it came from there)."""
    raw = copy.deepcopy(raw)
    origins: dict[str, str] = {}
    for item in overrides:
        key, sep, text = item.partition("=")
        key = key.strip()
        if not sep or not key:
            raise CaseError("--set", f"expected KEY.PATH=VALUE, got {item!r}")
        where = f"--set {item}"
        try:
            value = yaml.safe_load(text)
        except yaml.YAMLError:
            raise CaseError(key, f"value {text!r} is not valid YAML", where) from None
        parts = key.split(".")
        node = raw
        for depth, part in enumerate(parts[:-1]):
            prefix = ".".join(parts[: depth + 1])
            child = node.get(part) if isinstance(node, dict) else None
            if child is None:
                if not _may_create(parts[: depth + 1]):
                    _unknown(prefix, _valid_at(parts[:depth]), where)
                child = node[part] = {}
                origins[prefix + "."] = item
            elif not isinstance(child, dict):
                raise CaseError(prefix, "is a value, not a section", where)
            node = child
        node[parts[-1]] = value
        origins[key] = item
    return raw, origins


def _origin(key: str, origins: dict[str, str]) -> str | None:
    if key in origins:
        return origins[key]
    return next(
        (item for p, item in origins.items() if p.endswith(".") and key.startswith(p)), None
    )


def _may_create(parts: list[str]) -> bool:
    # an override may add a sensor, or a section that is all defaults; never a new section
    return len(parts) == 2 and parts[0] == "sensors" or (len(parts) == 1 and parts[0] in SECTIONS)


def _valid_at(parts: list[str]) -> list[str]:
    if not parts:
        return list(TOP_KEYS)
    if len(parts) == 1 and parts[0] in SECTIONS:
        return [f"{parts[0]}.{k.name}" for k in SECTIONS[parts[0]].keys]
    return []


def _unknown(key: str, valid: Iterable[str], source: str | None) -> None:
    valid = list(valid)
    close = difflib.get_close_matches(key, valid, n=1, cutoff=0.6)
    if close:
        hint = f"did you mean '{close[0]}'?"
    else:
        hint = "valid keys here: " + ", ".join(v.rsplit(".", 1)[-1] for v in valid)
    raise CaseError(key, f"unknown key; {hint}", source)


# --------------------------------------------------------------------------------------
# Validation
# --------------------------------------------------------------------------------------


def parse_case(raw: Mapping, source: str | Path | None = None) -> Case:
    """Validate a case given as a nested mapping (the YAML content) and convert it to SI.

    Raises
    ------
    CaseError
        Naming the first bad key: unknown, missing, of the wrong type, out of range, or
        not fitting the others (:func:`~taichi_bearing.case.validate.check_case`).
    """
    src = None if source is None else str(source)
    if not isinstance(raw, Mapping):
        raise CaseError("(top)", "expected a mapping of sections at the top level", src)
    for key in raw:
        if key not in TOP_KEYS:
            _unknown(str(key), TOP_KEYS, src)
    for key in TOP_KEYS:
        if key not in raw and not (key in SECTIONS and SECTIONS[key].optional):
            raise CaseError(key, "missing section" if key != "name" else "missing key", src)

    name = raw["name"]
    if not isinstance(name, str) or not name.strip() or any(c in name for c in "/\\"):
        raise CaseError("name", f"expected a non-empty folder-safe string, got {name!r}", src)
    sections = {sec: _parse_section(sec, raw.get(sec), src) for sec in SECTIONS}
    case = Case(
        name=name,
        sensors=_parse_sensors(raw["sensors"], src),
        source=None if source is None else Path(source),
        **sections,
    )
    check_case(case, src)
    return case


def _parse_section(name: str, raw: Any, src: str | None) -> Any:
    section = SECTIONS[name]
    if raw is None and section.optional:
        raw = {}
    if not isinstance(raw, Mapping):
        raise CaseError(name, f"expected a mapping of keys, got {type_name(raw)}", src)
    for key in raw:
        if section.find(key) is None:
            _unknown(f"{name}.{key}", [f"{name}.{k.name}" for k in section.keys], src)
    return section.load(raw, src)


def _parse_sensors(raw: Any, src: str | None) -> dict[str, Sensor]:
    if raw is None:
        return {}
    if not isinstance(raw, Mapping):
        raise CaseError("sensors", f"expected a mapping name -> point, got {type_name(raw)}", src)
    names = [k.name for k in SENSOR_KEYS]
    sensors = {}
    for name, point in raw.items():
        path = f"sensors.{name}"
        if not isinstance(name, str) or not name.isidentifier():
            raise CaseError(path, "sensor names must be identifiers (letters, digits, _)", src)
        if not isinstance(point, Mapping):
            raise CaseError(path, f"expected a mapping with {' and '.join(names)}", src)
        for key in point:
            if key not in names:
                _unknown(f"{path}.{key}", [f"{path}.{n}" for n in names], src)
        coords = {}
        for k in SENSOR_KEYS:
            if k.name not in point:
                raise CaseError(f"{path}.{k.name}", f"missing key (expected {k.expected()})", src)
            coords[k.attr] = k.load(point[k.name], f"{path}.{k.name}", src)
        sensors[name] = Sensor(**coords)
    return sensors


# --------------------------------------------------------------------------------------
# Writing back
# --------------------------------------------------------------------------------------


def case_to_dict(case: Case) -> dict:
    """The case as a YAML-ready mapping with unit-suffixed keys (inverse of parse_case)."""
    out: dict[str, Any] = {"name": case.name}
    for name, section in SECTIONS.items():
        out[name] = section.dump(getattr(case, name))
    out["sensors"] = {
        name: {k.name: k.dump(getattr(s, k.attr)) for k in SENSOR_KEYS}
        for name, s in case.sensors.items()
    }
    return out


def schema_attributes() -> dict[str, list[str]]:
    """Loaded attribute names per section, and ``sensors`` (for documentation and tests)."""
    attrs = {name: [k.attr for k in section.keys] for name, section in SECTIONS.items()}
    attrs["sensors"] = [k.attr for k in SENSOR_KEYS]
    return attrs
