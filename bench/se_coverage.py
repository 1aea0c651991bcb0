"""Coverage of fit standard errors on synthetic eq. 6.12 records (see docs/stochastic-features.md).

For each parameter set, ``--seeds`` realisations (45 s, dt 0.01 s, origin = record start, the
truth's t0) are fitted; for every parameter it prints the share of fits whose truth lies within
2 standard errors, and the median of |error|/SE (1.0 would be a calibrated Gaussian's 0.67).

    python bench/se_coverage.py [--seeds 40] [--seed0 1000]
"""

from __future__ import annotations

import argparse

import numpy as np

from stepframe.stochastic.features import record_features
from stepframe.stochastic.fit import PARAMETERS, fit_model
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

SETS = {
    "paper-site": GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, 5.0, 20.0),
    "stiff": GroundMotionModel.from_hz(10, 4, 1.5, 0.2, 0.4, t_max_s=8.0, t_dur_s=25.0),
    "soft": GroundMotionModel.from_hz(5, 2.5, 0.8, 0.3, 0.3, t_max_s=4.0, t_dur_s=15.0),
}
KEYS = (*PARAMETERS, "t_max_s")


def coverage(model: GroundMotionModel, seeds: int, seed0: int) -> dict[str, tuple[float, float]]:
    """Per parameter: (share within 2 SE, median |error|/SE)."""
    _, acc = synthetic_motions(model, duration_s=45.0, dt_s=0.01, n_realisations=seeds, seed=seed0)
    truth = {**model.to_dict()}
    z: dict[str, list[float]] = {k: [] for k in KEYS}
    for x in acc:
        result = fit_model(record_features(x, 0.01, t0="start"))
        fitted = result.to_dict()
        for key in KEYS:
            se = result.stderr.get(key, np.nan)
            z[key].append(abs(fitted[key] - truth[key]) / se if se > 0 else np.inf)
    return {k: (float(np.mean(np.asarray(v) <= 2.0)), float(np.median(v))) for k, v in z.items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=40)
    parser.add_argument("--seed0", type=int, default=1000)
    args = parser.parse_args()
    print("| set | " + " | ".join(KEYS) + " |")
    print("|---|" + "---|" * len(KEYS))
    for name, model in SETS.items():
        result = coverage(model, args.seeds, args.seed0)
        cells = [f"{100 * share:.0f} % ({med:.2f})" for share, med in result.values()]
        print(f"| {name} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()
