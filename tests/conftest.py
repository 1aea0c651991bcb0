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


#: Test files that take longest (seconds, serial, 2026-11-28), run first: the suite runs on
#: every core (pytest-xdist, ``--dist loadfile``: a file's tests on one worker, in order, since
#: several files run documented commands that read what an earlier one wrote), and a long file
#: collected last would run alone at the end (test_examples.py, a quarter of the suite, made the
#: two-worker suite 13.4 min instead of about 10).
LONGEST_FIRST = (
    "test_examples.py",  # 338 s: every documented command
    "hostile/test_corpus.py",  # 86 s
    "core/test_kernel_cache.py",  # 65 s
    "hostile/test_store_faults.py",  # 49 s
    "test_cli.py",  # 42 s
    "test_cli_schemas.py",  # 41 s
    "pipeline/reports/test_amplification_report.py",  # 40 s
    "hostile/test_memory_budget.py",  # 38 s
)


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Whole files of :data:`LONGEST_FIRST` moved to the front, in that order; every other
    file keeps its place and every test its order within its file."""

    def rank(item: pytest.Item) -> int:
        path = item.path.relative_to(TESTS).as_posix()
        return LONGEST_FIRST.index(path) if path in LONGEST_FIRST else len(LONGEST_FIRST)

    items.sort(key=rank)  # stable: the order within a rank is the collection's


def pytest_configure(config: pytest.Config) -> None:
    """In a worker of the parallel suite the CPUs are the workers' already: a command run with
    its default ``--jobs`` starts no pool of its own (``STEPFRAME_JOBS=1``), which could only
    contend for them (the demo costs 18.8 s of CPU on one worker, 22.1 s on two: the pool's
    start and the kernels loaded in each worker). Tests of the pools name their workers."""
    if hasattr(config, "workerinput"):
        os.environ.setdefault("STEPFRAME_JOBS", "1")


def pytest_xdist_auto_num_workers(config: pytest.Config) -> int:
    """``-n auto``: one worker per core, at most four (the longest file alone is a third of the
    two-worker suite, so more workers would wait on it; each worker holds its own numba kernels
    and report fixtures)."""
    return max(1, min(os.cpu_count() or 1, 4))


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
