"""``write_report(run_dir)``: ``report.md`` and ``report.html`` of a run folder.

Every number comes from the run folder (:mod:`taichi_bearing.output.run_folder`): ``summary.json``,
``case.yaml``, ``mesh_statistics.json`` and ``figures/figures.json`` (written with the figures by
:func:`taichi_bearing.post.run_figures.make_run_figures`, which is run first if the figures
are missing). The report is built once as a list of blocks (headings, paragraphs, tables,
figures) and rendered twice: Markdown with linked pictures, and a self-contained HTML page
with the pictures inline as base64 data URIs (no dependency beyond the standard library).

The report leads with what happened: the verdict (what the rollers did at the spall's
entry and exit, with the numbers, and which checks failed;
:func:`taichi_bearing.post.spall_report.verdict_blocks`), the checks table, the key
figures (contact forces through the spall, the sensor acceleration with the events
marked, the animation when the folder holds one), then the analyses (:data:`SECTIONS`);
the mesh, the run's times and the case close it as an appendix (:data:`APPENDIX`).
"""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

from taichi_bearing.output.layout import (
    FIGURES_DIR,
    FIGURES_INDEX_FILE,
    MESH_STATISTICS_FILE,
    REPORT_MD_FILE,
    SUMMARY_FILE,
)
from taichi_bearing.output.run_folder import passage_events, read_case_dict, read_json
from taichi_bearing.post.document import (
    Heading,
    Para,
    Table,
    figure_block,
    fmt,
    pct,
    write_documents,
)
from taichi_bearing.post.spall_report import (
    distribution_blocks,
    interval_blocks,
    spall_blocks,
    verdict_blocks,
)

__all__ = ["APPENDIX", "SECTIONS", "report_blocks", "write_report"]

# the report's sections (level 2), in order, then the appendix's (level 3)
SECTIONS = (
    "Verdict",
    "Checks",
    "Key figures",
    "Spall passages",
    "Spectral analysis",
    "Modes near the re-stressing band",
    "Defect size",
    "Numerical noise and notch filters",
    "Static load distribution",
    "Deformed mesh at the spall",
)
APPENDIX_TITLE = "Appendix: mesh, run and case"
APPENDIX = ("Mesh", "Stages and times", "Case")
KEY_FIGURES = ("contact_forces", "acceleration")


# --------------------------------------------------------------------------- sections


def _flatten(d: dict, prefix: str = "") -> list[tuple[str, object]]:
    out = []
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out += _flatten(v, key + ".")
        else:
            out.append((key, v))
    return out


def _case(case: dict) -> list:
    if not case:
        return [Para("case.yaml is missing from the run folder.")]
    rows = [[k, fmt(v)] for k, v in _flatten(case)]
    return [Table(["key", "value"], rows)]


def _group_parts(d: dict) -> str:
    rollers = {k: v for k, v in d.items() if re.fullmatch(r"roller\d+", k)}
    parts = [f"{k} {v}" for k, v in d.items() if k not in rollers]
    if rollers:
        vals = sorted(set(rollers.values()))
        span = f"{vals[0]}" if len(vals) == 1 else f"{vals[0]}-{vals[-1]}"
        parts.append(f"rollers ({len(rollers)}) {span} each")
    return ", ".join(parts)


# mesh_statistics keys (SI) shown in friendlier units
_MESH_UNITS = {
    "min_size": ("shortest element edge (mm)", 1e3),
    "max_size": ("longest element edge (mm)", 1e3),
    "min_char_length": ("smallest characteristic length (mm)", 1e3),
    "wave_speed": ("dilatational wave speed (m/s)", 1.0),
    "critical_dt": ("critical time step (ns)", 1e9),
    "worst_aspect": ("worst aspect ratio", 1.0),
    "worst_jacobian_ratio": ("worst Jacobian ratio", 1.0),
    "resolution_wave_speed": ("Rayleigh wave speed (m/s)", 1.0),
}


def _per_part(values: dict, scale: float, digits: int = 3) -> str:
    """Per-part numbers, the rollers gathered into one span."""
    return _group_parts({k: fmt(scale * v, digits) for k, v in values.items() if v is not None})


