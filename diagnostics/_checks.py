"""Input validation shared by every public function of ``diagnostics``, and the record's
scale (:func:`normalise`, :class:`RecordScale`) every estimator goes through.

Each check raises ``ValueError`` with a one-line message naming the offending argument, so a
user sees what to fix without reading a traceback.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

import numpy as np

from diagnostics._frequencies import BearingGeometry


def check_fs(fs: float, name: str = "fs") -> float:
    """Return ``fs`` as a float after checking it is a finite positive number (Hz).

    Raises
    ------
    ValueError
        If ``fs`` is not a real number, not finite or not positive.
    """
    return check_positive(fs, name, unit=" in Hz")


def check_signal(x, fs: float, name: str = "x", min_length: int = 2) -> np.ndarray:
    """Return ``x`` as a 1-D float64 array after validating it and the sampling rate.

    Parameters
    ----------
    x : array_like
        The signal. A column or row vector (shape (n, 1) or (1, n)) is flattened.
    fs : float
        Sampling rate in Hz (checked to be finite and positive).
    name : str
        Argument name used in error messages.
    min_length : int
        Fewest samples the caller needs.

    Raises
    ------
    ValueError
        If ``x`` is empty, not numeric, not 1-D, shorter than ``min_length``, holds NaN or
        inf, or ``fs`` is not a positive finite number.
    """
    arr = _numeric_array(x, name, "1-D numeric array")
    if arr.ndim == 2 and 1 in arr.shape:
        arr = arr.reshape(-1)
    if arr.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got an array of shape {arr.shape}")
    return check_signals(arr, fs, name=name, min_length=min_length)


def _numeric_array(x, name: str, what: str = "numeric array") -> np.ndarray:
    """``x`` as an array, refused when it is not real and numeric."""
    try:
        arr = np.asarray(x)
    except Exception as exc:  # ragged lists and the like
        raise ValueError(f"{name} must be a {what} ({exc})") from None
    if arr.dtype.kind == "c":
        raise ValueError(f"{name} must be real-valued, got a complex array")
    if arr.dtype.kind not in "biuf":
        raise ValueError(f"{name} must be a {what}, got dtype {arr.dtype}")
    return arr


def check_signals(x, fs: float, axis: int = -1, name: str = "x", min_length: int = 2) -> np.ndarray:
    """Return ``x`` as a float64 array with its time axis last, after validating it.

    The multi-channel counterpart of :func:`check_signal`, for functions that take
    ``axis``: any number of dimensions, samples along ``axis``, every other axis a channel.
    As before ``axis`` existed, a column vector (shape (n, 1)) with the default ``axis=-1``
    is one record of n samples.

    Returns
    -------
    numpy.ndarray
        The data with ``axis`` moved to the end (1-D for a single record). Use
        ``numpy.moveaxis(result, -1, axis)`` to put an output's time axis back.

    Raises
    ------
    ValueError
        If ``x`` is empty or not real and numeric, ``axis`` is out of range, the time axis
        is shorter than ``min_length``, ``x`` holds NaN or inf, or ``fs`` is invalid.
    """
    check_fs(fs)
    arr = _numeric_array(x, name)
    if arr.ndim == 0 or arr.size == 0:
        raise ValueError(f"{name} is empty")
    if isinstance(axis, bool) or not isinstance(axis, int | np.integer):
        raise ValueError(f"axis must be an integer, got {axis!r}")
    if not -arr.ndim <= axis < arr.ndim:
        raise ValueError(f"axis {axis} is out of range for {name} of shape {arr.shape}")
    if arr.ndim == 2 and axis == -1 and arr.shape[1] == 1:
        arr = arr[:, 0]
    arr = np.moveaxis(arr, axis, -1) if arr.ndim > 1 else arr
    if arr.shape[-1] < min_length:
        along = " along axis" if arr.ndim > 1 else ""
        raise ValueError(
            f"{name} is too short for this request: {arr.shape[-1]} samples{along}, need at "
            f"least {min_length}"
        )
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    finite = np.isfinite(arr)
    if not finite.all():
        bad = [int(i) for i in np.unravel_index(int(np.argmin(finite)), arr.shape)]
        channel = ", ".join(map(str, bad[:-1]))
        where = f"sample {bad[-1]}" + (f" of channel {channel}" if arr.ndim > 1 else "")
        raise ValueError(f"{name} holds NaN or inf (first at {where})")
    return arr


def check_varying(x: np.ndarray, name: str = "x") -> np.ndarray:
    """Return ``x`` after checking that it varies along its last axis.

    A constant record (a dead sensor, a disconnected channel, a file of zeros) carries no
    vibration; analyses that normalise by the signal's spread would divide by zero.

    Raises
    ------
    ValueError
        If every sample of ``x`` (of any channel, for a 2-D ``x``) has the same value.
    """
    arr = np.asarray(x)
    flat = arr.reshape(-1, arr.shape[-1]) if arr.ndim > 1 else arr[None, :]
    # max == min rather than a range of zero: the range of a record near 1e308 overflows
    constant = np.flatnonzero(flat.max(axis=-1) == flat.min(axis=-1))
    if constant.size:
        where = "" if arr.ndim <= 1 else f" (channel {int(constant[0])})"
        raise ValueError(
            f"{name} is constant{where}, every sample {float(flat[constant[0], 0]):g}: "
            "a dead sensor or a flat record holds no vibration to analyse"
        )
    return x


# A record is analysed as given where each channel's largest magnitude lies in
# 2**-64 .. 2**64, which holds every unit a vibration record comes in (g, m/s^2, mV, counts
# of a 32-bit converter, metres): its results stay what they were, bit for bit. Beyond, the
# squares and fourth powers the estimators form would overflow or underflow, and the channel
# is rescaled first (frexp exponents: a peak m * 2**e, 0.5 <= m < 1).
_MIN_EXPONENT, _MAX_EXPONENT = -63, 64


@dataclass(frozen=True, eq=False)
class RecordScale:
    """The powers of two a record's channels were divided by (:func:`normalise`).

    Attributes
    ----------
    exponent : numpy.ndarray
        Integer exponent ``e`` of each channel (shape: the channel axes, then 1), the
        channel divided by :math:`2^e`; 0 for a channel analysed as given.
    """

    exponent: np.ndarray

    @property
    def identity(self) -> bool:
        """Whether every channel was analysed as given."""
        return not self.exponent.any()

    def restore(self, y, power: int = 1, what: str = "the result", trailing: int = 1):
        r"""``y``, computed from the rescaled record, in the record's own unit.

        Multiplying by :math:`2^{\mathrm{power} \cdot e}` is exact: it adds no rounding to the
        result, and leaves an untouched record's result as it is.

        Parameters
        ----------
        y : numpy.ndarray
            Real or complex result: the channel axes first, then ``trailing`` axes of its
            own.
        power : int
            Power of the record's unit the result carries (1: an amplitude, 2: a power).
        what : str
            What ``y`` is, for the error message.
        trailing : int
            Number of axes of ``y`` after the channel axes.

        Raises
        ------
        ValueError
            If a channel's result, in the record's unit, lies outside the range of float64
            (its largest value would overflow, or fall below the smallest normal number).
        """
        if self.identity:
            return y
        e = power * self.exponent.reshape(self.exponent.shape[:-1] + (1,) * trailing)
        y = np.asarray(y)
        parts = (y.real, y.imag) if np.iscomplexobj(y) else (y,)
        out = np.empty_like(y)
        restored = (out.real, out.imag) if np.iscomplexobj(y) else (out,)
        axes = tuple(range(-trailing, 0))
        peak = np.zeros(e.shape)
        for part, into in zip(parts, restored, strict=True):
            with np.errstate(over="ignore", under="ignore"):
                into[...] = np.ldexp(part, e)
            peak = np.maximum(peak, np.max(np.abs(part), axis=axes, keepdims=True))
        with np.errstate(over="ignore", under="ignore"):
            reached = np.ldexp(peak, e)
        bad = ~np.isfinite(reached) | ((peak > 0.0) & (reached < np.finfo(float).tiny))
        if bad.any():
            i = np.flatnonzero(bad)[0]
            decade = math.log10(float(peak.flat[i])) + int(e.flat[i]) * math.log10(2.0)
            unit = "larger" if decade > 0 else "smaller"
            raise ValueError(
                f"{what} is out of the range of float64 numbers (it would reach 1e{decade:+.0f}"
                f"): give x in a {unit} unit"
            )
        return out

    def decibels(self, power: int = 2) -> np.ndarray | float:
        r""":math:`10 \log_{10} 2^{\mathrm{power} \cdot e}` per channel: what a level in dB of
        a result carrying ``power`` of the record's unit gains back (0.0 for an untouched
        record)."""
        if self.identity:
            return 0.0
        return 10.0 * power * math.log10(2.0) * self.exponent


def normalise(x: np.ndarray) -> tuple[np.ndarray, RecordScale]:
    r"""``x`` (time axis last) ready for an estimator, and the scale to restore results by.

    Every estimator of ``diagnostics`` goes through this, so that a record's unit does not
    change a result: each channel whose largest magnitude lies outside
    :math:`2^{-64} \dots 2^{64}` is divided by the power of two that brings it into
    :math:`[0.5, 1)` (exact in
    floating point, so quantities without a unit, such as kurtosis, p-values, frequencies
    and verdicts, come out as from any other power-of-two scaling of the record, and
    amplitudes restored by :meth:`RecordScale.restore` bit for bit). Other channels are
    left as they are.

    Parameters
    ----------
    x : numpy.ndarray
        Checked record (see :func:`check_signals`), samples along the last axis.

    Returns
    -------
    x : numpy.ndarray
        The record, rescaled where needed (``x`` itself where no channel is).
    scale : RecordScale
        The power of two of each channel.
    """
    peak = np.max(np.abs(x), axis=-1, keepdims=True)
    exponent = np.frexp(peak)[1]  # 0 for an all-zero channel: left as it is
    outside = (exponent < _MIN_EXPONENT) | (exponent > _MAX_EXPONENT)
    scale = RecordScale(np.where(outside, exponent, 0))
    return (x if scale.identity else np.ldexp(x, -scale.exponent)), scale


def check_frequency(f: float, fs: float, name: str = "f") -> float:
    """Return ``f`` as a float after checking 0 < f < fs/2.

    Raises
    ------
    ValueError
        If ``f`` is not a finite number strictly between 0 and the Nyquist frequency.
    """
    fs = check_fs(fs)
    if isinstance(f, bool) or not isinstance(f, Real | np.floating | np.integer):
        raise ValueError(f"{name} must be a frequency in Hz, got {f!r}")
    value = float(f)
    nyquist = fs / 2.0
    if not math.isfinite(value) or value <= 0.0 or value >= nyquist:
        raise ValueError(f"{name} = {f!r} Hz is outside the open range 0..{nyquist:g} Hz (fs/2)")
    return value


def check_band(f_lo: float, f_hi: float, fs: float, name: str = "band") -> tuple[float, float]:
    """Return ``(f_lo, f_hi)`` as floats after checking 0 <= f_lo < f_hi <= fs/2.

    An edge at 0 or at fs/2 is allowed: a band from 0 is a low-pass, a band to fs/2 a
    high-pass, and (0, fs/2) the whole spectrum (the kurtogram's level-0 band).

    Raises
    ------
    ValueError
        If an edge is not a finite number, the band is empty or reversed, or it reaches
        outside 0..fs/2.
    """
    fs = check_fs(fs)
    nyquist = fs / 2.0
    edges = []
    for label, value in (("lower edge", f_lo), ("upper edge", f_hi)):
        if isinstance(value, bool) or not isinstance(value, Real | np.floating | np.integer):
            raise ValueError(f"{name} {label} must be a frequency in Hz, got {value!r}")
        if not math.isfinite(float(value)):
            raise ValueError(f"{name} {label} must be finite, got {value!r}")
        edges.append(float(value))
    lo, hi = edges
    if not 0.0 <= lo < hi <= nyquist:
        raise ValueError(
            f"{name} ({lo:g}, {hi:g}) Hz must satisfy 0 <= low < high <= fs/2 = {nyquist:g} Hz"
        )
    return lo, hi


def check_positive_int(value, name: str, minimum: int = 1) -> int:
    """Return ``value`` as an int after checking it is an integer >= ``minimum``.

    Raises
    ------
    ValueError
        If ``value`` is not an integer or is below ``minimum``.
    """
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise ValueError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise ValueError(f"{name} must be at least {minimum}, got {value}")
    return int(value)


def check_positive(value, name: str, unit: str = "") -> float:
    """Return ``value`` as a float after checking it is finite and > 0.

    Raises
    ------
    ValueError
        If ``value`` is not a finite positive number.
    """
    if isinstance(value, bool) or not isinstance(value, Real | np.floating | np.integer):
        raise ValueError(f"{name} must be a number{unit}, got {value!r}")
    out = float(value)
    if not math.isfinite(out) or out <= 0.0:
        raise ValueError(f"{name} must be finite and positive{unit}, got {value!r}")
    return out


def check_bearing_inputs(geometry, fs: float, shaft_hz: float) -> tuple[float, float]:
    """Check the arguments every bearing analysis takes; return ``(fs, shaft_hz)`` as floats.

    Raises
    ------
    ValueError
        If ``geometry`` is not a BearingGeometry or a rate is not finite and positive.
    """
    if not isinstance(geometry, BearingGeometry):
        raise ValueError(f"geometry must be a BearingGeometry, got {type(geometry).__name__}")
    fs = check_positive(fs, "fs", unit=" in Hz")
    shaft_hz = check_positive(shaft_hz, "shaft_hz", unit=" in Hz")
    return fs, shaft_hz
