"""The simulator from Python in three calls: a case read, run, and its folder read back.

>>> import taichi_bearing as tb
>>> case = tb.load_case("cases/validation/coarse_spall.yaml",
...                     ["run.duration_ms=0.05", "run.frame_interval_ms=0.05"])
>>> run = tb.run(case, "coarse_run", threads=1)         # mesh, preload, transient, checks
>>> run.summary["status"], f"{1e3 * run.histories['time_s'].iloc[-1]:.3f} ms"
('finished', '0.050 ms')
>>> run.summary["n_rollers"], "roller0_outer_fn" in run.histories
(20, True)
>>> tb.load_run("coarse_run").summary == run.summary      # the folder alone, no Taichi
True

A case is read once (its keys in SI units, overrides as ``--set`` gives them), a run
writes its folder (:mod:`taichi_bearing.output.layout` says what each file holds), and
:func:`load_run` reads any run folder, a finished one or what a stopped run left.
"""

from __future__ import annotations

import os
from collections.abc import Iterable
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from taichi_bearing.case import Case
    from taichi_bearing.output.run_folder import RunData

__all__ = ["load_case", "load_run", "run"]

# The stages are imported when called: ``import taichi_bearing`` (and the command line's
# --help) loads neither Taichi nor pandas.


def load_case(path: str | os.PathLike, overrides: Iterable[str] = ()) -> Case:
    """Read a case file, apply ``overrides`` and validate it.

    Parameters
    ----------
    path : str or path-like
        YAML case file (``cases/line_spall.yaml`` is the study's default).
    overrides : iterable of str
        ``"section.key=value"`` strings, as ``--set`` takes them, e.g.
        ``["operating.load_kN=80"]``.

    Returns
    -------
    Case
        The validated case, in SI units (:func:`taichi_bearing.case.load_case`).

    Raises
    ------
    CaseError
        The file or a value is bad; the message names the key.
    """
    from taichi_bearing.case import load_case as _load_case

    return _load_case(path, overrides)


def run(
    case: Case,
    out_dir: str | os.PathLike | None = None,
    *,
    arch: str | None = None,
    threads: int | None = None,
    resume: bool = False,
    post: bool = False,
    quiet: bool = True,
) -> RunData:
    """Run a case end to end: mesh, preload, transient, checks (and, with ``post``, the
    figures and report), written to ``out_dir``.

    Parameters
    ----------
    case : Case
        From :func:`load_case`.
    out_dir : str or path-like, optional
        The run folder (default the case's ``output.out_dir``).
    arch : {"cpu", "cuda", ...}, optional
        Taichi's backend (default the case's ``run.arch``).
    threads : int, optional
        CPU threads (default the case's ``run.threads``).
    resume : bool
        Continue from the folder's last checkpoint.
    post : bool
        Draw the figures and write the report too (off by default here: they take longer
        than a short run).
    quiet : bool
        No progress bars or stage lines.

    Returns
    -------
    RunData
        The run folder read back (:func:`load_run`): ``summary``, ``histories`` and the rest.

    Raises
    ------
    SimulationError
        The run stopped (an instability, a preload that did not converge); the files so
        far are kept.
    """
    from taichi_bearing.pipeline import run_case

    out = Path(out_dir) if out_dir is not None else case.out_dir
    run_case(case, out, arch=arch, threads=threads, resume=resume, post=post, quiet=quiet)
    return load_run(out)


def load_run(run_dir: str | os.PathLike) -> RunData:
    """Read a run folder: ``summary``, ``histories`` (a DataFrame, SI units), ``case``,
    ``preload``, ``mesh_info`` (:class:`taichi_bearing.output.run_folder.RunData`).

    A run that did not finish is read as far as it got (``partial`` says so).

    Raises
    ------
    FileNotFoundError, ValueError
        Not a run folder, or one whose files cannot be read.
    """
    from taichi_bearing.output.run_folder import load_run as _load_run

    return _load_run(run_dir)
