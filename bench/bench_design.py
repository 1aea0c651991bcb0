"""Cost of the design-displacement fidelity ladder: closed form → iteration → numerical search.

Run: ``python bench/bench_design.py``. For the paper's Examples 1 and 2 (recomputed from their
inputs) it times each rung of :func:`stepframe.structure.quasi_dynamic.design_displacement`
(median of 7 repeats of a timed loop) and reports the ratio to the closed form measured in the
same run and the relative difference of δ* from the closed form. Prints a Markdown table for
docs/benchmarks.md. The machine's 2 cores are shared, so absolute times are noisy; ratios less so.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable
from functools import partial

from stepframe.structure.design_spectrum import TwoPeriodSpectrum
from stepframe.structure.quasi_dynamic import (
    PierInputs,
    SteppingMap,
    design_displacement,
)


def _per_call_s(func: Callable[[], object], repeat: int = 7) -> float:
    """Median over ``repeat`` timed loops of the time per call [s]."""
    number = 1
    while True:  # grow the loop until one timing takes ≥ 0.05 s
        start = time.perf_counter()
        for _ in range(number):
            func()
        if time.perf_counter() - start >= 0.05:
            break
        number *= 4
    samples = []
    for _ in range(repeat):
        start = time.perf_counter()
        for _ in range(number):
            func()
        samples.append((time.perf_counter() - start) / number)
    return statistics.median(samples)


def cases() -> dict[str, tuple[SteppingMap, TwoPeriodSpectrum, float]]:
    """(map, spectrum, iteration start) of Examples 1 and 2."""
    pier_1 = PierInputs(
        8000e3, 212e3, 9600e3, 7.0, 27.0, footing_width_m=7.0, bearing_capacity_pa=1e6
    )
    example_1 = (SteppingMap.from_pier(pier_1, 1.0), TwoPeriodSpectrum(5.2492 / 0.62, 5.2492), 0.05)
    spectrum_2 = TwoPeriodSpectrum.from_g(1.038, 0.456, g_m_s2=9.81)
    map_2 = SteppingMap.from_lambda_2(
        0.0416774 / 0.3048, 0.691857 * math.sqrt(0.3048), 0.8, spectrum_2.s_d1_m_s
    )
    return {"Example 1": example_1, "Example 2": (map_2, spectrum_2, 0.1 * 0.0254)}


def main() -> None:
    print("| case | method | time per call | ratio to closed form | rel. diff. of δ* |")
    print("|---|---|---|---|---|")
    for name, (smap, spectrum, start) in cases().items():
        reference = design_displacement(smap, spectrum, "closed-form")
        assert reference.delta_m is not None
        costs = {}
        for method in ("closed-form", "iteration", "search"):
            call = partial(design_displacement, smap, spectrum, method, delta0_m=start)
            costs[method] = (_per_call_s(call), call())
        base = costs["closed-form"][0]
        for method, (cost, result) in costs.items():
            assert result.delta_m is not None
            steps = ""
            if result.iteration is not None:
                steps = f" ({len(result.iteration.rows) - 1} steps)"
            diff = abs(result.delta_m - reference.delta_m) / reference.delta_m
            print(
                f"| {name} | {method}{steps} | {cost * 1e6:.1f} µs | {cost / base:.0f} | "
                f"{diff:.1e} |"
            )


if __name__ == "__main__":
    main()
