"""Scores: closed forms against the library, and records whose truth is known."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from stepframe.pipeline.selection import scores
from stepframe.pipeline.selection.band import FrameBand, frame_band
from stepframe.pipeline.selection.path import Paths, model_of_row, strong_motion_paths
from stepframe.stochastic.amplification import approx_eq_6_19_last, spectral_ratio_eq_6_18
from stepframe.structure.frame import PortalFrame

COMMON = {"xi_p": 0.3, "xi_r": 0.3, "t_max_s": 8.0, "t_dur_s": 25.0, "t0_s": 0.0}
#: ω_g sweeping through Example 4's band [0.654, 6.458] rad/s during strong motion, staying
#: above it, and staying below it (rad/s).
SWEEP = {"omega_p_rad_s": 40.0, "omega_s_rad_s": 8.0, "omega_r_rad_s": 0.7}
ABOVE = {"omega_p_rad_s": 60.0, "omega_s_rad_s": 30.0, "omega_r_rad_s": 20.0}
BELOW = {"omega_p_rad_s": 0.6, "omega_s_rad_s": 0.5, "omega_r_rad_s": 0.4}


def _paths(start: list[float], end: list[float]) -> Paths:
    nan = np.full(len(start), np.nan)
    return Paths(nan, nan, np.array(start), np.array(end))


def test_band_coverage_is_the_log_share_of_the_band(example4: PortalFrame) -> None:
    band = frame_band(example4)
    lo, hi = band.omega_low_rad_s, band.omega_1_rad_s
    middle = math.sqrt(lo * hi)  # the log midpoint
    got = scores.band_coverage(
        _paths([2 * hi, 2 * hi, hi, 2 * hi], [lo / 2, 1.5 * hi, middle, middle]), band
    )
    assert got == pytest.approx([1.0, 0.0, 0.5, 0.5])
    enters = scores.enters_from_above(
        _paths([2 * hi, hi, 2 * hi], [middle, middle, 1.5 * hi]), band
    )
    assert enters.tolist() == [True, False, False]


def test_spectral_ratios_match_the_library_row_by_row() -> None:
    table = pd.DataFrame([{**SWEEP, **COMMON}, {**ABOVE, **COMMON, "t_max_s": 3.0}])
    omega_0 = 6.4581
    got = scores.spectral_ratio_eq_6_18(table, omega_0)
    squares = scores.omega_p_over_s_sq(table)
    for i, row in table.iterrows():
        model = model_of_row(row)
        assert got[i] == pytest.approx(float(spectral_ratio_eq_6_18(model, omega_0)), rel=1e-12)
        assert squares[i] == pytest.approx(approx_eq_6_19_last(model), rel=1e-12)


def test_equivalent_damping_keeps_c_r_to_the_fourth_per_cycle() -> None:
    xi = scores.equivalent_damping(0.0, 0.9)
    assert math.exp(-4 * math.pi * xi) == pytest.approx(0.9**4)
    assert scores.equivalent_damping(0.02, 1.0) == 0.02
    assert scores.equivalent_damping(0.0, 1.0) == 0.005


def _scores_of(rows: list[dict[str, float]], band: FrameBand, frame: PortalFrame) -> pd.DataFrame:
    table = pd.DataFrame(rows)
    paths = strong_motion_paths(table, 0.3)
    table["band_coverage"] = scores.band_coverage(paths, band)
    table["enters_from_above"] = scores.enters_from_above(paths, band)
    physics = [
        scores.physics_scores(
            table.iloc[i],
            band,
            frame.xi_1,
            scores.equivalent_damping(frame.xi_2, frame.c_r),
            (paths.start_s[i], paths.end_s[i]),
        )
        for i in range(len(table))
    ]
    table["backbone_amplification"] = [p[0] for p in physics]
    table["descent_amplification"] = [p[1] for p in physics]
    return table


def test_sweeping_records_rank_first_by_the_sweep_scores(example4: PortalFrame) -> None:
    """Known truth: two sweeping paths, two above, two below (all at unit intensity)."""
    band = frame_band(example4)
    rows = [
        {**SWEEP, **COMMON},
        {**SWEEP, **COMMON, "omega_p_rad_s": 30.0, "omega_r_rad_s": 0.9, "t_max_s": 6.0},
        {**ABOVE, **COMMON},
        {**ABOVE, **COMMON, "omega_p_rad_s": 90.0, "omega_r_rad_s": 12.0},
        {**BELOW, **COMMON},
        {**BELOW, **COMMON, "omega_p_rad_s": 0.55, "omega_r_rad_s": 0.2},
    ]
    table = _scores_of(rows, band, example4)
    sweeping = [0, 1]
    for name in ("band_coverage", "descent_amplification"):
        ranked = table[name].sort_values(ascending=False).index.tolist()
        assert sorted(ranked[:2]) == sweeping, (name, table[name].tolist())
    assert table["enters_from_above"].tolist() == [True, True, False, False, False, False]
    # The backbone amplification measures long-period content along the backbone, not the
    # sweep: records below the band have more of it, records above less (docs/selection.md).
    backbone = table["backbone_amplification"]
    assert backbone[sweeping].min() > backbone[[2, 3]].max()
    assert backbone[[4, 5]].min() > backbone[sweeping].max()


def test_physics_scores_are_finite_at_extremes(example4: PortalFrame) -> None:
    band = frame_band(example4)
    extremes = [
        {**SWEEP, **COMMON, "xi_p": 0.999, "xi_r": 0.001},
        {**ABOVE, **COMMON, "t_max_s": 0.01, "t_dur_s": 200.0},
        {"omega_p_rad_s": 300.0, "omega_s_rad_s": 0.05, "omega_r_rad_s": 0.01, **COMMON},
    ]
    table = _scores_of(extremes, band, example4)
    assert np.all(np.isfinite(table[["backbone_amplification", "descent_amplification"]]))
    assert np.all(table["backbone_amplification"] > 0)
