"""Compiled kernels: where numba caches them, and one stderr line while they compile.

``numba.njit(cache=True)`` writes its cache next to the source file (``__pycache__``) and, when
that folder is read-only, under the user's home; with both read-only (a system or container
install) decorating the function raises ``RuntimeError: cannot cache function ...: no locator
available``. :func:`njit` is the drop-in that decides before decorating:

1. ``NUMBA_CACHE_DIR`` set by the user: numba's own choice, untouched;
2. the package folder writable: the cache goes beside the source, as numba does;
3. else ``$XDG_CACHE_HOME/stepframe/numba`` (default ``~/.cache/stepframe/numba``) if it can be
   created and written: numba is pointed there (``numba.config.CACHE_DIR``), after the cache the
   package's build compiled into its read-only folder is copied there (a system or container
   install loads the kernels as a writable one does), so a kernel missing from it compiles once
   per user, not on every call;
4. else no disk cache: the kernels compile in memory on every run, without a traceback.

The package's build compiles every kernel into the package's own cache
(:mod:`stepframe.core.kernel_cache`), so an installed stepframe normally loads them all (case 2);
the rest of this applies where that cache cannot (the cases listed there).

numba keys a cached kernel on its own source file only, but a kernel calling one of another
file carries that callee's machine code in its own cache entry: edit the callee's file and the
caller went on running the old callee from its cache, silently (a developer's checkout; met in
issue 26's work). stepframe's kernels are therefore keyed on all of them:
:func:`kernel_sources_stamp`, the hash of every package module that compiles kernels, is the
source stamp of each (:class:`_InTreeLocator`, :class:`_UserProvidedLocator`, placed before
numba's own). An edit to any kernel file recompiles every kernel once, as the test suite's
cache already did; an installed package is unaffected (its files, and so its stamp, are the
ones its build compiled with).

Compiling the kernels takes seconds to tens of seconds, once. While a stepframe kernel compiles
(a cache miss, not a cache load) one line goes to stderr, finished with the time it took:
``stepframe: compiling numba kernels once (cached in DIR for later runs)... 14.2 s``; a later
compilation in the same run says ``stepframe: compiling more numba kernels... 2.7 s``. The
workers of a :class:`stepframe.core.execution.WorkerPool` inherit the kernels the process that
forked them had loaded; a kernel it had not (a pool started by hashing the records, or a
kernel only the workers run, as the confirmation's bootstrap) they compile themselves on a
first run, and then the first of the pool says so once, in one
complete line (``stepframe: the worker processes are compiling numba kernels once ...``): lines
under way in several workers would interleave (``STEPFRAME_COMPILE_NOTICE=worker``, set by the
pool). Set :data:`ANNOUNCE` to False, or the environment variable
``STEPFRAME_COMPILE_NOTICE=0``, to silence it.
"""

from __future__ import annotations

import functools
import hashlib
import os
import shutil
import sys
import tempfile
import threading
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numba
from numba.core import caching, event

__all__ = ["ANNOUNCE", "cache_folder", "njit"]

#: Print the compile notice on stderr (one line per compiling run of a stepframe kernel).
ANNOUNCE = os.environ.get("STEPFRAME_COMPILE_NOTICE", "1") != "0"

_F = TypeVar("_F", bound=Callable[..., Any])
_lock = threading.Lock()
_decided: dict[str, str | None] = {}


