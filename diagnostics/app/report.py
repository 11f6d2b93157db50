"""One-page HTML reports of the command line: ``report.html`` of ``analyze`` (the verdict,
the evidence for and against each fault family, then the figures) and the table of
``benchmark --html``.

Each page is self-contained (CSS inline, figures as base64 PNG data URIs) and looks like
the simulator's run report: both are built from :mod:`bearing_io.report_html`. Every
number on the ``analyze`` page is read from the ``summary.json`` it writes beside it, and
every figure from the PNG files it drew into the same folder. Standard library only.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping, Sequence
from pathlib import Path

from bearing_io.files import atomic_path, to_jsonable
from bearing_io.report_html import REPORT_CSS, escape_text, html_page, html_table, png_figure

__all__ = [
    "REPORT_FILE",
    "analyze_report",
    "benchmark_html",
    "verdict_words",
    "write_analyze_report",
    "write_benchmark_html",
]

REPORT_FILE = "report.html"

# The simulator's look, and a box that makes the verdict the first thing read.
_CSS = REPORT_CSS + (
    ".verdict{border:1px solid #bbb;background:#f4f4f4;padding:0.4em 1em;margin:1em 0}"
    ".verdict .fault{font-size:1.5em;font-weight:bold;margin:0.3em 0}"
)

_FAMILY_NAMES = {"outer": "outer race", "inner": "inner race", "ball": "rolling element (ball)"}
_COMBS = {"outer": "BPFO", "inner": "BPFI", "ball": "2xBSF"}
_HARMONIC_COLUMNS = ("z", "z at p = 0.01", "p-value", "modulation")
# A harmonic "supports" its family at this p-value or less (diagnostics._comb.FamilyScore).
_SUPPORTING_P = 0.01


def verdict_words(fault: str) -> str:
    """The verdict as ``analyze`` prints it: ``"outer fault"``, ``"no bearing fault
    found"``, or where the evidence does not decide between families (``fault`` names
    them, ``diagnostics.Diagnosis.undecided``) ``"outer or ball: the evidence does not
    decide"``."""
    if fault == "none":
        return "no bearing fault found"
    if " or " in fault:
        return f"{fault}: the evidence does not decide"
    return f"{fault} fault"