def _mesh(summary: dict, run_dir: Path, case: dict, figs: dict) -> list:
    from taichi_bearing.mesh.quality import resolution_warning

    stats = summary.get("mesh_statistics") or {}
    path = run_dir / MESH_STATISTICS_FILE
    if not stats and path.is_file():
        stats = read_json(path)
    rows = [
        ["elements", fmt(summary.get("n_elements"))],
        ["nodes", fmt(summary.get("n_nodes"))],
    ]
    n_per = fmt(stats.get("elements_per_wavelength"))
    per_part = {
        "part_max_size": ("longest element edge per part (mm)", 1e3),
        "resolved_frequency": (f"resolves up to, {n_per} elements per wavelength (kHz)", 1e-3),
    }
    for key, value in stats.items():
        if key in ("n_nodes", "n_elements", "elements_per_wavelength"):
            continue
        label, scale = {**_MESH_UNITS, **per_part}.get(key, (key, None))
        if key in per_part:
            text = _group_parts({k: fmt(scale * v, 3) for k, v in (value or {}).items()})
        elif isinstance(value, dict):
            text = _group_parts(value)
        elif scale is not None and isinstance(value, (int, float)):
            text = fmt(scale * value)
        else:
            text = fmt(value)
        rows.append([label, text])
    out: list = [Table(["quantity", "value"], rows)]
    # the bands the run analyses: every spectrum up to Nyquist, the envelope in its band
    rate = (case.get("run") or {}).get("sample_rate_Hz")
    bands = [("run.sample_rate_Hz / 2", 0.5 * float(rate))] if rate else []
    if _envelope_band(figs):
        bands.append(("the envelope analysis band", _envelope_band(figs)[1]))
    notes = [n for n in (resolution_warning(stats, hz, what) for what, hz in bands) if n]
    if notes:  # the envelope band's, the more specific, when both warn
        out.append(Para(f"Warning: {notes[-1]}."))
    elif stats.get("resolved_frequency") and bands:
        out.append(Para("Every part resolves the bands the run analyses (criterion above)."))
    return out


def _stages(summary: dict) -> list:
    stages = summary.get("stage_times_s") or {}
    rows = [[name, fmt(t)] for name, t in stages.items()]
    if stages:
        rows.append(["total", fmt(sum(float(t) for t in stages.values() if t is not None))])
    out = [Table(["stage", "wall time (s)"], rows)] if rows else []
    run_rows = [
        ["time step dt (s)", fmt(summary.get("dt_s"))],
        ["steps", fmt(summary.get("n_steps"))],
        ["wall time (s)", fmt(summary.get("wall_time_s"))],
        ["element-steps per second", fmt(summary.get("element_steps_per_s"))],
        ["energy balance error", fmt(summary.get("energy_balance_error"))],
        ["cage speed relative error", fmt(summary.get("cage_speed_rel_error"))],
    ]
    return out + [Table(["run", "value"], run_rows)]


def _static(summary: dict) -> list:
    sim = summary.get("static_roller_forces_N") or []
    ana = summary.get("analytical_roller_forces_N") or []
    if not sim or not ana:
        return [Para("summary.json holds no static roller forces.")]
    ref = summary.get("reference_roller_forces_N") or [None] * len(sim)
    peak = max(abs(float(a)) for a in ana if a is not None) or 1.0
    peak_ref = max((abs(float(r)) for r in ref if r is not None), default=0.0) or 1.0
    rows = []
    for j, (s, a, r) in enumerate(zip(sim, ana, ref, strict=False)):
        loaded = a is not None and abs(float(a)) > 0.01 * peak
        loaded_ref = r is not None and abs(float(r)) > 0.01 * peak_ref
        rows.append(
            [
                str(j),
                fmt(s),
                fmt(a),
                pct(s, a) if loaded else "unloaded",
                fmt(r),
                pct(s, r) if loaded_ref else "unloaded",
            ]
        )
    js = max(range(len(sim)), key=lambda j: float(sim[j] or 0.0))
    ja = max(range(len(ana)), key=lambda j: float(ana[j] or 0.0))
    text = (
        f"End of preload against the analytical (rigid-ring, Harris) load distribution of "
        f"design section 4 and against the flexible-ring reference (the rings' own mesh and "
        f"supports with a Palmgren spring per roller, taichi_bearing.simulation.static_reference). "
        f"Q_max: simulated {fmt(sim[js])} N (roller {js}), analytical {fmt(ana[ja])} N "
        f"(roller {ja}), difference {pct(sim[js], ana[ja])}"
    )
    if any(r is not None for r in ref):
        jr = max(range(len(ref)), key=lambda j: float(ref[j] or 0.0))
        text += f"; flexible-ring reference {fmt(ref[jr])} N, difference {pct(sim[js], ref[jr])}"
    text += (
        ". An outer ring hung from the adapter is not rigid: the checks that apply to it are "
        "the flexible-ring ones (see Checks). Errors are shown for rollers carrying more "
        "than 1 % of Q_max."
    )
    head = ["roller", "simulated (N)", "analytical (N)", "error", "flexible ring (N)", "error"]
    return [Para(text), Table(head, rows)]


