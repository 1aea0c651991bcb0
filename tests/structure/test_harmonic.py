"""Closed-form harmonic integrator against closed forms and an independent solve_ivp solution."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from stepframe.errors import InputError
from stepframe.structure.frame import PortalFrame
from stepframe.structure.harmonic import simulate_harmonic, simulate_pulse, stroboscopic_map


def example3_frame() -> PortalFrame:
    """Example 3 of the paper (W_col = (W_T - W_S)/2 per column)."""
    return PortalFrame.from_physical(
        w_s_n=1.472e6,
        w_col_n=2.807e6 - 1.472e6,
        h_r_m=29.944,
        l_f_m=8.839,
        k_a_n_m=1.159e9,
        k_b_n_m=5.019e6,
        xi_1=0.05,
        xi_2=0.02,
        w_col_convention="per-column",
    )


def reference_portal(frame: PortalFrame, amp: float, om: float, t_end: float) -> np.ndarray:
    """Eqs. 4.11-4.12 with impact, by solve_ivp with terminal events (restarted at each)."""
    w1, w2, p1, p2 = frame.omega_1_rad_s, frame.omega_2_rad_s, frame.p_1, frame.p_2
    g1, xi1, xi2, xc, cr = frame.gamma_1_m_s2, frame.xi_1, frame.xi_2, frame.x_c_m, frame.c_r

    def rhs(phase: int) -> object:
        def f(t: float, y: np.ndarray) -> list[float]:
            ag = amp * math.cos(om * t)
            if phase == 0:
                return [y[1], -2 * xi1 * w1 * y[1] - w1 * w1 * y[0] - p1 * ag]
            return [y[1], -2 * xi2 * w2 * y[1] + w2 * w2 * y[0] - phase * g1 - p2 * ag]

        return f

    def surface(phase: int) -> list[object]:
        if phase == 0:
            up = lambda t, y: y[0] - xc  # noqa: E731
            dn = lambda t, y: y[0] + xc  # noqa: E731
            up.terminal = dn.terminal = True  # type: ignore[attr-defined]
            up.direction = 1  # type: ignore[attr-defined]
            dn.direction = -1  # type: ignore[attr-defined]
            return [up, dn]
        td = lambda t, y: phase * y[0] - xc  # noqa: E731
        td.terminal = True  # type: ignore[attr-defined]
        td.direction = -1  # type: ignore[attr-defined]
        return [td]

    t, y, phase = 0.0, np.zeros(2), 0
    while t < t_end:
        sol = solve_ivp(
            rhs(phase),
            (t, t_end),
            y,
            method="DOP853",
            rtol=1e-12,
            atol=1e-14,
            events=surface(phase),
        )
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.status == 1:
            if phase == 0:
                phase = 1 if sol.t_events[0].size else -1
                y[0] = phase * xc
            else:
                y[0] = phase * xc
                y[1] *= cr
                phase = 0
    return y


def test_unstepped_linear_response_matches_closed_form() -> None:
    frame = example3_frame()
    amp, om = 0.02, 3.0
    run = simulate_harmonic(frame, amp, om, 6.0, samples_per_period=10)
    w1, xi, p1 = frame.omega_1_rad_s, frame.xi_1, frame.p_1
    sol = solve_ivp(
        lambda t, y: [y[1], -2 * xi * w1 * y[1] - w1**2 * y[0] - p1 * amp * math.cos(om * t)],
        (0, 6.0),
        [0.0, 0.0],
        t_eval=run.time_s,
        rtol=1e-12,
        atol=1e-16,
        method="DOP853",
    )
    assert run.status == "ok" and run.n_liftoffs == 0
    np.testing.assert_allclose(run.x_m, sol.y[0], atol=1e-12 * np.max(abs(sol.y[0])) + 1e-15)


def test_undamped_resonance_uses_the_secular_solution() -> None:
    frame = PortalFrame.from_constants(
        omega_1_rad_s=5.0,
        omega_2_rad_s=1.0,
        p_1=1.2,
        p_2=1.1,
        gamma_1_m_s2=2.0,
        xi_1=0.0,
        xi_2=0.0,
        x_c_m=1.0,
        c_r=0.9,
    )
    amp, om = 0.01, 5.0
    run = simulate_harmonic(frame, amp, om, 4.0)
    # From rest: x = -P₁A t sin(ωt)/(2ω).
    exact = -frame.p_1 * amp * run.time_s * np.sin(om * run.time_s) / (2 * om)
    np.testing.assert_allclose(run.x_m, exact, atol=1e-15)


def test_stepping_response_matches_independent_solve_ivp() -> None:
    frame = example3_frame()
    amp, om = 0.30 * 9.81, 7.854
    run = simulate_harmonic(frame, amp, om, 8.0, samples_per_period=4)
    assert run.n_liftoffs >= 3 and run.n_impacts >= 3
    ref = reference_portal(frame, amp, om, 8.0)
    assert abs(run.x_m[-1] - ref[0]) < 1e-8
    assert abs(run.v_m_s[-1] - ref[1]) < 1e-7


def test_map_jacobian_matches_finite_differences_through_events() -> None:
    frame = example3_frame()
    amp, om = 0.30 * 9.81, 7.854
    step = stroboscopic_map(frame, amp, om, 0.25, 0.5, n_periods=2)
    assert step.n_impacts >= 1 and step.n_liftoffs >= 1
    h = 1e-7
    fd = np.empty((2, 2))
    for col, dh in enumerate((h, h * om)):
        z_p = [0.25, 0.5]
        z_m = [0.25, 0.5]
        z_p[col] += dh
        z_m[col] -= dh
        sp = stroboscopic_map(frame, amp, om, *z_p, n_periods=2)
        sm = stroboscopic_map(frame, amp, om, *z_m, n_periods=2)
        fd[:, col] = (np.array([sp.x_m, sp.v_m_s]) - np.array([sm.x_m, sm.v_m_s])) / (2 * dh)
    np.testing.assert_allclose(step.jacobian, fd, rtol=1e-6, atol=1e-6 * np.abs(fd).max())


def test_rest_without_forcing_stays_at_rest_and_zero_amplitude_is_exact() -> None:
    block = PortalFrame.housner_block(half_width_m=0.2, half_height_m=1.0)
    run = simulate_harmonic(block, 0.0, 2.0, 10.0)
    assert run.status == "ok" and np.all(run.x_m == 0.0) and run.n_liftoffs == 0


def test_forcing_exactly_at_the_uplift_threshold_does_not_lift() -> None:
    block = PortalFrame.housner_block(half_width_m=0.2, half_height_m=1.0)
    threshold = block.gamma_1_m_s2 / block.p_2  # g·α of the linearised block
    at = simulate_harmonic(block, threshold, 3.0, 5.0)
    above = simulate_harmonic(block, threshold * (1 + 1e-9), 3.0, 5.0)
    assert at.status == "ok" and at.n_liftoffs == 0
    assert above.status == "ok" and above.n_liftoffs >= 1


def test_separatrix_and_escape() -> None:
    block = PortalFrame.housner_block(half_width_m=0.2, half_height_m=1.0)
    x_star = block.x_star_m
    p = block.omega_2_rad_s
    on = simulate_harmonic(block, 0.0, 1.0, 3.0, x0_m=0.5 * x_star, v0_m_s=0.5 * x_star * p)
    # E = v² - p²(x - x*)² = 0: on the separatrix, not beyond it: creeps up to x*, no escape.
    assert on.status == "ok" and not on.overturned
    beyond = simulate_harmonic(
        block, 0.0, 1.0, 10.0, x0_m=0.5 * x_star, v0_m_s=0.5 * x_star * p * (1 + 1e-9)
    )
    assert beyond.overturned and beyond.t_end_s < 10.0


def test_very_low_frequency_is_quasi_static() -> None:
    frame = example3_frame()
    amp, om = 0.5 * 9.81, 1e-4  # below the static uplift acceleration ω₁²x_c/P₁
    assert amp < frame.uplift_acceleration_m_s2
    run = simulate_harmonic(frame, amp, om, 2e4, phase_rad=-0.5 * math.pi, samples_per_period=8)
    assert run.status == "ok" and run.n_liftoffs == 0
    quasi_static = -frame.p_1 * amp * np.sin(om * run.time_s) / frame.omega_1_rad_s**2
    # Damping lags the response by 2ξ₁ω/ω₁ ≈ 3e-6 of a radian: the quasi-static form to 1e-5.
    np.testing.assert_allclose(run.x_m, quasi_static, rtol=1e-5, atol=1e-9)


def test_sudden_static_push_above_capacity_overturns_with_a_status() -> None:
    # A cosine starting at its crest is a step load: 0.5 g overshoots the uplift, then tips.
    run = simulate_harmonic(example3_frame(), 0.5 * 9.81, 1e-4, 2e4, samples_per_period=2)
    assert run.status == "ok" and run.overturned and math.isfinite(run.t_end_s)


def test_very_high_frequency_barely_moves_the_frame() -> None:
    frame = example3_frame()
    om = 1e4
    run = simulate_harmonic(frame, 0.5 * 9.81, om, 20.0, samples_per_period=2)
    assert run.status == "ok" and np.all(np.isfinite(run.x_m))
    # Far above every frequency: |x| ≤ P₁A/ω² plus the transient of the same size.
    assert run.peak_abs_x_m < 2.5 * frame.p_1 * 0.5 * 9.81 / om**2


def test_pulse_below_uplift_does_nothing_and_bad_input_raises() -> None:
    block = PortalFrame.housner_block(half_width_m=0.2, half_height_m=1.0)
    out = simulate_pulse(block, 0.5 * block.gamma_1_m_s2 / block.p_2, 5.0)
    assert out.status == "ok" and not out.overturned and out.peak_abs_x_m == 0.0
    with pytest.raises(InputError):
        simulate_harmonic(block, -1.0, 1.0, 1.0)
    with pytest.raises(InputError):
        simulate_pulse(block, 1.0, 1.0, kind="square")  # type: ignore[arg-type]


@pytest.mark.parametrize(("factor", "lifts"), [(1 - 1e-9, False), (1.0, None), (1 + 1e-6, True)])
def test_grazing_steady_state_at_the_switching_surface(factor: float, lifts: bool | None) -> None:
    # The unstepped steady state whose amplitude is exactly x_c touches the surface tangentially
    # once per half period; started on it there is no transient.
    frame = example3_frame()
    om = 7.854
    h = 1 / complex(frame.omega_1_rad_s**2 - om**2, 2 * frame.xi_1 * frame.omega_1_rad_s * om)
    amp_graze = frame.x_c_m / (frame.p_1 * abs(h))
    amp = factor * amp_graze
    x0 = (-frame.p_1 * amp * h).real
    v0 = (-frame.p_1 * amp * 1j * om * h).real
    run = simulate_harmonic(frame, amp, om, 20 * 2 * math.pi / om, x0_m=x0, v0_m_s=v0)
    assert run.status == "ok" and np.all(np.isfinite(run.x_m))
    if lifts is not None:
        assert (run.n_liftoffs > 0) is lifts
    if lifts is False:
        assert run.peak_abs_x_m == pytest.approx(factor * frame.x_c_m, rel=1e-9)
