"""Recovery study: B-P parameters fitted to synthetic motions with known parameters.

For each parameter set, ``--seeds`` realisations of :func:`synthetic_motions` (45 s, dt 0.01 s,
default envelope) go through the default estimator (STFT + zero crossings + least squares,
t0 = record start); prints Markdown tables of the relative errors (fitted/true - 1): median of
the absolute error and the whole distribution of the signed error (min, 10/25/50/75/90 %
quantiles, max, and the share within ±15 % and ±30 %), plus t_max and t_dur, and
the same for deterministic chirps. Output pasted into docs/stochastic-features.md.

    python bench/recovery_study.py [--seeds 100]
"""

from __future__ import annotations

import argparse

import numpy as np
from scipy.integrate import cumulative_trapezoid

from stepframe.stochastic.envelope import default_envelope
from stepframe.stochastic.features import record_features
from stepframe.stochastic.fit import fit_model
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

SETS = {
    "paper site (7.43, 3.12, 1.11 Hz; ξ 0.096, 0.655; 5/20 s)": GroundMotionModel.from_hz(
        7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0
    ),
    "stiff (10, 4, 1.5 Hz; ξ 0.2, 0.4; 8/25 s)": GroundMotionModel.from_hz(
        10, 4, 1.5, 0.2, 0.4, t_max_s=8.0, t_dur_s=25.0
    ),
    "soft (5, 2.5, 0.8 Hz; ξ 0.3, 0.3; 4/15 s)": GroundMotionModel.from_hz(
        5, 2.5, 0.8, 0.3, 0.3, t_max_s=4.0, t_dur_s=15.0
    ),
    "narrow (6, 4, 2 Hz; ξ 0.05, 0.1; 6/18 s)": GroundMotionModel.from_hz(
        6, 4, 2, 0.05, 0.1, t_max_s=6.0, t_dur_s=18.0
    ),
}
NAMES = ("ω_p", "ω_s", "ω_r", "ξ_p", "ξ_r", "t_max", "t_dur")


def _errors(fitted: GroundMotionModel, true: GroundMotionModel) -> list[float]:
    keys = ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r", "t_max_s", "t_dur_s")
    return [getattr(fitted, k) / getattr(true, k) - 1 for k in keys]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=100)
    args = parser.parse_args()
    print(f"Random motions: {args.seeds} seeds per set, 45 s at dt = 0.01 s.\n")
    for name, true in SETS.items():
        _, acc = synthetic_motions(
            true, duration_s=45.0, dt_s=0.01, n_realisations=args.seeds, seed=12345
        )
        errors = np.array([_errors(fit_model(record_features(x, 0.01)).model, true) for x in acc])
        print(f"**{name}**\n")
        print("| | " + " | ".join(NAMES) + " |")
        print("|---" * (len(NAMES) + 1) + "|")
        print("| median abs | " + " | ".join(f"{v:.1%}" for v in np.median(abs(errors), 0)) + " |")
        for q in (0, 10, 25, 50, 75, 90, 100):
            row = np.percentile(errors, q, axis=0)
            label = {0: "min", 100: "max"}.get(q, f"{q} %")
            print(f"| {label} signed | " + " | ".join(f"{v:+.1%}" for v in row) + " |")
        for bound in (0.15, 0.30):
            share = np.mean(abs(errors) <= bound, axis=0)
            print(f"| within ±{bound:.0%} | " + " | ".join(f"{v:.0%}" for v in share) + " |")
        print()
    print(
        "Deterministic chirps (instantaneous frequency eq. 6.10, default envelope, dt 0.005 s):\n"
    )
    print("| set | estimator | ω_p | ω_s | ω_r | t_max |")
    print("|---|---|---|---|---|---|")
    t = np.arange(0, 45, 0.005)
    for name, true in SETS.items():
        phase = cumulative_trapezoid(true.omega_g(t), t, initial=0)
        x = default_envelope(t, true.t_max_s, true.t_dur_s) * np.cos(phase)
        for method in ("zero-crossing", "ridge", "moment", "wavelet-ridge"):
            features = record_features(x, 0.005, frequency=method)  # type: ignore[arg-type]
            e = _errors(fit_model(features).model, true)
            short = name.split(" (")[0]
            cells = " | ".join(f"{v:+.2%}" for v in (e[0], e[1], e[2], e[5]))
            print(f"| {short} | {method} | {cells} |")


if __name__ == "__main__":
    main()
