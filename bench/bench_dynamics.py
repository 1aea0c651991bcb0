"""Harmonic dynamics and IDA: bifurcation-diagram throughput and hunt-trace-fill cost.

Run: ``python bench/bench_dynamics.py [--quick]``. Prints Markdown tables for docs/benchmarks.md.

1. Bifurcation diagram of the paper's Example 3 frame (W_col per column, ξ₂ = 0) at
   ω = 7.854 rad/s: 200 amplitudes (0.05-0.5 g) × 50 initial states × 100 forcing periods through
   stepframe.core.execution.map_items on 2 processes (wall time includes starting the pool and
   loading the cached kernels), against the same work on 1 process.
2. IDA of the 100 FEMA P695 components on the Example 4 frame (x_c = 0.05 m, C_r = 0.9,
   x_cap = 0.6 m) by hunt-trace-fill in PGA [g] to a resolution of 0.01 g and 0.001 g: simulations
   used and wall time, against a fixed-step grid (0.05, 0.05 + resolution, ... up to each record's
   first overturning)
   that resolves the overturning intensity equally well (counted, and a sample of it timed).
"""

from __future__ import annotations

import sys
import time

import numpy as np

from stepframe.records.examples import fema_p695
from stepframe.structure.bifurcation import bifurcation_diagram, orbit_period
from stepframe.structure.frame import PortalFrame
from stepframe.structure.ida import IdaSettings, capacity_fractiles, fixed_step_runs, ida_records
from stepframe.structure.simulator import simulate_batch

EXAMPLE3 = PortalFrame.from_physical(
    w_s_n=1.472e6, w_col_n=2.807e6 - 1.472e6, h_r_m=29.944, l_f_m=8.839, k_a_n_m=1.159e9,
    k_b_n_m=5.019e6, xi_1=0.05, xi_2=0.0, w_col_convention="per-column",
)  # fmt: skip
EXAMPLE4 = PortalFrame(
    omega_1_rad_s=6.4581, omega_2_rad_s=0.6445, p_1=1.0901, p_2=1.2680,
    gamma_1_m_s2=0.1387, xi_1=0.05, xi_2=0.0, x_c_m=0.05, c_r=0.9, x_cap_m=0.6,
)  # fmt: skip


def bench_bifurcation(n_amp: int, n_init: int, n_per: int) -> None:
    amps = np.linspace(0.05, 0.5, n_amp) * 9.81
    # Warm the on-disk numba cache in this process (compilation is a one-time cost).
    bifurcation_diagram(EXAMPLE3, amps[:1], 7.854, n_initial=1, n_periods=2, n_keep=1, jobs=1)
    rows = []
    for jobs in (1, 2):
        t0 = time.perf_counter()
        ds = bifurcation_diagram(
            EXAMPLE3, amps, 7.854, n_initial=n_init, n_periods=n_per, n_keep=20, jobs=jobs
        )
        wall = time.perf_counter() - t0
        rows.append((jobs, wall, ds))
    runs = n_amp * n_init
    print(f"\nBifurcation diagram: {n_amp} amplitudes × {n_init} initial states × {n_per} periods")
    print("\n| processes | wall [s] | periods/s | µs per period per process |")
    print("|---|---|---|---|")
    for jobs, wall, _ds in rows:
        rate = runs * n_per / wall
        print(f"| {jobs} | {wall:.1f} | {rate:,.0f} | {1e6 * wall * jobs / (runs * n_per):.1f} |")
    ds = rows[-1][2]
    over = float((ds["outcome"].values == 1).mean())
    stopped = int((ds["outcome"].values == 2).sum())
    periods = [orbit_period(ds["x_m"].values[a, j]) for a in range(n_amp) for j in range(n_init)]
    counts = np.bincount(periods, minlength=9)
    print(
        f"\noverturned fraction {over:.3f}, stopped runs {stopped}; period histogram "
        f"(0 = none ≤ 8 or overturned): {counts.tolist()}"
    )