def _g(value, digits: int = 4) -> str:
    """A number to ``digits`` significant figures, but every digit of its integer part (a
    band edge of 24000 Hz, not 2.4e+04); '-' for none or a non-finite one."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    digits = max(digits, len(str(int(abs(value)))))
    return f"{value:.{digits}g}"


def _unit(summary: Mapping) -> str:
    """The unit of the frequencies: orders where the record was order-tracked."""
    return "orders" if summary.get("domain") == "order" else "Hz"


def _range(band, unit: str) -> str:
    return "-" if not band else f"{_g(band[0])}-{_g(band[1])} {unit}"


def _record(summary: Mapping) -> str:
    """The record in one paragraph: file, channel, rate, length, speed, bearing, fault
    frequencies."""
    unit = _unit(summary)
    speed = summary.get("speed") or {}
    bearing = summary.get("bearing") or {}
    # In orders where the record was order-tracked (summary.json's Hz are at the mean speed).
    freqs = summary.get("fault_orders" if unit == "orders" else "fault_frequencies_hz") or {}
    source = speed.get("source", "-")
    rpm = f"{_g(summary.get('rpm'))} rpm ({source})"
    if summary.get("domain") == "order":
        rpm = (
            f"{_g(speed.get('min_rpm'))}-{_g(speed.get('max_rpm'))} rpm ({source}): "
            "order-tracked, frequencies in orders"
        )
    geometry = (
        f"{bearing.get('n_rollers', '-')} rollers, d = {_g(1e3 * bearing['roller_diameter_m'])} "
        f"mm, D = {_g(1e3 * bearing['pitch_diameter_m'])} mm, contact angle "
        f"{_g(bearing.get('contact_angle_deg'))} deg"
        if bearing
        else "-"
    )
    frequencies = ", ".join(
        f"{label} {_g(freqs.get(f'{label.lower()}_hz'))}"
        for label in ("FTF", "BPFO", "BPFI", "BSF")
    )
    text = (
        f"Record <code>{escape_text(str(summary.get('file', '-')))}</code>, channel "
        f"{escape_text(str(summary.get('channel', '-')))}: {_g(summary.get('fs_hz'))} Hz, "
        f"{_g(summary.get('duration_s'), 3)} s; shaft {escape_text(rpm)}. Bearing: "
        f"{geometry}. Fault frequencies: {frequencies} {unit}. Every number below is read "
        "from <code>summary.json</code> in this folder."
    )
    return f"<p>{text}</p>"


def _verdict(summary: Mapping, notes: Sequence[str]) -> list[str]:
    """The verdict box: the fault (or none), the confidence, the band it was read in."""
    fault = str(summary.get("verdict", "none"))
    unit = _unit(summary)
    headline = f"{_FAMILY_NAMES[fault]} fault" if fault in _FAMILY_NAMES else verdict_words(fault)
    band_name = summary.get("band_name")
    band = _range(summary.get("band_hz"), unit) + (f" ({band_name})" if band_name else "")
    detail = (
        f"verdict <b>{escape_text(fault)}</b>; confidence {summary.get('confidence', 0.0):.2f}; "
        f"demodulation band {escape_text(band)}; false-alarm rate alpha = "
        f"{_g(summary.get('alpha'), 2)} over all tests"
    )
    out = [
        "<h2>Verdict</h2>",
        '<div class="verdict">'
        f'<p class="fault">{escape_text(headline[:1].upper() + headline[1:])}</p>'
        f"<p>{detail}</p></div>",
    ]
    return out + [f"<p>{escape_text(n)}</p>" for n in notes]


def _supporting(s: Mapping, unit: str) -> str:
    """The harmonics whose p-value is at most 0.01, as 'k x: f unit (p ...)'."""
    lines = [
        f"{k}x {_g(f)} {unit} (p {_g(p, 2)})"
        for k, (f, p) in enumerate(
            zip(s.get("lines_hz") or [], s.get("p_values") or [], strict=False), 1
        )
        if p is not None and p <= _SUPPORTING_P
    ]
    n = len(s.get("lines_hz") or [])
    return f"{len(lines)} of {n}: " + "; ".join(lines) if lines else f"none of {n}"


def _sidebands(s: Mapping, unit: str) -> str:
    spacing = s.get("sideband_hz") or 0.0
    if not spacing:
        return "not tested"
    n = 2 * len(s.get("lines_hz") or [])
    text = f"+-{_g(spacing)} {unit}: {s.get('n_sidebands_significant', 0)} of {n} significant"
    pair = s.get("sideband_pair_p")
    if pair is not None and pair < 1.0:
        text += f"; best line with its sideband p {_g(pair, 2)}"
    return text


def _against(family: str, s: Mapping | None, summary: Mapping, unit: str) -> str:
    """What speaks against naming ``family``, from summary.json alone."""
    if s is None:
        return "not tested: no candidate band holds two of its harmonics"
    if family in (summary.get("dominated") or []):
        other = (summary.get("other_series") or {}).get("fundamental")
        return f"set aside: its lines belong to a stronger series at {_g(other)} {unit}"
    if s.get("slower_period"):
        return (
            f"set aside: the lines between its harmonics repeat at 1/{s['slower_period']} "
            "of its rate, no fault frequency of this bearing"
        )
    if s.get("detected"):
        verdict = summary.get("verdict")
        if verdict == family:
            return "-"
        return f"detected, not named: the {verdict} family's own lines carry more evidence"
    n = s.get("n_supporting") or 0
    if n == 0:
        return "no harmonic stands out of its background (p <= 0.01)"
    if n == 1:
        return "one supporting harmonic only: detection needs two, or one and its sideband"
    return (
        f"{n} supporting harmonics, but no pair passes the detection rule (best pair p "
        f"{_g(s.get('pair_p'), 2)})"
    )


def _evidence(summary: Mapping, notes: Sequence[str]) -> list[str]:
    """Per family: its comb, the lines found, the sidebands, what speaks against it; then
    every tested harmonic."""
    unit = _unit(summary)
    families = summary.get("families") or {}
    scores = summary.get("scores") or {}
    rows, harmonics = [], []
    for family, s in families.items():
        name = _FAMILY_NAMES.get(family, family)
        if s is None:
            against = _against(family, s, summary, unit)
            rows.append([name, "-", "-", "no", _g(scores.get(family), 3), "-", "-", "-", against])
            continue
        comb = s.get("comb") or _COMBS.get(family, "")
        rows.append(
            [
                name,
                comb,
                f"{_g(s.get('found_hz'))} (expected {_g(s.get('expected_hz'))})",
                "yes" if s.get("detected") else "no",
                _g(scores.get(family), 3),
                _g(s.get("pair_p"), 2),
                _supporting(s, unit),
                _sidebands(s, unit),
                _against(family, s, summary, unit),
            ]
        )
        values = zip(*(s.get(k) or [] for k in ("lines_hz", "z", "threshold", "p_values",
                                                  "modulation")), strict=False)  # fmt: skip
        harmonics += [
            [name, comb, str(k), _g(f), _g(z, 3), _g(t, 3), _g(p, 2), _g(m, 2)]
            for k, (f, z, t, p, m) in enumerate(values, 1)
        ]
    head = ["family", "comb", f"fundamental ({unit})", "detected", "score", "best pair p",
            "supporting harmonics (p <= 0.01)", "sidebands", "against"]  # fmt: skip
    intro = (
        "A family is detected when a pair of its harmonics (or a harmonic and its modulation "
        "sideband) is significant at the false-alarm rate over all the tests, and a "
        "supporting line modulates the squared envelope; its score is the sum of the "
        "normalised values of its supporting harmonics, each near minus the log of its "
        "p-value. Best band of each family over the candidate bands."
    )
    out = ["<h2>Evidence for and against each fault family</h2>", f"<p>{intro}</p>"]
    out.append(html_table(head, rows))
    out += [f"<p>{escape_text(n)}</p>" for n in notes]
    if harmonics:
        out.append(
            "<details><summary>Every harmonic tested</summary>"
            + html_table(
                ["family", "comb", "k", f"frequency ({unit})", *_HARMONIC_COLUMNS], harmonics
            )
            + "</details>"
        )
    return out


def _figure(folder: Path, name: str, alt: str, caption: str) -> list[str]:
    path = folder / name
    if not path.is_file():
        return [f"<p>{escape_text(name)} was not drawn.</p>"]
    return [png_figure(path.read_bytes(), alt, caption)]


def _band_map(summary: Mapping) -> tuple[str, str]:
    """The map the verdict's band came from (the infogram's, or the kurtogram's), else the
    infogram, else the kurtogram: ``(name, caption)``."""
    band_name = str(summary.get("band_name") or "")
    order = ("infogram", "kurtogram")
    if band_name.startswith("kurtogram"):
        order = order[::-1]
    name = next((n for n in order if summary.get(n)), order[0])
    used = band_name.split(",")[0] == name
    unit = _unit(summary)
    caption = (
        f"{'Infogram' if name == 'infogram' else 'Fast kurtogram'} of the prewhitened record: "
        "its best band outlined solid, the band diagnosed dashed, a second band diagnosed "
        "dotted. "
        + (
            f"The verdict was read in its band {_range(summary.get('band_hz'), unit)}."
            if used
            else f"The verdict was read in the {band_name or 'whole'} band "
            f"{_range(summary.get('band_hz'), unit)}, not one of this map."
        )
    )
    return f"{name}.png", caption


def analyze_report(
    summary: Mapping,
    folder: str | Path,
    speed_notes: Sequence[str] = (),
    evidence_notes: Sequence[str] = (),
) -> str:
    """The ``analyze`` page as HTML text.

    Parameters
    ----------
    summary : mapping
        What ``analyze`` writes to ``summary.json``.
    folder : path-like
        The folder holding the figures (``envelope_spectrum.png``, ``infogram.png``, ...).
    speed_notes, evidence_notes : sequence of str
        Lines ``analyze`` printed about the speed (moved to the record's shaft lines, or
        none found there), shown under the verdict, and about the evidence (a ball named by
        a line and its sideband, a family set aside), under the evidence table.
    """
    folder = Path(folder)
    summary = to_jsonable(dict(summary))  # plain lists and floats, as summary.json holds them
    unit = _unit(summary)
    title = f"Diagnosis: {Path(str(summary.get('file', 'record'))).name}"
    band_map, band_caption = _band_map(summary)
    body = [f"<h1>{escape_text(title)}</h1>", _record(summary)]
    body += _verdict(summary, speed_notes) + _evidence(summary, evidence_notes)
    body += ["<h2>Envelope spectrum</h2>"] + _figure(
        folder,
        "envelope_spectrum.png",
        "envelope spectrum",
        f"Squared envelope spectrum of the verdict's band {_range(summary.get('band_hz'), unit)}"
        ", over its local background. Dashed: the harmonics of each fault frequency (BPFO, "
        "BPFI, 2xBSF, FTF; where a family was detected, at the frequency found). Dotted: the "
        "sidebands of a detected family (shaft rate for the inner race, cage rate for a ball).",
    )
    body += ["<h2>Band selection</h2>"] + _figure(folder, band_map, band_map[:-4], band_caption)
    body += ["<h2>Time trace</h2>"] + _figure(
        folder,
        "trace.png",
        "time trace",
        "The start of the record as analysed (after any notch filter); where a fault was "
        "named, its impacts in the demodulation band are marked.",
    )
    if "speed.png" in (summary.get("figures") or []):
        body += ["<h2>Shaft speed</h2>"] + _figure(
            folder, "speed.png", "shaft speed", "The shaft speed over the record."
        )
    body += ["<h2>Power spectral density</h2>"] + _figure(
        folder,
        "psd_notch.png",
        "power spectral density",
        "Welch PSD of the record before and after the notch filters (--notch; without one "
        "the two curves coincide).",
    )
    shown = {"envelope_spectrum.png", band_map, "trace.png", "speed.png", "psd_notch.png"}
    others = [f for f in summary.get("figures") or [] if f not in shown]
    if others:
        body.append(
            f"<p>Also in this folder: {escape_text(', '.join(others))}, and "
            "<code>summary.json</code>.</p>"
        )
    return html_page(title, body, _CSS)


def write_analyze_report(
    folder: str | Path,
    summary: Mapping,
    speed_notes: Sequence[str] = (),
    evidence_notes: Sequence[str] = (),
) -> Path:
    """Write ``report.html`` into ``folder`` (to a temporary name, then renamed); returns
    its path. See :func:`analyze_report`."""
    text = analyze_report(summary, folder, speed_notes, evidence_notes)
    return _write(Path(folder) / REPORT_FILE, text)


def _write(path: Path, text: str) -> Path:
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return path


# The per-record table's columns: (header, key of a benchmark row, format).
_BENCHMARK_COLUMNS = (
    ("record", "record", str),
    ("set", "set", str),
    ("expected", "expected", str),
    ("verdict", "verdict", str),
    ("confidence", "confidence", lambda v: f"{v:.2f}"),
    ("ok", "correct", lambda v: "yes" if v else "NO"),
    ("detail", "detail", str),
    ("speed change", "speed_change", lambda v: f"{100.0 * v:+.2f} %" if v else "0"),
    ("shaft lines", "shaft_lines", lambda v: "-" if v is None else ("yes" if v else "no")),
)


def benchmark_html(rows: Sequence[Mapping], table: str, title: str = "Benchmark") -> str:
    """The benchmark as a page: the counts (``table``, as printed), then one row per record.

    Parameters
    ----------
    rows : sequence of mapping
        One per record, as :func:`diagnostics.app.benchmark.record_rows` makes them.
    table : str
        The summary table as printed (:func:`diagnostics.app.benchmark.summary_table`).
    title : str
        Page title.
    """
    right = sum(bool(r["correct"]) for r in rows)
    body = [
        f"<h1>{html.escape(title)}</h1>",
        f"<p>{right} of {len(rows)} records named right.</p>",
        f"<pre>{escape_text(table)}</pre>",
        html_table(
            [c[0] for c in _BENCHMARK_COLUMNS],
            [[fmt(r[key]) for _, key, fmt in _BENCHMARK_COLUMNS] for r in rows],
        ),
    ]
    return html_page(title, body, _CSS)


def write_benchmark_html(
    path: str | Path, rows: Sequence[Mapping], table: str, title: str = "Benchmark"
) -> Path:
    """Write :func:`benchmark_html` to ``path`` (to a temporary name, then renamed)."""
    return _write(Path(path), benchmark_html(rows, table, title))
