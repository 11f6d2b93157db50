"""The cells of a study: the varied case keys (:class:`Axis`, ``--vary KEY=v1,v2,...``),
their grid, each cell's case validated through the case schema, and its run folder's name
from its key=value pairs (``load_50kN_speed_500rpm``, ``penalty_scale_0p3``).

The sweep, passages and convergence commands make their cells here and run them with
:func:`taichi_bearing.studies.sweep.run_sweep`.
"""

from __future__ import annotations

import itertools
import json
import math
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import yaml

from taichi_bearing.case import SECTIONS, load_case
from taichi_bearing.errors import CaseError, InputError

__all__ = [
    "LOAD_KEY",
    "SPEED_KEY",
    "Axis",
    "SweepCell",
    "cell_dir_name",
    "column_labels",
    "make_cells",
    "numeric_axis",
    "parse_values",
    "parse_vary",
    "tied_keys",
]

LOAD_KEY = "operating.load_kN"
SPEED_KEY = "operating.speed_rpm"
# YAML 1.1 reads an exponent without a dot (1e-5) as a string; a case value it is not
_NUMBER = re.compile(r"[-+]?(\d+\.?\d*|\.\d+)[eE][-+]?\d+")


@dataclass(frozen=True)
class Axis:
    """One varied case key and its values.

    Attributes
    ----------
    key : str
        Dotted key as written in a case file, e.g. ``mesh.surface_size_mm``; or several
        joined by ``+``, which take the same value together (:func:`tied_keys`), e.g.
        ``mesh.spall_size_mm+mesh.roller_surface_size_mm``.
    values : tuple
        The values, as YAML reads them (numbers, booleans, strings), distinct.
    option : str
        How the command line gave it (``--vary KEY=...``, ``--load-kN``): named in errors.
    """

    key: str
    values: tuple
    option: str = ""

    def __post_init__(self) -> None:
        if not self.values:
            raise InputError(f"{self.option or self.key}: no values")

    @property
    def keys(self) -> tuple[str, ...]:
        """The case keys this axis sets (one, or several tied by ``+``)."""
        return tied_keys(self.key)


def tied_keys(key: str) -> tuple[str, ...]:
    """The case keys of a varied key: ``"a.b+c.d"`` -> ``("a.b", "c.d")``, set to the same
    value in each cell (e.g. the raceway's and the rollers' fine element size, refined
    together in a mesh study)."""
    return tuple(key.split("+"))


@dataclass(frozen=True)
class SweepCell:
    """One case of the grid: what :func:`run_cell` needs, as plain picklable data.

    Attributes
    ----------
    case_path : str
        Absolute path of the case file (the workers must see the same file system).
    values : mapping
        Varied key -> this cell's value, in the order of the axes.
    out_dir : str
        Absolute path of the cell's run folder.
    overrides : tuple of str
        ``key=value`` overrides: the command's own ``--set`` ones first, then the duration
        scaled with speed (if any), then the varied keys.
    threads : int or None
        Taichi CPU threads; ``None``: decided where the task runs (see :func:`run_cell`).
    post : bool
        Make the run's figures and report.
    """

    case_path: str
    values: Mapping[str, object]
    out_dir: str
    overrides: tuple[str, ...] = ()
    threads: int | None = None
    post: bool = True

    @property
    def name(self) -> str:
        return Path(self.out_dir).name


# --------------------------------------------------------------------------- axes


def parse_values(text: str, option: str) -> list[float]:
    """``"25,50,80"`` -> ``[25.0, 50.0, 80.0]`` (positive, distinct, kept in order).

    Raises
    ------
    InputError
        Naming ``option`` on an empty list, a non-number, a value <= 0 or a repeat.
    """
    parts = [p.strip() for p in str(text).split(",")]
    if not parts or any(p == "" for p in parts):
        raise InputError(f"{option}: expected comma-separated numbers, got {text!r}")
    values = []
    for p in parts:
        try:
            v = float(p)
        except ValueError:
            raise InputError(f"{option}: {p!r} is not a number") from None
        if not (math.isfinite(v) and v > 0):
            raise InputError(f"{option}: values must be positive, got {p}")
        if v in values:
            raise InputError(f"{option}: {p} is given twice")
        values.append(v)
    return values


def _yaml_value(text: str, option: str):
    try:
        value = yaml.safe_load(text)
    except yaml.YAMLError:
        raise InputError(f"{option}: {text!r} is not a YAML value") from None
    if isinstance(value, str) and _NUMBER.fullmatch(value):
        return float(value)
    if isinstance(value, (list, dict)):
        raise InputError(f"{option}: {text!r}: one value per comma, not a list or mapping")
    return value


