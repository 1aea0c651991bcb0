"""Compiled kernels on a read-only install: cache in a user folder, or in memory, never a crash.

Root ignores permission bits, so the package folder and HOME are made read-only by read-only
bind mounts inside a private mount namespace (``unshare -m``); skipped where that is impossible.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import stepframe
from stepframe.core import jit

RECORD = Path(__file__).parents[1] / "data" / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"
PACKAGE = Path(stepframe.__file__).resolve().parent


def _spectrum_read_only(
    home: Path, env: dict[str, str], hide_shipped: Path | None = None
) -> subprocess.CompletedProcess[str]:
    """``records spectrum`` with the package folder and ``home`` mounted read-only; with
    ``hide_shipped`` (an empty folder), the package's cache of its spectra kernels hidden by it
    (a package whose build compiled nothing)."""
    command = (
        f"{sys.executable} -c 'from stepframe.cli import main; main()' records spectrum "
        f"{RECORD} --periods-s 0.1,1.0 --json"
    )
    script = f"mount --bind -o ro {PACKAGE} {PACKAGE} && mount --bind -o ro {home} {home} && "
    if hide_shipped is not None:
        script += f"mount --bind -o ro {hide_shipped} {PACKAGE / 'records' / '__pycache__'} && "
    script += command
    full = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "XDG_"))}
    # The suite silences the notice for its other tests (tests/conftest.py); these check it.
    full.update(HOME=str(home), STEPFRAME_COMPILE_NOTICE="1", **env)
    return subprocess.run(
        ["unshare", "-m", "sh", "-c", script], capture_output=True, text=True, env=full, timeout=300
    )


def test_nothing_writable_compiles_in_memory(tmp_path: Path, read_only_bind: None) -> None:
    home = tmp_path / "home"
    home.mkdir()
    run = _spectrum_read_only(home, {})
    assert run.returncode == 0, run.stderr
    assert "Traceback" not in run.stderr
    assert "compiling numba kernels in memory" in run.stderr
    psa = json.loads(run.stdout)["components"][0]["psa_g"]
    assert psa == pytest.approx([0.3377, 0.1303], rel=2e-3)  # as from a writable install
    assert list(home.iterdir()) == []


def _package_cache_of_spectra() -> None:
    """The package's own cache of its spectra kernels, as the build leaves it (compiled here,
    into the writable package folder, when a development checkout has none yet)."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("NUMBA_", "XDG_"))}
    code = "from stepframe.core.kernel_cache import _compile_group, ENTRY_POINTS; " + (
        "_compile_group([e for e in ENTRY_POINTS if 'spectra' in e.module])"
    )
    subprocess.run([sys.executable, "-c", code], check=True, env=env, timeout=300)


def test_user_cache_folder_is_used_and_reused(tmp_path: Path, read_only_bind: None) -> None:
    """A read-only package that shipped no cache: the kernels compile once into the user's
    folder, and the next run loads them."""
    home = tmp_path / "home"
    home.mkdir()
    cache = tmp_path / "cache"
    empty = tmp_path / "no-shipped-cache"
    empty.mkdir()
    (PACKAGE / "records" / "__pycache__").mkdir(exist_ok=True)
    first = _spectrum_read_only(home, {"XDG_CACHE_HOME": str(cache)}, hide_shipped=empty)
    assert first.returncode == 0, first.stderr
    assert f"cached in {cache / 'stepframe' / 'numba'}" in first.stderr
    assert list((cache / "stepframe" / "numba").rglob("*.nbi"))
    second = _spectrum_read_only(home, {"XDG_CACHE_HOME": str(cache)}, hide_shipped=empty)
    assert second.returncode == 0, second.stderr
    assert "compiling" not in second.stderr  # loaded from the user cache, not compiled again


def test_read_only_package_lends_its_cache_to_the_user_folder(
    tmp_path: Path, read_only_bind: None
) -> None:
    """A read-only package with the cache its build compiled: copied into the user's folder, so
    the first run compiles nothing, and gives the numbers a compiling run gives."""
    _package_cache_of_spectra()
    home = tmp_path / "home"
    home.mkdir()
    cache = tmp_path / "cache"
    run = _spectrum_read_only(home, {"XDG_CACHE_HOME": str(cache)})
    assert run.returncode == 0, run.stderr
    assert "compiling" not in run.stderr
    shipped = {p.name for p in (PACKAGE / "records" / "__pycache__").glob("_spectra_kernels*.nb?")}
    copied = {p.name for p in (cache / "stepframe" / "numba").rglob("_spectra_kernels*.nb?")}
    assert shipped and shipped <= copied
    psa = json.loads(run.stdout)["components"][0]["psa_g"]
    assert psa == pytest.approx([0.3377, 0.1303], rel=2e-3)  # as from a writable install


