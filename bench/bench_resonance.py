"""Cost of the moving-resonance index beside the exact simulation of a candidate (issue 26).

Run: ``python bench/bench_resonance.py [--repeat 5]``. Prints a Markdown table for
docs/benchmarks.md.

The runs are the selection confirmation's (bench/bench_simulator.py :func:`cases`: the Example 4
frame and the wide frame under the two shortest FEMA P695 components of each class, elastic,
stepping and standing, overturning). For each run, medians over ``repeat`` calls of CPU time
of the benchmarking thread (the cores are shared; ratios are the numbers to compare):

- one exact simulation without history (``simulate(..., record_history=False)``);
- the candidate's exact simulation as the selection's ranking runs it
  (:func:`stepframe.pipeline.selection.exact.simulated_response`: the 5-level ladder at the
  stated intensity and the bisection of the overturning factor when it overturns);
- the run at the stated intensity with history (what the index reads: x, v and the phase at
  every sample);
- the band spectrum of the record over the frame's band as the index reads it
  (:func:`band_power`, once per record and frame, at any scale) and the index itself (ω_f(t),
  the ground's work, closeness, half-cycles).

"Index cost" is what the index adds: the history's own cost (the run at the stated intensity
kept with history instead of without), the band spectrum and the index; it is given over one
run and over the candidate's ranking work.

``--catalogue`` measures the same for every candidate of the example catalogue rather than the
two shortest of each class: the 100 FEMA P695 components at each frame's confirmation scale
(equal PSA at T_1, ratio × the onset of stepping), so the ratio is read over the lengths a
selection actually ranks (8-100 s), with its distribution over the candidates.
"""

from __future__ import annotations

import argparse
import statistics
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from bench_simulator import TAIL_S, cases, confirmation_scales, fema_series
from stepframe.pipeline.dynamics.resonance import band_power, default_band, resonance_index
from stepframe.pipeline.selection.exact import simulated_response
from stepframe.records.examples import fema_p695
from stepframe.structure.simulator import simulate


def _cpu(fn: Callable[[], Any], repeat: int) -> tuple[Any, float]:
    """The last result of ``fn()`` and the median thread CPU time of ``repeat`` calls [s]."""
    times, out = [], None
    for _ in range(repeat):
        start = time.thread_time()
        out = fn()
        times.append(time.thread_time() - start)
    return out, statistics.median(times)


def _measure(
    frame: Any, band: tuple[float, float], acc: np.ndarray, dt_s: float, scale: float, repeat: int
) -> dict[str, float]:
    """One run's CPU times [s] (one simulation without and with history, the candidate's ranking,
    band spectrum, index; ``extra`` what the index adds) and its R_m and M."""
    kw: dict[str, Any] = {"scale": scale, "tail_s": TAIL_S}
    _, plain = _cpu(lambda: simulate(frame, acc, dt_s, record_history=False, **kw), repeat)
    ranking_args = (frame, [(acc, dt_s)], np.array([scale]))
    _, ranked = _cpu(lambda: simulated_response(*ranking_args), repeat)
    result, full = _cpu(lambda: simulate(frame, acc, dt_s, **kw), repeat)
    n_samples = result.raw.hist_x.size
    spectrum, spec_s = _cpu(lambda: band_power(acc, dt_s, band, n_samples=n_samples), repeat)
    measures, index_s = _cpu(lambda: resonance_index(result, spectrum, band), repeat)
    return {
        "plain": plain, "ranked": ranked, "full": full, "spectrum": spec_s, "index": index_s,
        "history": max(full - plain, 0.0),
        "extra": max(full - plain, 0.0) + spec_s + index_s,
        "R_m": measures.moving_resonance_index, "M": measures.moving_resonance_share,
    }  # fmt: skip


def _part_sum(rows: list[dict[str, float]], key: str) -> float:
    """One part of the index's cost summed over the candidates [s]."""
    return sum(row[key] for row in rows)


def catalogue(stream: Any, repeat: int) -> None:
    """Index cost over the candidate's ranking for every FEMA P695 component, per frame."""
    from selection_confirmation import frames

    series = fema_series(stream)
    print(
        "| frame | candidates | samples per candidate, median (range) | candidates' ranking "
        "| index cost | index cost / ranking, all | per candidate: median | 90th percentile "
        "| max | candidates ≤ 0.20 | history / band spectrum / index |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, (frame, ratio) in frames().items():
        band = default_band(frame)
        simulate(frame, np.zeros(3), 0.01)  # load the kernel before timing
        scales = confirmation_scales(frame, ratio, series)
        rows = [
            _measure(frame, band, acc, dt_s, float(scale), repeat)
            for (acc, dt_s), scale in zip(series, scales, strict=True)
        ]
        ranked = np.array([row["ranked"] for row in rows])
        extra = np.array([row["extra"] for row in rows])
        ratios = extra / ranked
        sizes = np.array([acc.size for acc, _ in series])
        print(
            f"| {name} ({ratio:g} × onset) | {len(rows)} | {int(np.median(sizes)):,} "
            f"({sizes.min():,}-{sizes.max():,}) | {ranked.sum():.2f} s | {extra.sum():.2f} s "
            f"| {extra.sum() / ranked.sum():.3f} | {np.median(ratios):.3f} "
            f"| {np.quantile(ratios, 0.9):.3f} | {ratios.max():.2f} "
            f"| {int((ratios <= 0.2).sum())} of {len(rows)} "
            f"| {_part_sum(rows, 'history'):.3f} / {_part_sum(rows, 'spectrum'):.3f} / "
            f"{_part_sum(rows, 'index'):.3f} s |"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5, help="calls per timing (median)")
    parser.add_argument(
        "--catalogue", action="store_true", help="every FEMA P695 component, not twelve runs"
    )
    args = parser.parse_args()
    repeat = args.repeat
    stream, _ = fema_p695()
    if args.catalogue:
        catalogue(stream, repeat)
        return
    print(
        "| case | record (index: samples + tail) | one run, no history | candidate's ranking "
        "| with history | band spectrum | index | index cost / one run "
        "| index cost / candidate's ranking | R_m | M |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    totals = {"plain": 0.0, "ranked": 0.0, "extra": 0.0}
    for label, (frame, runs) in cases(stream).items():
        band = default_band(frame)
        simulate(frame, np.zeros(3), 0.01)  # load the kernel before timing
        for index, acc, dt_s, scale in runs:
            row = _measure(frame, band, acc, dt_s, scale, repeat)
            for key in totals:
                totals[key] += row[key]
            print(
                f"| {label} | {index}: {acc.size:,} + {round(TAIL_S / dt_s)} | "
                f"{1e3 * row['plain']:.2f} ms | {1e3 * row['ranked']:.2f} ms | "
                f"{1e3 * row['full']:.2f} ms | {1e3 * row['spectrum']:.2f} ms | "
                f"{1e3 * row['index']:.2f} ms | {row['extra'] / row['plain']:.2f} | "
                f"{row['extra'] / row['ranked']:.2f} | {row['R_m']:.2f} | {row['M']:.2f} |"
            )
    print(
        f"\nAll runs: one simulation without history {1e3 * totals['plain']:.1f} ms, the "
        f"candidates' ranking {1e3 * totals['ranked']:.1f} ms, the index's extra cost "
        f"{1e3 * totals['extra']:.1f} ms ({totals['extra'] / totals['plain']:.2f} × one run, "
        f"{totals['extra'] / totals['ranked']:.2f} × the ranking)."
    )


if __name__ == "__main__":
    main()
