"""Filters, choice of the set, spectral scaling and the confirmation's statistics."""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stepframe.errors import InputError
from stepframe.pipeline.selection import SelectionOptions
from stepframe.pipeline.selection.band import frame_band
from stepframe.pipeline.selection.choose import Units, choose, objective, percentile_scores
from stepframe.pipeline.selection.confirm import spearman_interval
from stepframe.pipeline.selection.filters import apply_filters
from stepframe.pipeline.selection.intensity import equal_intensity_scales
from stepframe.pipeline.selection.path import strong_motion_paths
from stepframe.pipeline.selection.spectral import read_target_csv, scale_factors, spectral_misfit
from stepframe.structure.frame import PortalFrame

BASE = {
    "omega_p_rad_s": 40.0,
    "omega_s_rad_s": 15.0,
    "omega_r_rad_s": 8.0,
    "xi_p": 0.3,
    "xi_r": 0.3,
    "t_max_s": 5.0,
    "t_dur_s": 20.0,
    "t0_s": 0.0,
    "plausible": True,
}


def _table() -> pd.DataFrame:
    rows = []
    for k, (m, r, pga) in enumerate(
        [(6.0, 10, 0.2), (7.0, 30, 0.5), (7.5, 80, 0.1), (6.9, 20, 0.3), (7.2, 15, 0.4)]
    ):
        rows.append(
            {
                **BASE,
                "file": f"dir/RSN{k}_a.AT2",
                "component": "H1",
                "rsn": k,
                "magnitude": m,
                "rrup_km": r,
                "pga_g": pga,
            }
        )
    table = pd.DataFrame(rows)
    table.loc[4, "plausible"] = False
    return table


def test_filters_report_what_each_dropped(example4: PortalFrame) -> None:
    table = _table()
    band = frame_band(example4)
    options = SelectionOptions(
        n=1, magnitude_min=6.5, distance_max_km=50.0, pga_min_g=0.25, exclude=("3",),
        require_plausible=True,
    )  # fmt: skip
    dropped, reports = apply_filters(table, options, band, strong_motion_paths(table, 0.3))
    assert dropped.tolist() == ["magnitude", "", "distance", "exclude", "fit_quality"]
    assert [(r.name, r.dropped, r.left) for r in reports] == [
        ("path", 0, 5),
        ("vertical", 0, 5),
        ("fit_quality", 1, 4),
        ("exclude", 1, 3),
        ("magnitude", 1, 2),
        ("distance", 1, 1),
        ("pga", 0, 1),
    ]


def test_filter_without_its_column_is_an_error(example4: PortalFrame) -> None:
    table = _table().drop(columns="magnitude")
    options = SelectionOptions(n=1, magnitude_min=6.5)
    with pytest.raises(InputError, match="needs column 'magnitude'"):
        apply_filters(table, options, frame_band(example4), strong_motion_paths(table, 0.3))


def test_exclude_by_file_name() -> None:
    table = _table()
    options = SelectionOptions(
        n=1, exclude=("RSN1_a.AT2", "dir/RSN2_a.AT2"), require_plausible=False
    )
    band = frame_band(PortalFrame(6.4581, 0.6445, 1.1884, 1.268, 0.1387, 0.05, 0.0, 0.19, 0.95))
    dropped, _ = apply_filters(table, options, band, strong_motion_paths(table, 0.3))
    assert dropped.tolist() == ["", "exclude", "exclude", "", ""]


def _units(z: list[float], events: list[str], log_psa: np.ndarray | None = None) -> Units:
    return Units(
        np.array(z),
        [[i] for i in range(len(z))],
        np.array(events, dtype=object),
        np.array([f"s{i}" for i in range(len(z))], dtype=object),
        log_psa,
    )


def test_greedy_takes_the_best_under_the_event_cap() -> None:
    units = _units([0.9, 0.8, 0.7, 0.6, 0.5], ["A", "A", "A", "B", "C"])
    assert choose(units, 3) == [0, 1, 2]
    assert choose(units, 3, max_per_event=2) == [0, 1, 3]
    assert choose(units, 5, max_per_event=1) == [0, 3, 4]


def test_swaps_reach_the_best_set_with_a_spectral_objective() -> None:
    rng = np.random.default_rng(3)
    n_units, n_periods = 9, 4
    log_psa = rng.normal(size=(n_units, n_periods))
    target = rng.normal(size=n_periods)
    units = _units(list(rng.uniform(size=n_units)), [f"e{i}" for i in range(n_units)], log_psa)
    chosen = choose(units, 3, weight=2.0, log_target=target)
    best = max(
        itertools.combinations(range(n_units), 3),
        key=lambda s: objective(list(s), units, 2.0, target),
    )
    got = objective(chosen, units, 2.0, target)
    assert got >= objective(list(best), units, 2.0, target) - 0.05
    assert choose(units, 3, weight=2.0, log_target=target) == chosen  # deterministic


def test_percentiles() -> None:
    got = percentile_scores(np.array([3.0, np.nan, 1.0, 2.0, 2.0]))
    assert got[[0, 2]].tolist() == [1.0, 0.0]
    assert got[3] == got[4] == pytest.approx(0.5)
    assert np.isnan(got[1])


