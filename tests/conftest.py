"""Shared fixtures: paths of the small real files in tests/data, and the optional shared/ data."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

# Which test happens to compile the numba kernels first depends on order and on the cache; the
# one-line compile notice on stderr would then show up in whichever command a test runs. The
# suite silences it (subprocesses inherit this); tests/core/test_jit.py turns it on to check it.
os.environ.setdefault("STEPFRAME_COMPILE_NOTICE", "0")

TESTS = Path(__file__).parent
DATA = TESTS / "data"
#: The project's reference data folder beside the repository (absent on a bare clone).
SHARED_DATA = TESTS.parent.parent / "shared" / "data"


@pytest.fixture
def data_dir() -> Path:
    """tests/data: small real files with their provenance."""
    return DATA


@pytest.fixture
def shared_data() -> Path:
    """../shared/data, skipping the test when the clone has no shared/ folder beside it."""
    if not SHARED_DATA.is_dir():
        pytest.skip("../shared/data is not beside this clone")
    return SHARED_DATA
