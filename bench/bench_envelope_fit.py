"""Benchmark: the envelope fit of t_max (``peak_time_by_envelope``) against its former solver.

The features stage fits a gamma envelope to each component's I_g(t) to locate its peak
(``stochastic.features.peak_time_by_envelope``): a bounded 4-parameter ``least_squares(trf)``.
It ran with a 2-point finite-difference Jacobian (five residual passes per iteration), about
ten of the features' twenty milliseconds per component on NGA-length records (issue 29: the
per-component cost of a 43,000-component catalogue). The peer is that former call: the
same function with ``least_squares``'s ``jac`` dropped while it runs (its default 2-point finite
differences on the same residuals, start, bounds and tolerances); the current call supplies the
analytic Jacobian (``features._GammaEnvelope``).

Inputs: the (time, I_g) of every component as ``record_features`` passes them, for the 100
FEMA P695 components and the first ``--nga`` components of ``bench/nga_catalogue.py``'s
catalogue (when written; synthetic records of 20-80 s). CPU time of this process over all
inputs, median of ``--repeat``; then how the two solutions compare.

    python bench/bench_envelope_fit.py [--repeat 3] [--nga 300]
"""

from __future__ import annotations

import argparse
import time
from typing import Any
from unittest import mock

import numpy as np
from scipy.optimize import least_squares as _least_squares

import nga_catalogue
from stepframe.records import read
from stepframe.records.examples import fema_p695
from stepframe.stochastic import features


def _finite_differences(*args: Any, **kwargs: Any) -> Any:
    """``scipy.optimize.least_squares`` without the analytic Jacobian (its default 2-point
    finite differences): the former call."""
    kwargs.pop("jac", None)
    return _least_squares(*args, **kwargs)


def former(time_s: Any, intensity: Any, window_s: float) -> tuple[float, float] | None:
    """``peak_time_by_envelope`` as it was: the same function with the trust-region fit
    differentiating by finite differences (``least_squares`` patched while it runs)."""
    with mock.patch("scipy.optimize.least_squares", _finite_differences):
        return features.peak_time_by_envelope(time_s, intensity, window_s)


def envelope_inputs(n_nga: int) -> tuple[list[tuple[Any, Any, float]], dict[str, int]]:
    """The envelope fit's inputs for the FEMA components and ``n_nga`` catalogue components."""
    captured: list[tuple[Any, Any, float]] = []
    current = features.peak_time_by_envelope

    def capture(time_s: Any, intensity: Any, window_s: float = features.DEFAULT_WINDOW_S) -> Any:
        captured.append((time_s.copy(), intensity.copy(), window_s))
        return current(time_s, intensity, window_s)

    features.peak_time_by_envelope = capture  # type: ignore[assignment]
    try:
        stream, _ = fema_p695()
        for trace in stream:
            features.record_features(trace)
        counts = {"FEMA P695": len(captured)}
        folder = nga_catalogue.OUT / "records"
        files = sorted(folder.glob("*.AT2"))[:n_nga] if folder.is_dir() else []
        for path in files:
            features.record_features(read(path)[0])
        counts["nga_catalogue"] = len(captured) - counts["FEMA P695"]
    finally:
        features.peak_time_by_envelope = current  # type: ignore[assignment]
    return captured, counts


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--nga", type=int, default=300, help="catalogue components")
    args = parser.parse_args()
    inputs, counts = envelope_inputs(args.nga)
    times: dict[str, list[float]] = {"former": [], "now": []}
    results: dict[str, list[Any]] = {}
    for _ in range(args.repeat):  # interleaved: both see the same load
        for name, solver in (("former", former), ("now", features.peak_time_by_envelope)):
            start = time.process_time()
            results[name] = [solver(*x) for x in inputs]
            times[name].append(time.process_time() - start)
    former_ms, now_ms = (1e3 * float(np.median(times[n])) / len(inputs) for n in ("former", "now"))
    pairs = [(a, b) for a, b in zip(results["former"], results["now"], strict=True) if a and b]
    t_diff = np.array([abs(a[0] - b[0]) for a, b in pairs])
    se_rel = np.array([abs(a[1] - b[1]) / a[1] for a, b in pairs if a[1] > 0])
    failed = {n: sum(r is None for r in results[n]) for n in results}
    print(f"inputs: {counts}, failed fits: {failed}")
    print("| fit | per component, former (trf, finite differences) | now (trf, analytic) "
          "| former / now | abs t_max difference [s]: median, max | SE rel. difference: median, "
          "max |")  # fmt: skip
    print("|---|---|---|---|---|---|")
    print(
        f"| envelope t_max, {len(inputs)} components | {former_ms:.2f} ms | {now_ms:.2f} ms "
        f"| {former_ms / now_ms:.2f} | {np.median(t_diff):.1e}, {t_diff.max():.1e} "
        f"| {np.median(se_rel):.1e}, {se_rel.max():.1e} |"
    )


if __name__ == "__main__":
    main()