def _checks(summary: dict) -> list:
    checks = summary.get("checks") or {}
    if not checks:
        return [Para("summary.json holds no checks.")]
    rows = []
    for name, c in checks.items():
        c = c or {}
        passed = c.get("passed")
        rows.append(
            [
                name,
                fmt(c.get("value")),
                fmt(c.get("limit")),
                "PASS" if passed else ("FAIL" if passed is not None else "-"),
                str(c.get("note") or ""),
            ]
        )
    return [Table(["check", "value", "limit", "result", "note"], rows)]


def _passages(summary: dict, figs: dict, run_dir: Path) -> list:
    ev = passage_events(summary)
    out: list = []
    if ev:
        rows = [
            [
                fmt(e["roller"]),
                fmt(1e3 * e["entry_time_s"]),
                fmt(1e3 * e["first_impact_time_s"]) if "first_impact_time_s" in e else "-",
                fmt(1e3 * e["exit_time_s"]),
                fmt(1e3 * (e["exit_time_s"] - e["entry_time_s"])),
                fmt(e.get("exit_impulses")),
                fmt(e.get("exit_force_peak_ratio"), 3),
            ]
            for e in ev
        ]
        head = ["roller", "entry (ms)", "first touch of the exit edge (ms)", "exit (ms)",
                "entry to exit (ms)", "impulses at exit", "exit force peak / F0"]  # fmt: skip
        out.append(Table(head, rows))
        out += distribution_blocks(summary, len(ev))  # the finding is the distribution
        exits = [e["exit_time_s"] for e in ev if math.isfinite(e["exit_time_s"])]
        out += interval_blocks(summary, exits)
    else:
        out.append(Para("No spall passage was recorded (summary.json events)."))
    return out + spall_blocks(summary, figs, run_dir)


def _key_figures(figs: dict, run_dir: Path) -> list:
    """The contact forces through the spall and the sensor acceleration with the events
    marked, and a link to the animation when the folder holds one."""
    from taichi_bearing.post.animation import animation_note

    out = [b for name in KEY_FIGURES for b in figure_block(figs, run_dir, name)]
    return out + [Para(n) for n in [animation_note(run_dir)] if n]


