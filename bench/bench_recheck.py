"""Re-measured numbers for docs/benchmarks.md ("Re-measured" section): PSA against a scipy
``lfilter`` implementation of the same recurrence, and features + fit per component.

PSA peer: the Nigam-Jennings step ``x_{i+1} = A x_i + B0 a_i + B1 a_{i+1}`` (x = (u, v)) is a
linear time-invariant filter from a to u with transfer function
``(B1_0 z² + (B0_0 - A11 B1_0 + A01 B1_1) z + (A01 B0_1 - A11 B0_0)) / (z² - tr(A) z + det A)``,
so ``scipy.signal.lfilter`` runs it per period in C: the realistic peer of a compiled loop. Both
use stepframe's coefficients and band-limited upsampling, so they compute the same numbers.
Times are CPU time of this thread (median of ``--repeat``) with one numba/BLAS thread.

    python bench/bench_recheck.py [--repeat 9]
"""

from __future__ import annotations

import os

os.environ.setdefault("NUMBA_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

# Thread limits above must be set before numpy loads, hence the imports below them.
import argparse
import json
from pathlib import Path

import numpy as np
from scipy import signal

from stepframe.records import read
from stepframe.records.examples import fema_p695
from stepframe.records.spectra import (
    nigam_jennings_coefficients,
    response_spectrum,
    upsample,
    upsampling_factors,
)
from stepframe.stochastic.features import record_features
from stepframe.stochastic.fit import fit_model
from timing import median_cpu_seconds

PEER = Path(__file__).parents[1] / "tests" / "data" / "peer_nga_west2"


def lfilter_psa_g(acc: np.ndarray, dt: float, periods: np.ndarray, damping: float) -> np.ndarray:
    """PSA [g] by scipy.signal.lfilter of the same recurrence, one period at a time."""
    out = np.empty(periods.size)
    factors = upsampling_factors(periods, dt)
    for factor in np.unique(factors):
        index = np.flatnonzero(factors == factor)
        fine = upsample(acc, int(factor))
        coeffs = nigam_jennings_coefficients(2 * np.pi / periods[index], damping, dt / factor)
        for j, c in zip(index, coeffs, strict=True):
            # Kernel layout: A = [[c0, c1], [c2, c3]], B0 (a_i) = (c4, c6), B1 (a_{i+1}) = (c5, c7).
            a00, a01, a10, a11 = c[0], c[1], c[2], c[3]
            b0_u, b0_v, b1_u, b1_v = c[4], c[6], c[5], c[7]
            num = [b1_u, b0_u - a11 * b1_u + a01 * b1_v, a01 * b0_v - a11 * b0_u]
            den = [1.0, -(a00 + a11), a00 * a11 - a01 * a10]
            # Zero initial state as if a = 0 before the record (the recurrence starts at rest at
            # the first sample: the two differ by the response to a_0, a record's near-zero start).
            u = signal.lfilter(num, den, fine)
            out[j] = np.abs(u).max() * (2 * np.pi / periods[j]) ** 2
    return out / 9.80665


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=9)
    args = parser.parse_args()
    reference = json.loads((PEER / "RSN8883_peer_spectra.json").read_text())
    periods = np.array(reference["period"])
    trace = read(PEER / "RSN8883_14383980_13849360.AT2")[0]
    acc, dt = np.asarray(trace.data, dtype=np.float64), float(trace.stats.delta)
    ours = np.asarray(response_spectrum(acc, dt, periods, 0.05).psa_m_s2) / 9.80665
    theirs = lfilter_psa_g(acc, dt, periods, 0.05)
    t_ours = median_cpu_seconds(lambda: response_spectrum(acc, dt, periods, 0.05), args.repeat)
    t_lf = median_cpu_seconds(
        lambda: lfilter_psa_g(acc, dt, periods, 0.05), max(3, args.repeat // 3)
    )
    print(f"PSA, RSN 8883 (16,396 samples), 111 periods, 5 %; max |difference| "
          f"{np.max(np.abs(theirs / ours - 1)):.1e} (relative)\n")  # fmt: skip
    print("| method | CPU per component (median) | ratio to stepframe |")
    print("|---|---|---|")
    print(f"| stepframe `nigam_jennings` (numba) | {1e3 * t_ours:.1f} ms | 1 |")
    print(f"| scipy `lfilter`, same recurrence | {1e3 * t_lf:.1f} ms | {t_lf / t_ours:.1f} |")
    stream, _ = fema_p695()
    components = [(np.asarray(tr.data, dtype=np.float64), float(tr.stats.delta)) for tr in stream]

    def features_and_fit() -> None:
        for data, step in components:
            fit_model(record_features(data, step))

    features_and_fit()  # warm
    total = median_cpu_seconds(features_and_fit, 3)
    print(f"\nfeatures + fit (default t0='auto'), 100 FEMA components: "
          f"{1e3 * total / len(components):.1f} ms CPU per component (median of 3)")  # fmt: skip


if __name__ == "__main__":
    main()
