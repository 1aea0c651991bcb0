"""Structure models side by side (issue 31): cost, the equivalent-viscous route's error, and the
linearised rocking block against the full nonlinear one.

Run: ``python bench/bench_structure_models.py [--quick]`` from the repository root. Prints
Markdown tables for docs/benchmarks.md ("Structure models") and docs/structure-dynamics.md.

1. Cost per simulation on the same records (the first N FEMA P695 components scaled to a PGA):
   the linearised block (exact piecewise-analytic kernel) against the nonlinear block
   (Runge-Kutta 5(4), rtol 1e-10), and the A-frame's equivalent-viscous portal frame (exact
   kernel) against its hysteretic integration with sticking. Median of 3 single-threaded runs
   per record, summed over the records.
2. The equivalent-viscous route's error: three A-frames × the records × ground motions scaled to
   0.5, 1, 2 and 4 times each frame's static uplift acceleration, peak |x| of
   ``AFrame.to_portal_frame(hysteretic="equivalent-viscous")`` against the hysteretic model
   (median and worst over the runs neither overturned, and the overturning verdicts that differ).
3. Linearisation of Housner's block under a one-cosine pulse: the minimum overturning amplitude
   of both models over ω_p/p, and the linearised peak rotation's error over ω_p/p × amplitude,
   for the blocks b/h = 0.25 (α = 0.245) and 0.1 (α = 0.0997).
4. The command lines that hung (more than 60 s) before issue 31, timed as fresh processes.
"""

from __future__ import annotations

import math
import statistics
import subprocess
import sys
import time
import warnings
from collections.abc import Callable
from functools import partial
from typing import Any

import numpy as np

from stepframe.records.examples import fema_p695
from stepframe.structure.aframe_hysteretic import (
    equivalent_viscous_error,
    equivalent_viscous_summary,
    simulate_aframe,
)
from stepframe.structure.frame import AFrame, EquivalentViscousWarning, RockingBlock
from stepframe.structure.harmonic import simulate_pulse
from stepframe.structure.rocking_block import block_pulse, simulate_block
from stepframe.structure.simulator import simulate
from timing import median_seconds

#: The A-frames of the comparison: the one of tests/structure/test_aframe_hysteretic.py (a weak
#: stepped phase: it holds 0.11 m/s²), one with a strong stepped phase and hysteresis, one between.
FRAMES = {
    "weak (ξ₁ 0.05)": AFrame(
        omega_1_rad_s=6.0, omega_2_rad_s=0.7, p_1=1.1, p_2=1.2, gamma_1_m_s2=0.15, xi_1=0.05,
        theta_rad=0.2, x_c_m=0.04, c_r=0.9, x_cap_m=0.6,
    ),
    "strong (ξ₁ 0.15)": AFrame(
        omega_1_rad_s=6.0, omega_2_rad_s=1.5, p_1=1.1, p_2=1.2, gamma_1_m_s2=2.0, xi_1=0.15,
        theta_rad=0.2, x_c_m=0.04, c_r=0.85, x_cap_m=0.8,
    ),
    "stiff (ξ₁ 0.10)": AFrame(
        omega_1_rad_s=10.0, omega_2_rad_s=1.0, p_1=1.2, p_2=1.3, gamma_1_m_s2=0.6, xi_1=0.10,
        theta_rad=0.15, x_c_m=0.03, c_r=0.92, x_cap_m=0.55,
    ),
}  # fmt: skip
BLOCKS = (RockingBlock(0.25, 1.0), RockingBlock(0.1, 1.0))


def records(n: int) -> list[tuple[np.ndarray, float]]:
    stream, _table = fema_p695()
    return [(tr.data.astype(float), float(tr.stats.delta)) for tr in stream[:n]]


def uplift_m_s2(frame: AFrame) -> float:
    """Static ground acceleration at which the unstepped A-frame, loaded slowly, steps."""
    return frame.omega_1_rad_s**2 * (1 + math.pi * frame.xi_1) * frame.x_c_m / frame.p_1


