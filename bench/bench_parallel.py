"""Parallel efficiency on 2 cores, measured as ratios in the same run (docs/benchmarks.md).

1. The features stage: ``catalog_features`` on the FEMA P695 catalogue (100 components) with
   ``n_jobs=1`` and ``n_jobs=2``, runs interleaved, ``--repeat`` times; the speed-up is the
   ratio of the medians.
2. The batch simulator: ``simulate_batch`` (a thread per core) on 100 (record, scale) pairs with
   numba's thread count set to 1 and to 2, interleaved the same way.

The load average is printed with the numbers: on a shared machine other jobs take cores and
the ratio falls whatever the code does.

    python bench/bench_parallel.py [--repeat 3]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from collections.abc import Callable

import numpy as np

from stepframe.records.examples import fema_p695
from stepframe.stochastic.catalog_features import catalog_features

CPU: list[float] = []


def timed(function: Callable[[], object]) -> float:
    """Wall time [s]; the CPU time it used (this process and its children) goes to ``CPU``."""
    before = os.times()
    start = time.perf_counter()
    function()
    wall = time.perf_counter() - start
    after = os.times()
    CPU.append(sum(after[:4]) - sum(before[:4]))
    return wall


def features_stage(repeat: int) -> tuple[float, float]:
    stream, _ = fema_p695()
    catalog_features(stream[:4], n_jobs=1)  # warm imports
    one, two, cpu_one, cpu_two = [], [], [], []
    for _ in range(repeat):
        one.append(timed(lambda: catalog_features(stream, n_jobs=1)))
        cpu_one.append(CPU[-1])
        two.append(timed(lambda: catalog_features(stream, n_jobs=2)))
        cpu_two.append(CPU[-1])
    # CPU time used per wall second: 1.0 = one core kept busy, 2.0 = both.
    busy1 = statistics.median(c / w for c, w in zip(cpu_one, one, strict=True))
    busy2 = statistics.median(c / w for c, w in zip(cpu_two, two, strict=True))
    print(
        f"features: CPU s per wall s: {busy1:.2f} (1 worker), {busy2:.2f} (2 workers); "
        f"CPU s in total: {statistics.median(cpu_one):.2f} vs {statistics.median(cpu_two):.2f}\n"
    )
    return statistics.median(one), statistics.median(two)


def batch_simulator(repeat: int) -> tuple[float, float]:
    import numba

    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.simulator import simulate_batch

    stream, _ = fema_p695()
    records = [(np.asarray(tr.data), float(tr.stats.delta)) for tr in stream[:50]]
    frame = PortalFrame(
        omega_1_rad_s=6.4581,
        omega_2_rad_s=0.6445,
        p_1=1.0901,
        p_2=1.2680,
        gamma_1_m_s2=0.1387,
        xi_1=0.05,
        xi_2=0.0,
        x_c_m=0.05,
        c_r=0.9,
        x_cap_m=0.6,
    )  # fmt: skip (bench/bench_simulator.py's frame)
    simulate_batch(frame, records[:2], [0.1], tail_s=0.0)  # compile / load the cached kernels
    one, two = [], []
    for _ in range(repeat):
        numba.set_num_threads(1)
        one.append(timed(lambda: simulate_batch(frame, records, [0.1, 0.2], tail_s=0.0)))
        numba.set_num_threads(2)
        two.append(timed(lambda: simulate_batch(frame, records, [0.1, 0.2], tail_s=0.0)))
    return statistics.median(one), statistics.median(two)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--skip-simulator", action="store_true")
    args = parser.parse_args()
    print(f"load average before: {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs\n")
    print("| stage | items | 1 worker [s] | 2 workers [s] | speed-up |")
    print("|---|---|---|---|---|")
    t1, t2 = features_stage(args.repeat)
    print(f"| features + fit (processes) | 100 components | {t1:.2f} | {t2:.2f} | {t1 / t2:.2f} |")
    if not args.skip_simulator:
        s1, s2 = batch_simulator(args.repeat)
        print(f"| simulate_batch (threads) | 100 pairs | {s1:.2f} | {s2:.2f} | {s1 / s2:.2f} |")
    print(f"\nload average after: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