def _noise(summary: dict, figs: dict, run_dir: Path) -> list:
    pred = summary.get("noise_frequencies_predicted_hz") or []
    meas = summary.get("noise_frequencies_measured_hz") or []
    # The run writes {surface: Hz}; a plain list is accepted too.
    if not isinstance(pred, dict):
        pred = {str(i): v for i, v in enumerate(pred)}
    if not isinstance(meas, dict):
        meas = {str(i): v for i, v in enumerate(meas)}
    out: list = [
        Para(
            "Rolling over the polygonal mesh surfaces excites tones at the facet passing "
            "frequencies (smooth arc contact removes most of them). Predicted (from the edge "
            "counts) against the highest spectral peak within 10 % of each, which counts as "
            "a tone when it stands at least 10 dB over the band's median:"
        )
    ]
    prom = summary.get("noise_peak_prominence_db") or {}
    rows = [
        [
            name,
            fmt(pred.get(name)),
            fmt(meas.get(name)),
            pct(meas.get(name), pred.get(name)),
            fmt(prom.get(name), 3) if isinstance(prom, dict) else "-",
        ]
        for name in dict.fromkeys([*pred, *meas])
    ]
    head = ["source", "predicted (Hz)", "highest peak nearby (Hz)", "difference", "dB over band"]
    out.append(Table(head, rows))
    check = (summary.get("checks") or {}).get("noise_frequencies") or {}
    if check.get("note"):
        out.append(Para(f"Check: {check['note']}."))
    notches = ((figs.get("psd_notch") or {}).get("values") or {}).get("notches") or []
    if notches:
        out.append(Para("Notch filters (Q = 30) at each predicted frequency, measured on the PSD:"))
        out.append(
            Table(
                ["notch (Hz)", "peak bin (Hz)", "PSD before", "PSD after", "attenuation (dB)"],
                [
                    [
                        fmt(r["frequency_hz"]),
                        fmt(r["peak_hz"]),
                        fmt(r["before"]),
                        fmt(r["after"]),
                        fmt(r["attenuation_db"], 3),
                    ]
                    for r in notches
                ],
            )
        )
    return out + figure_block(figs, run_dir, "psd_notch")


def _spectral(figs: dict, run_dir: Path) -> list:
    out: list = []
    for name in ("envelope_spectrum", "kurtogram", "spectral_kurtosis", "spectrogram"):
        out += figure_block(figs, run_dir, name)
    return out + figure_block(figs, run_dir, "third_octave")


def _envelope_band(figs: dict) -> tuple[float, float] | None:
    """The band of the envelope analysis (the kurtogram's band above fs/16, where the
    re-stressing impulses ring), Hz."""
    band = ((figs.get("envelope_spectrum") or {}).get("values") or {}).get("band_hz")
    return (float(band[0]), float(band[1])) if band and len(band) == 2 else None


def _modes(run_dir: Path, figs: dict) -> list:
    """The outer ring's modes nearest the envelope band, computed here from case.yaml
    (the mesh and a shift-invert Lanczos solve: a few seconds, no Taichi)."""
    import warnings

    from taichi_bearing.case import load_case
    from taichi_bearing.errors import InputError
    from taichi_bearing.modes.band import modes_near_band
    from taichi_bearing.output.layout import CASE_FILE

    band = _envelope_band(figs)
    if band is None:
        return [Para("No envelope band was found (figures.json), so no modes are named.")]
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            case = load_case(run_dir / CASE_FILE)
        result = modes_near_band(case, band)
    except (InputError, ValueError, KeyError, RuntimeError) as exc:
        return [Para(f"The outer ring's modes were not computed: {exc}.")]
    lo, hi = band
    where = ["below" if m.frequency < lo else "above" if m.frequency > hi else "inside"
             for m in result.modes]  # fmt: skip
    rows = [
        [fmt(m.frequency, 5), w, m.description] for m, w in zip(result.modes, where, strict=True)
    ]
    text = (
        f"The envelope analysis uses {fmt(lo / 1e3, 3)}-{fmt(hi / 1e3, 3)} kHz, the band "
        "the re-stressing impulses excite (the kurtogram's best band above fs/16). Of the "
        f"{len(rows)} modes of the outer ring (with its adapter, held as in the run) "
        f"nearest it, {where.count('inside')} lie inside; `python -m taichi_bearing modes` "
        "lists the ring's modes from 0 Hz."
    )
    return [Para(text), Table(["frequency (Hz)", "band", "shape"], rows)]


def _defect(summary: dict) -> list:
    est, true = summary.get("defect_size_estimate_m"), summary.get("defect_size_true_m")
    rows = [
        ["estimated from the simulated signal (mm)", fmt(None if est is None else 1e3 * est)],
        ["true spall length (mm)", fmt(None if true is None else 1e3 * true)],
        ["difference", pct(est, true)],
    ]
    return [
        Para(
            "Spall length from the entry-to-exit time of each passage "
            "(diagnostics.estimate_defect_size) against the case's spall length."
        ),
        Table(["quantity", "value"], rows),
    ]


