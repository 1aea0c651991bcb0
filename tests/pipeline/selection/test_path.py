"""Strong-motion windows (Lambert W closed form) and ω_g in them, against the model itself."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from stepframe.pipeline.selection.path import model_of_row, strong_motion_paths
from stepframe.stochastic.envelope import default_envelope

ROWS = pd.DataFrame(
    {
        "omega_p_rad_s": [48.5, 90.0, 20.0],
        "omega_s_rad_s": [15.9, 30.0, 19.0],
        "omega_r_rad_s": [13.6, 5.0, 2.0],
        "xi_p": [0.19, 0.3, 0.5],
        "xi_r": [0.57, 0.2, 0.5],
        "t_max_s": [7.0, 3.0, 12.0],
        "t_dur_s": [23.0, 30.0, 13.0],
        "t0_s": [0.0, 1.5, 0.0],
    }
)


@pytest.mark.parametrize("fraction", [0.2, 0.3, 0.7])
def test_window_ends_where_the_envelope_is_the_fraction(fraction: float) -> None:
    paths = strong_motion_paths(ROWS, fraction)
    for i, row in ROWS.iterrows():
        ends = np.array([paths.start_s[i], paths.end_s[i]])
        assert ends[0] < row.t_max_s < ends[1]
        envelope = default_envelope(ends, row.t_max_s, row.t_dur_s)
        assert np.allclose(envelope, fraction, rtol=1e-10)
        model = model_of_row(row)
        omega = model.omega_g(ends + row.t0_s)
        assert paths.omega_start_rad_s[i] == pytest.approx(omega[0], rel=1e-12)
        assert paths.omega_end_rad_s[i] == pytest.approx(omega[1], rel=1e-12)
    assert np.all(paths.end_s <= ROWS["t_dur_s"].to_numpy() + 1e-9)


def test_no_envelope_when_t_max_reaches_t_dur() -> None:
    rows = ROWS.copy()
    rows.loc[0, "t_max_s"] = rows.loc[0, "t_dur_s"]
    paths = strong_motion_paths(rows, 0.3)
    assert np.isnan(paths.start_s[0]) and np.isnan(paths.omega_end_rad_s[0])
    assert np.isfinite(paths.start_s[1])