def test_cache_false_and_in_process_kernel_agree() -> None:
    """The decorator passes options through: a kernel without cache gives numba's result."""

    def total(x: np.ndarray) -> float:
        s = 0.0
        for value in x:
            s += value
        return s

    compiled = jit.njit(cache=False)(total)
    assert compiled(np.arange(5.0)) == 10.0
    compiled_any: Any = compiled
    assert type(compiled_any._cache).__name__ == "NullCache"


def test_user_cache_root_follows_xdg(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert jit.user_cache_root() == tmp_path / "stepframe" / "numba"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path))
    assert jit.user_cache_root() == tmp_path / ".cache" / "stepframe" / "numba"


WORKERS_COMPILE = """
import os, sys, time
from stepframe.core.execution import map_items

def item(seconds):
    time.sleep(seconds)  # both workers busy before either compiles
    from stepframe.structure import _exact
    had = bool(_exact._ecs.signatures)
    _exact._ecs(0.1, -1.0, 0.5)
    return os.getpid(), had

results, failures = map_items(item, [0.5, 0.5, 0.0, 0.0], jobs=2, chunk_size=1, worth_s=0.0)
assert not failures, failures
print(len({pid for pid, had in results if not had}))
"""


@pytest.mark.parametrize("setting", ["1", "0"])
def test_workers_that_compile_announce_it_once_for_the_pool(tmp_path: Path, setting: str) -> None:
    """Workers forked before the kernels were loaded (a pool started by the records' hashing)
    compile them on a first run: one complete line for the pool, not one under way per worker
    (which interleaved), and none when the user silenced the notice."""
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env.update(NUMBA_CACHE_DIR=str(tmp_path / "cache"), STEPFRAME_COMPILE_NOTICE=setting)
    run = subprocess.run(
        [sys.executable, "-c", WORKERS_COMPILE], capture_output=True, text=True, env=env,
        timeout=300,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "2"  # each worker compiled the kernel itself
    notices = [line for line in run.stderr.splitlines() if "compiling" in line]
    if setting == "0":
        assert notices == []
    else:
        assert notices == [
            "stepframe: the worker processes are compiling numba kernels once "
            "(cached for later runs)"
        ]


CALLEE = """
from stepframe.core.jit import njit


@njit(cache=True)
def value():
    return {value}
"""
CALLER = """
from stepframe.core.jit import njit
from callee import value


@njit(cache=True)
def twice():
    return 2.0 * value()
"""


def test_a_kernel_recompiles_when_a_kernel_it_calls_changes(tmp_path: Path) -> None:
    # numba keys a cache entry on its own file only, while a caller's entry holds its callees'
    # code: without the package-wide stamp, the second run below printed 2.0 from the cache
    # after the callee had changed to return 5. The two modules stand in for the package's
    # kernel files (PACKAGE pointed at their folder in the child).
    (tmp_path / "callee.py").write_text(CALLEE.format(value=1.0))
    (tmp_path / "caller.py").write_text(CALLER)
    child = (
        "import sys\n"
        "from pathlib import Path\n"
        "from stepframe.core import jit\n"
        f"jit.PACKAGE = Path({str(tmp_path)!r})\n"
        f"sys.path.insert(0, {str(tmp_path)!r})\n"
        "import caller\n"
        "print(caller.twice(), len(caller.twice.stats.cache_hits))\n"
    )
    env = {k: v for k, v in os.environ.items() if not k.startswith("NUMBA_")}
    env["STEPFRAME_COMPILE_NOTICE"] = "0"

    def run() -> str:
        done = subprocess.run(
            [sys.executable, "-c", child], capture_output=True, text=True, env=env, check=True
        )
        return done.stdout.split()

    assert run() == ["2.0", "0"]  # compiled and cached
    assert run() == ["2.0", "1"]  # loaded from the cache
    (tmp_path / "callee.py").write_text(CALLEE.format(value=5.0))
    assert run() == ["10.0", "0"]  # the caller's entry is stale: compiled again
    assert run() == ["10.0", "1"]


def test_the_kernels_stamp_is_every_kernel_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Any module that compiles kernels changes the stamp; one that does not, does not.
    (tmp_path / "a_kernel.py").write_text("from stepframe.core.jit import njit\n")
    (tmp_path / "plain.py").write_text("x = 1\n")
    monkeypatch.setattr(jit, "PACKAGE", tmp_path)
    stamps = []
    for path, text in [(None, ""), ("plain.py", "x = 2\n"), ("a_kernel.py", "njit  # edited\n")]:
        if path is not None:
            (tmp_path / path).write_text(text)
        jit.kernel_sources_stamp.cache_clear()
        stamps.append(jit.kernel_sources_stamp())
    jit.kernel_sources_stamp.cache_clear()
    assert stamps[0] == stamps[1] != stamps[2]
