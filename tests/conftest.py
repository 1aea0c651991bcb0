"""Shared fixtures: paths of the small real files in tests/data, and the optional shared/ data."""

from __future__ import annotations

import contextlib
import hashlib
import importlib.metadata
import importlib.util
import os
import shutil
import subprocess
import sys
import tempfile
import time
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


#: Environment variable naming the folder of the build's kernels compiled for this suite
#: (:func:`_built_kernels`): ``cache/`` as ``python -m stepframe.core.kernel_cache`` left it in
#: an empty ``NUMBA_CACHE_DIR``, and ``build.log``, its stderr. tests/core/test_kernel_cache.py
#: checks the commands against it; the suite runs on a copy of it.
BUILT_KERNELS = "STEPFRAME_TEST_BUILT_KERNELS"


def pytest_configure(config: pytest.Config) -> None:
    """In a worker of the parallel suite the CPUs are the workers' already: a command run with
    its default ``--jobs`` starts no pool of its own (``STEPFRAME_JOBS=1``), which could only
    contend for them (the demo costs 18.8 s of CPU on one worker, 22.1 s on two: the pool's
    start and the kernels loaded in each worker). Tests of the pools name their workers.

    In the controlling process (or the only one), once for the whole suite: the kernels of
    :data:`stepframe.core.kernel_cache.ENTRY_POINTS` compiled as the package's build compiles
    them, into a folder of their own (:func:`_built_kernels`, kept between runs while the
    kernels' sources are unchanged), and every test and command of the suite then runs on a copy
    of it (``NUMBA_CACHE_DIR``, which the workers and subprocesses inherit). Before, the
    kernels compiled once lazily in whichever tests ran them first (an editable install has no
    compiled cache) and once more in tests/core/test_kernel_cache.py, into its own empty cache
    (65-73 s of that file). A user's own ``NUMBA_CACHE_DIR`` is left alone, and the test then
    compiles its own.
    """
    if hasattr(config, "workerinput"):
        os.environ.setdefault("STEPFRAME_JOBS", "1")
        return
    if os.environ.get("NUMBA_CACHE_DIR") or os.environ.get("NUMBA_DISABLE_JIT") == "1":
        return
    built = _built_kernels()
    if built is None:  # the build failed: test_kernel_cache.py compiles again and says why
        return
    suite_cache = Path(tempfile.mkdtemp(prefix="stepframe-test-numba-"))
    shutil.copytree(built / "cache", suite_cache, dirs_exist_ok=True)
    config.add_cleanup(lambda: shutil.rmtree(suite_cache, ignore_errors=True))
    os.environ[BUILT_KERNELS] = str(built)
    os.environ["NUMBA_CACHE_DIR"] = str(suite_cache)
    if "numba" in sys.modules:  # numba reads its settings on import: this process read them
        import numba

        numba.config.reload_config()  # type: ignore[no-untyped-call]


def _kernel_sources_key() -> str:
    """What the compiled kernels depend on: each kernel source file's path, size and time
    (numba's own stamp of a cached function's source) and the list the build compiles
    (core/kernel_cache.py), numba's version and this interpreter."""
    spec = importlib.util.find_spec("stepframe")
    assert spec is not None and spec.origin is not None, "stepframe is not installed"
    package = Path(spec.origin).parent
    listing = package / "core" / "kernel_cache.py"
    digest = hashlib.sha256()
    for path in sorted(package.rglob("*.py")):
        if path == listing or b"njit" in path.read_bytes():
            stat = path.stat()
            digest.update(f"{path}\0{stat.st_size}\0{stat.st_mtime_ns}\n".encode())
    digest.update(
        f"{importlib.metadata.version('numba')}\0{sys.executable}\0{sys.version}".encode()
    )
    return digest.hexdigest()[:16]


def _built_kernels() -> Path | None:
    """The folder of the build's kernels for the present sources (see :data:`BUILT_KERNELS`),
    compiled now when there is none (2 processes; 30-40 s), else the one an earlier run left in
    the temporary folder; None when the build fails. Folders of other sources untouched for a
    day are removed (not sooner: another clone's suite may be reading its own)."""
    root = Path(tempfile.gettempdir())
    folder = root / f"stepframe-test-kernels-{_kernel_sources_key()}"
    if (folder / "build.log").is_file():
        return folder
    for old in root.glob("stepframe-test-kernels-*"):
        with contextlib.suppress(OSError):
            if time.time() - old.stat().st_mtime > 86_400:
                shutil.rmtree(old, ignore_errors=True)
    partial = Path(tempfile.mkdtemp(prefix=f"{folder.name}.partial-", dir=root))
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.update(NUMBA_CACHE_DIR=str(partial / "cache"))
    print("\nstepframe tests: compiling the kernels as the build does (once)", file=sys.stderr)
    built = subprocess.run(
        [sys.executable, "-m", "stepframe.core.kernel_cache", "--jobs", "2"],
        capture_output=True, text=True, env=env, timeout=900, cwd=partial,
    )  # fmt: skip
    if built.returncode != 0:
        shutil.rmtree(partial, ignore_errors=True)
        return None
    (partial / "build.log").write_text(built.stderr)
    try:
        partial.rename(folder)
    except OSError:  # another run finished it first
        shutil.rmtree(partial, ignore_errors=True)
    return folder


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
