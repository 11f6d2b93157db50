"""What the command line takes and refuses: :class:`UsageError` (one line, exit status 2),
the ``--bearing`` geometry with units, and the checks of ``--fs`` and ``--notch``."""

from __future__ import annotations

import math
import re

from diagnostics import BearingGeometry

__all__ = ["MAX_FS_HZ", "UsageError", "check_fs_option", "check_notches", "parse_bearing"]

_LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "in": 25.4e-3}
# Highest sampling rate taken for a vibration record (acoustic-emission systems reach tens
# of MHz); a larger --fs is a typo or a unit slip.
MAX_FS_HZ = 1e8


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


def _length(text: str, key: str) -> float:
    match = re.fullmatch(r"\s*([-+0-9.eE]+)\s*([a-z]+)\s*", text)
    if not match or match.group(2) not in _LENGTH_UNITS:
        raise UsageError(
            f"--bearing {key}={text!r}: give a length with a unit "
            f"({', '.join(_LENGTH_UNITS)}), e.g. {key}=7.94mm"
        )
    try:
        value = float(match.group(1))
    except ValueError:
        raise UsageError(f"--bearing {key}={text!r}: not a number") from None
    return value * _LENGTH_UNITS[match.group(2)]


def parse_bearing(text: str) -> BearingGeometry:
    """Parse ``n=9,d=7.94mm,D=39.04mm[,angle=0]`` into a BearingGeometry (metres, degrees).

    Raises
    ------
    UsageError
        On a malformed item, an unknown or missing key, or an invalid geometry.
    """
    items: dict[str, str] = {}
    for part in filter(None, (p.strip() for p in text.split(","))):
        key, sep, value = part.partition("=")
        if not sep or not value.strip():
            raise UsageError(f"--bearing: expected key=value, got {part!r}")
        key = key.strip()
        if key not in ("n", "d", "D", "angle"):
            raise UsageError(f"--bearing: unknown key {key!r} (use n, d, D, angle)")
        items[key] = value.strip()
    missing = [k for k in ("n", "d", "D") if k not in items]
    if missing:
        raise UsageError(
            f"--bearing: missing {', '.join(missing)} (e.g. n=9,d=7.94mm,D=39.04mm,angle=0)"
        )
    try:
        n = int(items["n"])
    except ValueError:
        raise UsageError(f"--bearing n={items['n']!r}: not an integer") from None
    try:
        angle = float(items.get("angle", "0"))
    except ValueError:
        raise UsageError(f"--bearing angle={items['angle']!r}: not a number (degrees)") from None
    try:
        return BearingGeometry(n, _length(items["d"], "d"), _length(items["D"], "D"), angle)
    except ValueError as exc:
        raise UsageError(f"--bearing: {exc}") from None


def check_fs_option(fs: float | None) -> None:
    """Refuse an ``--fs`` that is no sampling rate (not positive, or beyond ``MAX_FS_HZ``)."""
    if fs is None:
        return
    if not (math.isfinite(fs) and fs > 0):
        raise UsageError(f"--fs must be a positive frequency in Hz, got {fs:g}")
    if fs > MAX_FS_HZ:
        raise UsageError(
            f"--fs {fs:g} Hz is beyond any vibration record's sampling rate "
            f"(at most {MAX_FS_HZ:g} Hz); give the rate in Hz, e.g. --fs 12000"
        )


def check_notches(notches: list[float], fs: float) -> None:
    """Each ``--notch`` frequency strictly between 0 and fs/2."""
    for f0 in notches:
        if not (math.isfinite(f0) and 0.0 < f0 < fs / 2.0):
            raise UsageError(
                f"--notch {f0:g} Hz is outside 0..{fs / 2.0:g} Hz (fs/2, the Nyquist "
                f"frequency at {fs:g} Hz)"
            )
