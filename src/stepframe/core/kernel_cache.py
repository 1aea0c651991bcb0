"""The compiled kernels built when the package is built, so that no command compiles on a first run.

Numba compiles a kernel on its first call with a given signature and caches the machine code
beside the source (``__pycache__``, :mod:`stepframe.core.jit`). Compiling all of stepframe's
kernels takes 30-50 s of CPU (the exact simulator's event loop alone 9-13 s); left to the first
call, every command paid its share on its first run. Instead the package's build
(``setup.py``'s ``build_py``) runs ``python -m stepframe.core.kernel_cache`` on the built tree,
which compiles each entry point below for the signature the package calls it with, and the
cache files go into the wheel with the sources.

Why the shipped cache is valid where it is installed: numba (0.68 and later) stamps a cache
index with the sha256 of the source file, not its time, and keys each entry by the signature,
the CPU name and its features and numba's version. ``pip install .`` builds on the machine it
installs on, with the numba it resolves for both the build and the install, so the entries
match. A read-only install copies them into the user's cache folder (:mod:`stepframe.core.jit`).
Anywhere they do not apply (a wheel built on another CPU, another numba, ``NUMBA_CACHE_DIR`` set,
no writable folder at all), numba compiles on first use as before and says so; nothing is
wrong, only slower once.

The list below is checked against the commands, not trusted: ``tests/core/test_kernel_cache.py``
compiles it into an empty cache, runs a command of each kernel family on it, and fails if any
of them compiled anything (a new kernel, or a changed signature, that the list misses).
Helpers called only from kernels need no entry: compiling their caller compiles and caches them
with the signatures it calls them with.
"""

from __future__ import annotations

import argparse
import importlib
import os
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from typing import Any

__all__ = ["ENTRY_POINTS", "EntryPoint", "compile_entry_points", "main"]


@dataclass(frozen=True)
class EntryPoint:
    """One kernel called from Python, and the argument types it is called with.

    ``signatures`` holds, per signature, a tuple of numba type names (``"f8"``, ``"i8"``,
    ``"b1"``) or arrays (``"f8[:]"``, ``"f8[:, :]"``, C-contiguous, writable; ``"ro f8[:]"``
    read-only): spelled as text so this module imports numba only when it compiles.
    """

    module: str
    function: str
    signatures: tuple[tuple[str, ...], ...]


_F12 = ("f8",) * 12
#: h, nodes, weights of the mean-square quadrature
_QUADRATURE = ("f8", "f8[:]", "f8[:]")
#: psd, frame times, band centres, reach, band (low, high), NEAR_LN of the resonance index
_SPECTRUM = ("f8[:, :]", "i8", "f8[:]", "i8", "f8", "f8", "f8")
_HIST = ("f8[:]", "f8[:]", "i1[:]", "f8[:]", "i1[:]", "f8[:]", "f8[:]", "f8[:]")

