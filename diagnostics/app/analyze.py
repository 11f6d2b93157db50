"""``python -m diagnostics analyze``: one record read, its speed found, diagnosed, drawn and
summarised (``summary.json``, the figures, ``report.html``, the lines printed).

Importing this module loads numpy only: scipy and matplotlib load when the command runs, so
that ``--help`` answers at once (their imports below sit inside the functions for that).
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from bearing_io.files import output_folder, write_json
from diagnostics import BearingGeometry, bearing_frequencies
from diagnostics.app._figure_files import save_figure as _save
from diagnostics.app._options import UsageError, check_fs_option, check_notches, parse_bearing
from diagnostics.app.report import REPORT_FILE, verdict_words, write_analyze_report

if TYPE_CHECKING:  # scipy loads when a command runs, not for --help
    from diagnostics import Diagnosis

__all__ = ["add_analyze_arguments", "check_record_fits", "run_analyze", "shaft_rate"]

# Seconds of the record drawn in the time trace and the spectrogram.
_TRACE_S = 0.25


def add_analyze_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``analyze`` on ``parser``."""
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
    included) with the comb it was found by, else the kinematic one; the kinematic BPFO,
    BPFI, 2xBSF and FTF not marked so; and the other source's series where it set a
    detected family aside."""
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
    f = d.frequencies
    for label, f0 in (("BPFO", f.bpfo), ("BPFI", f.bpfi), ("2xBSF", 2.0 * f.bsf), ("FTF", f.ftf)):
        if not any(k.startswith(label) for k in out):  # every comb, for reference
            out[label] = f0
    if d.dominated:  # the series that set a detected family aside
        out["other series"] = d.other_series[0]
    return out


def _sideband_markers(d: Diagnosis, unit: str) -> dict[str, tuple[float, float]]:
    """The modulation sidebands of each detected family that has them (the inner race's at
    the shaft rate, a ball's at the cage rate): ``{label: (fundamental, spacing)}``."""
    return {
        f"{s.comb} sidebands (+-{s.sideband_hz:.4g} {unit})": (s.found_hz, s.sideband_hz)
        for s in d.families.values()
        if s is not None and s.detected and s.sideband_hz > 0
    }


def _kinematic(d: Diagnosis, family: str) -> float:
    f = d.frequencies
    return {"outer": f.bpfo, "inner": f.bpfi, "ball": 2.0 * f.bsf}[family]


def _figures(x, fs: float, d: Diagnosis, notch: list[float], raw, out: Path) -> list[str]:
    from diagnostics import plots  # matplotlib only when figures are drawn
    from diagnostics.app.compare import impact_times  # scipy: when the command runs, not for --help

    freqs = d.frequencies
    n_show = min(x.size, int(_TRACE_S * fs))
    events = None
    orders = d.domain == "order"
    unit = "orders" if orders else "Hz"
    if d.fault in ("outer", "inner", "ball") and not orders:
        rate = {"outer": freqs.bpfo, "inner": freqs.bpfi, "ball": 2.0 * freqs.bsf}[d.fault]
        times = impact_times(x[:n_show], fs, d.band, rate)
        events = {f"{d.fault} impacts": times}
    best = d.best_band
    markers = _markers(d)
    envelope_figure = plots.plot_envelope_spectrum(
        best.f,
        best.z,
        markers,
        title=f"Squared envelope spectrum, band {best.band[0]:.4g}-"
        f"{best.band[1]:.4g} {unit} ({best.name})",
        ylabel="power / local background",
        sidebands=_sideband_markers(d, unit),
        # The y range from the race and spin combs' lines: the cage-rate comb, drawn for
        # reference, sits among the shaft's low harmonics, which would flatten them.
        scale_from=0.5 * min(v for k, v in markers.items() if k != "FTF"),
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
    from diagnostics import plots  # matplotlib only when figures are drawn

    return _save(plots.plot_speed(rates, fs, title=f"Shaft speed ({source})"), out / "speed.png")


def _family_summary(d: Diagnosis) -> dict:
    out = {}
    for name, s in d.families.items():
        if s is None:
            out[name] = None
            continue
        out[name] = {
            "comb": s.comb,
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


def check_record_fits(sig, geometry: BearingGeometry, shaft_hz: float, fs_given: bool) -> None:
    """One line naming ``--fs`` (or the file) when the record cannot be diagnosed: a dead
    channel, a rate too low for the fault frequencies, or a record too short."""
    from diagnostics import record_requirements  # scipy: when the command runs, not for --help

    source = "--fs" if fs_given else f"the file's rate of {sig.fs:g} Hz"
    where = f"{sig.meta.get('path', '')}:{sig.name}"
    if sig.x.max() == sig.x.min():  # (a range of a record near 1e308 overflows)
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


# An estimated speed is used when at least this share of its frames found the ridge clearly.
_MIN_SPEED_CONFIDENCE = 0.5


def shaft_rate(args: argparse.Namespace, sig):
    """Shaft rate (Hz) for ``analyze``: one value (``--rpm`` or the file's), or one per sample
    (``--tacho`` channel, ``--speed-profile`` table, or estimated within ``--rpm-range``).
    Returns ``(rate, source, confidence)``, the confidence None unless estimated."""
    from diagnostics import (  # scipy: when the command runs, not for --help
        estimate_speed,
        read_speed_profile,
        speed_from_tacho,
    )

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
    """Run ``analyze`` on parsed options: read the record, find its speed, diagnose it, write
    ``summary.json``, the figures and ``report.html`` (the verdict, the evidence, the key
    figures on one page: :mod:`diagnostics.app.report`) into ``--out``, print the verdict;
    returns 0.

    Raises
    ------
    UsageError
        On options that do not fit the record (one line for the user, exit status 2).
    """
    from diagnostics import (  # scipy: when the command runs, not for --help
        diagnose,
        notch_filter,
        read_signal,
    )

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
        "undecided": list(d.undecided),
        "candidates": [_candidate_summary(c) for c in d.candidates],
        "confidence": d.confidence,
        "band_hz": list(d.band),
        "band_name": d.best_band.name,
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
    unit = "orders" if d.domain == "order" else "Hz"
    write_analyze_report(out, summary, _speed_check_lines(d, unit), _evidence_lines(d, unit))
    _print_summary(sig, rpm, d, out, len(figures) + 2)
    return 0


def _candidate_summary(c) -> dict:
    """One :class:`diagnostics.Candidate` for summary.json."""
    return {
        "family": c.family,
        "comb": c.comb,
        "band_hz": list(c.band),
        "p_value": c.p_value,
        "evidence": c.evidence,
        "unique_evidence": c.unique_evidence,
        "harmonics": list(c.harmonics),
        "sidebands": list(c.sidebands),
        "detected": c.detected,
        "decides": c.decides,
        "explained_by": list(c.explained_by),
    }


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


def _evidence_lines(d: Diagnosis, unit: str) -> list[str]:
    """What the verdict rests on beyond the scores: a ball named by a line and its
    sideband, and each family not named though its lines stood out, with the reason."""
    lines = []
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
    return lines


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
    lines += [
        f"verdict: {verdict_words(d.fault)} (confidence {d.confidence:.2f}; "
        f"band {d.band[0]:.4g}-{d.band[1]:.4g} {unit})",
        "scores: " + "  ".join(f"{k} {v:.0f}" for k, v in d.scores.items()),
    ]
    lines += _evidence_lines(d, unit)
    lines += [
        f"wrote {n_files} files to {out}; the page to read first: {out / REPORT_FILE}",
    ]
    print("\n".join(lines))