def _partial_text(partial: dict) -> str:
    """The report's warning for a run that did not finish (``summary["partial"]``)."""
    until, duration = partial.get("recorded_until_s"), partial.get("duration_s")
    span = (
        f"{fmt(1e3 * until)} ms of {fmt(1e3 * duration)} ms"
        if until is not None and duration is not None
        else "part of the run"
    )
    return (
        f"Partial run (status {partial.get('status') or 'unknown'}): {span} recorded "
        f"({partial.get('histories', '-')}); {partial.get('note', '')}. Checks, figures and "
        "numbers below are of what was recorded."
    )


def _record(meta: dict, summary: dict) -> str:
    """The time the analysed signal covers, in words (for a run without a passage)."""
    n, fs = meta.get("n_samples"), meta.get("fs_hz")
    if isinstance(n, (int, float)) and isinstance(fs, (int, float)) and fs > 0 and n > 0:
        return f"the {fmt(1e3 * n / fs, 3)} ms recorded"
    until = (summary.get("partial") or {}).get("recorded_until_s")
    return f"the {fmt(1e3 * until, 3)} ms recorded" if until is not None else "the record"


def report_blocks(run_dir: str | os.PathLike) -> list:
    """The report as a list of blocks (Heading, Para, Table, Image), in order: the
    verdict, the checks, the key figures, the analyses (:data:`SECTIONS`), then the
    appendix (:data:`APPENDIX`)."""
    run_dir = Path(run_dir)
    summary = read_json(run_dir / SUMMARY_FILE)
    case = read_case_dict(run_dir)
    figs_path = run_dir / FIGURES_DIR / FIGURES_INDEX_FILE
    if not figs_path.is_file():
        from taichi_bearing.post.run_figures import make_run_figures

        make_run_figures(run_dir)
    meta = read_json(figs_path)
    figs = meta.get("figures", {})
    name = summary.get("case_name") or case.get("name") or run_dir.name
    blocks: list = [
        Heading(f"Run report: {name}", 1),
        Para(
            f"Run folder `{run_dir}`. Signal analysed: {meta.get('sensor', '-')}, "
            f"{fmt(meta.get('fs_hz'))} Hz, {meta.get('n_samples', '-')} samples. "
            "Every number below is read from the run folder."
        ),
    ]
    verdict: list = []
    partial = summary.get("partial")
    if partial:
        verdict.append(Para(_partial_text(partial)))
    verdict += verdict_blocks(summary, figs, _record(meta, summary))
    if summary.get("missing_keys"):
        verdict.append(Para(f"summary.json lacks: {', '.join(summary['missing_keys'])}."))
    sections = {
        "Verdict": verdict,
        "Checks": _checks(summary),
        "Key figures": _key_figures(figs, run_dir),
        "Spall passages": _passages(summary, figs, run_dir),
        "Spectral analysis": _spectral(figs, run_dir),
        "Modes near the re-stressing band": _modes(run_dir, figs),
        "Defect size": _defect(summary),
        "Numerical noise and notch filters": _noise(summary, figs, run_dir),
        "Static load distribution": _static(summary),
        "Deformed mesh at the spall": figure_block(figs, run_dir, "deformed_spall"),
    }
    for title in SECTIONS:
        blocks.append(Heading(title, 2))
        blocks += sections[title]
    appendix = {
        "Mesh": _mesh(summary, run_dir, case, figs),
        "Stages and times": _stages(summary),
        "Case": _case(case),
    }
    blocks.append(Heading(APPENDIX_TITLE, 2))
    for title in APPENDIX:
        blocks.append(Heading(title, 3))
        blocks += appendix[title]
    return blocks


def write_report(run_dir: str | os.PathLike) -> Path:
    """Write ``report.md`` and ``report.html`` into a run folder; returns ``report.md``.

    Draws the figures first (:func:`~taichi_bearing.post.run_figures.make_run_figures`) when
    ``figures/figures.json`` is missing. Both files are written to a temporary name and
    renamed.
    """
    run_dir = Path(run_dir)
    md_path, _ = write_documents(report_blocks(run_dir), run_dir / REPORT_MD_FILE)
    return md_path
