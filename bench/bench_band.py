"""Cost and stability of the response amplification's band from the site parameters' errors.

Run: ``python bench/bench_band.py [--seeds 4] [--sizes 64,128,256,512,1024] [--n-steps 1000]``.

Two sites from records, combined as the report combines them (the median of the plausible fits,
its standard error 1.2533·s/√n): RSN 8883's two horizontal components (tests/data, large
standard errors from two records) and the plausible components of the embedded example
catalogue (100 FEMA P695 components, small standard errors), each over the report's default f0
grid (0.1-10 Hz, 60 points, ξ_0 = 0.05).

Measured, in one process (CPU time of this thread, medians of 3):

- the cost of one curve, of the delta band (1 + 2k curves, k = 5 parameters) and of a Monte
  Carlo band per parameter set, at ``--n-steps`` and at the report's 4,000 steps;
- the Monte Carlo band's stability in N, for scrambled Sobol points (the default sampler) and
  independent draws: over ``--seeds`` seeds at each N, the seed-to-seed standard deviation of
  each edge (2.5 % and 97.5 %) as a fraction of the band's half-width, median and largest over
  f0;
- the delta band against the Sobol band of all seeds' sets pooled at the largest N: the
  median and largest relative difference of each edge over f0;
- how far the curve at ``--n-steps`` is from the curve at 4,000 steps (the stability study runs
  at ``--n-steps`` to keep its 20,000 curves affordable).

Prints Markdown tables for docs/benchmarks.md ("Issue 30").

``--jobs 1,2`` measures instead the report's default band (512 Sobol sets, 4,000 steps, RSN
8883's two components) on each number of worker processes, in turn and alternated
``--rounds`` times in the same run: wall time and the CPU time of this process and its workers,
and whether the curves are the same bit for bit.

``--grids`` measures the band's time grids (``band_grids``: each f0 on the coarsest of 4,000,
2,000, 1,000 and 500 steps with four steps a period of it) against 4,000 steps for every f0,
the report's 512 Sobol sets over each site's report f0 (the 0.1-10 Hz grid and its extension
past an edge), alternated ``--rounds`` times in one process: CPU time of each, and how far the
curves and the band's edges move (relative, and as a fraction of the band's half-width).
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path

import numpy as np

from stepframe.pipeline.amplification.band import (
    VARIED,
    monte_carlo_curves,
    parameter_band,
    vs_fixed_curve,
)
from stepframe.pipeline.amplification.site import (
    site_from_features,
    site_from_records,
)
from timing import median_cpu_seconds

ROOT = Path(__file__).resolve().parents[1]
XI0 = 0.05


def _sites() -> list[tuple[str, object, dict[str, float]]]:
    rsn = site_from_records(ROOT / "tests" / "data" / "peer_nga_west2")
    from stepframe.pipeline.catalogue.example_files import write_example_files
    from stepframe.stochastic.catalog_features import catalog_features

    with tempfile.TemporaryDirectory() as tmp:
        write_example_files(Path(tmp))
        table, _ = catalog_features(Path(tmp), n_jobs=1)
    catalogue = site_from_features(table)
    n = catalogue.site.source["n_components"]
    return [
        ("RSN 8883 (2 components)", rsn.model, rsn.stderr),
        (f"example catalogue ({n} plausible components)", catalogue.model, catalogue.stderr),
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=4)
    parser.add_argument("--sizes", default="64,128,256,512,1024")
    parser.add_argument("--n-steps", type=int, default=1000)
    parser.add_argument("--jobs", help="comma-separated worker counts: the band on each")
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--grids", action="store_true", help="the band's grids against 4,000")
    parser.add_argument(
        "--grid-errors", action="store_true", help="only the central curve's error by f0, steps"
    )
    args = parser.parse_args()
    if args.grids or args.grid_errors:
        grid_errors()
        if args.grids:
            compare_grids(args.rounds)
        return
    if args.jobs:
        compare_jobs([int(n) for n in args.jobs.split(",")], args.rounds)
        return
    sizes = [int(n) for n in args.sizes.split(",")]
    f0 = np.geomspace(0.1, 10.0, 60)
    vs_fixed_curve(*_sites()[0][1:2], f0, XI0, 200)  # type: ignore[arg-type]  # compile first
    cost_rows, stability_rows, agreement_rows = [], [], []
    for name, model, stderr in _sites():
        relative = {k: v / float(getattr(model, k)) for k, v in stderr.items()}
        for steps in (args.n_steps, 4000):
            curve = median_cpu_seconds(lambda: vs_fixed_curve(model, f0, XI0, steps), 3)  # noqa: B023
            delta = median_cpu_seconds(
                lambda: parameter_band(model, stderr, f0, XI0, n_steps=steps),  # noqa: B023
                3,
            )
            cost_rows.append((name, steps, curve, delta))
        centre = vs_fixed_curve(model, f0, XI0, args.n_steps)
        varied = tuple(k for k in VARIED if stderr.get(k, 0) > 0)
        fine = vs_fixed_curve(model, f0, XI0, 4000)
        steps_error = float(np.max(np.abs(centre / fine - 1)))
        pooled: list[np.ndarray] = []
        for sampler in ("sobol", "random"):
            for n in sizes:
                edges = []
                seconds = []
                for seed in range(1, args.seeds + 1):
                    start = time.thread_time()
                    # the draws and percentiles of parameter_band(method="monte-carlo")
                    curves, _ = monte_carlo_curves(
                        model, stderr, varied, f0, XI0, args.n_steps, n, seed, sampler=sampler
                    )
                    edges.append(np.percentile(curves, [2.5, 97.5], axis=0))
                    seconds.append(time.thread_time() - start)
                    if n == sizes[-1] and sampler == "sobol":
                        pooled.append(curves)
                lows = np.vstack([e[0] for e in edges])
                highs = np.vstack([e[1] for e in edges])
                half = (highs.mean(axis=0) - lows.mean(axis=0)) / 2
                scatter_low = lows.std(axis=0, ddof=1) / half
                scatter_high = highs.std(axis=0, ddof=1) / half
                stability_rows.append(
                    (name, sampler, n, statistics.median(seconds),
                     float(np.median(scatter_low)), float(scatter_low.max()),
                     float(np.median(scatter_high)), float(scatter_high.max()))
                )  # fmt: skip
        # the largest N's sets of every seed, pooled: the reference band
        stack = np.vstack(pooled)
        ref_low, ref_high = np.percentile(stack, [2.5, 97.5], axis=0)
        delta = parameter_band(model, stderr, f0, XI0, n_steps=args.n_steps, central=centre)
        assert delta is not None
        agreement_rows.append(
            (name, relative, len(stack), steps_error,
             float(np.max(np.abs(delta.low / ref_low - 1))),
             float(np.max(np.abs(delta.high / ref_high - 1))),
             float(np.median(np.abs(delta.low / ref_low - 1))),
             float(np.median(np.abs(delta.high / ref_high - 1))))
        )  # fmt: skip
    print("| site | n_steps | one curve (60 f0) [s] | delta band, 11 curves [s] |")
    print("|---|---|---|---|")
    for name, steps, curve, delta_s in cost_rows:
        print(f"| {name} | {steps} | {curve:.3f} | {delta_s:.2f} |")
    print()
    print(
        f"| site | sampler | N | Monte Carlo band at {args.n_steps} steps [s] | low edge scatter "
        "/ half-width, median (max) | high edge scatter / half-width, median (max) |"
    )
    print("|---|---|---|---|---|---|")
    for name, sampler, n, seconds, lm, lx, hm, hx in stability_rows:
        print(
            f"| {name} | {sampler} | {n} | {seconds:.1f} | {lm:.3f} ({lx:.3f}) "
            f"| {hm:.3f} ({hx:.3f}) |"
        )
    print()
    print(
        "| site | relative standard errors | pooled Sobol sets | curve at n_steps vs 4,000 "
        "steps, largest relative difference | delta vs pooled Monte Carlo, low edge: median "
        "(max) | high edge: median (max) |"
    )
    print("|---|---|---|---|---|---|")
    for name, relative, count, steps_error, low_max, high_max, low_med, high_med in agreement_rows:
        rel = ", ".join(f"{k.removesuffix('_rad_s')} {v:.2f}" for k, v in relative.items())
        print(
            f"| {name} | {rel} | {count} | {steps_error:.1e} | {low_med:.3f} ({low_max:.3f}) "
            f"| {high_med:.3f} ({high_max:.3f}) |"
        )
    print(f"\nmachine: {_machine()}")


def compare_jobs(jobs: list[int], rounds: int) -> None:
    """The report's default Monte Carlo band of RSN 8883 on each worker count, alternated."""
    import os

    _, model, stderr = _sites()[0]
    varied = tuple(k for k in VARIED if stderr.get(k, 0) > 0)
    f0 = np.geomspace(0.1, 10.0, 60)
    vs_fixed_curve(model, f0, XI0, 200)  # type: ignore[arg-type]  # kernels loaded first
    times: dict[int, list[tuple[float, float]]] = {n: [] for n in jobs}
    reference = None
    for _ in range(rounds):
        for n in jobs:
            before, start = os.times(), time.perf_counter()
            args = (model, stderr, varied, f0, XI0, 4000, 512, 1)
            curves, _ = monte_carlo_curves(*args, jobs=n)  # type: ignore[arg-type]
            wall, after = time.perf_counter() - start, os.times()
            cpu = sum(after[:4]) - sum(before[:4])  # user + system, this process and children
            times[n].append((wall, cpu))
            if reference is None:
                reference = curves
            assert np.array_equal(curves, reference), f"jobs {n}: different curves"
    print("| workers | wall [s], each round | CPU [s], each round | wall / 1 worker's |")
    print("|---|---|---|---|")
    base = statistics.median(w for w, _ in times[jobs[0]])
    for n in jobs:
        walls = ", ".join(f"{w:.1f}" for w, _ in times[n])
        cpus = ", ".join(f"{c:.1f}" for _, c in times[n])
        ratio = statistics.median(w for w, _ in times[n]) / base
        print(f"| {n} | {walls} | {cpus} | {ratio:.2f} |")
    print(f"\nthe curves of every run the same bit for bit; machine: {_machine()}")


