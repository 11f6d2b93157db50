"""Public bearing data sets: what a record's name says, and how to read it for ``diagnose``.

Two sets are known by their file names:

* Case Western Reserve University (CWRU) Bearing Data Center. Faults seeded by EDM in a
  6205 drive-end and a 6203 fan-end deep-groove ball bearing of a 2 hp motor; names as the
  public mirrors give them, e.g. ``12k_Drive_End_IR007_0_105.mat``,
  ``48k_Drive_End_OR007@6_0_135.mat``, ``12k_Fan_End_B014_2_288.mat``, ``normal_0_97.mat``,
  a folder ``12k Drive End .../IR007_0.mat``, or the data center's own record number
  (``105.mat``, read from the published table of records): fault ``IR`` (inner race), ``OR`` (outer
  race, ``@6``/``@3``/``@12`` o'clock) or ``B`` (ball), size in mils, motor load in hp,
  record number. Channels ``XNNN_DE_time`` (drive end) and
  ``XNNN_FE_time`` (fan end), shaft speed ``XNNNRPM``. A fan-end fault is read on the
  fan-end channel with the fan-end bearing, every other record on the drive end.
* Society for Machinery Failure Prevention Technology (MFPT): ``InnerRaceFault_vload_N``,
  ``OuterRaceFault_N``, ``OuterRaceFault_vload_N``, ``baseline_N``; a struct ``bearing``
  with ``gs`` (g), ``sr`` (Hz), ``rate`` (shaft Hz) and ``load``.

Bearing geometry (inches, from the data sets' own documentation):

* CWRU drive end, SKF 6205-2RS JEM: 9 balls of 0.3126, pitch diameter 1.537, contact 0.
* CWRU fan end, SKF 6203-2RS JEM: 8 balls of 0.2656, pitch diameter 1.122, contact 0
  (BPFO 3.0530, BPFI 4.9469, FTF 0.3817, 2 BSF 3.9874 times the shaft rate).
* MFPT: 8 rollers of 0.235, pitch diameter 1.245, contact 0.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from diagnostics import BearingGeometry, read_signal

__all__ = [
    "CWRU_DRIVE_END",
    "CWRU_FAN_END",
    "MFPT_BEARING",
    "RecordLabel",
    "LabelledRecord",
    "label_from_name",
    "read_labelled_record",
]

_INCH = 25.4e-3
CWRU_DRIVE_END = BearingGeometry(9, 0.3126 * _INCH, 1.537 * _INCH)
CWRU_FAN_END = BearingGeometry(8, 0.2656 * _INCH, 1.122 * _INCH)
MFPT_BEARING = BearingGeometry(8, 0.235 * _INCH, 1.245 * _INCH)
# CWRU nominal motor speed per load (hp), for a record that holds no RPM variable.
CWRU_NOMINAL_RPM = {0: 1797.0, 1: 1772.0, 2: 1750.0, 3: 1730.0}
# The CWRU baseline (normal) records were sampled at 48 kHz.
CWRU_NORMAL_FS = 48_000.0

# Record numbers of the CWRU Bearing Data Center's own file names (``105.mat``): rate and
# end, then the fault and its record numbers at motor loads 0, 1, 2, 3 ("n:load" where the
# series does not start at load 0).
_CWRU_NUMBERS = {
    (12000.0, "drive"): {
        "IR007": "105 106 107 108", "B007": "118 119 120 121", "OR007@6": "130 131 132 133",
        "OR007@3": "144 145 146 147", "OR007@12": "156 158 159 160",
        "IR014": "169 170 171 172", "B014": "185 186 187 188", "OR014@6": "197 198 199 200",
        "IR021": "209 210 211 212", "B021": "222 223 224 225", "OR021@6": "234 235 236 237",
        "OR021@3": "246 247 248 249", "OR021@12": "258 259 260 261",
        "IR028": "3001 3002 3003 3004", "B028": "3005 3006 3007 3008",
    },
    (48000.0, "drive"): {
        "IR007": "109 110 111 112", "B007": "122 123 124 125", "OR007@6": "135 136 137 138",
        "OR007@3": "148 149 150 151", "OR007@12": "161 162 163 164",
        "IR014": "174 175 176 177", "B014": "189 190 191 192", "OR014@6": "201 202 203 204",
        "IR021": "213 214 215 217", "B021": "226 227 228 229", "OR021@6": "238 239 240 241",
        "OR021@3": "250 251 252 253", "OR021@12": "262 263 264 265",
    },
    (12000.0, "fan"): {
        "IR007": "278 279 280 281", "IR014": "274 275 276 277", "IR021": "270 271 272 273",
        "B007": "282 283 284 285", "B014": "286 287 288 289", "B021": "290 291 292 293",
        "OR007@6": "294 295 296 297", "OR007@3": "298 299 300 301",
        "OR007@12": "302 305 306 307", "OR014@3": "310 309 311 312", "OR014@6": "313",
        "OR021@6": "315", "OR021@3": "316:1 317:2 318:3",
    },
    (48000.0, "none"): {"normal": "97 98 99 100"},
}  # fmt: skip


def _number_labels() -> dict[int, RecordLabel]:
    labels = {}
    for (fs, end), series in _CWRU_NUMBERS.items():
        for name, numbers in series.items():
            fault = _CWRU_FAULT.match(name + "_0")
            for load, item in enumerate(numbers.split()):
                number, _, at = item.partition(":")
                load_text = at or str(load)
                if fault is None:
                    labels[int(number)] = RecordLabel(
                        "CWRU", "none", "drive", load=load_text, fs=fs
                    )
                    continue
                labels[int(number)] = RecordLabel(
                    "CWRU",
                    _FAULTS[fault.group(1).lower()],
                    end,
                    size_in=int(fault.group(2)) / 1000.0,
                    position=f"@{fault.group(3)}" if fault.group(3) else "",
                    load=load_text,
                    fs=fs,
                )
    return labels


_CWRU_FAULT = re.compile(r"(?<![a-z])(ir|or|b)(\d{3})(?:@(\d{1,2}))?_(\d)(?!\d)", re.IGNORECASE)
_CWRU_NORMAL = re.compile(r"(?<![a-z])normal(?:[ _-]?baseline)?(?:[ _-]+(\d))?", re.IGNORECASE)
_CWRU_END = re.compile(r"(drive|fan)[ _-]?end|(?<![a-z])(de|fe)(?![a-z])", re.IGNORECASE)
_CWRU_RATE = re.compile(
    r"(?<!\d)(12|48)(?:[ _-]?k(?:hz)?(?![a-z])|(?=[ _-]?(?:drive|fan)[ _-]?end))", re.IGNORECASE
)
# The layout of the ``cwru`` Python package's downloads: ``12DriveEndFault/1797/0.007-Ball.mat``,
# ``0.021-OuterRace6.mat``, ``NormalBaseline/1772/Normal.mat``; the load from the speed folder.
_CWRU_SIZE_FAULT = re.compile(
    r"(?<![\d.])0?\.(\d{3})[ _-]*(ball|inner[ _-]?race|outer[ _-]?race)(\d{1,2})?(?![a-z])",
    re.IGNORECASE,
)
_CWRU_LOAD_RPM = re.compile(r"(?<!\d)(1797|1772|1750|1730)(?!\d)")
_MFPT = re.compile(r"(innerrace|outerrace)fault|(?<![a-z])baseline_\d", re.IGNORECASE)
_FAULTS = {"ir": "inner", "or": "outer", "b": "ball"}


@dataclass(frozen=True)
class RecordLabel:
    """What a public record's name says about it.

    Attributes
    ----------
    source : str
        ``"CWRU"`` or ``"MFPT"``.
    fault : str
        ``"outer"``, ``"inner"``, ``"ball"`` or ``"none"`` (a baseline record).
    end : str
        CWRU: ``"drive"`` or ``"fan"`` (the bearing that carries the fault, the drive end for
        a baseline); MFPT: ``"-"``.
    size_in : float or None
        Fault diameter in inches (CWRU).
    position : str
        Outer-race fault position, e.g. ``"@6"`` (CWRU), else ``""``.
    load : str
        Motor load in hp (CWRU), the MFPT record's series, or ``""``.
    fs : float or None
        Sampling rate the name implies (CWRU ``12k``/``48k``, baseline 48 kHz), or None.
    """

    source: str
    fault: str
    end: str
    size_in: float | None = None
    position: str = ""
    load: str = ""
    fs: float | None = None

    @property
    def group(self) -> str:
        """The benchmark table row the record counts in (its set, its rate and the end)."""
        if self.source == "MFPT":
            return "MFPT"
        rate = f" {self.fs / 1000:g}k" if self.fs else ""
        return f"CWRU{rate} {self.end} end"


@dataclass(frozen=True)
class LabelledRecord:
    """A record read for diagnosis: samples, rate, speed, bearing and label."""

    path: Path
    x: np.ndarray
    fs: float
    shaft_hz: float
    geometry: BearingGeometry
    channel: str
    label: RecordLabel


def label_from_name(path) -> RecordLabel | None:
    """Label of a CWRU or MFPT record from its path, or None for a name neither set uses.

    The whole path is read, so ``48k Drive End/OR007@6_0.mat`` takes the rate and end
    from its folder.

    Examples
    --------
    >>> label_from_name("12k_Fan_End_OR014@3_1_309.mat")
    RecordLabel(source='CWRU', fault='outer', end='fan', size_in=0.014, position='@3', load='1', fs=12000.0)
    >>> label_from_name("normal_0_97.mat").fault
    'none'
    >>> label_from_name("mfpt/InnerRaceFault_vload_3.mat").fault
    'inner'
    >>> label_from_name("317.mat")                  # the data center's own file name
    RecordLabel(source='CWRU', fault='outer', end='fan', size_in=0.021, position='@3', load='2', fs=12000.0)
    >>> label_from_name("12FanEndFault/1772/0.014-OuterRace3.mat")  # the cwru package's
    RecordLabel(source='CWRU', fault='outer', end='fan', size_in=0.014, position='@3', load='1', fs=12000.0)
    >>> label_from_name("notes.mat") is None
    True
    """  # noqa: E501
    text = str(Path(path).as_posix())
    name = Path(path).name
    mfpt = _MFPT.search(name)
    if mfpt:
        kind = (mfpt.group(1) or "baseline").lower()
        fault = {"innerrace": "inner", "outerrace": "outer"}.get(kind, "none")
        series = re.search(r"(vload_\d+|_\d+)\.", name)
        return RecordLabel("MFPT", fault, "-", load=series.group(1).strip("_.") if series else "")
    rate = _last(_CWRU_RATE, text)
    fs = float(rate.group(1)) * 1000.0 if rate else None
    fault = _last(_CWRU_FAULT, name) or _last(_CWRU_FAULT, text)
    sized = None if fault else _last(_CWRU_SIZE_FAULT, name)
    if sized:
        kind = sized.group(2).lower()[0]
        return RecordLabel(
            "CWRU",
            {"b": "ball", "i": "inner", "o": "outer"}[kind],
            _end_from(text),
            size_in=int(sized.group(1)) / 1000.0,
            position=f"@{sized.group(3)}" if sized.group(3) and kind == "o" else "",
            load=_load_from_rpm(text),
            fs=fs,
        )
    if fault:
        return RecordLabel(
            "CWRU",
            _FAULTS[fault.group(1).lower()],
            _end_from(text),
            size_in=int(fault.group(2)) / 1000.0,
            position=f"@{fault.group(3)}" if fault.group(3) else "",
            load=fault.group(4),
            fs=fs,
        )
    normal = _last(_CWRU_NORMAL, name) or _last(_CWRU_NORMAL, text)
    if normal:
        load = normal.group(1) or _load_from_rpm(text)
        return RecordLabel("CWRU", "none", "drive", load=load, fs=CWRU_NORMAL_FS)
    number = re.fullmatch(r"x?0*(\d+)", Path(path).stem, re.IGNORECASE)
    if number:  # the data center's own names: the record number alone
        return _NUMBER_LABELS.get(int(number.group(1)))
    return None


_NUMBER_LABELS = _number_labels()


def _end_from(text: str) -> str:
    """The end a CWRU path names (drive end unless it names the fan end)."""
    match = _last(_CWRU_END, text)
    if match and (match.group(1) or match.group(2))[0].lower() == "f":
        return "fan"
    return "drive"


def _load_from_rpm(text: str) -> str:
    """Motor load (hp) of a path holding a nominal speed folder (1797 rpm: 0), or ""."""
    match = _last(_CWRU_LOAD_RPM, text)
    if match is None:
        return ""
    by_rpm = {int(rpm): load for load, rpm in CWRU_NOMINAL_RPM.items()}
    return str(by_rpm[int(match.group(1))])


def _last(pattern: re.Pattern, text: str):
    matches = list(pattern.finditer(text))
    return matches[-1] if matches else None


def read_labelled_record(
    path, label: RecordLabel | None = None, end: str | None = None
) -> LabelledRecord:
    """Read a CWRU or MFPT record with the channel, rate, speed and bearing its label implies.

    Parameters
    ----------
    path : str or path-like
        A ``.mat`` record of either set.
    label : RecordLabel, optional
        Default: :func:`label_from_name`.
    end : {"drive", "fan"}, optional
        CWRU only: read this end's accelerometer with this end's bearing instead of the
        faulty one's (the other end is healthy in every record of the set).

    Returns
    -------
    LabelledRecord

    Raises
    ------
    ValueError
        If the name is neither set's, the file lacks the channel, or no speed or rate can
        be found.
    """
    path = Path(path)
    label = label if label is not None else label_from_name(path)
    if label is None:
        raise ValueError(f"{path}: not a CWRU or MFPT record name")
    if end is not None and (label.source != "CWRU" or end not in ("drive", "fan")):
        raise ValueError(f"{path}: end must be 'drive' or 'fan' for a CWRU record, got {end!r}")
    if label.source == "MFPT":
        sig = read_signal(path)
        if "rpm" not in sig.meta:
            raise ValueError(f"{path}: no shaft rate in the file (bearing.rate)")
        return LabelledRecord(
            path, sig.x, sig.fs, sig.meta["rpm"] / 60.0, MFPT_BEARING, sig.name, label
        )
    if label.fs is None:
        raise ValueError(f"{path}: the name gives no sampling rate (12k or 48k)")
    names = read_signal(path, channel=0, fs=label.fs).meta["channels"]
    end = end or label.end
    suffix = "_FE_time" if end == "fan" else "_DE_time"
    candidates = [c for c in names if c.endswith(suffix)]
    if not candidates:
        raise ValueError(f"{path}: no *{suffix} channel; channels: {', '.join(names)}")
    # The record's own number first: some files carry a second record's channels too.
    number = re.search(r"(\d+)$", path.stem)
    own = [c for c in candidates if number and re.match(rf"X0*{int(number.group(1))}_", c)]
    channel = (own or candidates)[0]
    sig = read_signal(path, channel=channel, fs=label.fs)
    rpm = sig.meta.get("rpm")
    if rpm is None or not np.isfinite(rpm) or rpm <= 0:
        rpm = CWRU_NOMINAL_RPM.get(int(label.load or 0), CWRU_NOMINAL_RPM[0])
    geometry = CWRU_FAN_END if end == "fan" else CWRU_DRIVE_END
    return LabelledRecord(path, sig.x, sig.fs, rpm / 60.0, geometry, channel, label)