def bench_cost(recs: list[tuple[np.ndarray, float]]) -> None:
    block = BLOCKS[0]
    linear = block.linearised()
    frame = FRAMES["weak (ξ₁ 0.05)"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EquivalentViscousWarning)
        viscous = frame.to_portal_frame(hysteretic="equivalent-viscous")
    pga_block = 0.4 * 9.81
    pga_frame = 1.0 * uplift_m_s2(frame)
    # Compile every kernel once (a cache load at most) before timing.
    acc, dt = recs[0]
    simulate(linear, acc, dt, record_history=False)
    simulate_block(block, acc, dt)
    simulate(viscous, acc, dt, record_history=False)
    simulate_aframe(frame, acc, dt)
    totals = dict.fromkeys(("linear", "nonlinear", "viscous", "hysteretic"), 0.0)
    samples = 0
    for acc, dt in recs:
        pga = float(np.max(np.abs(acc)))
        sb, sf = pga_block / pga, pga_frame / pga
        samples += acc.size
        runs = {
            "linear": partial(simulate, linear, acc, dt, scale=sb, record_history=False),
            "nonlinear": partial(simulate_block, block, acc, dt, scale=sb),
            "viscous": partial(simulate, viscous, acc, dt, scale=sf, record_history=False),
            "hysteretic": partial(simulate_aframe, frame, acc, dt, scale=sf),
        }
        for key, run in runs.items():
            totals[key] += median_seconds(run, 3)
    n = len(recs)
    print(
        f"\nCost per simulation: {n} FEMA P695 components ({samples / n:,.0f} samples on average,"
    )
    print("plus a 10 s tail), single thread, median of 3 runs per record")
    print("\n| model | method | ms per simulation | ratio |")
    print("|---|---|---|---|")
    rows = (
        ("linearised block (0.25 × 1.0 m, PGA 0.4 g)", "exact closed form", "linear", "linear"),
        ("nonlinear block (same)", "Runge-Kutta 5(4), rtol 1e-10", "nonlinear", "linear"),
        ("A-frame, equivalent viscous (PGA = uplift)", "exact closed form", "viscous", "viscous"),
        ("A-frame, hysteretic with sticking (same)", "exact closed form", "hysteretic", "viscous"),
    )
    for label, method, key, ref in rows:
        ms = 1e3 * totals[key] / n
        print(f"| {label} | {method} | {ms:.3f} | {totals[key] / totals[ref]:.1f} |")


def bench_equivalent_viscous(recs: list[tuple[np.ndarray, float]]) -> None:
    print(f"\nEquivalent-viscous route against the hysteretic A-frame: {len(recs)} records × 4")
    print(
        "\n| frame | PGA / uplift | runs | median abs. error | worst | record | verdicts differ |"
    )
    print("|---|---|---|---|---|---|---|")
    every = []
    for name, frame in FRAMES.items():
        for level in (0.5, 1.0, 2.0, 4.0):
            pga = level * uplift_m_s2(frame)
            tables = [
                equivalent_viscous_error(
                    frame, [rec], [pga / float(np.max(np.abs(rec[0])))], tail_s=10.0
                ).assign(record=k)
                for k, rec in enumerate(recs)
            ]
            import pandas as pd

            table = pd.concat(tables, ignore_index=True)
            every.append(table)
            s = equivalent_viscous_summary(table)
            if s["runs"]:
                median = f"{100 * s['median_abs_rel_error']:.1f} %"
                worst = f"{100 * s['worst_rel_error']:+.0f} % | {s['worst_record']}"
            else:
                median, worst = "-", "- | -"
            print(
                f"| {name} | {level:g} | {s['runs']} | {median} | {worst} | "
                f"{s['verdicts_differing']} of {s['all_runs']} differ |"
            )
    import pandas as pd

    s = equivalent_viscous_summary(pd.concat(every, ignore_index=True))
    print(
        f"\nAll: median {100 * s['median_abs_rel_error']:.1f} %, worst "
        f"{100 * s['worst_rel_error']:+.0f} %, verdicts differing in {s['verdicts_differing']} of "
        f"{s['all_runs']} runs."
    )


def _overturns(model: Any, unit: float, omega: float, amplitude: float) -> bool:
    """Whether a one-cosine pulse of ``amplitude`` × ``unit`` [m/s²] overturns the block model."""
    if isinstance(model, RockingBlock):
        return block_pulse(model, amplitude * unit, omega).overturned
    return simulate_pulse(model, amplitude * unit, omega).overturned