def grid_errors() -> None:
    """RSN 8883's central curve on 500-4,000 steps against 8,000, relative error by f0."""
    from stepframe.stochastic.mean_square import analysis_grid

    _, model, _ = _sites()[0]
    f0 = np.array([0.1, 1.0, 4.0, 10.0, 16.0, 26.0])
    reference = vs_fixed_curve(model, f0, XI0, 8000)  # type: ignore[arg-type]
    duration_s = float(analysis_grid(model, n_steps=8000)[-1])  # type: ignore[arg-type]
    print("| steps (h) | " + " | ".join(f"{f:g} Hz" for f in f0) + " |")
    print("|---" * (f0.size + 1) + "|")
    for steps in (500, 700, 1000, 2000, 4000):
        curve = vs_fixed_curve(model, f0, XI0, steps)  # type: ignore[arg-type]
        errors = " | ".join(f"{e:.0e}" for e in np.abs(curve / reference - 1))
        print(f"| {steps:,} ({duration_s / steps:.3f} s) | {errors} |")
    print()


def compare_grids(rounds: int) -> None:
    """The report's Monte Carlo band on the band's grids and on 4,000 steps, alternated."""
    from stepframe.pipeline.amplification.analysis import AmplificationOptions
    from stepframe.pipeline.amplification.band import band_grids
    from stepframe.pipeline.amplification.report import response_curve

    print(
        "| site | report f0 | grids: f0 on each of 500 / 1,000 / 2,000 / 4,000 steps "
        "| CPU [s] each round: 4,000 steps | band's grids | ratio "
        "| curves: max rel. difference | edges: max rel. difference | edges / half-width |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for name, model, stderr in _sites():
        varied = tuple(k for k in VARIED if stderr.get(k, 0) > 0)
        options = AmplificationOptions(band="none", monte_carlo=0)
        f0 = response_curve(model, options).f0_hz  # type: ignore[arg-type]
        grids = band_grids(model, f0, XI0, 4000)  # type: ignore[arg-type]
        counts = " / ".join(str(int(np.sum(grids == n))) for n in (500, 1000, 2000, 4000))
        seconds: dict[str, list[float]] = {"fine": [], "grids": []}
        curves: dict[str, np.ndarray] = {}
        for _ in range(rounds):
            for key, steps in (("fine", 4000), ("grids", grids)):
                start = time.process_time()
                curves[key], _ = monte_carlo_curves(model, stderr, varied, f0, XI0, steps, 512, 1)  # type: ignore[arg-type]
                seconds[key].append(time.process_time() - start)
        fine, coarse = curves["fine"], curves["grids"]
        edges = [np.percentile(c, [2.5, 97.5], axis=0) for c in (fine, coarse)]
        half = (edges[0][1] - edges[0][0]) / 2
        moved = np.abs(edges[1] - edges[0])
        ratio = statistics.median(seconds["grids"]) / statistics.median(seconds["fine"])
        print(
            f"| {name} | {f0.size}: {f0.min():.3g}-{f0.max():.3g} Hz | {counts} "
            f"| {', '.join(f'{t:.1f}' for t in seconds['fine'])} "
            f"| {', '.join(f'{t:.1f}' for t in seconds['grids'])} | {ratio:.2f} "
            f"| {np.max(np.abs(coarse / fine - 1)):.1e} | {np.max(moved / edges[0]):.1e} "
            f"| {np.max(moved / half):.1e} |"
        )
    print(f"\nmachine: {_machine()}")


def _machine() -> str:
    import os
    import platform

    return f"{platform.processor() or platform.machine()}, {os.cpu_count()} cores (shared)"


if __name__ == "__main__":
    main()
