"""Test configuration: headless plotting, Taichi offline cache in a temp dir, shared data."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")
# Taichi's offline kernel cache goes to a throw-away folder, never the user's home. The
# pytest-xdist workers inherit the controller's folder: each takes a subfolder of it, so
# that two processes never write one cache at once.
_cache = os.environ.get("TAICHI_BEARING_CACHE_DIR") or tempfile.mkdtemp(
    prefix="taichi_bearing_test_cache_"
)
if os.environ.get("PYTEST_XDIST_WORKER"):
    _cache = os.path.join(_cache, os.environ["PYTEST_XDIST_WORKER"])
    os.makedirs(_cache, exist_ok=True)
os.environ["TAICHI_BEARING_CACHE_DIR"] = _cache

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
