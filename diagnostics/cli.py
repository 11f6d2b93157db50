"""Command line of ``diagnostics``: ``python -m diagnostics analyze|compare ...``.

Each subcommand is a pair ``add_<name>_arguments(parser)`` / ``run_<name>(args) -> int``
registered in ``COMMANDS``: ``analyze`` (one record); ``compare`` only points to
``python -m taichi_bearing compare``, which reads a simulated run folder and calls
:mod:`diagnostics.compare`. Bad input
is reported as one line on stderr with exit status 2, never a traceback.
"""

from __future__ import annotations

import argparse
import math
import re
import sys
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from bearing_io.files import atomic_path, output_folder, write_json
from bearing_io.progress import LOG_INTERVAL_S, RecordProgress
from diagnostics.frequencies import BearingGeometry, bearing_frequencies

if TYPE_CHECKING:  # scipy loads when a command runs, not for --help
    from diagnostics.diagnose import Diagnosis

__all__ = ["main", "build_parser", "parse_bearing", "UsageError"]

_LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "in": 25.4e-3}
# Seconds of the record drawn in the time trace and the spectrogram.
_TRACE_S = 0.25
# Highest sampling rate taken for a vibration record (acoustic-emission systems reach tens
# of MHz); a larger --fs is a typo or a unit slip.
MAX_FS_HZ = 1e8


class UsageError(Exception):
    """Bad command-line input: reported as one line, exit status 2."""


class _Parser(argparse.ArgumentParser):
    # argparse prints the whole usage block on an error; one line is enough.
    def error(self, message: str):  # noqa: D401 - argparse API
        raise UsageError(f"{self.prog}: {message}")


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


def add_analyze_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("file", metavar="FILE", help="vibration record (csv, txt, wav, mat, ...)")
    parser.add_argument("--fs", type=float, help="sampling rate in Hz (if the file has none)")
    parser.add_argument("--rpm", type=float, help="shaft speed in rpm (default: from the file)")
    parser.add_argument(
        "--bearing",
        required=True,
        help="geometry: n=ROLLERS,d=ROLLER_DIAMETER,D=PITCH_DIAMETER[,angle=DEG], "
        "lengths with units (m, mm, in), e.g. n=9,d=7.94mm,D=39.04mm,angle=0",
    )
    parser.add_argument("--channel", help="column, variable or key to read")
    parser.add_argument(
        "--tacho",
        metavar="CHANNEL",
        help="tachometer channel of the same file: the speed varies, diagnose in orders",
    )
    parser.add_argument(
        "--ppr", type=int, default=1, help="tachometer pulses per shaft revolution (default 1)"
    )
    parser.add_argument(
        "--speed-profile",
        type=Path,
        metavar="FILE.csv",
        help="table of time_s and rpm (or shaft_hz): the speed varies, diagnose in orders",
    )
    parser.add_argument(
        "--rpm-range",
        type=float,
        nargs=2,
        metavar=("MIN", "MAX"),
        help="no tachometer: find the shaft speed in the vibration within MIN-MAX rpm "
        "(estimate_speed; give the narrowest range you know); stops if none is found with "
        "confidence",
    )
    parser.add_argument(
        "--keep-speed",
        action="store_true",
        help="analyse at the speed given even where the record's shaft harmonics stand "
        "elsewhere (by default they are sought within 5 %% of it and the analysis runs at "
        "their rate)",
    )
    parser.add_argument(
        "--notch",
        type=float,
        nargs="+",
        default=[],
        metavar="HZ",
        help="frequencies to notch out before the analysis",
    )
    parser.add_argument(
        "--out", metavar="DIR", help="output folder (default: FILE_STEM-diagnostics)"
    )


def _markers(d: Diagnosis) -> dict[str, float]:
    """Comb fundamentals to mark: where a family was detected, the frequency found (slip
    included) with the comb it was found by, else the kinematic one; and the other source's
    series where it set a detected family aside."""
    labels = {"outer": "BPFO", "inner": "BPFI", "ball": "2xBSF"}
    out = {}
    for family, label in labels.items():
        s = d.families.get(family)
        if s is None:
            continue
        if s.detected:
            found = "set aside" if family in d.dominated else "found"
            out[f"{s.comb or label} ({found})"] = s.found_hz
        else:
            out[label] = s.expected_hz if s.comb in ("", label) else _kinematic(d, family)
    if d.dominated:  # the series that set a detected family aside
        out["other series"] = d.other_series[0]
    return out


