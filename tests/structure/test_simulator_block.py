"""Linearised Housner block from the simulator (x_c = 0 limit: impact at θ = 0).

Closed forms (Housner 1963, linearised): from rest at θ₀ the block reaches θ = 0 after the
quarter period (1/p)·arccosh(1/(1 - θ₀/α)); an impact multiplies the angular velocity by
η = 1 - 1.5 sin²α, so the next amplitude θ₁ solves 1 - (1 - θ₁/α)² = η²(1 - (1 - θ₀/α)²)
(energy θ̇² - p²(α - θ)² is conserved between impacts).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.structure.simulator import simulate_rigid_block

P_RAD_S = 2.2
ALPHA_RAD = 0.25
ETA = 1.0 - 1.5 * math.sin(ALPHA_RAD) ** 2


def _quarter_period_s(theta_rad: float) -> float:
    return math.acosh(1.0 / (1.0 - theta_rad / ALPHA_RAD)) / P_RAD_S


def _next_amplitude(theta_rad: float) -> float:
    inner = 1.0 - ETA**2 * (1.0 - (1.0 - theta_rad / ALPHA_RAD) ** 2)
    return ALPHA_RAD * (1.0 - math.sqrt(inner))


@pytest.mark.parametrize("theta0_rad", [0.01, 0.1, 0.2])
def test_free_rocking_quarter_period_and_decay(theta0_rad: float) -> None:
    result = simulate_rigid_block(
        P_RAD_S, ALPHA_RAD, ETA, np.zeros(2), 0.01, theta0_rad=theta0_rad, tail_s=8.0
    )
    impacts = result.events[result.events["kind"] == "touchdown"]["time_s"].to_numpy()
    assert impacts.size >= 4
    assert impacts[0] == pytest.approx(_quarter_period_s(theta0_rad), rel=1e-6)
    # Each later impact comes after two quarter periods of the amplitude reached in between.
    theta = theta0_rad
    amplitudes = []
    for j in range(1, 4):
        theta = _next_amplitude(theta)
        amplitudes.append(theta)
        gap = impacts[j] - impacts[j - 1]
        assert gap == pytest.approx(2.0 * _quarter_period_s(theta), rel=1e-6)
    peaks = result.episodes["peak_abs_x_m"].to_numpy()
    # Episode 0 starts at θ₀ without a lift-off event; episodes list the later ones.
    np.testing.assert_allclose(peaks[:3], amplitudes, rtol=1e-6)
    sides = result.episodes["side"].to_numpy()[:3]
    np.testing.assert_array_equal(sides, [-1.0, 1.0, -1.0])
    v_in = np.abs(result.impact_velocities_m_s[:3])
    v_closed = [
        P_RAD_S * math.sqrt(ALPHA_RAD**2 - (ALPHA_RAD - th) ** 2)
        for th in [theta0_rad, *amplitudes[:2]]
    ]
    np.testing.assert_allclose(v_in, v_closed, rtol=1e-6)


def test_block_at_rest_starts_rocking_only_above_g_tan_alpha() -> None:
    g = block_g()  # the structure API's one default gravity
    below = np.full(200, 0.99 * g * ALPHA_RAD)
    assert (
        simulate_rigid_block(P_RAD_S, ALPHA_RAD, ETA, below, 0.01).summary.n_stepping_episodes == 0
    )
    above = np.full(200, 1.01 * g * ALPHA_RAD)
    result = simulate_rigid_block(P_RAD_S, ALPHA_RAD, ETA, above, 0.01, tail_s=0.0)
    # Constant push beyond the threshold: θ̈ = p²θ + p²(0.01α) from rest on the side s = -1,
    # so |θ(t)| = 0.01α(cosh(pt) - 1) exactly.
    t_end = 199 * 0.01
    assert result.summary.n_stepping_episodes == 1
    assert result.summary.residual_x_m == pytest.approx(
        -0.01 * ALPHA_RAD * (math.cosh(P_RAD_S * t_end) - 1.0), rel=1e-9
    )


def test_portal_frame_housner_block_through_simulate() -> None:
    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.simulator import simulate

    block = PortalFrame.housner_block(half_width_m=0.3, half_height_m=1.2)
    alpha = math.atan2(0.3, 1.2)
    p = math.sqrt(3.0 * block_g() / (4.0 * math.hypot(0.3, 1.2)))
    x0 = 0.5 * block.x_star_m
    result = simulate(block, np.zeros(2), 0.01, x0_m=x0, tail_s=6.0)
    first = result.switching_times_s[0]
    assert first == pytest.approx(math.acosh(1.0 / (1.0 - x0 / block.x_star_m)) / p, rel=1e-6)
    eta = 1.0 - 1.5 * math.sin(alpha) ** 2
    theta1 = 1.0 - math.sqrt(1.0 - eta**2 * (1.0 - (1.0 - x0 / block.x_star_m) ** 2))
    assert result.episodes["peak_abs_x_m"].iloc[0] == pytest.approx(
        theta1 * block.x_star_m, rel=1e-6
    )


def block_g() -> float:
    from stepframe.structure.frame import PAPER_G_M_S2

    return float(PAPER_G_M_S2)
