"""The main job, over every stage: a case simulated, its run checked, its figures drawn and
its report written (:func:`run_case`, what ``python -m taichi_bearing CASE.yaml`` does),
and a run folder's checks, figures and report redone from the folder alone
(:func:`recheck_run`, ``python -m taichi_bearing post RUN_DIR``).

The stages themselves never call a later one: the simulation writes the run folder
(:mod:`taichi_bearing.simulation`), the checks read it (:mod:`taichi_bearing.checks`), the
figures and report render it (:mod:`taichi_bearing.post`); this module runs them in turn.
The simulation is imported when a run (or ``post --remesh``) needs it, so that ``post``
redoes a run's checks and report without loading Taichi.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from pathlib import Path

from bearing_io.files import write_json
from bearing_io.progress import LOG_INTERVAL_S
from taichi_bearing.case import Case, load_case, load_case_for_cli
from taichi_bearing.checks import run_checks
from taichi_bearing.errors import InputError
from taichi_bearing.output.histories import read_histories
from taichi_bearing.output.layout import (
    CASE_FILE,
    HISTORIES_FILE,
    HISTORIES_PARTS_DIR,
    MESH_INFO_FILE,
    PRELOAD_FILE,
    REFERENCE_KEY,
    ROLLING_RATES_KEY,
    STATUS_FINISHED,
    STATUS_RUNNING,
)
from taichi_bearing.output.run_folder import RunData, load_run, missing_for_checks
from taichi_bearing.output.summary import write_partial_summary, write_summary
from taichi_bearing.post.report import write_report
from taichi_bearing.post.run_figures import make_run_figures

__all__ = ["recheck_run", "run_case", "run_ensemble"]


def run_case(
    case: Case,
    out_dir: str | Path | None = None,
    *,
    resume: bool = False,
    arch: str | None = None,
    threads: int | None = None,
    quiet: bool = False,
    progress_interval: float | None = LOG_INTERVAL_S,
    post: bool = True,
    log=print,
) -> dict:
    """Run a case end to end and write its run folder: mesh, preload, transient, checks,
    figures and report.

    Parameters
    ----------
    case : Case
    out_dir : path, optional
        Run folder (default ``case.out_dir``).
    resume : bool
        Continue from the last checkpoint in ``out_dir/checkpoints`` (no preload).
    arch, threads : optional
        Override ``run.arch`` / ``run.threads``.
    quiet : bool
        No progress bar and no stage lines.
    progress_interval : float, optional
        Wall seconds between progress lines of the preload and the transient when stderr
        is not a terminal (a log); None: none.
    post : bool
        Make figures and the report.
    log : callable
        Where stage lines go.

    Returns
    -------
    dict
        The summary written to ``summary.json``.

    Raises
    ------
    SimulationError
        The run stopped (instability, preload not converged); files so far are kept.
    KeyboardInterrupt
        After the histories up to that point and a partial summary have been written.
    """
    from taichi_bearing.simulation.simulate import simulate  # Taichi: only for a run

    say = (lambda *a: None) if quiet else log
    out = Path(out_dir) if out_dir is not None else case.out_dir
    done = simulate(
        case, out, resume=resume, arch=arch, threads=threads, quiet=quiet,
        progress_interval=progress_interval, log=log,
    )  # fmt: skip
    return _check_run(case, out, done, post, say)


def _check_run(case: Case, out: Path, done, post: bool, say) -> dict:
    """A simulated run's checks (and figures and report): its summary finished."""
    summary, times = done.summary, done.summary["stage_times_s"]
    t0 = time.perf_counter()
    hist = read_histories(out)
    summary.update(run_checks(case, done.mesh_info, hist, done.preload))
    summary["status"] = STATUS_FINISHED
    times["post"] = time.perf_counter() - t0
    write_summary(out, summary)
    if post:
        _figures_and_report(out, say)
        times["post"] = time.perf_counter() - t0
        write_summary(out, summary)
    failed = [k for k, c in summary["checks"].items() if c["passed"] is False]
    say(f"checks: {len(summary['checks']) - len(failed)} passed, failed: {failed or 'none'}")
    return summary


def run_ensemble(
    cases: Sequence[Case],
    out_dirs: Sequence[str | Path],
    *,
    arch: str | None = None,
    threads: int | None = None,
    quiet: bool = False,
    progress_interval: float | None = LOG_INTERVAL_S,
    post: bool = True,
    log=print,
) -> list[dict | Exception]:
    """:func:`run_case` of several cases stepped as one model (an ensemble,
    :func:`~taichi_bearing.simulation.ensemble.simulate_ensemble`): each case's run folder
    as its run alone writes it, histories bit for bit.

    Returns
    -------
    list
        Per case, its summary, or the error that stopped it (its folder keeps what it
        recorded and says why).
    """
    from taichi_bearing.simulation.ensemble import simulate_ensemble  # Taichi

    say = (lambda *a: None) if quiet else log
    done = simulate_ensemble(
        cases, out_dirs, arch=arch, threads=threads, quiet=quiet,
        progress_interval=progress_interval, log=log,
    )  # fmt: skip
    return [
        d if isinstance(d, Exception) else _check_run(case, Path(out), d, post, say)
        for case, out, d in zip(cases, out_dirs, done, strict=True)
    ]


