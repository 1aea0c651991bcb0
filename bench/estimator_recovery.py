"""Recovery of ω_g(t) and of ω_p, ω_s, ω_r by every ω_g estimator, on synthetic motions whose
ω_g falls from 60 to 0.5 rad/s.

Sets: the four of ``recovery_study.py`` (45 s, ω_g 5-63 rad/s), a broadband one (ξ 0.8-1.2, 45 s)
and two that fall to ω_r = 0.5 rad/s along eq. 6.10 (120 s: from 2 Hz, and from the top of
Example 4's band, 6.46 rad/s). Each set is simulated ``--seeds`` times (``synthetic_motions``,
dt 0.01 s, default envelope, seed 2026), then every estimator runs on the same motions
(t0 = record start, as in the truth) and the fit follows.

Printed (Markdown, pasted into docs/stochastic-features.md), per set and estimator:

- ω_p, ω_s, ω_r: bias = median of the signed relative error (fitted/true - 1) and spread =
  its interquartile range / 1.349 (a robust standard deviation); fits that failed are counted;
- ω_g(t_max): the fitted path at the true t_max against ω_s (ω_s itself also carries the error
  of t_max, which the envelope fit sets the same way for every estimator);
- ω_g(t) per frame, on the frames the fit uses (I_g ≥ 0.02 max I_g): bias and spread of
  estimate/true - 1 split at π rad/s (the 2-s window's floor), and the share of those frames
  with an estimate at all.

    python bench/estimator_recovery.py [--seeds 40] [--methods zero-crossing,multiwindow]
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from recovery_study import SETS
from stepframe.errors import InputError
from stepframe.stochastic.features import FREQUENCY_METHODS, record_features
from stepframe.stochastic.fit import fit_model
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

DT_S = 0.01
#: name → (model, record length [s]).
CASES: dict[str, tuple[GroundMotionModel, float]] = {
    **{name.split(" (")[0]: (model, 45.0) for name, model in SETS.items()},
    "broadband (6, 3, 1.2 Hz; ξ 0.8, 1.2; 5/18 s)": (
        GroundMotionModel.from_hz(6, 3, 1.2, 0.8, 1.2, t_max_s=5.0, t_dur_s=18.0),
        45.0,
    ),
    "to 0.5 rad/s (12.6, 3, 0.5 rad/s; ξ 0.3, 0.3; 15/50 s)": (
        GroundMotionModel(4 * math.pi, 3.0, 0.5, 0.3, 0.3, t_max_s=15.0, t_dur_s=50.0),
        120.0,
    ),
    "in the band (6.46, 2, 0.5 rad/s; ξ 0.2, 0.3; 15/50 s)": (
        GroundMotionModel(6.46, 2.0, 0.5, 0.2, 0.3, t_max_s=15.0, t_dur_s=50.0),
        120.0,
    ),
}
KEYS = ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s")
FIT_THRESHOLD = 0.02  # the fit's default: frames above it are the ones that matter


def _bias_spread(values: np.ndarray) -> str:
    values = values[np.isfinite(values)]
    if values.size < 3:
        return "-"
    q25, q50, q75 = np.percentile(values, [25, 50, 75])
    return f"{q50:+.1%} / {(q75 - q25) / 1.349:.1%}"


def study(model: GroundMotionModel, duration_s: float, seeds: int, method: str) -> list[str]:
    """One table row: the cells of the module docstring, and the CPU time per record."""
    _, acc = synthetic_motions(
        model, duration_s=duration_s, dt_s=DT_S, n_realisations=seeds, seed=2026
    )
    errors, at_t_max, low, high, covered = [], [], [], [], []
    failed = 0
    start = time.process_time()
    for x in acc:
        features = record_features(x, DT_S, frequency=method, t0="start")  # type: ignore[arg-type]
        truth = model.omega_g(features.time_s)
        use = features.intensity >= FIT_THRESHOLD * features.peak_intensity
        error = features.omega_g_rad_s[use] / truth[use] - 1
        covered.append(np.isfinite(error).mean())
        low.append(error[truth[use] < math.pi])
        high.append(error[truth[use] >= math.pi])
        try:
            fitted = fit_model(features).model
        except InputError:
            failed += 1
            continue
        errors.append([getattr(fitted, k) / getattr(model, k) - 1 for k in KEYS])
        at_t_max.append(float(fitted.omega_g(model.t_max_s)) / model.omega_s_rad_s - 1)
    seconds = (time.process_time() - start) / seeds
    table = np.array(errors).reshape(-1, 3)
    cells = [_bias_spread(table[:, i]) for i in range(3)]
    cells.append(_bias_spread(np.array(at_t_max)))
    cells += [_bias_spread(np.concatenate(low)), _bias_spread(np.concatenate(high))]
    cells += [f"{np.mean(covered):.0%}", str(failed), f"{1e3 * seconds:.0f}"]
    return cells


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=40)
    parser.add_argument("--methods", default=",".join(FREQUENCY_METHODS))
    args = parser.parse_args()
    methods = args.methods.split(",")
    print(f"{args.seeds} records per set, dt {DT_S} s; bias / spread (module docstring).\n")
    header = (
        "| set | estimator | ω_p | ω_s | ω_r | fitted ω_g(true t_max) | ω_g(t), ω_g < π "
        "| ω_g(t), ω_g ≥ π | frames with ω_g | fits failed | ms per record |"
    )
    print(header)
    print("|---" * (header.count("|") - 1) + "|")
    for name, (model, duration) in CASES.items():
        for method in methods:
            cells = study(model, duration, args.seeds, method)
            print(f"| {name.split(' (')[0]} | {method} | " + " | ".join(cells) + " |", flush=True)
    print("\nSets:\n")
    for name, (_, duration) in CASES.items():
        print(f"- {name}, {duration:.0f} s")


if __name__ == "__main__":
    main()
