"""Shared fixtures: paths of the small real files in tests/data, and the optional shared/ data."""

from __future__ import annotations

from pathlib import Path

import pytest

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
