"""The Beck-Papadimitriou model (eqs. 6.10-6.12) against quadrature and its own definitions."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate

from stepframe.errors import InputError
from stepframe.stochastic.model import GroundMotionModel

SITE = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)


@pytest.mark.parametrize("t", [0.0, 2.5, 5.0, 12.0, 40.0])
def test_psd_integrates_to_intensity_squared(t: float) -> None:
    intensity = 1.7
    value, _ = integrate.quad(lambda w: SITE.psd(w, t, intensity), -np.inf, np.inf, limit=400)
    assert value / (2 * math.pi) == pytest.approx(intensity**2, rel=1e-8)


def test_omega_g_end_points_and_monotone() -> None:
    two_pi = 2 * math.pi
    assert SITE.omega_g(0.0) == pytest.approx(two_pi * 7.43, rel=1e-14)
    assert SITE.omega_g(5.0) == pytest.approx(two_pi * 3.12, rel=1e-14)
    assert SITE.omega_g(1e4) == pytest.approx(two_pi * 1.11, rel=1e-12)
    t = np.linspace(0, 60, 500)
    assert np.all(np.diff(SITE.omega_g(t)) < 0)


def test_alpha_readings() -> None:
    start, end = SITE.omega_p_rad_s * SITE.xi_p, SITE.omega_r_rad_s * SITE.xi_r
    assert SITE.alpha_g(20.0) == pytest.approx(end)
    assert SITE.alpha_g(10.0) == pytest.approx(0.5 * (start + end))
    paper = GroundMotionModel(**{**SITE.to_dict(), "alpha_reading": "paper"})
    assert paper.alpha_g(5.0) == pytest.approx(end)
    assert paper.alpha_g(100.0) == pytest.approx(end)


def test_time_origin_shifts_the_model() -> None:
    shifted = GroundMotionModel(**{**SITE.to_dict(), "t0_s": 3.0})
    assert shifted.omega_g(8.0) == pytest.approx(SITE.omega_g(5.0))
    assert shifted.omega_g(1.0) == pytest.approx(SITE.omega_p_rad_s)  # held before the origin


def test_degenerate_p_equals_s_and_s_equals_r() -> None:
    flat = GroundMotionModel(20.0, 20.0, 5.0, 0.1, 0.5, 4.0, 10.0)
    np.testing.assert_allclose(flat.omega_g([0, 4, 50]), 20.0)
    drop = GroundMotionModel(20.0, 5.0, 5.0, 0.1, 0.5, 4.0, 10.0)
    assert drop.omega_g(0.0) == pytest.approx(20.0)
    np.testing.assert_allclose(drop.omega_g([1.0, 4.0, 50.0]), 5.0)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"omega_r_rad_s": 0.0}, "omega_r_rad_s"),
        ({"omega_s_rad_s": 100.0}, "expected p ≥ s ≥ r"),
        ({"xi_p": 0.0}, "xi_p = 0.0, expected > 0"),  # ξ ≥ 1 is valid: test_broadband.py
        ({"t_max_s": 30.0}, "t_max ≤ t_dur"),
        ({"xi_r": float("nan")}, "finite"),
        ({"alpha_reading": "other"}, "alpha_reading"),
    ],
)
def test_validation_names_parameter_and_bound(change: dict[str, object], message: str) -> None:
    with pytest.raises(InputError, match=message):
        GroundMotionModel(**{**SITE.to_dict(), **change})


def test_dict_round_trip_and_unknown_key() -> None:
    assert GroundMotionModel.from_dict(SITE.to_dict()) == SITE
    with pytest.raises(InputError, match="unknown"):
        GroundMotionModel.from_dict({**SITE.to_dict(), "omega_x": 1.0})


def test_corner_high_pass_in_the_spectrum() -> None:
    """ω_c multiplies eq. 6.12 by ω⁴/(ω² + ω_c²)²: half-power-squared (1/4) at ω = ω_c."""
    cornered = GroundMotionModel(**{**SITE.to_dict(), "omega_c_rad_s": 3.0})
    omega = np.array([0.0, 3.0, 30.0, 300.0])
    ratio = cornered.psd(omega, 2.0) / SITE.psd(omega, 2.0)
    np.testing.assert_allclose(ratio, [0.0, 0.25, (900 / 909) ** 2, (90000 / 90009) ** 2])
    np.testing.assert_allclose(cornered.omega_g([0, 5, 30]), SITE.omega_g([0, 5, 30]))
    with pytest.raises(InputError, match="omega_c_rad_s"):
        GroundMotionModel(**{**SITE.to_dict(), "omega_c_rad_s": -1.0})
