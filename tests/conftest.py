"""Test configuration: headless plotting, Taichi offline cache in a temp dir, shared data."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
# Taichi's offline kernel cache goes to a throw-away folder, never the user's home.
os.environ.setdefault(
    "TAICHI_BEARING_CACHE_DIR", tempfile.mkdtemp(prefix="taichi_bearing_test_cache_")
)

ROOT = Path(__file__).resolve().parents[1]
CWRU_DIR = ROOT.parent / "shared" / "data" / "cwru"


@pytest.fixture(scope="session")
def cwru_dir() -> Path:
    """Folder of the measured CWRU records; the test is skipped where it is absent."""
    if not CWRU_DIR.is_dir():
        pytest.skip(f"measured data not available at {CWRU_DIR}")
    return CWRU_DIR


@pytest.fixture(scope="session")
def default_case_path() -> Path:
    return ROOT / "cases" / "line_spall.yaml"
