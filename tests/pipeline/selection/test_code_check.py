"""The code's suite rule on a small set, against a hand computation (ASCE 7-22, Eurocode 8)."""

from __future__ import annotations

import numpy as np
import pytest

from stepframe.pipeline.selection.code_check import check_periods_s, check_suite, period_range_s
from stepframe.pipeline.selection.set_spectra import set_spectra
from stepframe.records.spectra import response_spectrum
from stepframe.structure.code_spectra import Asce7TwoPeriod, Ec8Elastic


def test_period_ranges() -> None:
    # ASCE 7-22: [0.2 T_1, max(2 T_1, T(A_max))]; Eurocode 8: [0.2 T_1, 2 T_1]
    assert period_range_s("asce7-22", 1.0, 9.6) == (0.2, 9.6)
    assert period_range_s("asce7-22", 1.0, 1.5) == (0.2, 2.0)
    assert period_range_s("ec8", 1.0, 9.6) == (0.2, 2.0)
    grid = np.array([0.1, 0.3, 1.0, 3.0])
    assert check_periods_s(grid, (0.2, 2.0)).tolist() == [0.2, 0.3, 1.0, 2.0]


def test_asce7_22_rule_by_hand() -> None:
    # Three records' spectra at four periods [g] against S_DS = 1.0 g, S_D1 = 0.6 g
    # (T_s = 0.6 s): target 1.0, 1.0, 0.6, 0.3 g at 0.2, 0.5, 1.0, 2.0 s.
    periods = np.array([0.2, 0.5, 1.0, 2.0])
    spectra = np.array(
        [
            [1.2, 0.9, 0.50, 0.20],
            [0.9, 1.0, 0.60, 0.30],
            [0.9, 0.8, 0.46, 0.25],
        ]
    )
    target = Asce7TwoPeriod(1.0, 0.6)
    target_g = np.array([target.sa_g(t) for t in periods])
    # means by hand: 3.0/3 = 1.0, 2.7/3 = 0.9, 1.56/3 = 0.52, 0.75/3 = 0.25
    # ratios: 1.0, 0.9, 0.52/0.6 = 0.8667, 0.25/0.3 = 0.8333 → fails from 1 s to 2 s
    check = check_suite(
        "asce7-22", periods, spectra.mean(axis=0), target_g, (0.2, 2.0), measure="rotd100",
        n_units=3,
    )  # fmt: skip
    np.testing.assert_allclose(check.ratio, [1.0, 0.9, 0.52 / 0.6, 0.25 / 0.3], rtol=1e-12)
    assert not check.passes
    assert check.below == [(1.0, 2.0)]
    assert check.worst == pytest.approx((0.25 / 0.3, 2.0))
    assert check.factor_to_pass == pytest.approx(0.9 / (0.25 / 0.3))  # 1.08
    assert "FAILS below it at 1-2 s, lowest 83% at 2 s" in check.line()
    assert "scale every record by 1.08 to pass" in check.line()
    # Below at the range's last period only: that period, not a span "2-2 s".
    at_end = check_suite(
        "asce7-22", periods, np.array([1.0, 0.95, 0.6, 0.25]), target_g, (0.2, 2.0),
        measure="rotd100", n_units=3,
    )  # fmt: skip
    assert at_end.below == [(2.0, 2.0)]
    assert "FAILS below it at 2 s, lowest 83% at 2 s" in at_end.line()
    assert check.notes == ()  # maximum direction, as §16.2.3 asks
    # the set scaled by 1.08 passes, the lowest ratio now exactly 0.9
    scaled = check_suite(
        "asce7-22", periods, 1.08 * spectra.mean(axis=0), target_g, (0.2, 2.0),
        measure="rotd50", n_units=3,
    )  # fmt: skip
    assert scaled.passes and scaled.worst[0] == pytest.approx(0.9)
    assert scaled.notes == ("§16.2.3 asks for maximum-direction spectra (rotd100); rotd50 used",)


def test_ec8_rule_by_hand_with_its_pga_condition() -> None:
    # Type 1, ground B, a_gR 0.2 g: a_g S = 0.24 g, plateau 2.5·0.24 = 0.6 g (T_B 0.15 s,
    # T_C 0.5 s), 0.6·0.5/T beyond T_C
    target = Ec8Elastic("type1", "B", 0.2)
    periods = np.array([0.2, 0.5, 1.0])
    target_g = np.array([target.sa_g(t) for t in periods])
    np.testing.assert_allclose(target_g, [0.6, 0.6, 0.3], rtol=1e-12)
    spectra = np.array([[0.7, 0.5, 0.30], [0.5, 0.6, 0.28]])  # means 0.6, 0.55, 0.29
    pgas = np.array([0.25, 0.21])  # mean 0.23 < a_g S = 0.24
    check = check_suite(
        "ec8", periods, spectra.mean(axis=0), target_g, (0.2, 2.0), measure="rotd50",
        n_units=2, mean_pga_g=pgas.mean(), target_pga_g=target.pga_g,
    )  # fmt: skip
    np.testing.assert_allclose(check.ratio, [1.0, 0.55 / 0.6, 0.29 / 0.3], rtol=1e-12)
    # every spectral ratio ≥ 0.9 (0.9167 lowest), but the mean PGA is below a_g S: fails
    assert check.below == []
    assert check.pga == {"mean_g": pytest.approx(0.23), "required_g": pytest.approx(0.24),
                         "passes": False}  # fmt: skip
    assert not check.passes
    assert check.line().endswith("mean PGA 0.23 g ≥ a_g S 0.24 g: FAILS")


def test_set_spectra_of_components_and_pairs() -> None:
    # A component's spectrum is its response spectrum times its scale; a pair's geometric mean
    # is √(PSA₁·PSA₂) times the record's one scale.
    rng = np.random.default_rng(4)
    a, b = rng.standard_normal(2000), rng.standard_normal(2000)
    periods = np.array([0.1, 0.5, 1.0])
    one = response_spectrum(a, 0.01, periods, 0.05).psa_g
    two = response_spectrum(b, 0.01, periods, 0.05).psa_g
    spectra = set_spectra(
        [("x", [(a, 0.01)], 2.0), ("pair", [(a, 0.01), (b, 0.01)], 0.5)], periods, 0.05,
        "geomean",
    )  # fmt: skip
    np.testing.assert_allclose(spectra.psa_g[0], 2.0 * one, rtol=1e-12)
    np.testing.assert_allclose(spectra.psa_g[1], 0.5 * np.sqrt(one * two), rtol=1e-12)
    assert spectra.measure == "geomean"
    np.testing.assert_allclose(spectra.mean_psa_g, (2.0 * one + 0.5 * np.sqrt(one * two)) / 2)
