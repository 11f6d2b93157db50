"""Figures written to files: the one place the application saves a matplotlib Figure, for
the ``analyze`` command (:mod:`diagnostics.app.cli`) and the comparison of records
(:mod:`diagnostics.app.compare`) alike."""

from __future__ import annotations

from pathlib import Path

from bearing_io.files import atomic_path


def save_figure(fig, path: Path) -> str:
    """Save a matplotlib Figure as PNG atomically; returns the file name."""
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format="png", dpi=110)
    return path.name