def test_scale_factors_and_misfit() -> None:
    psa_t1 = np.array([1.0, 2.0, 4.0])
    scales, clipped = scale_factors("psa-at-t1", psa_t1, None, 3.0, None, (0.25, 2.0))
    assert scales.tolist() == [2.0, 1.5, 0.75]
    assert clipped.tolist() == [True, False, False]
    median, _ = scale_factors("psa-at-t1", psa_t1, None, None, None, (0.1, 10.0))
    assert median.tolist() == [2.0, 1.0, 0.5]
    psa = np.array([[1.0, 2.0, 4.0], [2.0, 2.0, 2.0]])
    target = np.array([2.0, 2.0, 2.0])
    best, _ = scale_factors("target-mse", psa[:, 0], psa, 2.0, target, (0.1, 10.0))
    residual = np.log(best[:, None] * psa / target)
    assert np.allclose(residual.mean(axis=1), 0.0)  # least squares in ln PSA
    misfit = spectral_misfit(psa, best, target)
    assert misfit[1] == pytest.approx(0.0)
    assert misfit[0] == pytest.approx(math.log(2) * math.sqrt(2 / 3))


def test_target_csv(tmp_path: Path) -> None:
    good = tmp_path / "t.csv"
    good.write_text("period_s,sa_g\n0.1,1.0\n1.0,0.5\n")
    spectrum = read_target_csv(good)
    assert spectrum.sa_m_s2(0.55) == pytest.approx(0.75 * 9.80665)
    bad = tmp_path / "bad.csv"
    bad.write_text("period_s,sa_g\n0.1,1.0\n1.0,half\n")
    with pytest.raises(InputError) as error:
        read_target_csv(bad)
    assert error.value.line == 3 and "expected two numbers" in error.value.one_line()
    # a point the table refuses: on its line, in the file's units (g, not m/s²)
    for rows, line, message in (
        ("0.1,1.0\n0.5,1.2\n0.4,0.8\n", 4, "period_s = 0.4, sa_g = 0.8, expected strictly "
         "increasing periods (after 0.5 s)"),
        ("0.1,1.0\n0.5,-1.0\n", 3, "period_s = 0.5, sa_g = -1.0, expected a spectral "
         "acceleration > 0"),
        ("-0.1,1.0\n0.5,1.0\n", 2, "period_s = -0.1, sa_g = 1.0, expected a finite period ≥ 0"),
        ("0.1,nan\n0.5,1.0\n", 2, "period_s = 0.1, sa_g = nan, expected a spectral accel"),
    ):  # fmt: skip
        bad.write_text("period_s,sa_g\n" + rows)
        with pytest.raises(InputError) as error:
            read_target_csv(bad)
        assert error.value.line == line and error.value.what.startswith(message), error.value
    headless = tmp_path / "headless.csv"
    headless.write_text("a,b\n0.1,1.0\n")
    with pytest.raises(InputError, match="expected that header"):
        read_target_csv(headless)
    with pytest.raises(InputError, match="cannot read the target spectrum"):
        read_target_csv(tmp_path / "missing.csv")


def test_spearman_matches_scipy() -> None:
    from scipy.stats import spearmanr

    rng = np.random.default_rng(1)
    x = rng.normal(size=40)
    y = x + rng.normal(size=40)
    y[3] = np.inf  # an overturned run ranks last, not dropped
    rho, low, high, n = spearman_interval(x, y, seed=0)
    assert rho == pytest.approx(spearmanr(x, y)[0], rel=1e-12)
    assert low < rho < high and n == 40
    x[5] = np.nan
    assert spearman_interval(x, y, seed=0)[3] == 39


def test_bootstrap_in_blocks_gives_the_intervals_of_one_draw(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """The resamples are drawn and ranked in blocks (memory at catalogue size); the intervals
    equal those of every resample drawn at once, recomputed here from one draw."""
    from scipy.stats import spearmanr

    from stepframe.pipeline.selection import confirm

    rng = np.random.default_rng(11)
    x, r = rng.normal(size=57), rng.normal(size=57)
    y = x + 0.5 * r + rng.normal(size=57)
    picks = np.random.default_rng(3).integers(0, 57, size=(200, 57))
    direct = np.array([spearmanr(x[p], y[p])[0] for p in picks])
    paired = direct - np.array([spearmanr(r[p], y[p])[0] for p in picks])
    monkeypatch.setattr(confirm, "BLOCK_INDICES", 5 * 57 + 3)  # blocks of 5 resamples
    _, low, high, _ = confirm.spearman_interval(x, y, seed=3, n_resamples=200)
    assert [low, high] == pytest.approx(np.percentile(direct, [2.5, 97.5]), rel=1e-12)
    _, low, high, _ = confirm.paired_delta_rho(x, r, y, seed=3, n_resamples=200)
    assert [low, high] == pytest.approx(np.percentile(paired, [2.5, 97.5]), rel=1e-12)


def test_equal_intensity_puts_the_linear_peak_at_the_ratio(example4: PortalFrame) -> None:
    """Below the onset of stepping the frame is linear: its peak is P_1·SD(T_1, ξ_1), so the
    scale for onset ratio 0.8 gives a simulated peak of 0.8·x_c."""
    from stepframe.records.spectra import response_spectrum
    from stepframe.structure.simulator import simulate

    rng = np.random.default_rng(5)
    t = np.arange(0, 20, 0.01)
    acc = rng.normal(size=t.size) * np.exp(-(((t - 6) / 3) ** 2))
    sd = response_spectrum(acc, 0.01, [2 * math.pi / example4.omega_1_rad_s], example4.xi_1).sd_m
    scale = equal_intensity_scales(np.asarray(sd), example4, 0.8)[0]
    result = simulate(example4, acc, 0.01, scale=scale, tail_s=0.0)
    assert result.summary.n_stepping_episodes == 0
    assert result.summary.peak_abs_x_m == pytest.approx(0.8 * example4.x_c_m, rel=2e-3)
