"""Run :func:`diagnostics.diagnose` over a folder of public bearing records and tabulate.

Each ``.mat`` file whose name :func:`diagnostics.app.datasets.label_from_name` understands (CWRU
or MFPT) is read with its own channel, rate, speed and bearing, diagnosed, and compared with
the fault its name gives. The table counts, per set, end and fault type, how many records
got the right verdict and what the others were called: the measure of Smith and Randall's
CWRU benchmark (MSSP 64-65, 2015), where the verdict is the fault type.
"""

from __future__ import annotations

import math
from collections import Counter, defaultdict
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from diagnostics import diagnose
from diagnostics.app.datasets import RecordLabel, label_from_name, read_labelled_record

__all__ = [
    "BenchmarkResult",
    "find_records",
    "labelled_records",
    "run_benchmark",
    "summary_table",
    "speed_summary",
    "record_rows",
    "record_table",
]

VERDICTS = ("outer", "inner", "ball", "none")
FAMILIES = ("outer", "inner", "ball")
# The column of a verdict that names more than one family (the evidence did not decide).
UNDECIDED = "undecided"
# A speed moved by the record's shaft lines is reported from this relative change on.
_SPEED_SHOWN = 5e-4


@dataclass(frozen=True)
class BenchmarkResult:
    """Verdict on one record.

    Attributes
    ----------
    path : pathlib.Path
        The record.
    group : str
        Table row it belongs to (set, rate, end), e.g. ``"CWRU 48k drive end"``.
    expected : str
        Fault the name gives.
    verdict : str
        Fault ``diagnose`` named, or ``"error"`` when the record could not be diagnosed.
    confidence : float
        Confidence of the verdict (0 on an error).
    detail : str
        Fault size and position (and the families set aside for another source's series,
        with its rate in shaft orders; the speed's correction from the record's own shaft
        lines, or that none were found), or the error message.
    speed_change : float
        Relative change of the shaft rate analysed from the file's (the record's own
        shaft lines; 0 where they were not used).
    shaft_lines : bool or None
        Whether the record shows a shaft series near the file's speed (None where the
        diagnosis does not say, or on an error).
    """

    path: Path
    group: str
    expected: str
    verdict: str
    confidence: float
    detail: str = ""
    speed_change: float = 0.0
    shaft_lines: bool | None = None

    @property
    def correct(self) -> bool:
        return self.verdict == self.expected

    @property
    def undecided(self) -> bool:
        """Whether the verdict names several families (``"outer or ball"``): the evidence
        did not decide between them."""
        return " or " in self.verdict

    @property
    def wrong(self) -> bool:
        """Whether the verdict names one fault family, not the record's: the error that
        sends an engineer to the wrong part (worse than a miss or an undecided verdict)."""
        return self.verdict in FAMILIES and self.verdict != self.expected

    @property
    def column(self) -> str:
        """The verdict's column in the table (a family, ``"none"``, ``"undecided"`` or
        ``"error"``)."""
        return UNDECIDED if self.undecided else self.verdict