def _writable(folder: Path) -> bool:
    """Whether files can be created in ``folder`` (made if missing); root's permission bypass
    is no guide on read-only mounts, so this tries it."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=folder):
            pass
    except OSError:
        return False
    return True


def user_cache_root() -> Path:
    """``$XDG_CACHE_HOME/stepframe/numba``, default ``~/.cache/stepframe/numba``."""
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "stepframe" / "numba"


def cache_folder(source_file: str) -> str | None:
    """Where the kernels of ``source_file`` are cached: ``"numba"`` (numba's own choice: the
    user's ``NUMBA_CACHE_DIR`` or the writable package folder), a user cache folder (numba is
    pointed at it), or None (no writable folder: compile in memory)."""
    package = str(Path(source_file).resolve().parent)
    with _lock:
        if package in _decided:
            return _decided[package]
        choice: str | None
        if os.environ.get("NUMBA_CACHE_DIR") or _writable(Path(package) / "__pycache__"):
            choice = "numba"
        elif _writable(user_cache_root()):
            choice = str(user_cache_root())
            numba.config.CACHE_DIR = choice  # type: ignore[attr-defined]
            _seed_from_package(Path(package), source_file, Path(choice))
        else:
            choice = None
        _decided[package] = choice
        return choice


def _seed_from_package(package: Path, source_file: str, cache_dir: Path) -> None:
    """Copy the cache the package's build compiled (:mod:`stepframe.core.kernel_cache`) from
    the read-only ``package/__pycache__`` into numba's folder for it under ``cache_dir``, each
    function's files where that folder has none of its own yet: numba then loads them as if it
    had compiled them there (its cache is stamped with the source's content, not its path).

    Each file is written under a temporary name and renamed, the index after its data, so
    another process never reads half of one. A failure (a full disk) only leaves the kernels to
    compile, as without the copy.
    """
    from numba.core.caching import UserProvidedCacheLocator

    shipped = package / "__pycache__"
    # numba's own folder for the source under CACHE_DIR (its locator's naming, not ours).
    subpath = UserProvidedCacheLocator.get_suitable_cache_subpath(source_file)  # type: ignore[no-untyped-call]
    target = cache_dir / subpath
    try:
        for index in shipped.glob("*.nbi"):
            if (target / index.name).exists():
                continue
            target.mkdir(parents=True, exist_ok=True)
            for source in [*shipped.glob(f"{index.stem}.*.nbc"), index]:
                partial = target / f".{source.name}.{os.getpid()}.partial"
                shutil.copyfile(source, partial)
                os.replace(partial, target / source.name)
    except OSError:
        return


#: The package whose kernels share one stamp (:func:`kernel_sources_stamp`).
PACKAGE = Path(__file__).resolve().parents[1]


@functools.lru_cache(maxsize=1)
def kernel_sources_stamp() -> bytes:
    """sha256 over every module of :data:`PACKAGE` that compiles kernels (its path in the
    package and its content): the source stamp of each stepframe kernel's cache entry (module
    docstring). Read once a process (some 12 ms for the package's 180 modules)."""
    digest = hashlib.sha256()
    for path in sorted(PACKAGE.rglob("*.py")):
        text = path.read_bytes()
        if b"njit" in text:
            digest.update(path.relative_to(PACKAGE).as_posix().encode() + b"\0")
            digest.update(hashlib.sha256(text).digest())
    return digest.digest()


class _PackageStamp:
    """Cache locator mixin: a stepframe kernel's entry is stamped with
    :func:`kernel_sources_stamp` instead of its own file's hash; other functions are left to
    numba's own locators."""

    def get_source_stamp(self) -> bytes:
        return kernel_sources_stamp()

    @classmethod
    def from_function(cls, py_func: Any, py_file: str) -> Any:
        if not Path(py_file).resolve().is_relative_to(PACKAGE):
            return None
        return super().from_function(py_func, py_file)  # type: ignore[misc]


class _UserProvidedLocator(_PackageStamp, caching.UserProvidedCacheLocator):
    """numba's locator for ``NUMBA_CACHE_DIR`` (and case 3's user folder), package-stamped."""


class _InTreeLocator(_PackageStamp, caching.InTreeCacheLocator):
    """numba's locator for the package's own ``__pycache__``, package-stamped."""


def _install_locators() -> None:
    """Put the package-stamped locators before numba's (once; numba tries them in order, and a
    user's ``NUMBA_CACHE_LOCATOR_CLASSES`` replaces the list altogether)."""
    # CacheImpl in the numba the build needs (0.68), _CacheImpl in older ones.
    impl = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl")  # noqa: B009
    classes = impl._locator_classes
    if _InTreeLocator not in classes:
        classes[:0] = [_UserProvidedLocator, _InTreeLocator]


def njit(**options: Any) -> Callable[[_F], _F]:
    """``numba.njit(**options)`` with ``cache=True`` (the default) only where a cache can be
    written (module docstring); ``cache=False`` is passed through."""

    def decorate(function: _F) -> _F:
        cache = bool(options.pop("cache", True))
        if cache:
            source = getattr(function, "__code__", None)
            cache = source is not None and cache_folder(source.co_filename) is not None
        _install_listener()
        _install_locators()
        return numba.njit(cache=cache, **options)(function)  # type: ignore[no-any-return]

    return decorate


class _CompileNotice(event.Listener):
    """Prints the notice around the outermost compilation of a stepframe kernel."""

    def __init__(self) -> None:
        self.depth = 0
        self.started = 0.0
        self.printed = False
        self.episodes = 0

    def on_start(self, ev: Any) -> None:
        self.depth += 1
        # Read at each compile, not at import: a forked worker inherits this module imported.
        mode = os.environ.get("STEPFRAME_COMPILE_NOTICE", "1")
        if self.depth != 1 or not ANNOUNCE or mode == "0":
            return
        function = getattr((ev.data or {}).get("dispatcher"), "py_func", None)
        module = getattr(function, "__module__", "") or ""
        if function is None or not module.startswith("stepframe."):
            return
        self.episodes += 1
        where = cache_folder(function.__code__.co_filename)
        if mode == "worker":
            from stepframe.core.execution import claim_compile_notice

            if claim_compile_notice():
                what = _what(where, first=True)
                print(f"stepframe: the worker processes are {what}", file=sys.stderr, flush=True)
            return
        self.started = time.perf_counter()
        self.printed = True
        print(f"stepframe: {_what(where, self.episodes == 1)}...", end="", file=sys.stderr)
        sys.stderr.flush()

    def on_end(self, ev: Any) -> None:
        self.depth -= 1
        if self.depth == 0 and self.printed:
            self.printed = False
            print(f" {time.perf_counter() - self.started:.1f} s", file=sys.stderr, flush=True)


def _what(where: str | None, first: bool) -> str:
    """The notice's words for a compilation cached in ``where`` (:func:`cache_folder`)."""
    if not first:
        return "compiling more numba kernels"
    if where is None:
        return "compiling numba kernels in memory (no writable cache folder: again next run)"
    if where == "numba":
        return "compiling numba kernels once (cached for later runs)"
    return f"compiling numba kernels once (cached in {where} for later runs)"


_listener: _CompileNotice | None = None


def _install_listener() -> None:
    global _listener
    with _lock:
        if _listener is None:
            _listener = _CompileNotice()
            event.register("numba:compile", _listener)  # type: ignore[no-untyped-call]