def parse_vary(text: str) -> Axis:
    """``"KEY=v1,v2,..."`` (a ``--vary`` argument) -> :class:`Axis`, values read as YAML
    like ``--set``'s; ``"KEY1+KEY2=v1,v2,..."`` sets both keys to each value. The keys and
    values are checked against the case schema later, when the cells are made
    (:func:`make_cells`).

    Raises
    ------
    InputError
        Naming the argument: no ``=``, no key, an empty or non-YAML value, a repeat.

    Examples
    --------
    >>> parse_vary("contact.penalty_scale=0.1,0.3,1e0").values
    (0.1, 0.3, 1.0)
    >>> parse_vary("mesh.spall_size_mm+mesh.roller_surface_size_mm=0.5,0.25").keys
    ('mesh.spall_size_mm', 'mesh.roller_surface_size_mm')
    """
    key, sep, rest = str(text).partition("=")
    key = key.strip()
    option = f"--vary {text}"
    keys = tied_keys(key)
    if not sep or any(not k or any(c.isspace() for c in k) for k in keys):
        raise InputError(f"--vary: expected KEY=v1,v2,... or KEY1+KEY2=v1,v2,..., got {text!r}")
    if len(set(keys)) < len(keys):
        raise InputError(f"{option}: a key is tied to itself")
    parts = [p.strip() for p in rest.split(",")]
    if any(p == "" for p in parts):
        raise InputError(f"{option}: expected comma-separated values")
    values: list = []
    for p in parts:
        v = _yaml_value(p, option)
        # 1 and 1.0 are one value (the same case); True is not 1
        if any(v == u and type(v) is type(u) or _same_number(v, u) for u in values):
            raise InputError(f"{option}: {p} is given twice")
        values.append(v)
    return Axis(key, tuple(values), option)


def _same_number(a, b) -> bool:
    numbers = (int, float)
    return (
        isinstance(a, numbers)
        and isinstance(b, numbers)
        and not isinstance(a, bool)
        and not isinstance(b, bool)
        and a == b
    )


def numeric_axis(axis: Axis, minimum: int = 1) -> list[float]:
    """The axis's values as floats, at least ``minimum`` of them.

    Raises
    ------
    InputError
        Naming the axis's option on a value that is not a finite number or too few values.
    """
    out = []
    for v in axis.values:
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InputError(f"{axis.option}: {v!r} is not a number")
        out.append(float(v))
    if len(out) < minimum:
        raise InputError(f"{axis.option}: needs at least {minimum} values, got {len(out)}")
    return out


def _yaml_text(value) -> str:
    """A value as ``--set`` text that YAML reads back as the same value."""
    if isinstance(value, float):
        if not math.isfinite(value):
            return ".nan" if math.isnan(value) else (".inf" if value > 0 else "-.inf")
        text = repr(value)
        mantissa, e, exponent = text.partition("e")
        # YAML 1.1 wants a dot and a signed exponent to read a float
        if e and "." not in mantissa:
            text = f"{mantissa}.0e{exponent if exponent[0] in '+-' else '+' + exponent}"
        return text
    return json.dumps(value)  # JSON scalars are YAML: 1, true, null, "soft"


# --------------------------------------------------------------------------- names


def _key_unit(key: str) -> tuple[str, str]:
    """``operating.load_kN`` -> (``load_kN``, ``kN``); no unit for a key the schema does
    not declare with one. Tied keys: the first one's."""
    section, _, name = tied_keys(key)[0].rpartition(".")
    sec = SECTIONS.get(section)
    k = sec.find(name) if sec is not None else None
    return name, (k.unit if k is not None else "")


def column_labels(keys: Iterable[str]) -> dict[str, str]:
    """The column of each varied key in a study's tables: its last component
    (``load_kN``), or the whole key with ``_`` for dots where two keys share it; tied keys
    by their first key's (``spall_size_mm``)."""
    keys = list(keys)
    last = [tied_keys(k)[0].rpartition(".")[2] for k in keys]
    return {
        k: (s if last.count(s) == 1 else tied_keys(k)[0].replace(".", "_"))
        for k, s in zip(keys, last, strict=True)
    }


def _value_text(value) -> str:
    """A value in a folder name: 25.0 -> "25", 2.5 -> "2p5", -4.25 -> "-4p25", "soft"."""
    if isinstance(value, bool) or value is None:
        return json.dumps(value)
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return f"{value:g}".replace(".", "p").replace("+", "")
    return re.sub(r"[^A-Za-z0-9-]+", "-", str(value)).strip("-") or "empty"


def _schema_rank(key: str) -> tuple:
    """Where a key stands in the case schema (sections, then their keys, in order); keys
    it does not declare (sensors) after them, by name. Tied keys: where the first stands."""
    key = tied_keys(key)[0]
    section, _, name = key.rpartition(".")
    names = list(SECTIONS)
    if section in SECTIONS:
        keys = [k.name for k in SECTIONS[section].keys]
        if name in keys:
            return (names.index(section), keys.index(name), "")
    return (len(names), 0, key)