#: The kernels the package calls from Python, grouped by source file: a group compiles in one
#: process (its kernels share helpers), the groups in parallel.
ENTRY_POINTS: tuple[EntryPoint, ...] = (
    EntryPoint(
        "stepframe.structure._exact",
        "integrate",
        (("f8[:]", "f8", "i8", *_F12, *_HIST),),
    ),
    EntryPoint(
        "stepframe.structure._exact",
        "integrate_batch",
        (("f8[:]", "i8[:]", "i8[:]", "f8[:]", "f8[:]", "i8[:]", "f8[:]", "f8[:, :]"),),
    ),
    EntryPoint(
        "stepframe.structure.aframe_hysteretic",
        "integrate_aframe",
        (("f8[:]", "f8", "i8", "f8[:]", "i8", "f8", "f8", "f8[:]"),),
    ),
    EntryPoint(
        "stepframe.structure.rocking_block",
        "advance_block",
        (("f8[:]", "i8", *("f8",) * 11, "i8", "f8", "f8", "f8[:]"),),
    ),
    EntryPoint(
        "stepframe.structure.rocking_block",
        "_free_verdict",
        (("f8", "f8", "f8[:]"),),
    ),
    EntryPoint(
        "stepframe.structure._harmonic_kernel",
        "start_phase",
        (("f8", "f8", "f8", "f8[:]"),),
    ),
    EntryPoint(
        "stepframe.structure._harmonic_kernel",
        "advance",
        (("f8[:]", *("f8",) * 7, "i8", "f8[:, :]", "b1", "i8", "f8"),),
    ),
    EntryPoint(
        "stepframe.structure._harmonic_kernel",
        "strobe_grid",
        (("f8[:]", "f8[:]", "f8", "f8", "f8[:]", "f8[:]", "i8", "i8", "i8"),),
    ),
    EntryPoint(
        "stepframe.records._spectra_kernels",
        "peak_displacements",
        (("f8[:]", "f8[:, :]"),),
    ),
    EntryPoint(
        "stepframe.records._spectra_kernels",
        "displacement_histories",
        (("f8[:]", "f8[:, :]"),),
    ),
    EntryPoint(
        "stepframe.stochastic._wavelet_kernel",
        "folded_bands",
        (("c16[:]", "f8[:]", "f8[:]", "f8", "i8", "f8"),),
    ),
    EntryPoint(
        "stepframe.stochastic._wavelet_kernel",
        "band_powers",
        (("c16[:, :]", "i8", "i8", "f8[:]"),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "zero_crossings",
        (("f8[:]", "f8[:]", "f8"),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "turning_points",
        (("f8[:]", "f8[:]", "f8"),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "interval_work",
        (("f8[:]", "f8[:]", "i1[:]", "f8[:]", "f8", "f8", "f8"),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "swing_law",
        (("f8[:]", "f8[:]", "f8", "i8[:]", "b1", *("f8",) * 4),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "quarter_periods",
        (("f8[:]", *("f8",) * 4),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "law_frequencies",
        (("f8[:]", *("f8",) * 4),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "potentials",
        (("f8[:]", *("f8",) * 4),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "energy_amplitudes",
        (("f8[:]", "f8[:]", *("f8",) * 4),),
    ),
    EntryPoint(
        "stepframe.pipeline.dynamics._resonance_kernel",
        "closeness_many",
        (("f8[:, :]", "f8[:]", "f8[:]", "i8", "f8[:]", "f8[:]"),),
    ),
    EntryPoint(
        "stepframe.pipeline.dynamics._resonance_kernel",
        "resonance_sums",
        (("f8[:]", "f8[:]", "i1[:]", "f8[:]", *("f8",) * 3, "b1", "f8[:]", *_SPECTRUM),),
    ),
    EntryPoint(
        "stepframe.structure._frequency_kernel",
        "swing_frequencies",
        (("f8[:]", "f8[:]", "i1[:]", "f8", "i8[:]", "f8[:]", "b1", "b1", *("f8",) * 4, "b1"),),
    ),
    EntryPoint(
        "stepframe.pipeline.dynamics._resonance_kernel",
        "bank_energies",
        (
            ("f4[:]", "f4[:, :]", "f4[:, :]", "f4[:]", "i8"),
            ("f8[:]", "f8[:, :]", "f8[:, :]", "f8[:]", "i8"),
        ),
    ),
    EntryPoint(
        "stepframe.pipeline.dynamics._resonance_kernel",
        "triangle_decimated",
        (("f8[:]", "i8", "i8"),),
    ),
    EntryPoint(
        "stepframe.pipeline.selection._bootstrap_kernel",
        "resampled_rhos",
        (("i8[:, :]", "i8[:, :]", "i8[:, :]", "i8[:]", "i8[:, :]"),),
    ),
    EntryPoint(
        "stepframe.stochastic.mean_square",
        "_filter_kernel",
        (("f8[:]", "f8[:]", "f8", "f8[:]", "f8"),),
    ),
    EntryPoint(
        "stepframe.stochastic.mean_square",
        "_covariance_run",
        tuple(
            (
                "f8[:, :]",
                "f8[:]",
                "f8[:]",
                "f8[:]",
                ig,
                "f8[:, :]",
                "f8[:, :]",
                "f8[:, :, :]",
                *_QUADRATURE,
            )
            for ig in ("f8[:]", "ro f8[:]")
        ),
    ),
    EntryPoint(
        "stepframe.stochastic.mean_square",
        "_covariance_step",
        (("f8[:]", *("f8",) * 5, "f8[:]", "f8[:]", "f8[:, :]", "f8", "f8[:]", "f8[:]"),),
    ),
    EntryPoint(
        "stepframe.stochastic.mean_square",
        "_forced_step",
        (("f8[:]", "f8[:]", "f8"),),
    ),
    EntryPoint(
        "stepframe.stochastic.mean_square",
        "_white_noise_run",
        (("f8[:]", "f8", "f8[:]", "f8"),),
    ),
)


def numba_type(spelling: str) -> Any:
    """The numba type of one spelling of :class:`EntryPoint` (``"f8"``, ``"ro i8[:, :]"``)."""
    from numba.core import types

    scalars = {
        "f8": types.float64,
        "f4": types.float32,
        "i8": types.int64,
        "i1": types.int8,
        "b1": types.boolean,
        "c16": types.complex128,
    }
    readonly = spelling.startswith("ro ")
    name, _, dims = spelling.removeprefix("ro ").partition("[")
    if name not in scalars:
        raise ValueError(f"unknown kernel argument type {spelling!r}: expected one of {scalars}")
    if not dims:
        if readonly:
            raise ValueError(f"{spelling!r}: only an array can be read-only")
        return scalars[name]
    return types.Array(scalars[name], dims.count(":"), "C", readonly=readonly)


def _compile_group(entries: Sequence[EntryPoint]) -> list[tuple[str, float]]:
    """Compile (or load from the cache) each signature of ``entries``; returns (name, seconds)."""
    timings = []
    for entry in entries:
        kernel = getattr(importlib.import_module(entry.module), entry.function)
        started = time.perf_counter()
        for signature in entry.signatures:
            kernel.compile(tuple(numba_type(t) for t in signature))
        timings.append((f"{entry.module}.{entry.function}", time.perf_counter() - started))
    return timings


def compile_entry_points(jobs: int = 1) -> list[tuple[str, float]]:
    """Compile every kernel of :data:`ENTRY_POINTS` into numba's cache, ``jobs`` source files
    at a time; returns (kernel, seconds) in the order of the list.

    The cache is wherever :mod:`stepframe.core.jit` puts it (``NUMBA_CACHE_DIR`` when set, else
    beside the sources when their folder is writable, else the user's cache).
    """
    groups: dict[str, list[EntryPoint]] = {}
    for entry in ENTRY_POINTS:
        groups.setdefault(entry.module, []).append(entry)
    # The longest first (the simulator's file), so that two workers finish together.
    ordered = sorted(groups.values(), key=lambda g: g[0].module != "stepframe.structure._exact")
    if jobs <= 1:
        results = [_compile_group(group) for group in ordered]
    else:
        with ProcessPoolExecutor(max_workers=jobs) as pool:
            results = list(pool.map(_compile_group, ordered))
    timed = dict(t for group in results for t in group)
    return [(name, timed[name]) for name in (f"{e.module}.{e.function}" for e in ENTRY_POINTS)]


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m stepframe.core.kernel_cache [--jobs N]``: compile the kernels now."""
    parser = argparse.ArgumentParser(
        prog="python -m stepframe.core.kernel_cache",
        description="Compile stepframe's numba kernels into the cache (the package's build "
        "runs this; run it by hand after an editable install, or after upgrading numba).",
    )
    parser.add_argument(
        "--jobs",
        type=int,
        default=min(2, os.cpu_count() or 1),
        help="processes compiling at once (default: 2, or 1 on one CPU)",
    )
    args = parser.parse_args(argv)
    if args.jobs < 1:
        parser.error(f"--jobs {args.jobs}: expected a positive number of processes")
    os.environ["STEPFRAME_COMPILE_NOTICE"] = "0"
    started = time.perf_counter()
    timings = compile_entry_points(args.jobs)
    for name, seconds in timings:
        print(f"  {name}: {seconds:.1f} s")
    print(
        f"stepframe: {len(timings)} numba kernels compiled in "
        f"{time.perf_counter() - started:.1f} s ({args.jobs} processes)",
        file=sys.stderr,
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
