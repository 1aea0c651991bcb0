"""The built-in code spectra against values worked by hand from the standards' equations.

ASCE/SEI 7-22 §11.4.5.2 (two-period design response spectrum) and EN 1998-1:2004 §3.2.2.2
(eqs. 3.2-3.6, Tables 3.2 and 3.3); each expected value below is the equation evaluated by hand
at the stated inputs.
"""

from __future__ import annotations

import math

import pytest

from stepframe.errors import InputError
from stepframe.structure.code_spectra import Asce7TwoPeriod, Ec8Elastic
from stepframe.structure.design_spectrum import TwoPeriodSpectrum


@pytest.mark.parametrize(
    ("period_s", "expected_g"),
    [
        (0.0, 0.4),  # S_DS·0.4 at T = 0
        (0.06, 0.7),  # half-way up the ramp: T_0 = 0.2·0.6/1.0 = 0.12 s
        (0.12, 1.0),  # T_0
        (0.3, 1.0),  # plateau
        (0.6, 1.0),  # T_s = 0.6 s
        (1.2, 0.5),  # S_D1/T
        (8.0, 0.075),  # T_L
        (10.0, 0.048),  # S_D1·T_L/T² = 0.6·8/100
    ],
)
def test_asce7_22_two_period(period_s: float, expected_g: float) -> None:
    spectrum = Asce7TwoPeriod(1.0, 0.6, t_l_s=8.0, g_m_s2=9.80665)
    assert spectrum.sa_g(period_s) == pytest.approx(expected_g, rel=1e-12)
    assert spectrum.sa_m_s2(period_s) == pytest.approx(expected_g * 9.80665, rel=1e-12)


def test_asce7_22_equals_the_papers_shape_above_t0() -> None:
    asce = Asce7TwoPeriod(0.8, 0.5, t_l_s=6.0, g_m_s2=9.80665)
    paper = TwoPeriodSpectrum.from_g(0.8, 0.5, g_m_s2=9.80665, t_l_s=6.0)
    for period in (0.125, 0.3, 0.625, 1.0, 4.0, 6.0, 9.0):
        assert asce.sa_m_s2(period) == pytest.approx(paper.sa_m_s2(period), rel=1e-12)
    assert asce.sa_g(0.0) == pytest.approx(0.4 * 0.8)  # the ramp the paper's shape lacks


@pytest.mark.parametrize(
    ("period_s", "expected_g"),
    [
        (0.0, 0.2875),  # a_g·S = 0.25·1.15
        (0.1, 0.503125),  # 0.2875·[1 + (0.1/0.2)(2.5 - 1)]
        (0.2, 0.71875),  # T_B: 2.5·0.2875
        (0.4, 0.71875),
        (0.6, 0.71875),  # T_C
        (1.0, 0.43125),  # 0.71875·0.6/1.0
        (2.0, 0.215625),  # T_D
        (3.0, 0.71875 * 0.6 * 2.0 / 9.0),
    ],
)
def test_ec8_type1_ground_c(period_s: float, expected_g: float) -> None:
    spectrum = Ec8Elastic("type1", "C", 0.25)
    assert spectrum.sa_g(period_s) == pytest.approx(expected_g, rel=1e-12)


def test_ec8_type2_ground_d_with_importance_and_damping() -> None:
    # a_g = 1.2·0.1 = 0.12 g; S 1.8, T_B 0.1, T_C 0.3, T_D 1.2 s; η = √(10/15) at 10 %
    spectrum = Ec8Elastic("type2", "D", 0.1, importance=1.2, damping=0.10)
    eta = math.sqrt(10.0 / 15.0)
    assert spectrum.eta == pytest.approx(0.816496580927726, rel=1e-12)
    assert spectrum.sa_g(0.05) == pytest.approx(0.216 * (1 + 0.5 * (2.5 * eta - 1)), rel=1e-12)
    assert spectrum.sa_g(0.2) == pytest.approx(2.5 * 0.216 * eta, rel=1e-12)
    assert spectrum.sa_g(0.6) == pytest.approx(2.5 * 0.216 * eta * 0.3 / 0.6, rel=1e-12)
    assert spectrum.sa_g(2.4) == pytest.approx(2.5 * 0.216 * eta * 0.3 * 1.2 / 2.4**2, rel=1e-12)
    assert spectrum.pga_g == pytest.approx(0.216)


def test_ec8_corner_tables() -> None:
    # Tables 3.2 and 3.3 as printed: (S, T_B, T_C, T_D)
    assert Ec8Elastic("type1", "A", 0.3).parameters == (1.0, 0.15, 0.4, 2.0)
    assert Ec8Elastic("type1", "E", 0.3).parameters == (1.4, 0.15, 0.5, 2.0)
    assert Ec8Elastic("type2", "B", 0.3).parameters == (1.35, 0.05, 0.25, 1.2)
    assert Ec8Elastic("type2", "C", 0.3).parameters == (1.5, 0.10, 0.25, 1.2)
    # η's floor 0.55 (eq. 3.6): at 30 % damping √(10/35) = 0.53 is raised to 0.55
    assert Ec8Elastic("type1", "A", 0.3, damping=0.30).eta == 0.55


def test_bad_code_spectra_inputs() -> None:
    with pytest.raises(InputError, match="expected > T_s"):
        Asce7TwoPeriod(1.0, 0.6, t_l_s=0.5)
    with pytest.raises(InputError, match="ground type 'F'"):
        Ec8Elastic("type1", "F", 0.2)  # type: ignore[arg-type]