def _kinematic(d: Diagnosis, family: str) -> float:
    f = d.frequencies
    return {"outer": f.bpfo, "inner": f.bpfi, "ball": 2.0 * f.bsf}[family]


def save_figure(fig, path: Path) -> str:
    """Save a matplotlib Figure as PNG atomically; returns the file name."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    return path.name


_save = save_figure


def _figures(x, fs: float, d: Diagnosis, notch: list[float], raw, out: Path) -> list[str]:
    from diagnostics import plots  # matplotlib only when figures are drawn
    from diagnostics.compare import impact_times

    freqs = d.frequencies
    n_show = min(x.size, int(_TRACE_S * fs))
    events = None
    orders = d.domain == "order"
    unit = "orders" if orders else "Hz"
    if d.fault != "none" and not orders:
        rate = {"outer": freqs.bpfo, "inner": freqs.bpfi, "ball": 2.0 * freqs.bsf}[d.fault]
        times = impact_times(x[:n_show], fs, d.band, rate)
        events = {f"{d.fault} impacts": times}
    best = d.best_band
    envelope_figure = plots.plot_envelope_spectrum(
        best.f,
        best.z,
        _markers(d),
        title=f"Squared envelope spectrum, band {best.band[0]:.4g}-"
        f"{best.band[1]:.4g} {unit} ({best.name})",
        ylabel="power / local background",
    )
    band_maps = {
        name: plots.plot_kurtogram(
            band_map, used_band=_band_used(d, name), second_band=_band_used(d, f"{name}, second")
        )
        for name, band_map in (("kurtogram", d.kurtogram), ("infogram", d.infogram))
        if band_map is not None
    }
    if orders:  # envelope spectrum and band maps of the order-tracked record
        for figure in (envelope_figure, *band_maps.values()):
            figure.axes[0].set_xlabel("order (cycles per shaft revolution)")
    written = [
        _save(plots.plot_time_trace(x[:n_show], fs, events), out / "trace.png"),
        _save(plots.plot_spectrogram(x[:n_show], fs, events), out / "spectrogram.png"),
        _save(plots.plot_spectral_kurtosis(x, fs), out / "spectral_kurtosis.png"),
        _save(envelope_figure, out / "envelope_spectrum.png"),
        _save(plots.plot_psd_notch(raw, fs, notch), out / "psd_notch.png"),
        _save(plots.plot_third_octave(x, fs), out / "third_octave.png"),
    ]
    written += [_save(figure, out / f"{name}.png") for name, figure in band_maps.items()]
    return written


def _speed_figure(rates: np.ndarray, fs: float, source: str, out: Path) -> str:
    from diagnostics import plots

    return _save(plots.plot_speed(rates, fs, title=f"Shaft speed ({source})"), out / "speed.png")


def _family_summary(d: Diagnosis) -> dict:
    out = {}
    for name, s in d.families.items():
        if s is None:
            out[name] = None
            continue
        out[name] = {
            "expected_hz": s.expected_hz,
            "found_hz": s.found_hz,
            "band_hz": list(s.band),
            "lines_hz": s.lines_hz,
            "z": s.z,
            "threshold": s.threshold,
            "p_values": s.p_values,
            "modulation": s.modulation,
            "n_supporting": s.n_significant,
            "pair_p": s.pair_p,
            "detected": s.detected,
            "evidence": s.evidence,
            "sideband_hz": s.sideband_hz,
            "n_sidebands_significant": s.n_sidebands_significant,
            "sideband_pair_p": s.sideband_pair_p,
            "slower_period": s.slower_period,
        }
    return out


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


def check_record_fits(sig, geometry: BearingGeometry, shaft_hz: float, fs_given: bool) -> None:
    """One line naming ``--fs`` (or the file) when the record cannot be diagnosed: a dead
    channel, a rate too low for the fault frequencies, or a record too short."""
    from diagnostics.diagnose import record_requirements

    source = "--fs" if fs_given else f"the file's rate of {sig.fs:g} Hz"
    where = f"{sig.meta.get('path', '')}:{sig.name}"
    if np.ptp(sig.x) == 0.0:
        raise UsageError(
            f"{where} is constant (every sample {sig.x[0]:g}): a dead sensor or a flat "
            "record, nothing to diagnose; choose another --channel"
        )
    min_fs, min_s = record_requirements(geometry, shaft_hz)
    if sig.fs < min_fs:
        raise UsageError(
            f"{source} = {sig.fs:g} Hz is too low for this bearing's fault frequencies at "
            f"{shaft_hz * 60:g} rpm: give at least {min_fs:.0f} Hz"
        )
    if sig.x.size / sig.fs < min_s:
        raise UsageError(
            f"{where}: {sig.x.size} samples at {source} = {sig.fs:g} Hz last "
            f"{sig.x.size / sig.fs:.3g} s; diagnosis needs at least {min_s:.3g} s "
            "(check --fs, or give a longer record)"
        )


def check_notches(notches: list[float], fs: float) -> None:
    """Each ``--notch`` frequency strictly between 0 and fs/2."""
    for f0 in notches:
        if not (math.isfinite(f0) and 0.0 < f0 < fs / 2.0):
            raise UsageError(
                f"--notch {f0:g} Hz is outside 0..{fs / 2.0:g} Hz (fs/2, the Nyquist "
                f"frequency at {fs:g} Hz)"
            )


# An estimated speed is used when at least this share of its frames found the ridge clearly.
_MIN_SPEED_CONFIDENCE = 0.5


def shaft_rate(args: argparse.Namespace, sig):
    """Shaft rate (Hz) for ``analyze``: one value (``--rpm`` or the file's), or one per sample
    (``--tacho`` channel, ``--speed-profile`` table, or estimated within ``--rpm-range``).
    Returns ``(rate, source, confidence)``, the confidence None unless estimated."""
    from diagnostics.io import read_speed_profile
    from diagnostics.speed import estimate_speed, speed_from_tacho

    given = [o for o, v in (("--rpm", args.rpm), ("--tacho", args.tacho),
                            ("--speed-profile", args.speed_profile),
                            ("--rpm-range", args.rpm_range)) if v is not None]  # fmt: skip
    if len(given) > 1:
        raise UsageError(f"give one speed source, not {' and '.join(given)}")
    if args.ppr < 1:
        raise UsageError(
            f"--ppr must be a positive number of pulses per revolution, got {args.ppr}"
        )
    if args.tacho is not None:
        try:
            tacho = sig.channel(args.tacho)
            return speed_from_tacho(tacho, sig.fs, pulses_per_rev=args.ppr), "tacho", None
        except ValueError as exc:
            raise UsageError(f"--tacho {args.tacho}: {exc}") from None
    if args.speed_profile is not None:
        try:
            profile = read_speed_profile(args.speed_profile, sig.fs, sig.x.size)
            return profile, "speed profile", None
        except ValueError as exc:
            raise UsageError(f"--speed-profile: {exc}") from None
    if args.rpm_range is not None:
        low, high = args.rpm_range
        if not (math.isfinite(low) and math.isfinite(high) and 0 < low < high):
            raise UsageError(f"--rpm-range must be two speeds 0 < MIN < MAX, got {low:g} {high:g}")
        try:
            est = estimate_speed(sig.x, sig.fs, low / 60.0, high / 60.0)
        except ValueError as exc:
            # The library speaks of f_min in Hz; here it is the lower speed given.
            hint = " (f_min: the lower --rpm-range speed / 60)" if "f_min" in str(exc) else ""
            raise UsageError(f"--rpm-range: {exc}{hint}") from None
        if est.confidence < _MIN_SPEED_CONFIDENCE:
            raise UsageError(
                f"--rpm-range: no shaft speed found with confidence within {low:g}-{high:g} "
                f"rpm (confidence {est.confidence:.2f}, best guess "
                f"{float(np.median(est.shaft_hz)) * 60:.0f} rpm); narrow the range or give "
                "--rpm, --tacho or --speed-profile"
            )
        return est.shaft_hz, "estimated", est.confidence
    rpm = args.rpm if args.rpm is not None else sig.meta.get("rpm")
    if rpm is None:
        raise UsageError(
            f"{args.file}: the file holds no shaft speed; give --rpm, --tacho, "
            "--speed-profile or --rpm-range"
        )
    if not (math.isfinite(rpm) and rpm > 0):
        raise UsageError(f"--rpm must be a positive speed, got {rpm:g}")
    return rpm / 60.0, "--rpm" if args.rpm is not None else "file", None


def _shaft_lines_summary(d: Diagnosis) -> dict | None:
    lines = d.shaft_lines
    if lines is None:
        return None
    return {
        "given": lines.given_hz,
        "found": lines.found_hz,
        "present": lines.present,
        "n_standing": lines.n_standing,
        "n_harmonics": lines.n_harmonics,
        "p_value": lines.p_value,
        "analysed_at": d.frequencies.shaft,
        "unit": "orders" if d.domain == "order" else "Hz",
    }


def _speed_check_lines(d: Diagnosis, unit: str) -> list[str]:
    """What the record's own shaft lines said of the speed given."""
    lines = d.shaft_lines
    if lines is None:
        return []
    given = f"{lines.given_hz:.4g} {unit}"
    if not lines.present:
        return [
            f"warning: no shaft harmonics within {100 * lines.tolerance:g} % of the shaft rate "
            f"given ({given}): check the speed, the sampling rate and the channel"
        ]
    change = 100.0 * d.speed_change
    if abs(change) >= 0.05:
        return [
            f"speed: the record's shaft harmonics stand at {d.frequencies.shaft:.4g} {unit}, "
            f"{abs(change):.1f} % {'below' if change < 0 else 'above'} the {given} given: "
            "analysed there"
        ]
    return []


def run_analyze(args: argparse.Namespace) -> int:
    from diagnostics.diagnose import diagnose
    from diagnostics.filters import notch_filter
    from diagnostics.io import read_signal

    geometry = parse_bearing(args.bearing)
    check_fs_option(args.fs)
    sig = read_signal(args.file, channel=args.channel, fs=args.fs)
    shaft_hz, speed_source, speed_confidence = shaft_rate(args, sig)
    rates = np.atleast_1d(shaft_hz)
    rpm = float(rates.mean()) * 60.0
    check_notches(args.notch, sig.fs)
    check_record_fits(sig, geometry, float(rates.max()), args.fs is not None)
    default_out = f"{Path(args.file).stem}-diagnostics"
    out = output_folder(default_out if args.out is None else args.out, "--out")
    raw = sig.x
    x = raw
    for f0 in args.notch:
        x = notch_filter(x, sig.fs, f0)
    d = diagnose(x, sig.fs, geometry, shaft_hz, correct_speed=not args.keep_speed)
    figures = _figures(x, sig.fs, d, list(args.notch), raw, out)
    if rates.size > 1:
        figures.append(_speed_figure(rates, sig.fs, speed_source, out))
    kg = d.kurtogram
    summary = {
        "file": str(args.file),
        "channel": sig.name,
        "fs_hz": sig.fs,
        "n_samples": int(x.size),
        "duration_s": x.size / sig.fs,
        "rpm": rpm,
        "speed": {
            "source": speed_source,
            "min_rpm": float(rates.min()) * 60.0,
            "max_rpm": float(rates.max()) * 60.0,
            "confidence": speed_confidence,
        },
        "domain": d.domain,
        "samples_per_rev": d.samples_per_rev,
        "bearing": {
            "n_rollers": geometry.n_rollers,
            "roller_diameter_m": geometry.roller_diameter,
            "pitch_diameter_m": geometry.pitch_diameter,
            "contact_angle_deg": geometry.contact_angle_deg,
        },
        "fault_frequencies_hz": (
            d.frequencies if d.domain == "time" else bearing_frequencies(geometry, rpm / 60.0)
        ).as_dict(),
        "fault_orders": bearing_frequencies(geometry, 1.0).as_dict(),
        "kurtogram": _band_map_summary(kg, "kurtosis", _band_used(d, "kurtogram")),
        "infogram": _band_map_summary(
            d.infogram, "negentropy", _band_used(d, "infogram"), _band_used(d, "infogram, second")
        ),
        "verdict": d.fault,
        "confidence": d.confidence,
        "band_hz": list(d.band),
        "scores": d.scores,
        "alpha": d.alpha,
        "families": _family_summary(d),
        "dominated": list(d.dominated),
        "other_series": dict(zip(("fundamental", "strength"), d.other_series, strict=True)),
        "shaft_lines": _shaft_lines_summary(d),
        "notch_hz": list(args.notch),
        "figures": figures,
    }
    write_json(out / "summary.json", summary)
    _print_summary(sig, rpm, d, out, len(figures) + 1)
    return 0


def _band_used(d: Diagnosis, name: str) -> tuple[float, float] | None:
    """The band diagnose demodulated from the kurtogram or infogram ``name``, if any."""
    return next((b.band for b in d.bands if b.name == name), None)


def _band_map_summary(band_map, value: str, used, second=None) -> dict | None:
    """A kurtogram's or infogram's best band, and the band of it diagnosed (None where
    diagnose did not take one from it), with the infogram's second band, for summary.json."""
    if band_map is None:
        return None
    summary = {
        "fc_hz": band_map.fc,
        "bw_hz": band_map.bw,
        "band_hz": list(band_map.band),
        "level": band_map.level,
        value: band_map.kurtosis,
        "diagnosed_band_hz": None if used is None else list(used),
    }
    if band_map.quantity != "kurtosis":
        summary["second_band_hz"] = None if second is None else list(second)
    return summary


def _print_summary(sig, rpm: float, d: Diagnosis, out: Path, n_files: int) -> None:
    f = d.frequencies
    kg = d.kurtogram
    unit = "orders" if d.domain == "order" else "Hz"
    speed = (
        f"{rpm:g} rpm (shaft {rpm / 60.0:.2f} Hz)"
        if d.domain == "time"
        else f"varying speed, mean {rpm:.0f} rpm: order domain, {d.samples_per_rev:g} samples/rev"
    )
    lines = [
        f"{sig.name}: {sig.fs:g} Hz, {sig.x.size / sig.fs:.2f} s, {speed}",
        f"fault frequencies: FTF {f.ftf:.4g}  BPFO {f.bpfo:.4g}  BPFI {f.bpfi:.4g}  "
        f"BSF {f.bsf:.4g} {unit}",
    ]
    lines[1:1] = _speed_check_lines(d, unit)
    for name, band_map in (("kurtogram", kg), ("infogram", d.infogram)):
        if band_map is not None:
            used = _band_used(d, name)
            lines.append(
                f"{name} best band: {band_map.band[0]:.4g}-{band_map.band[1]:.4g} {unit} "
                f"(level {band_map.level:.1f}, {band_map.quantity} {band_map.kurtosis:.2f})"
                + (
                    ""
                    if used is None or used == band_map.band
                    else f"; diagnosed in {used[0]:.4g}-{used[1]:.4g} {unit}, its best band "
                    "wide enough for two fault harmonics and above their range"
                )
            )
            second = _band_used(d, f"{name}, second")
            if second is not None:
                lines[-1] += (
                    f"; also in {second[0]:.4g}-{second[1]:.4g} {unit}, the best band of "
                    "that kind that does not overlap it"
                )
    verdict = "no bearing fault found" if d.fault == "none" else f"{d.fault} fault"
    lines += [
        f"verdict: {verdict} (confidence {d.confidence:.2f}; "
        f"band {d.band[0]:.4g}-{d.band[1]:.4g} {unit})",
        "scores: " + "  ".join(f"{k} {v:.0f}" for k, v in d.scores.items()),
    ]
    named = d.families.get(d.fault)
    if named is not None and named.detected and named.sideband_pair_p < named.pair_p:
        lines.append(
            f"evidence: a {named.comb} line and its cage-rate sideband ({named.sideband_hz:.4g} "
            f"{unit} away; joint p {named.sideband_pair_p:.2g}, the best pair of harmonics "
            f"{named.pair_p:.2g})"
        )
    for family, s in d.families.items():
        if s is not None and s.slower_period:
            rate = s.found_hz / s.slower_period
            lines.append(
                f"not named: {family} (the lines between its {s.comb} harmonics show impacts "
                f"at {rate:.4g} {unit}, 1/{s.slower_period} of its rate: no fault of this "
                "bearing)"
            )
    for family in d.dominated:
        lines.append(
            f"not named: {family} (its lines belong to a stronger series at "
            f"{d.other_series[0]:.4g} {unit}, no fault frequency of this bearing: another "
            "component?)"
        )
    lines += [
        f"wrote {n_files} files to {out}",
    ]
    print("\n".join(lines))


# The comparison of a simulated run folder moved to the simulator's command line; the
# comparison itself (arrays in, figures out) stays in diagnostics.compare.
COMPARE_MOVED = (
    "compare moved to the simulator: python -m taichi_bearing compare RUN_DIR MEASURED_FILE "
    "[--fs HZ] [--rpm RPM] [--bearing ...] [--out DIR]"
)


def add_compare_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("args", nargs=argparse.REMAINDER, help=argparse.SUPPRESS)


def run_compare(args: argparse.Namespace) -> int:
    raise UsageError(COMPARE_MOVED)


def add_benchmark_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "folders",
        metavar="DIR",
        nargs="+",
        type=Path,
        help="folder(s) of CWRU or MFPT .mat records, named as the public sets name them",
    )
    parser.add_argument(
        "--records", action="store_true", help="also print one line per record as it is done"
    )
    parser.add_argument("--csv", type=Path, help="write every record's verdict to this CSV file")
    parser.add_argument(
        "--other-bearing",
        action="store_true",
        help="false-alarm check: read each CWRU record's other accelerometer with the other "
        "end's (healthy) bearing; every right verdict is none",
    )
    parser.add_argument(
        "--quiet", action="store_true", help="no progress bar or progress lines on stderr"
    )
    parser.add_argument(
        "--progress-interval",
        type=float,
        default=LOG_INTERVAL_S,
        metavar="S",
        help="seconds between progress lines when stderr is not a terminal (a log, a pipe; "
        f"default {LOG_INTERVAL_S:g}); on a terminal a bar",
    )