def bench_ida(n_records: int, resolution: float) -> None:
    stream, _table = fema_p695()
    recs = [(tr.data.astype(float), float(tr.stats.delta)) for tr in stream[:n_records]]
    settings = IdaSettings(
        start=0.05,
        step=0.1,
        step_increment=0.05,
        resolution=resolution,
        max_intensity=5.0,
        probe_factor=2.0,
        n_probe=8,
        n_fill=4,
        max_runs=80,
    )
    simulate_batch(EXAMPLE4, recs[:1], [0.1], tail_s=5.0)  # compile / load cache
    t0 = time.perf_counter()
    items = ida_records(EXAMPLE4, recs, settings=settings, tail_s=5.0)
    wall = time.perf_counter() - t0
    n_htf = sum(i.n_runs for i in items)
    n_grid = fixed_step_runs(items, settings)
    # Time a sample of the fixed grid (the first 10 records' grids) to estimate its wall time.
    sample = []
    for k, (item, (acc, _dt)) in enumerate(zip(items, recs, strict=True)):
        if k >= 10:
            break
        top = item.first_overturning or settings.max_intensity
        grid = np.arange(settings.start, top + 1e-9, settings.resolution)
        pga = np.max(np.abs(acc)) / 9.80665
        sample.extend((k, s / pga) for s in grid)
    t1 = time.perf_counter()
    simulate_batch(
        EXAMPLE4, [recs[k] for k, _ in sample], [s for _, s in sample], pairs="zip", tail_s=5.0
    )
    grid_sample_wall = time.perf_counter() - t1
    grid_wall_est = grid_sample_wall * n_grid / max(len(sample), 1)
    resurrected = sum(bool(i.resurrections) for i in items)
    lower = sum(i.status == "lower_bound" for i in items)
    fr = capacity_fractiles(items)
    print(
        f"\nIDA: {n_records} FEMA P695 components, Example 4 frame, resolution {resolution} g PGA"
    )
    print("\n| method | simulations | wall [s] |")
    print("|---|---|---|")
    print(f"| hunt-trace-fill (+ resurrection probes) | {n_htf} | {wall:.1f} |")
    print(
        f"| fixed step {resolution} g up to first overturning | {n_grid} | {grid_wall_est:.1f} "
        f"(estimated from {len(sample)} timed runs) |"
    )
    print(
        f"\nratio of simulations fixed/htf = {n_grid / n_htf:.1f}; records resurrected: "
        f"{resurrected}; lower bounds: {lower}; first-overturning PGA fractiles [g]: "
        + ", ".join(f"{k} {v:.3f}" for k, v in fr.items())
    )


def bench_aframe(n_records: int) -> None:
    """Hysteretic A-frame (exact pieces) against its equivalent-viscous substitute."""
    from stepframe.structure.aframe_hysteretic import equivalent_viscous_error
    from stepframe.structure.frame import AFrame

    frame = AFrame(
        omega_1_rad_s=6.0, omega_2_rad_s=0.7, p_1=1.1, p_2=1.2, gamma_1_m_s2=0.15, xi_1=0.05,
        theta_rad=0.2, x_c_m=0.04, c_r=0.9, x_cap_m=0.6,
    )  # fmt: skip
    stream, _table = fema_p695()
    recs = [(tr.data.astype(float), float(tr.stats.delta)) for tr in stream[:n_records]]
    t0 = time.perf_counter()
    table = equivalent_viscous_error(frame, recs, [0.02, 0.1, 0.2], tail_s=5.0)
    wall = time.perf_counter() - t0
    print(
        f"\nA-frame (ξ₁ = 0.05 hysteretic) vs equivalent viscous, {n_records} records × 3 "
        f"scales, {wall:.1f} s"
    )
    print("\n| scale | median |rel. error of peak| | max | overturning verdicts differing |")
    print("|---|---|---|---|")
    for s, grp in table.groupby("scale"):
        both = grp[~grp.overturned_hysteretic & ~grp.overturned_viscous]
        err = both["rel_error"].abs()
        differ = int((grp.overturned_hysteretic != grp.overturned_viscous).sum())
        print(f"| {s:g} | {err.median():.3f} | {err.max():.3f} | {differ} of {len(grp)} |")


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    bench_bifurcation(20 if quick else 200, 10 if quick else 50, 100)
    for res in (0.01, 0.001):
        bench_ida(10 if quick else 100, res)
    bench_aframe(10 if quick else 100)