def find_records(folder) -> list[Path]:
    """Every ``.mat`` file below ``folder`` whose name is a CWRU or MFPT record, sorted.

    Raises
    ------
    ValueError
        If ``folder`` is not a folder.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise ValueError(f"{folder}: not a folder (give a folder of CWRU or MFPT .mat records)")
    return sorted(p for p in folder.rglob("*") if _is_record(p))


def _is_record(path: Path) -> bool:
    return path.suffix.lower() == ".mat" and path.is_file() and label_from_name(path) is not None


def labelled_records(
    paths: Iterable, other_bearing: bool = False
) -> list[tuple[Path, RecordLabel]]:
    """The records :func:`run_benchmark` diagnoses, each with its label: those whose name
    either set uses (with ``other_bearing``, the CWRU ones only: MFPT records have one
    bearing)."""
    chosen = []
    for path in map(Path, paths):
        label = label_from_name(path)
        if label is not None and not (other_bearing and label.source != "CWRU"):
            chosen.append((path, label))
    return chosen


def run_benchmark(
    paths: Iterable,
    diagnose_fn: Callable = diagnose,
    progress: Callable[[BenchmarkResult], None] | None = None,
    other_bearing: bool = False,
    **options,
) -> list[BenchmarkResult]:
    """Diagnose every record and compare with its label.

    Parameters
    ----------
    paths : iterable of path-like
        Records (see :func:`find_records`).
    diagnose_fn : callable
        ``diagnose_fn(x, fs, geometry, shaft_hz, **options)`` returning an object with
        ``fault`` and ``confidence`` (default :func:`diagnostics.diagnose`).
    progress : callable, optional
        Called with each result as it is made.
    other_bearing : bool
        A false-alarm check on measured data: read each CWRU record's other accelerometer
        with the other end's bearing, which is healthy in every record of the set, so the
        right verdict is ``"none"`` (MFPT records, one bearing, are left out). The detail
        says where that channel is a copy of the faulty end's (some 48 kHz files): there
        the check applies the wrong bearing to the faulty signal itself.
    **options
        Passed to ``diagnose_fn``.

    Returns
    -------
    list of BenchmarkResult
        One per record; a record that cannot be read or diagnosed has verdict ``"error"``.

    References
    ----------
    Smith, W. A. and Randall, R. B. (2015). Rolling element bearing diagnostics using the
    Case Western Reserve University data: a benchmark study. *Mechanical Systems and Signal
    Processing* 64-65, 100-131.
    """
    results = []
    for path, label in labelled_records(paths, other_bearing):
        detail = f"{label.size_in:.3f} in{label.position}" if label.size_in else ""
        group, expected, end = label.group, label.fault, None
        if other_bearing:
            end = "fan" if label.end == "drive" else "drive"
            group, expected = f"{group}, {end}-end channel and bearing", "none"
        try:
            rec = read_labelled_record(path, label, end=end)
            copies = other_bearing and _copies(rec.x, read_labelled_record(path, label).x)
            d = diagnose_fn(rec.x, rec.fs, rec.geometry, rec.shaft_hz, **options)
            notes = [f"channel copies the {label.end} end's"] if copies else []
            notes += _notes(d, rec.shaft_hz)
            if notes:
                detail = f"{detail} ({'; '.join(notes)})".strip()
            lines = getattr(d, "shaft_lines", None)
            result = BenchmarkResult(
                path,
                group,
                expected,
                d.fault,
                float(d.confidence),
                detail,
                float(getattr(d, "speed_change", 0.0)),
                None if lines is None else bool(lines.present),
            )
        except ValueError as exc:
            result = BenchmarkResult(path, group, expected, "error", 0.0, str(exc))
        if progress is not None:
            progress(result)
        results.append(result)
    return results


def _notes(d, shaft_hz: float) -> list[str]:
    """What a record's detail says of a diagnosis besides the fault size: the families set
    aside for another source's series, and a speed the record's shaft lines corrected or
    could not confirm (``shaft_hz``: the file's speed, where ``d`` gives none)."""
    notes = []
    frequencies = getattr(d, "frequencies", None)
    shaft = frequencies.shaft if frequencies is not None else shaft_hz
    aside = getattr(d, "dominated", ())
    if aside:
        orders = d.other_series[0] / shaft
        notes.append(f"set aside: {', '.join(aside)}; other series at {orders:.3f} orders")
    lines = getattr(d, "shaft_lines", None)
    if lines is not None and getattr(d, "domain", "time") == "time":
        if not lines.present:
            notes.append(f"no shaft lines within {100 * lines.tolerance:g} % of the speed")
        elif abs(d.speed_change) >= _SPEED_SHOWN:
            notes.append(f"speed {100.0 * d.speed_change:+.1f} % from the shaft lines")
    return notes


def _copies(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two channels of a record hold the same signal (correlation above 0.999)."""
    n = min(a.size, b.size)
    a, b = a[:n] - a[:n].mean(), b[:n] - b[:n].mean()
    scale = math.sqrt(float(a @ a) * float(b @ b))
    return scale > 0.0 and float(a @ b) / scale > 0.999


def summary_table(results: list[BenchmarkResult]) -> str:
    """Plain-text table: per set/end and fault, records, correct and every verdict given.

    Examples
    --------
    >>> r = [BenchmarkResult(Path("a.mat"), "MFPT", "inner", "inner", 1.0),
    ...      BenchmarkResult(Path("b.mat"), "MFPT", "inner", "none", 0.9)]
    >>> print(summary_table(r))
    set   fault  records  correct  outer  inner   ball   none  undecided  error
    MFPT  inner        2      1/2      0      1      0      1          0      0
    all                2      1/2
    wrong fault named: 0 of 2

    ``undecided``: verdicts naming several families (``"outer or ball"``), the evidence
    not deciding between them; a wrong fault named is a single family not the record's.
    """
    groups: dict[tuple[str, str], Counter] = defaultdict(Counter)
    for r in results:
        groups[(r.group, r.expected)][r.column] += 1
    order = {v: i for i, v in enumerate(VERDICTS)}
    keys = sorted(groups, key=lambda k: (k[0], order.get(k[1], 9)))
    width = max([len("set")] + [len(k[0]) for k in keys])
    columns = (*VERDICTS, UNDECIDED, "error")
    head = f"{'set':<{width}}  fault  records  correct  " + "  ".join(f"{v:>5}" for v in columns)
    lines = [head]
    for group, fault in keys:
        counts = groups[(group, fault)]
        n = sum(counts.values())
        cells = "  ".join(f"{counts[v]:>{max(5, len(v))}}" for v in columns)
        lines.append(f"{group:<{width}}  {fault:<5}  {n:>7}  {f'{counts[fault]}/{n}':>7}  {cells}")
    total = len(results)
    right = sum(r.correct for r in results)
    lines.append(f"{'all':<{width}}  {'':<5}  {total:>7}  {f'{right}/{total}':>7}")
    lines.append(f"wrong fault named: {sum(r.wrong for r in results)} of {total}")
    return "\n".join(line.rstrip() for line in lines)


def speed_summary(results: list[BenchmarkResult]) -> str:
    """What the records' own shaft lines said of the files' speeds, in two lines (empty
    where no diagnosis reported its shaft lines).

    Examples
    --------
    >>> r = [BenchmarkResult(Path("a.mat"), "MFPT", "inner", "inner", 1.0, "", -0.0065, True),
    ...      BenchmarkResult(Path("b.mat"), "MFPT", "inner", "none", 1.0, "", 0.0, False)]
    >>> print(speed_summary(r))
    speed read from the shaft lines: 1 of 2 records 0.05 % or more from the file's (-0.65 %)
    no shaft lines within 5 % of the file's speed: b.mat
    """
    checked = [r for r in results if r.shaft_lines is not None]
    if not checked:
        return ""
    moved = [r.speed_change for r in checked if abs(r.speed_change) >= _SPEED_SHOWN]
    span = ""
    if moved:
        lo, hi = 100.0 * min(moved), 100.0 * max(moved)
        span = f" ({lo:+.2f} %)" if lo == hi else f" ({lo:+.2f} to {hi:+.2f} %)"
    missing = [r.path.name for r in checked if not r.shaft_lines]
    lines = [
        f"speed read from the shaft lines: {len(moved)} of {len(checked)} records 0.05 % or "
        f"more from the file's{span}"
    ]
    if missing:
        lines.append(f"no shaft lines within 5 % of the file's speed: {', '.join(missing)}")
    return "\n".join(lines)


def record_rows(results: list[BenchmarkResult]) -> list[dict]:
    """One row per record, as ``--csv`` and ``--html`` write them: record, set, expected,
    verdict, confidence, correct, detail, speed_change, shaft_lines."""
    return [
        {
            "record": str(r.path),
            "set": r.group,
            "expected": r.expected,
            "verdict": r.verdict,
            "confidence": r.confidence,
            "correct": r.correct,
            "detail": r.detail,
            "speed_change": r.speed_change,
            "shaft_lines": r.shaft_lines,
        }
        for r in results
    ]


def record_table(results: list[BenchmarkResult]) -> str:
    """One line per record: file, expected fault, verdict, confidence, detail."""
    width = max([len("record")] + [len(r.path.name) for r in results])
    lines = [f"{'record':<{width}}  expected  verdict  confidence  ok  detail"]
    for r in results:
        ok = "yes" if r.correct else "NO"
        lines.append(
            f"{r.path.name:<{width}}  {r.expected:<8}  {r.verdict:<7}  {r.confidence:>10.2f}"
            f"  {ok:<3} {r.detail}"
        )
    return "\n".join(line.rstrip() for line in lines)