def run_benchmark(args: argparse.Namespace) -> int:
    from diagnostics import benchmark

    paths = [p for folder in args.folders for p in benchmark.find_records(folder)]
    if not paths:
        raise UsageError(
            f"{', '.join(map(str, args.folders))}: no CWRU or MFPT record found (.mat files "
            "named e.g. 12k_Drive_End_IR007_0_105.mat, normal_0_97.mat, "
            "InnerRaceFault_vload_1.mat)"
        )

    if args.csv is not None:  # before the records are read, not after
        if not str(args.csv).strip() or args.csv.is_dir():
            raise UsageError(f"--csv {str(args.csv)!r}: give a file name, e.g. verdicts.csv")
        output_folder(args.csv.parent, "--csv")
    if not math.isfinite(args.progress_interval) or args.progress_interval < 0:
        raise UsageError(f"--progress-interval {args.progress_interval:g}: give seconds, 0 or more")
    # With --records each record's line is the progress.
    progress = RecordProgress(
        len(benchmark.labelled_records(paths, args.other_bearing)),
        log_every_s=args.progress_interval,
        enabled=not (args.quiet or args.records),
    )

    def show(r: benchmark.BenchmarkResult) -> None:
        progress.update(r.path.name)
        if args.records:
            mark = "ok" if r.correct else "MISS"
            print(
                f"{r.path.name}: {r.expected} -> {r.verdict} ({r.confidence:.2f}) {mark} {r.detail}"
            )

    try:
        results = benchmark.run_benchmark(paths, progress=show, other_bearing=args.other_bearing)
    finally:
        progress.close()
    if not results:
        raise UsageError(
            f"{', '.join(map(str, args.folders))}: no CWRU record for --other-bearing (MFPT "
            "records have one bearing)"
        )
    if args.records:
        print()
    speeds = benchmark.speed_summary(results)
    if speeds:
        print(speeds + "\n")
    print(benchmark.summary_table(results))
    if args.csv is not None:
        import pandas as pd

        rows = [
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
        with atomic_path(args.csv) as tmp:
            pd.DataFrame(rows).to_csv(tmp, index=False)
        print(f"wrote {args.csv}")
    return 0


COMMANDS = {
    "analyze": (
        "diagnose one vibration record: figures, summary.json and a verdict",
        add_analyze_arguments,
        run_analyze,
    ),
    "compare": (
        "moved: use python -m taichi_bearing compare RUN_DIR MEASURED_FILE ...",
        add_compare_arguments,
        run_compare,
    ),
    "benchmark": (
        "diagnose every CWRU or MFPT record in a folder and tabulate the verdicts",
        add_benchmark_arguments,
        run_benchmark,
    ),
}


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="python -m diagnostics",
        description="Bearing vibration diagnostics on measured or simulated records.",
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, (help_text, add_arguments, _) in COMMANDS.items():
        add_arguments(sub.add_parser(name, help=help_text, description=help_text))
    return parser


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            parser.print_help(sys.stderr)
            return 2
        return int(COMMANDS[args.command][2](args) or 0)
    except (UsageError, ValueError, OSError) as exc:
        message = " ".join(str(exc).split())  # one line, whatever the message held
        print(f"error: {message}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
