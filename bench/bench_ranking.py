"""The exact ranking's cost: per candidate on one core, and 43,000 candidates on all cores.

Run: ``python bench/bench_ranking.py [--n 43000]``. Prints Markdown tables for
docs/benchmarks.md. Records: synthetic Beck-Papadimitriou motions of 6,000 samples (60 s at
0.01 s), ω_p drawn log-uniformly in [15, 60] rad/s, made in chunks of 2,000 (the making is not
timed: "reading the files aside"). Frame: Example 4's, ranked (the library's
:func:`~stepframe.pipeline.selection.exact.simulated_response`, the default 5-level ladder and
its overturning bisection) as recorded at unit peak intensity (the default intensity, "as
used"), and at equal PSA(T_1) at the onset ratio 1 (the demo's), where SD(T_1, ξ_1) of each
record (one spectrum call) is part of the work timed.

- One core: CPU time of this process with numba on one thread, per candidate, over 200 records;
  peer: the same simulations one by one through :func:`stepframe.structure.simulator.simulate`
  (the per-record entry point), and a single run at the stated intensity.
- All cores: wall and CPU time of ranking ``--n`` candidates with numba on every core (the
  batch's parallel loop), chunk by chunk; the machine's load average is printed beside.
"""

from __future__ import annotations

import argparse
import math
import os
import time
import tomllib
from typing import Any

import numpy as np

CHUNK = 2000


def motions(n: int, seed: int) -> list[tuple[np.ndarray, float]]:
    """``n`` synthetic 6,000-sample records, in one model per 500."""
    from stepframe.stochastic.model import GroundMotionModel
    from stepframe.stochastic.synthetic import synthetic_motions

    rng = np.random.default_rng(seed)
    out: list[tuple[np.ndarray, float]] = []
    while len(out) < n:
        wp = float(np.exp(rng.uniform(np.log(15.0), np.log(60.0))))
        model = GroundMotionModel(wp, 0.5 * wp, 0.2 * wp, 0.3, 0.3, 8.0, 25.0)
        count = min(500, n - len(out))
        _, acc = synthetic_motions(
            model, duration_s=59.99, dt_s=0.01, n_realisations=count,
            seed=int(rng.integers(2**31)),
        )  # fmt: skip
        out += [(row, 0.01) for row in acc]
    return out


def rank(frame: Any, records: list[tuple[np.ndarray, float]], onset: bool) -> Any:
    """The default exact ranking of ``records`` (the spectrum at T_1 first when at the onset)."""
    from stepframe.pipeline.selection.exact import simulated_response
    from stepframe.pipeline.selection.intensity import equal_intensity_scales
    from stepframe.records.spectra import peak_displacements_m

    if onset:
        t1 = 2 * math.pi / frame.omega_1_rad_s
        sd = np.array([peak_displacements_m(a, dt, [t1], frame.xi_1)[0] for a, dt in records])
        base = equal_intensity_scales(sd, frame, 1.0)
    else:
        base = np.ones(len(records))
    return simulated_response(frame, records, base)


def main() -> None:
    import numba

    from stepframe.pipeline.selection.exact import LADDER
    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping
    from stepframe.structure.simulator import simulate

    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--n", type=int, default=43_000)
    args = parser.parse_args()
    frame = frame_from_mapping(tomllib.loads(FRAME_TEMPLATE))
    sample = motions(200, seed=1)
    assert all(a.size == 6000 for a, _ in sample)
    rank(frame, sample[:4], True)  # compile
    numba.set_num_threads(1)
    print(f"load average before: {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs\n")
    print("| one core, 6,000-sample records (CPU ms per candidate) | as recorded | onset ratio 1 |")
    print("|---|---|---|")
    rows: dict[str, list[str]] = {}
    for onset in (False, True):
        start = time.process_time()
        result = rank(frame, sample, onset)
        per = (time.process_time() - start) / len(sample) * 1e3
        over = int(np.isfinite(result.overturn_factor).sum())
        rows.setdefault("default exact ranking (simulated_response)", []).append(
            f"{per:.2f} ({over} of {len(sample)} overturn: bisected)"
        )
        base = np.ones(len(sample))
        if onset:
            from stepframe.pipeline.selection.intensity import equal_intensity_scales
            from stepframe.records.spectra import peak_displacements_m

            t1 = 2 * math.pi / frame.omega_1_rad_s
            sd = np.array([peak_displacements_m(a, dt, [t1], frame.xi_1)[0] for a, dt in sample])
            base = equal_intensity_scales(sd, frame, 1.0)
        start = time.process_time()
        for (acc, dt), scale in zip(sample[:50], base[:50], strict=True):
            for factor in LADDER:
                simulate(frame, acc, dt, scale=scale * factor, record_history=False)
        rows.setdefault("peer: the ladder's 5 runs through simulate, one by one", []).append(
            f"{(time.process_time() - start) / 50 * 1e3:.2f}"
        )
        start = time.process_time()
        for (acc, dt), scale in zip(sample[:50], base[:50], strict=True):
            simulate(frame, acc, dt, scale=scale, record_history=False)
        rows.setdefault("one run at the stated intensity (simulate)", []).append(
            f"{(time.process_time() - start) / 50 * 1e3:.2f}"
        )
    for name, cells in rows.items():
        print(f"| {name} | {' | '.join(cells)} |")
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    print(f"\n{args.n:,} candidates, every core ({numba.get_num_threads()} numba threads):\n")
    print("| ranking | candidates | wall [s] | CPU [s] | CPU / cores [s] | load average |")
    print("|---|---|---|---|---|---|")
    for onset in (False, True):
        wall = cpu = 0.0
        done = 0
        seed = 100
        while done < args.n:
            records = motions(min(CHUNK, args.n - done), seed)
            seed += 1
            start_wall, start_cpu = time.perf_counter(), time.process_time()
            rank(frame, records, onset)
            wall += time.perf_counter() - start_wall
            cpu += time.process_time() - start_cpu
            done += len(records)
        cores = numba.get_num_threads()
        print(
            f"| default, {'onset ratio 1' if onset else 'as recorded'} | {done:,} | {wall:.0f} | "
            f"{cpu:.0f} | {cpu / cores:.0f} | {os.getloadavg()[0]:.1f} |"
        )


if __name__ == "__main__":
    main()
