"""Two-period and tabulated design spectra."""

from __future__ import annotations

import math

import pytest

from stepframe.errors import InputError
from stepframe.structure.design_spectrum import (
    TabulatedSpectrum,
    TwoPeriodSpectrum,
    spectrum_from_dict,
)


def test_two_period_corner_and_branches() -> None:
    # Paper Example 2: S_DS = 1.038 g, S_D1 = 0.456 g, T_s = 0.439 s (printed).
    spectrum = TwoPeriodSpectrum.from_g(1.038, 0.456, g_m_s2=9.81)
    assert spectrum.s_ds_m_s2 == pytest.approx(10.18278)
    assert spectrum.t_s_s == pytest.approx(0.456 / 1.038)
    assert round(spectrum.t_s_s, 3) == 0.439
    assert spectrum.sa_m_s2(0.1) == spectrum.s_ds_m_s2
    assert spectrum.sa_m_s2(2.0) == pytest.approx(0.456 * 9.81 / 2.0)
    assert spectrum.branch(spectrum.t_s_s) == "short"
    assert spectrum.branch(spectrum.t_s_s * (1 + 1e-12)) == "long"
    # Continuous at T_s: S_D1/T_s = S_DS.
    assert spectrum.sa_m_s2(spectrum.t_s_s * (1 + 1e-12)) == pytest.approx(spectrum.s_ds_m_s2)


def test_long_period_transition_is_constant_displacement() -> None:
    spectrum = TwoPeriodSpectrum(8.0, 4.0, t_l_s=6.0)
    assert spectrum.branch(7.0) == "very-long"
    # Continuous at T_L, and S_d = S_a T²/4π² is constant beyond it.
    assert spectrum.sa_m_s2(6.0) == pytest.approx(4.0 / 6.0)
    assert spectrum.sa_m_s2(6.0 + 1e-9) == pytest.approx(4.0 / 6.0)
    s_d = [spectrum.sa_m_s2(t) * t**2 / (4 * math.pi**2) for t in (6.5, 9.0, 20.0)]
    assert s_d == pytest.approx([4.0 * 6.0 / (4 * math.pi**2)] * 3)


def test_tabulated_interpolation_and_ends() -> None:
    table = TabulatedSpectrum((0.0, 0.5, 1.0, 2.0), (4.0, 10.0, 6.0, 3.0))
    assert table.sa_m_s2(0.25) == pytest.approx(7.0)
    assert table.sa_m_s2(1.5) == pytest.approx(4.5)
    assert table.sa_m_s2(0.5) == pytest.approx(10.0)
    assert table.sa_m_s2(4.0) == pytest.approx(3.0 / 4.0)  # ∝ 1/T² beyond the table
    assert table.branch(1.0) == "table"


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"s_ds_m_s2": 0.0, "s_d1_m_s": 1.0}, "s_ds_m_s2 = 0.0, expected > 0"),
        ({"s_ds_m_s2": 5.0, "s_d1_m_s": math.nan}, "s_d1_m_s = nan, expected a finite number"),
        ({"s_ds_m_s2": 5.0, "s_d1_m_s": 5.0, "t_l_s": 0.5}, "t_l_s = 0.5 s, expected > T_s"),
    ],
)
def test_two_period_validation(kwargs: dict[str, float], message: str) -> None:
    with pytest.raises(InputError, match=message.replace("(", r"\(")):
        TwoPeriodSpectrum(**kwargs)


def test_tabulated_validation() -> None:
    with pytest.raises(InputError, match="expected strictly increasing periods"):
        TabulatedSpectrum((0.0, 1.0, 1.0), (1.0, 2.0, 3.0))
    with pytest.raises(InputError, match="expected equal counts"):
        TabulatedSpectrum((0.0, 1.0), (1.0,))


def test_from_dict_routes_and_unknown_keys() -> None:
    two = spectrum_from_dict({"s_ds_g": 1.0, "s_d1_m_s": 4.0}, g_m_s2=9.81)
    assert isinstance(two, TwoPeriodSpectrum)
    assert two.s_ds_m_s2 == pytest.approx(9.81)
    table = spectrum_from_dict({"periods_s": [0.0, 1.0], "sa_g": [1.0, 0.5]}, g_m_s2=10.0)
    assert isinstance(table, TabulatedSpectrum)
    assert table.sa_m_s2(1.0) == pytest.approx(5.0)
    with pytest.raises(InputError, match=r"unknown key\(s\) \['sds'\]"):
        spectrum_from_dict({"sds": 1.0, "s_d1_g": 0.4})
    with pytest.raises(InputError, match="exactly one of s_ds_m_s2 or s_ds_g"):
        spectrum_from_dict({"s_ds_g": 1.0, "s_ds_m_s2": 9.8, "s_d1_g": 0.4})


def test_round_trips() -> None:
    two = TwoPeriodSpectrum(8.0, 4.0, t_l_s=6.0)
    assert TwoPeriodSpectrum.from_dict(two.to_dict()) == two
    table = TabulatedSpectrum((0.0, 1.0), (2.0, 1.0))
    assert TabulatedSpectrum.from_dict(table.to_dict()) == table
    with pytest.raises(InputError, match="expected s_ds and s_d1"):
        TwoPeriodSpectrum.from_dict(table.to_dict())
