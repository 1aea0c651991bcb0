"""Benchmark: the Beck-Papadimitriou fit (``fit_model``) against its former solver (issue 29).

The former solver, reproduced here as the peer: scipy ``least_squares(method="trf")`` with a
2-point finite-difference Jacobian on the same bounded problem (θ = (ω_p, ρ, f), the same
residuals, start, bounds, scaling and tolerances). The current one (``fit._fit_omega``): MINPACK
LM on a sine transform of θ with the analytic Jacobian, finished by ``trf`` when it ends in a
flagged bound region. Both run inside ``fit_model`` (the peer patched in for ``_fit_omega``) on
the features of the 100 FEMA P695 components and of 100 synthetic paper-site records, in the
same run; CPU time of this process, median of ``--repeat``. Also prints how the solutions
compare: the residual sum of squares of the current fit relative to the former one's.

    python bench/bench_fit.py [--repeat 5]
"""

from __future__ import annotations

import argparse
import functools
import time
from collections.abc import Callable
from typing import Any
from unittest import mock

import numpy as np

from stepframe.records.examples import fema_p695
from stepframe.stochastic import fit
from stepframe.stochastic.features import RecordFeatures, record_features
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions
from timing import median_seconds

PAPER_SITE = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)


def former_fit_omega(
    tau: Any, obs: Any, weight: Any, use: Any, kernel: Any, t_max_s: float, start: Any,
    p_bounds: tuple[float, float],
) -> tuple[Any, Any, Any]:  # fmt: skip
    """``_fit_omega`` as it was before issue 29: trf with a finite-difference Jacobian."""
    from scipy.optimize import least_squares

    residuals = fit._OmegaResiduals(tau, obs, weight, use, kernel, t_max_s)
    lower = [p_bounds[0], 0.0, fit._MIN_R_OVER_P]
    upper = [p_bounds[1], 1.0, 1.0 - 1e-9]
    x0 = np.clip(start, np.add(lower, 1e-9), np.subtract(upper, 1e-9))
    result = least_squares(
        residuals.residual, x0, bounds=(lower, upper), x_scale=[float(x0[0]), 0.1, 0.1],
        method="trf", ftol=1e-6, xtol=1e-6,
    )  # fmt: skip
    return np.asarray(result.x), np.asarray(result.jac), np.asarray(result.fun)


def fit_all(features: list[RecordFeatures]) -> list[Any]:
    return [fit.fit_model(f) for f in features]


def sums_of_squares(features: list[RecordFeatures], solver: Callable[..., Any]) -> np.ndarray:
    """Residual sum of squares of each record's eq. 6.10 fit by ``solver``."""
    out = []
    captured: list[float] = []

    def spy(*args: Any) -> Any:
        theta, jac, fun = solver(*args)
        captured.append(float(fun @ fun))
        return theta, jac, fun

    with mock.patch.object(fit, "_fit_omega", spy):
        for f in features:
            fit.fit_model(f)
            out.append(captured[-1])
    return np.array(out)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    stream, _ = fema_p695()
    catalogues = {
        "100 FEMA P695 components": [
            record_features(np.asarray(tr.data, dtype=np.float64), float(tr.stats.delta))
            for tr in stream
        ],
    }
    _, acc = synthetic_motions(PAPER_SITE, duration_s=45.0, dt_s=0.01, n_realisations=100, seed=7)
    catalogues["100 synthetic paper-site records (45 s)"] = [record_features(x, 0.01) for x in acc]
    current = fit._fit_omega
    print(
        "| features | fit_model per record, former (trf, finite differences) | fit_model per "
        "record, now | former / now | RSS now / former - 1: median, max |"
    )
    print("|---|---|---|---|---|")
    for name, features in catalogues.items():
        run = functools.partial(fit_all, features)
        run()  # warm-up: imports
        with mock.patch.object(fit, "_fit_omega", former_fit_omega):
            t_former = median_seconds(run, args.repeat, time.process_time)
        t_now = median_seconds(run, args.repeat, time.process_time)
        relative = (
            sums_of_squares(features, current) / sums_of_squares(features, former_fit_omega) - 1.0
        )
        n = len(features)
        times = f"{1e3 * t_former / n:.2f} ms | {1e3 * t_now / n:.2f} ms | {t_former / t_now:.2f}"
        spread = f"{np.median(relative):+.1e}, {relative.max():+.1e}"
        print(f"| {name} | {times} | {spread} |")


if __name__ == "__main__":
    main()
