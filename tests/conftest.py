"""Shared fixtures: paths of the small real files in tests/data, and the optional shared/ data."""

from __future__ import annotations

import os
import shutil
import subprocess
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


@pytest.fixture
def read_only_bind(tmp_path: Path) -> None:
    """Skip the test unless ``unshare -m`` with a read-only bind mount works here (the tests
    that need an unwritable folder as root, who ignores permission bits)."""
    if shutil.which("unshare") is None or shutil.which("mount") is None:
        pytest.skip("unshare/mount not installed")
    probe = tmp_path / "probe"
    probe.mkdir()
    script = f"mount --bind -o ro {probe} {probe} && touch {probe}/x"
    run = subprocess.run(["unshare", "-m", "sh", "-c", script], capture_output=True, text=True)
    probe.rmdir()
    if "Read-only file system" not in run.stderr:
        why = run.stderr.strip() or run.returncode
        pytest.skip(f"no private read-only bind mounts here ({why})")