def cell_dir_name(values: Mapping[str, object]) -> str:
    """Run folder name of a cell from its key=value pairs, in the case schema's order
    (whatever order the keys were varied in): the key's name with its value before the
    unit, e.g. ``load_50kN_speed_500rpm``, ``penalty_scale_0p3``.

    Examples
    --------
    >>> cell_dir_name({"operating.speed_rpm": 500.0, "operating.load_kN": 50.0})
    'load_50kN_speed_500rpm'
    >>> cell_dir_name({"run.first_roller_angle_deg": -4.25})
    'first_roller_angle_-4p25deg'
    """
    labels = column_labels(values)
    parts = []
    for key in sorted(values, key=_schema_rank):
        _, unit = _key_unit(key)
        stem = labels[key][: -len(unit) - 1] if unit else labels[key]
        parts.append(f"{stem}_{_value_text(values[key])}{unit}")
    return "_".join(parts)


# --------------------------------------------------------------------------- cells


def _duration_overrides(case, speed_rpm: float) -> list[str]:
    """Duration and intervals scaled by (case speed / cell speed): every cell covers the
    same roller travel, so the same spall passages, whatever its speed."""
    factor = case.operating.shaft_rpm / speed_rpm
    run = case.run
    # Case units are ms; the loaded Case holds seconds.
    return [
        f"run.duration_ms={run.duration * factor * 1e3!r}",
        f"run.frame_interval_ms={run.frame_interval * factor * 1e3!r}",
        f"run.checkpoint_interval_ms={run.checkpoint_interval * factor * 1e3!r}",
    ]


def _load_cell(case_path: Path, overrides: Sequence[str], origin: Mapping[str, str], name: str):
    """The cell's case; an error in a varied value names the axis's option."""
    try:
        return load_case(case_path, overrides)
    except CaseError as exc:
        item = (exc.source or "").removeprefix("--set ")
        if item in origin:
            raise CaseError(exc.key, exc.message, origin[item]) from None
        raise InputError(f"cell {name}: {exc}") from None


def make_cells(
    case_path: str | os.PathLike,
    axes: Sequence[Axis],
    out_dir: str | os.PathLike,
    overrides: Iterable[str] = (),
    *,
    scale_duration: bool = True,
    threads: int | None = None,
    post: bool = True,
) -> list[SweepCell]:
    """The cells of the grid, each one's case validated here (bad input fails early).

    Parameters
    ----------
    case_path : path
        Case file.
    axes : sequence of Axis
        The varied keys; one cell per combination of their values.
    out_dir : path
        Study folder; cell folders are made inside it (:func:`cell_dir_name`).
    overrides : iterable of str
        ``--set`` overrides applied to every cell (before the varied keys).
    scale_duration : bool
        Where ``operating.speed_rpm`` is varied, scale ``run.duration_ms`` (and the frame
        and checkpoint intervals) by case speed / cell speed, so that every cell covers
        the same roller travel.
    threads, post
        Passed to every cell (see :class:`SweepCell`).

    Raises
    ------
    InputError, CaseError
        On an unreadable case, a bad override, a key varied twice, a cell whose case is
        invalid (naming the ``--vary`` argument of a bad key or value) or two cells that
        would share a folder.
    """
    if not axes:
        raise InputError("--vary: nothing to vary (give --vary KEY=v1,v2,...)")
    keys = [a.key for a in axes]
    seen: list[str] = []
    for a in axes:
        for k in a.keys:
            if k in seen:
                raise InputError(f"{a.option or a.key}: {k} is varied twice")
            seen.append(k)
    case_path = Path(case_path).resolve()
    base = tuple(overrides)
    case = load_case(case_path, base)
    out = Path(out_dir).resolve()
    cells: list[SweepCell] = []
    names: dict[str, dict] = {}
    for combo in itertools.product(*(a.values for a in axes)):
        values = dict(zip(keys, combo, strict=True))
        varied, origin = [], {}
        for a, v in zip(axes, combo, strict=True):
            for k in a.keys:
                varied.append(f"{k}={_yaml_text(v)}")
                origin[varied[-1]] = a.option or f"--vary {a.key}"
        name = cell_dir_name(values)
        cell_case = _load_cell(case_path, (*base, *varied), origin, name)
        timing: list[str] = []
        if scale_duration and SPEED_KEY in seen:
            timing = _duration_overrides(case, cell_case.operating.shaft_rpm)
            # validates the scaled cell (e.g. intervals vs duration)
            _load_cell(case_path, (*base, *timing, *varied), origin, name)
        if name in names:
            raise InputError(
                f"--vary: {names[name]} and {values} would both run in folder {name}; "
                "give values that differ in their first 6 digits"
            )
        names[name] = values
        cells.append(
            SweepCell(
                str(case_path), values, str(out / name), (*base, *timing, *varied), threads, post
            )  # fmt: skip
        )
    return cells
