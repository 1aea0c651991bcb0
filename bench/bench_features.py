"""Benchmark: features + B-P fit per component on the example catalogue; pyFFTW vs scipy FFT.

Prints a Markdown table (docs/benchmarks.md, "Features"). The default method is STFT (scipy FFT) +
zero crossings + least-squares fit, no bootstrap, t0 = record start. Timings are medians of
``--repeat`` runs; the machine has 2 cores shared with other jobs, so absolute numbers are noisy
and the ratios, measured in the same run, are what to compare.

    python bench/bench_features.py [--repeat 5]
    python bench/bench_features.py --estimators [--repeat 3]

``--before-after`` prints only the per-component table of issue 29 (docs/benchmarks.md,
"Per-component CPU of the selection workflow"): on the first ``2 × --records`` components of
the synthetic NGA catalogue (:mod:`nga_catalogue`, built if missing), CPU per component of
reading the AT2 file (the same code both times: a control of the noise), of ``record_features``
and of ``fit_model``, with the code as it is and as it was at :data:`FORMER` (their modules
read from git, not copied), interleaved in one process: the largest relative difference of the
features and of the fitted parameters printed (the spectral moments' product changes rounding).

``--estimators`` prints only the ω_g(t) estimator table (docs/benchmarks.md, issue 26): for every
registered estimator, features + fit per component over all 100 components (CPU, median of
``--repeat``), its ratio to zero crossings measured in the same run, the estimator's usable floor
on these records (median and range of ``RecordFeatures.usable_floor_rad_s``) and how many
components it left without a fit.
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import importlib.util
import math
import os
import subprocess
import sys
import time
import types
from pathlib import Path

import numpy as np

from stepframe.errors import InputError
from stepframe.records.examples import fema_p695
from stepframe.stochastic.catalog_features import catalog_features
from stepframe.stochastic.features import FREQUENCY_METHODS, record_features
from stepframe.stochastic.fit import fit_model
from stepframe.stochastic.transforms import stft_power
from timing import median_seconds

TARGET_COMPONENTS = 43_000
CORES = 2
#: The commit whose code ``--before-after`` compares with (before issue 29's per-component work).
FORMER = "6345b31"


def former_module(name: str, path: str) -> types.ModuleType:
    """The module at ``src/stepframe/<path>`` as it was at :data:`FORMER`, loaded as ``name``
    (its imports are of the current package)."""
    root = Path(__file__).resolve().parents[1]
    source = subprocess.run(
        ["git", "-C", str(root), "show", f"{FORMER}:src/stepframe/{path}"],
        capture_output=True, text=True, check=True,
    ).stdout  # fmt: skip
    spec = importlib.util.spec_from_loader(name, loader=None)
    assert spec is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module  # dataclasses look their module up
    exec(compile(source, f"{FORMER}:{path}", "exec"), module.__dict__)
    return module


def _largest_difference(a: object, b: object) -> float:
    """The largest relative difference between the floats of two feature sets or fit results
    (0: the same bits; inf: a different shape, NaN pattern or other value)."""
    if dataclasses.is_dataclass(a) and dataclasses.is_dataclass(b):
        pairs = [(getattr(a, f.name), getattr(b, f.name)) for f in dataclasses.fields(a)]
        return max((_largest_difference(x, y) for x, y in pairs), default=0.0)
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            return math.inf
        return max((_largest_difference(a[k], b[k]) for k in a), default=0.0)
    if isinstance(a, tuple | list) and isinstance(b, tuple | list):
        if len(a) != len(b) or any(isinstance(x, str) for x in a):
            return 0.0 if a == b else math.inf
        return max((_largest_difference(x, y) for x, y in zip(a, b, strict=True)), default=0.0)
    if isinstance(a, np.ndarray | float) or isinstance(b, np.ndarray | float):
        x, y = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
        if x.shape != y.shape or not np.array_equal(np.isnan(x), np.isnan(y)):
            return math.inf
        if x.tobytes() == y.tobytes():
            return 0.0
        both = np.isfinite(x) & np.isfinite(y)
        if not np.array_equal(x[~both], y[~both]):
            return math.inf
        scale = np.maximum(np.abs(x[both]), np.finfo(np.float64).tiny)
        return float(np.max(np.abs(x[both] - y[both]) / scale, initial=0.0))
    return 0.0 if a == b else math.inf


def before_after(records: int, repeat: int) -> None:
    """CPU per component of reading, features and fit, now and at :data:`FORMER`, and of the
    two steps of the features that changed (module docstring)."""
    import nga_catalogue
    from stepframe.records import read

    folder = nga_catalogue.build(nga_catalogue.OUT / f"records-{records}", range(records))
    files = sorted(folder.glob("*.AT2"))[: 2 * records]
    former_features = former_module("former_features", "stochastic/features.py")
    former_fit = former_module("former_fit", "stochastic/fit.py")

    def read_all() -> list[tuple[np.ndarray, float]]:
        return [(np.asarray(t.data, dtype=np.float64), float(t.stats.delta))
                for t in (read(f)[0] for f in files)]  # fmt: skip

    features = {"former": former_features.record_features, "current": record_features}
    fitting = {"former": former_fit.fit_model, "current": fit_model}
    out: dict[str, dict[str, object]] = {"former": {}, "current": {}}
    cpu: dict[str, dict[str, list[float]]] = {
        k: {"read": [], "features": [], "fit": []} for k in out
    }
    fit_model(record_features(*read_all()[0]))  # imports
    for _ in range(repeat):
        for version in ("former", "current"):  # interleaved: the same load on both
            start = time.process_time()
            out[version]["records"] = read_all()  # the reader is unchanged: a control
            middle = time.process_time()
            found = [features[version](x, dt) for x, dt in out[version]["records"]]  # type: ignore[attr-defined]
            end = time.process_time()
            fits = [fitting[version](f) for f in found]
            cpu[version]["read"].append(middle - start)
            cpu[version]["features"].append(end - middle)
            cpu[version]["fit"].append(time.process_time() - end)
            out[version]["features"], out[version]["fits"] = found, fits
    differences = {
        key: _largest_difference(out["former"][key], out["current"][key])
        for key in ("records", "features", "fits")
    }
    assert differences["records"] == 0.0, f"the records read differ from {FORMER}"
    n = len(files)
    samples = np.mean([x.size for x, _ in out["current"]["records"]])  # type: ignore[attr-defined]
    print(f"{n} components ({samples:.0f} samples on average), one core, CPU ms per component, "
          f"median of {repeat} interleaved; load {os.getloadavg()[0]:.1f}; largest relative "
          f"difference: records {differences['records']:.1e}, features "
          f"{differences['features']:.1e}, fit {differences['fits']:.1e}\n")  # fmt: skip
    print(f"| part | at {FORMER} | now | now / before |\n|---|---:|---:|---:|")
    total = dict.fromkeys(out, 0.0)
    for part in ("read", "features", "fit"):
        ms = {k: 1e3 * float(np.median(cpu[k][part])) / n for k in out}
        for k in out:
            total[k] += ms[k]
        print(f"| {part} | {ms['former']:.2f} | {ms['current']:.2f} | "
              f"{ms['current'] / ms['former']:.2f} |")  # fmt: skip
    print(f"| sum | {total['former']:.2f} | {total['current']:.2f} | "
          f"{total['current'] / total['former']:.2f} |")  # fmt: skip
    _changed_steps(out["current"]["records"], former_features, repeat)  # type: ignore[arg-type]


def _changed_steps(
    records: list[tuple[np.ndarray, float]], former: types.ModuleType, repeat: int
) -> None:
    """CPU per component of ``crossing_density`` and ``spectral_moments`` (all blocks of a
    record's STFT) at :data:`FORMER` and now, interleaved, and the largest relative difference."""
    from stepframe.stochastic import features as current
    from stepframe.stochastic.transforms import DEFAULT_WINDOW_S, stft_grid, stft_power_blocks

    grids = [stft_grid(x.size, dt, window_s=DEFAULT_WINDOW_S, hop_s=current.DEFAULT_HOP_S)
             for x, dt in records]  # fmt: skip
    blocks = [[b for _, b in stft_power_blocks(x, dt, g)] for (x, dt), g in zip(records, grids,
              strict=True)]  # fmt: skip

    def crossings(module: types.ModuleType) -> list[np.ndarray]:
        return [module.crossing_density(x, dt, g.time_s, DEFAULT_WINDOW_S)
                for (x, dt), g in zip(records, grids, strict=True)]  # fmt: skip

    def moments(module: types.ModuleType) -> list[tuple[np.ndarray, ...]]:
        return [module.spectral_moments(g.omega_rad_s, b) for g, bs in zip(grids, blocks,
                strict=True) for b in bs]  # fmt: skip

    print("\n| step | at {FORMER} | now | now / before | largest relative difference |\n"
          "|---|---:|---:|---:|---:|".replace("{FORMER}", FORMER))  # fmt: skip
    for name, step in (("crossing_density", crossings), ("spectral_moments", moments)):
        seconds: dict[str, list[float]] = {"former": [], "now": []}
        values: dict[str, object] = {}
        for _ in range(repeat):
            for version, module in (("former", former), ("now", current)):
                start = time.process_time()
                values[version] = step(module)
                seconds[version].append(time.process_time() - start)
        ms = {k: 1e3 * float(np.median(v)) / len(records) for k, v in seconds.items()}
        difference = _largest_difference(values["former"], values["now"])
        print(f"| `{name}` | {ms['former']:.2f} | {ms['now']:.2f} | "
              f"{ms['now'] / ms['former']:.2f} | {difference:.1e} |")  # fmt: skip


def estimator_table(records: list[tuple[np.ndarray, float]], repeat: int) -> None:
    """Cost per component and usable floor of every ω_g(t) estimator (module docstring)."""
    floors: dict[str, list[float]] = {}
    failed: dict[str, int] = {}
    seconds: dict[str, float] = {}
    for method in FREQUENCY_METHODS:
        floors[method], failed[method] = [], 0
        for x, dt in records:  # also the warm-up of the timed runs below
            features = record_features(x, dt, frequency=method)  # type: ignore[arg-type]
            floors[method].append(features.usable_floor_rad_s)
            try:
                fit_model(features)
            except InputError:
                failed[method] += 1

        def run(method: str = method) -> None:
            for x, dt in records:
                with contextlib.suppress(InputError):  # counted above
                    fit_model(record_features(x, dt, frequency=method))  # type: ignore[arg-type]

        seconds[method] = median_seconds(run, repeat, time.process_time) / len(records)
    base = seconds["zero-crossing"]
    print(f"{len(records)} components; CPU time, median of {repeat}\n")
    print("| estimator | features + fit per component | × zero-crossing | usable floor, median "
          "(range) [rad/s] | no fit |")  # fmt: skip
    print("|---|---|---|---|---|")
    for method in FREQUENCY_METHODS:
        low = np.asarray(floors[method])
        floor = f"{np.median(low):.2f} ({low.min():.2f}-{low.max():.2f})"
        cost = f"{1e3 * seconds[method]:.1f} ms | {seconds[method] / base:.2f}"
        print(f"| {method} | {cost} | {floor} | {failed[method]} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--estimators", action="store_true")
    parser.add_argument("--before-after", action="store_true")
    parser.add_argument("--records", type=int, default=200, help="with --before-after")
    args = parser.parse_args()
    if args.before_after:
        before_after(args.records, args.repeat)
        return
    stream, meta = fema_p695()
    records = [(np.asarray(tr.data, dtype=np.float64), float(tr.stats.delta)) for tr in stream]
    if args.estimators:
        estimator_table(records, args.repeat)
        return
    n = len(records)
    samples = sum(x.size for x, _ in records)

    def stft_all(fft: str, engine: str = "batched") -> None:
        for x, dt in records:
            stft_power(x, dt, fft=fft, engine=engine)  # type: ignore[arg-type]

    def features_all(fft: str) -> None:
        for x, dt in records:
            fit_model(record_features(x, dt, fft=fft))  # type: ignore[arg-type]

    # Warm-up: imports, FFTW plans (cached by pyfftw.interfaces.cache), scipy's own caches.
    stft_all("pyfftw")
    stft_all("scipy")
    features_all("scipy")
    # CPU time of this process: what one core spends, whatever else shares the machine.
    cpu = time.process_time
    t_stft_fftw = median_seconds(lambda: stft_all("pyfftw"), args.repeat, cpu)
    t_stft_scipy = median_seconds(lambda: stft_all("scipy"), args.repeat, cpu)
    t_stft_slices = median_seconds(lambda: stft_all("scipy", "shorttimefft"), 1, cpu)
    t_feat_fftw = median_seconds(lambda: features_all("pyfftw"), args.repeat, cpu)
    t_feat_scipy = median_seconds(lambda: features_all("scipy"), args.repeat, cpu)
    t_feat_wall = median_seconds(lambda: features_all("scipy"), 1)
    lows = list(meta["lowest_usable_frequency_hz"])
    t_parallel = median_seconds(
        lambda: catalog_features(stream, n_jobs=CORES, lowest_usable_hz=lows),
        max(1, args.repeat // 2),
    )
    per_component = t_feat_scipy / n  # the default FFT
    # Scaling: 4 copies of the catalogue (400 components), so start-up is a smaller share.
    big = stream.copy() + stream.copy() + stream.copy() + stream.copy()
    t_big = median_seconds(
        lambda: catalog_features(big, n_jobs=CORES, lowest_usable_hz=lows * 4, chunk_size=8), 1
    )
    ladder = {}
    subset = records[:20]
    for method in FREQUENCY_METHODS:

        def run(method: str = method) -> None:
            for x, dt in subset:
                fit_model(record_features(x, dt, frequency=method))  # type: ignore[arg-type]

        ladder[method] = median_seconds(run, max(1, args.repeat // 2), cpu) / len(subset)
    extrapolated = TARGET_COMPONENTS * per_component / CORES
    print(f"machine: {os.cpu_count()} CPUs (shared); {n} components, {samples:,} samples\n")
    print("| quantity | value |")
    print("|---|---|")
    print(f"| STFT only, batched, pyFFTW, per component (CPU, median of {args.repeat}) | "
          f"{1e3 * t_stft_fftw / n:.2f} ms |")  # fmt: skip
    print(f"| STFT only, batched, scipy FFT, per component | {1e3 * t_stft_scipy / n:.2f} ms |")
    print(f"| STFT speed-up pyFFTW / scipy FFT | {t_stft_scipy / t_stft_fftw:.2f} x |")
    slices_ms, slices_ratio = 1e3 * t_stft_slices / n, t_stft_slices / t_stft_scipy
    print(f"| STFT only, ShortTimeFFT.stft (one FFT call per slice), scipy FFT | "
          f"{slices_ms:.2f} ms ({slices_ratio:.1f} x batched) |")  # fmt: skip
    print(f"| features + fit, scipy FFT (default), per component, 1 core (CPU) | "
          f"{1e3 * per_component:.1f} ms |")  # fmt: skip
    print(f"| features + fit, pyFFTW, per component, 1 core (CPU) | "
          f"{1e3 * t_feat_fftw / n:.1f} ms |")  # fmt: skip
    print(
        f"| features + fit, default, per component, wall clock | {1e3 * t_feat_wall / n:.1f} ms |"
    )
    print(
        f"| catalogue of {n} with {CORES} processes, wall (incl. start-up) | {t_parallel:.2f} s |"
    )
    print(f"| parallel speed-up vs 1 core (CPU time) | {t_feat_scipy / t_parallel:.2f} x |")
    print(f"| 4 × catalogue (400 components) with {CORES} processes, wall | {t_big:.2f} s "
          f"({4 * n * per_component / t_big:.2f} x one core's CPU time) |")  # fmt: skip
    for method, seconds in ladder.items():
        print(f"| features + fit with ω_g by {method}, per component (first 20, CPU) | "
              f"{1e3 * seconds:.1f} ms |")  # fmt: skip
    print(f"| extrapolated: {TARGET_COMPONENTS:,} components on {CORES} cores | "
          f"{extrapolated / 60:.1f} min (target < 20 min, ~50 ms/component/core) |")  # fmt: skip


if __name__ == "__main__":
    main()
