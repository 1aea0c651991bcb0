"""Coverage of fit standard errors on synthetic eq. 6.12 records (see docs/stochastic-features.md).

For each parameter set, ``--seeds`` realisations (45 s, dt 0.01 s, origin = record start, the
truth's t0) are fitted; for every parameter it prints the share of fits whose truth lies within
2 standard errors, and the median of |error|/SE (1.0 would be a calibrated Gaussian's 0.67);
then the 90th percentile of |error|/(2 SE), the factor the standard error would need for 90 %
coverage. ``--frequency`` picks the ω_g(t) estimator (default: the library's).

    python bench/se_coverage.py [--seeds 40] [--seed0 1000] [--frequency multiwindow]
"""

from __future__ import annotations

import argparse

import numpy as np

from stepframe.stochastic.features import FREQUENCY_METHODS, record_features
from stepframe.stochastic.fit import PARAMETERS, fit_model
from stepframe.stochastic.methods import DEFAULT_FREQUENCY_METHOD
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

SETS = {
    "paper-site": GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, 5.0, 20.0),
    "stiff": GroundMotionModel.from_hz(10, 4, 1.5, 0.2, 0.4, t_max_s=8.0, t_dur_s=25.0),
    "soft": GroundMotionModel.from_hz(5, 2.5, 0.8, 0.3, 0.3, t_max_s=4.0, t_dur_s=15.0),
}
KEYS = (*PARAMETERS, "t_max_s")


def coverage(
    model: GroundMotionModel, seeds: int, seed0: int, frequency: str = DEFAULT_FREQUENCY_METHOD
) -> dict[str, tuple[float, float, float]]:
    """Per parameter: (share within 2 SE, median |error|/SE, 90th percentile of |error|/(2 SE))."""
    _, acc = synthetic_motions(model, duration_s=45.0, dt_s=0.01, n_realisations=seeds, seed=seed0)
    truth = {**model.to_dict()}
    z: dict[str, list[float]] = {k: [] for k in KEYS}
    for x in acc:
        features = record_features(x, 0.01, t0="start", frequency=frequency)  # type: ignore[arg-type]
        result = fit_model(features)
        fitted = result.to_dict()
        for key in KEYS:
            se = result.stderr.get(key, np.nan)
            z[key].append(abs(fitted[key] - truth[key]) / se if se > 0 else np.inf)
    return {
        k: (
            float(np.mean(np.asarray(v) <= 2.0)),
            float(np.median(v)),
            float(np.percentile(v, 90)) / 2,
        )
        for k, v in z.items()
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=40)
    parser.add_argument("--seed0", type=int, default=1000)
    parser.add_argument("--frequency", default=DEFAULT_FREQUENCY_METHOD, choices=FREQUENCY_METHODS)
    args = parser.parse_args()
    print("| set | " + " | ".join(KEYS) + " |")
    print("|---|" + "---|" * len(KEYS))
    factors = {}
    for name, model in SETS.items():
        result = coverage(model, args.seeds, args.seed0, args.frequency)
        cells = [f"{100 * share:.0f} % ({med:.2f})" for share, med, _ in result.values()]
        print(f"| {name} | " + " | ".join(cells) + " |")
        factors[name] = [p90 for _, _, p90 in result.values()]
    print("\n90th percentile of |error|/(2 SE):\n")
    print("| set | " + " | ".join(KEYS) + " |")
    print("|---|" + "---|" * len(KEYS))
    for name, row in factors.items():
        print(f"| {name} | " + " | ".join(f"{v:.2f}" for v in row) + " |")


if __name__ == "__main__":
    main()