def minimum_overturning(overturns: Callable[[float], bool], lo: float, hi: float) -> float:
    """The smallest amplitude that overturns, from a grid of 800 on [lo, hi] and bisection."""
    grid = np.linspace(lo, hi, 800)
    first = next(x for x in grid if overturns(x))
    a, b = first - (grid[1] - grid[0]), first
    while b - a > 1e-6 * b:
        m = 0.5 * (a + b)
        a, b = (a, m) if overturns(m) else (m, b)
    return b


def bench_linearisation(quick: bool) -> None:
    ratios = (1.0, 2.0, 3.0, 4.0, 6.0) if not quick else (2.0, 4.0)
    amps = (1.05, 1.25, 1.5, 2.0, 3.0, 5.0, 10.0)
    for block in BLOCKS:
        linear = block.linearised()
        p, unit, alpha = block.p_rad_s, block.uplift_acceleration_m_s2, block.alpha_rad
        print(
            f"\nBlock b/h = {block.half_width_m / block.half_height_m:g} (α = {alpha:.4f} rad), "
            "one-cosine pulse: minimum overturning amplitude [g·tan α]"
        )
        print("\n| ω_p/p | nonlinear | linearised | difference | linearised [its g·α] |")
        print("|---|---|---|---|---|")
        for r in ratios:
            nl = minimum_overturning(partial(_overturns, block, unit, r * p), 1.0, 80.0)
            li = minimum_overturning(partial(_overturns, linear, unit, r * p), 0.9, 80.0)
            print(
                f"| {r:g} | {nl:.5f} | {li:.5f} | {100 * (li / nl - 1):+.2f} % | "
                f"{li * math.tan(alpha) / alpha:.5f} |"
            )
        print(
            "\nPeak rotation: nonlinear θ_max/α, and the linearised peak's error (O/S: the verdicts"
            " of the nonlinear/linearised models where either overturns)"
        )
        print("\n| ω_p/p | " + " | ".join(f"A = {a:g} g·tan α" for a in amps) + " |")
        print("|---|" + "---|" * len(amps))
        for r in ratios:
            cells = []
            for a in amps:
                nl = block_pulse(block, a * unit, r * p)
                li = simulate_pulse(linear, a * unit, r * p)
                if nl.overturned or li.overturned:
                    cells.append(f"{'O' if nl.overturned else 'S'}/{'O' if li.overturned else 'S'}")
                    continue
                err = li.peak_abs_x_m / block.half_height_m / nl.peak_rotation_rad - 1.0
                mark = "**" if abs(err) <= 0.01 else ""
                cells.append(f"{nl.peak_over_alpha:.3f}: {mark}{100 * err:+.1f} %{mark}")
            print(f"| {r:g} | " + " | ".join(cells) + " |")


def bench_commands() -> None:
    lines = [
        "structure harmonic --block 0.25,1.0 --amplitude-g 0.3 --omega-rad-s 1e-12 --periods 1",
        "structure harmonic --block 0.25,1.0 --amplitude-g 0.3 --omega-rad-s 1e4 --periods 1000000",
        "structure harmonic --block 0.25,1.0 --amplitude-g 0.2449786633718428 --omega-rad-s 16 "
        "--periods 20 --json",
        "structure ida --block 0.25,1.0 --pulse cosine --omega-rad-s 1e-12",
    ]
    print("\nCommand lines that hung or answered wrongly before issue 31 (fresh processes)")
    print("\n| command | exit | wall [s] | answer |")
    print("|---|---|---|---|")
    for line in lines:
        argv = [sys.executable, "-m", "stepframe.cli", *line.split()]
        walls, proc = [], None
        for _ in range(3):
            start = time.perf_counter()
            proc = subprocess.run(argv, capture_output=True, text=True, timeout=120, check=False)
            walls.append(time.perf_counter() - start)
        assert proc is not None
        answer = (
            (proc.stderr.strip().splitlines() or [""])[-1][:90] if proc.returncode else "status ok"
        )
        wall = statistics.median(walls)
        print(f"| `stepframe {line}` | {proc.returncode} | {wall:.2f} | {answer} |")


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    recs = records(10 if quick else 100)
    bench_commands()
    bench_cost(recs[: 10 if quick else 30])
    bench_equivalent_viscous(recs)
    bench_linearisation(quick)
