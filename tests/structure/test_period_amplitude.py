"""T(A) closed form against independent integration of the free, conservative two-phase model."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stepframe.errors import InputError
from stepframe.structure.frame import PortalFrame
from stepframe.structure.period_amplitude import period_amplitude, quarter_periods_s

# Example 4's constants (P1 corrected, see docs/paper-notes.md), with x_c from eq. 4.10.
FRAME = PortalFrame(
    omega_1_rad_s=6.4581,
    omega_2_rad_s=0.6445,
    p_1=1.1884,
    p_2=1.2680,
    gamma_1_m_s2=0.1387,
    xi_1=0.0,
    xi_2=0.0,
    x_c_m=0.19042556469654862,
    c_r=1.0,
)


def _quarter_period_by_ode(frame: PortalFrame, amplitude_m: float) -> tuple[float, float]:
    """Time from rest at A down to x_c (stepped phase), then from x_c to 0 (unstepped phase).

    DOP853 at rtol 1e-12 with terminal events: independent of the closed form.
    """
    w1, w2, gamma, x_c = frame.omega_1_rad_s, frame.omega_2_rad_s, frame.gamma_1_m_s2, frame.x_c_m

    def stepped(_t: float, y: np.ndarray) -> list[float]:
        return [y[1], w2 * w2 * y[0] - gamma]

    def unstepped(_t: float, y: np.ndarray) -> list[float]:
        return [y[1], -w1 * w1 * y[0]]

    def at_x_c(_t: float, y: np.ndarray) -> float:
        return float(y[0] - x_c)

    def at_zero(_t: float, y: np.ndarray) -> float:
        return float(y[0])

    at_x_c.terminal = True  # type: ignore[attr-defined]
    at_zero.terminal = True  # type: ignore[attr-defined]
    first = solve_ivp(
        stepped, (0, 1e4), [amplitude_m, 0.0], method="DOP853", rtol=1e-13, atol=1e-15,
        events=at_x_c,
    )  # fmt: skip
    t_stepped = float(first.t_events[0][0])
    state = first.y_events[0][0]
    second = solve_ivp(
        unstepped, (0, 1e3), state, method="DOP853", rtol=1e-13, atol=1e-15, events=at_zero
    )
    return float(second.t_events[0][0]), t_stepped


@pytest.mark.parametrize(
    "fraction",
    [1e-6, 1e-3, 0.1, 0.5, 0.9, 0.999, 1 - 1e-6],
    ids=lambda f: f"{f:g}",
)
def test_closed_form_matches_integration_from_x_c_to_x_star(fraction: float) -> None:
    x_c, x_star = FRAME.x_c_m, FRAME.x_star_m
    amplitude = x_c + fraction * (x_star - x_c)
    t_unstepped, t_stepped = _quarter_period_by_ode(FRAME, amplitude)
    period = period_amplitude(FRAME, amplitude)
    assert period == pytest.approx(4 * (t_unstepped + t_stepped), rel=1e-6, abs=0)
    parts = quarter_periods_s(FRAME, amplitude)
    assert float(parts[0]) == pytest.approx(t_unstepped, rel=1e-6)
    assert float(parts[1]) == pytest.approx(t_stepped, rel=1e-6, abs=1e-12)


def test_small_amplitudes_have_the_fixed_base_period() -> None:
    periods = period_amplitude(FRAME, np.array([0.0, 0.01, FRAME.x_c_m]))
    np.testing.assert_allclose(periods, 2 * math.pi / FRAME.omega_1_rad_s, rtol=1e-15)


def test_period_is_continuous_at_x_c_and_increasing() -> None:
    x_c, x_star = FRAME.x_c_m, FRAME.x_star_m
    # The stepped time grows like √(A - x_c): about 1e-5 s at A - x_c = 2e-13 m.
    assert period_amplitude(FRAME, x_c * (1 + 1e-12)) == pytest.approx(
        2 * math.pi / FRAME.omega_1_rad_s, abs=3e-5
    )
    amplitudes = np.linspace(x_c, x_star * (1 - 1e-9), 200)
    periods = period_amplitude(FRAME, amplitudes)
    assert periods.shape == amplitudes.shape
    assert np.all(np.diff(periods) > 0)


def test_logarithmic_elongation_near_x_star() -> None:
    # T ≈ (4/ω₂) ln(1/(x* - A)) + const: the slope against ln(1/(x* - A)) tends to 4/ω₂.
    x_star = FRAME.x_star_m
    gaps = np.array([1e-7, 1e-8])
    periods = period_amplitude(FRAME, x_star - gaps)
    slope = (periods[1] - periods[0]) / math.log(10.0)
    assert slope == pytest.approx(4 / FRAME.omega_2_rad_s, rel=1e-6)


def test_rigid_block_limit_is_housners_quarter_period() -> None:
    block = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0, g_m_s2=9.81)
    alpha = math.atan(0.25)
    p = math.sqrt(3 * 9.81 / (4 * math.hypot(0.25, 1.0)))
    for theta0 in (0.01, 0.1, 0.2, 0.24):
        x0 = 1.0 * theta0  # x = h θ
        expected = 4 * math.acosh(1 / (1 - theta0 / alpha)) / p
        assert period_amplitude(block, x0) == pytest.approx(expected, rel=1e-12)


def test_bad_amplitudes() -> None:
    with pytest.raises(InputError, match=r"amplitude_m = -0\.1, expected a finite amplitude"):
        period_amplitude(FRAME, -0.1)
    with pytest.raises(InputError, match="amplitude_m = nan"):
        period_amplitude(FRAME, [0.1, float("nan")])
    with pytest.raises(InputError, match="expected A < x"):
        period_amplitude(FRAME, FRAME.x_star_m)
    out = period_amplitude(FRAME, [0.1, 1.0], beyond_x_star="inf")
    assert np.isinf(out[1]) and np.isfinite(out[0])
    with pytest.raises(InputError, match="beyond_x_star"):
        period_amplitude(FRAME, 0.1, beyond_x_star="nan")  # type: ignore[arg-type]


@pytest.mark.parametrize("fraction", [1e-6, 0.5, 0.99, 1 - 1e-6], ids=lambda f: f"{f:g}")
def test_closed_form_matches_the_exact_simulator(fraction: float) -> None:
    from stepframe.structure.simulator import simulate

    amplitude = FRAME.x_c_m + fraction * (FRAME.x_star_m - FRAME.x_c_m)
    period = period_amplitude(FRAME, amplitude)
    t_unstepped, t_stepped = quarter_periods_s(FRAME, amplitude)
    free = simulate(
        FRAME, np.zeros(2), 0.01, tail_s=1.6 * period, x0_m=amplitude, record_history=False
    )
    # Events alternate touchdown (side +), liftoff (side -), touchdown (-), liftoff (+), ...
    times = free.switching_times_s
    assert times[0] == pytest.approx(float(t_stepped), rel=1e-6, abs=1e-12)
    assert times[1] - times[0] == pytest.approx(2 * float(t_unstepped), rel=1e-6)
    quarter = times[0] + (times[1] - times[0]) / 2
    assert 4 * quarter == pytest.approx(period, rel=1e-6)
    assert not free.summary.overturned
    if fraction < 0.999:
        # A whole simulated cycle: the amplitude reached on the far side depends on the
        # touchdown speed through (x* - A)² = (x* - x_c)² - v_c²/ω₂², a difference that loses
        # all digits as A → x* (at 1 - 1e-6, a 1e-13 relative error in v_c moves T by 0.5 s).
        assert times[4] - times[0] == pytest.approx(period, rel=1e-6)


def test_housner_block_constructor_runs_in_the_simulator() -> None:
    from stepframe.structure.simulator import simulate

    block = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0, g_m_s2=9.81)
    theta0 = 0.1
    quarter = float(period_amplitude(block, theta0 * 1.0)) / 4
    free = simulate(block, np.zeros(2), 0.01, tail_s=3 * quarter, x0_m=theta0 * 1.0)
    first_impact = free.switching_times_s[0]
    assert first_impact == pytest.approx(quarter, rel=1e-6)
    # Each impact multiplies the velocity by C_r = 1 - 1.5 sin²α (Housner's η).
    speeds = np.abs(free.impact_velocities_m_s)
    eta = 1 - 1.5 * math.sin(math.atan(0.25)) ** 2
    assert speeds[1] / speeds[0] == pytest.approx(eta, rel=1e-6)


def test_amplitude_for_period_inverts_the_law() -> None:
    from stepframe.structure.period_amplitude import amplitude_for_period

    x_c, x_star = FRAME.x_c_m, FRAME.x_star_m
    amplitudes = x_c + np.array([1e-3, 0.2, 0.7, 0.99]) * (x_star - x_c)
    recovered = amplitude_for_period(FRAME, period_amplitude(FRAME, amplitudes))
    np.testing.assert_allclose(recovered, amplitudes, rtol=1e-12)
    assert isinstance(amplitude_for_period(FRAME, 10.0), float)
    with pytest.raises(InputError, match=r"period_s = 0\.5, expected a finite period > 0\.9729"):
        amplitude_for_period(FRAME, [5.0, 0.5])
    block = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0)
    assert period_amplitude(block, amplitude_for_period(block, 1.0)) == pytest.approx(1.0, 1e-12)