def recheck_run(out_dir: str | Path, *, post: bool = True, remesh: bool = False, say=print) -> dict:
    """Redo the checks (and figures and report) of a run from its folder.

    Pure post-processing: the case, the mesh info, the preload (with the flexible-ring
    reference) and the histories are read from the folder
    (:func:`taichi_bearing.output.run_folder.load_run`); nothing is meshed or solved. What
    the run measured (steps, times) is kept from ``summary.json``. A run that did not finish
    (Ctrl-C, a solver stop, ``kill -9`` with the histories only in parts) is checked on
    what was recorded and marked partial: ``summary["partial"]`` says how far it got.

    Parameters
    ----------
    out_dir : str or path
        The run folder.
    post : bool
        Also redraw the figures and rewrite the report.
    remesh : bool
        For a folder written before runs recorded ``mesh_info.json`` and the reference:
        mesh ``case.yaml`` again and solve them now (written to the folder; the
        ``preload.json`` entries say they were computed by ``post --remesh``).
    say : callable
        Where notes go.

    Returns
    -------
    dict
        The summary written.

    Raises
    ------
    InputError
        Not a run folder, no histories, or the folder lacks what the checks need (one
        line naming it).
    """
    out = Path(out_dir)
    try:
        run = load_run(out)
        if remesh and missing_for_checks(run) and (out / CASE_FILE).is_file():
            _remesh_for_checks(load_case(out / CASE_FILE), run)
            run = load_run(out)
    except (FileNotFoundError, ValueError) as exc:
        raise InputError(" ".join(str(exc).split())) from None
    missing = missing_for_checks(run)
    if missing:
        hint = "" if remesh else "; `post --remesh` meshes case.yaml and solves them now"
        raise InputError(
            f"{out}: lacks {', '.join(missing)} (a run folder from before runs recorded them){hint}"
        )
    case = load_case_for_cli(out / CASE_FILE)  # its warnings as one line each
    summary = {"case_name": case.name, **run.summary}
    t0 = time.perf_counter()
    summary.update(run_checks(case, run.mesh_info, run.histories, run.preload))
    if run.partial:
        summary["partial"] = {
            "status": run.status,
            "recorded_until_s": run.t_end,
            "duration_s": case.run.duration,
            "histories": HISTORIES_FILE if run.merged else f"{HISTORIES_PARTS_DIR}/ only",
            "note": "the run did not finish"
            + (" (killed, or still going)" if run.status in (None, STATUS_RUNNING) else "")
            + "; the checks are of what was recorded",
        }
        say(
            f"partial run (status {run.status}): checked on the "
            f"{1e3 * run.t_end:.4g} ms recorded of {1e3 * case.run.duration:.4g} ms"
        )
    else:
        summary.pop("partial", None)
    write = write_partial_summary if run.partial else write_summary
    write(out, summary)
    if post:
        _figures_and_report(out, say)
    summary.setdefault("stage_times_s", {})["post"] = time.perf_counter() - t0
    write(out, summary)
    return summary


def _remesh_for_checks(case: Case, run: RunData) -> None:
    """Write what a run folder from before ``mesh_info.json`` and the ``preload.json``
    check entries lacks, from a new mesh of its case (``post --remesh``)."""
    from taichi_bearing.simulation.simulate import check_entries, stage_mesh  # Taichi

    mesh, _ = stage_mesh(case)
    if run.mesh_info is None:
        write_json(run.run_dir / MESH_INFO_FILE, mesh.info)
    lacking = [k for k in (REFERENCE_KEY, ROLLING_RATES_KEY) if k not in (run.preload or {})]
    if run.preload is not None and lacking:
        entries = check_entries(case, mesh)
        pre = {**run.preload, **{k: entries[k] for k in lacking}}
        pre["computed_after_the_run"] = {
            "keys": lacking,
            "note": "computed by `post --remesh` from case.yaml (the run folder predates them)",
        }
        write_json(run.run_dir / PRELOAD_FILE, pre)


def _figures_and_report(out: Path, say) -> None:
    """The run's figures and report; a failure is reported and the run's results stand."""
    for func in (make_run_figures, write_report):
        try:
            func(out)
        except Exception as exc:  # noqa: BLE001 - the run's results stand without them
            say(f"post: {func.__name__} failed: {type(exc).__name__}: {exc}")
