"""Standard errors that cover: the truth within 2 SE in ≥ 90 % of 30 synthetic eq. 6.12 records.

The full table (three parameter sets, 40 seeds, before and after calibration) is in
docs/stochastic-features.md, from bench/se_coverage.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from stepframe.stochastic.features import record_features
from stepframe.stochastic.fit import PARAMETERS, fit_model
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions

SOFT = GroundMotionModel.from_hz(5, 2.5, 0.8, 0.3, 0.3, t_max_s=4.0, t_dur_s=15.0)


@pytest.mark.parametrize("seed", [5000, 6000])
def test_truth_within_two_standard_errors_90_percent(seed: int) -> None:
    _, acc = synthetic_motions(SOFT, duration_s=45.0, dt_s=0.01, n_realisations=30, seed=seed)
    truth = SOFT.to_dict()
    keys = (*PARAMETERS, "t_max_s")
    inside = dict.fromkeys(keys, 0)
    for x in acc:
        result = fit_model(record_features(x, 0.01, t0="start"))
        fitted = result.to_dict()
        for key in keys:
            inside[key] += abs(fitted[key] - truth[key]) <= 2 * result.stderr[key]
    coverage = {key: count / len(acc) for key, count in inside.items()}
    assert min(coverage.values()) >= 0.9, coverage
    assert np.isfinite(list(coverage.values())).all()
