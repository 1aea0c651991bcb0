"""Amplitudes within 1e-15 to 1e-3 of a switching threshold: never an impossible answer.

Each threshold here is known in closed form, so the amplitude can be put a relative δ on either
side of it: the block's uplift g·α under A cos(ωt) (the crest reaches it), the portal frame's
steady state whose amplitude is exactly x_c (grazing), and a constant ground acceleration from
rest (the step) for the block and the portal frame. Below a threshold nothing lifts and the peak
is the closed form; above it every run ends "ok" with a finite peak within the physical bound of
the excess (or overturns, for the block's step). The exact excursion just above the block's
threshold is checked against an independent solve_ivp solution of the linearised Housner
equation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from stepframe.structure.frame import PortalFrame
from stepframe.structure.harmonic import simulate_harmonic, simulate_pulse
from stepframe.structure.simulator import simulate

BLOCK = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0)
#: g·α of the linearised block [m/s²]: the crest of A cos(ωt) lifts it when A exceeds it.
UPLIFT = BLOCK.gamma_1_m_s2 / BLOCK.p_2
#: The paper's Example 3 frame (W_col per column), with stepped-phase damping.
FRAME = PortalFrame.from_physical(
    w_s_n=1.472e6, w_col_n=2.807e6 - 1.472e6, h_r_m=29.944, l_f_m=8.839, k_a_n_m=1.159e9,
    k_b_n_m=5.019e6, xi_1=0.05, xi_2=0.02, w_col_convention="per-column",
)  # fmt: skip

#: Relative distance to the threshold, 1e-15 to 1e-3, on either side.
deltas = st.builds(
    lambda u, side: side * 10.0**u, st.floats(-15.0, -3.0), st.sampled_from([-1.0, 1.0])
)


def block_first_rocking(excess: float, omega: float, full_window: bool) -> float:
    """Peak |x| of the block's first rocking under A = gα(1 + excess), by solve_ivp.

    Written from the linearised Housner equation on the side the crest pushes it to,
    ẍ = p²x + γ₁ - P₂A cos(ωt), with the net push γ₁[2 sin²(ωt/2) - excess·cos(ωt)] so that
    the tiny difference is not lost to cancellation; from rest at the start of the crest's
    window (or at the crest itself), until the block is back at x = 0.
    """
    p, g1 = BLOCK.omega_2_rad_s, BLOCK.gamma_1_m_s2
    t0 = -math.acos(1.0 / (1.0 + excess)) / omega if full_window else 0.0

    def rhs(t: float, y: np.ndarray) -> list[float]:
        push = g1 * (2.0 * math.sin(0.5 * omega * t) ** 2 - excess * math.cos(omega * t))
        return [y[1], p * p * y[0] + push]

    def back(t: float, y: np.ndarray) -> float:
        return float(y[0])

    back.terminal = True  # type: ignore[attr-defined]
    back.direction = 1  # type: ignore[attr-defined]
    sol = solve_ivp(
        rhs, (t0, t0 + 1.0), [0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-30,
        events=back, dense_output=True, first_step=1e-7,
    )  # fmt: skip
    assert sol.t_events[0].size == 1
    t = np.linspace(t0, sol.t_events[0][0], 20001)
    return float(-sol.sol(t)[0].min())


@pytest.mark.parametrize("excess", [1e-6, 1e-5, 1e-4, 1e-3])
def test_block_excursion_just_above_uplift_matches_an_independent_solver(excess: float) -> None:
    omega = 16.0
    amp = UPLIFT * (1.0 + excess)
    # From the crest (half its window above the threshold): a quarter period holds the rocking.
    run = simulate_harmonic(BLOCK, amp, omega, 0.5 * math.pi / omega, samples_per_period=4)
    expected = block_first_rocking(excess, omega, full_window=False)
    assert run.status == "ok" and not run.overturned and run.n_impacts >= 1
    # 1e-14 m at δ = 1e-6: the closed form resolves it to its rounding (16 ulps of x*).
    assert run.peak_abs_x_m == pytest.approx(expected, rel=1e-9, abs=16 * 2.2e-16 * BLOCK.x_star_m)
    # The crest a period later has its whole window: the largest rocking of a long run.
    pulse = simulate_pulse(BLOCK, amp, omega)
    full = block_first_rocking(excess, omega, full_window=True)
    assert pulse.status == "ok" and not pulse.overturned
    assert pulse.peak_abs_x_m == pytest.approx(full, rel=1e-9, abs=16 * 2.2e-16 * BLOCK.x_star_m)


def test_the_threshold_case_of_the_command_line_is_a_tiny_rocking_not_1e8_m() -> None:
    # stepframe structure harmonic --block 0.25,1.0 --amplitude-g 0.2449786633718428
    # --omega-rad-s 16 --periods 20 (the uplift threshold × (1 + 1e-9)): was "ok" with 1.5e8 m.
    amp = 0.2449786633718428 * 9.81
    run = simulate_harmonic(BLOCK, amp, 16.0, 20 * 2 * math.pi / 16.0, samples_per_period=32)
    assert run.status == "ok" and not run.overturned
    assert run.peak_abs_x_m < 1e-15 and np.all(np.abs(run.x_m) < 1e-15)


def excursion_bound_m(delta: float, omega: float) -> float:
    """Largest excursion of the block a crest δ above the threshold can cause [m].

    The outward push is at most γ₁δ and lasts at most the window 2√(2δ)/ω where the crest is
    above the threshold; the block returns within twice that, so |x| ≤ ½γ₁δ(4√(2δ)/ω)², plus
    the rounding of the closed form.
    """
    return 16.0 * BLOCK.gamma_1_m_s2 * delta * delta / omega**2 + 1e-15


@settings(max_examples=60, deadline=None)
@given(delta=deltas, omega=st.floats(2.0, 40.0))
def test_block_harmonic_near_uplift(delta: float, omega: float) -> None:
    amp = UPLIFT * (1.0 + delta)
    run = simulate_harmonic(BLOCK, amp, omega, 6 * 2 * math.pi / omega, samples_per_period=16)
    pulse = simulate_pulse(BLOCK, amp, omega, free_periods=2.0)
    for status, overturned, peak in (
        (run.status, run.overturned, run.peak_abs_x_m),
        (pulse.status, pulse.overturned, pulse.peak_abs_x_m),
    ):
        assert status == "ok" and not overturned
        if delta < 0:
            assert peak == 0.0
        else:
            assert peak <= excursion_bound_m(delta, omega)
    if delta < 0:
        assert run.n_liftoffs == 0


@settings(max_examples=60, deadline=None)
@given(delta=deltas)
def test_block_sampled_near_uplift(delta: float) -> None:
    # The sampled simulator: a cosine record whose first sample is the crest, and a step.
    dt = 0.001
    t = np.arange(0.0, 2.0, dt)
    amp = UPLIFT * (1.0 + delta)
    run = simulate(BLOCK, amp * np.cos(16.0 * t), dt, tail_s=1.0, record_history=False).summary
    assert run.status == "ok" and not run.overturned
    assert run.peak_abs_x_m <= (excursion_bound_m(delta, 16.0) if delta > 0 else 0.0)
    step = simulate(BLOCK, np.full(200, amp), 0.01, tail_s=0.0, record_history=False).summary
    assert step.status == "ok"
    if delta < 0:
        assert step.peak_abs_x_m == 0.0 and step.n_stepping_episodes == 0
    else:
        # Pushed beyond its shifted equilibrium x = -δx*: it leaves as γ₁δ(cosh pt - 1)/p²,
        # the push γ₁δ being the difference of two terms of size γ₁ (rounding 1e-16/δ of it).
        p = BLOCK.omega_2_rad_s
        grown = BLOCK.gamma_1_m_s2 * delta * (math.cosh(p * 1.99) - 1.0) / p**2
        rel = 1e-9 + 1e-14 / delta
        assert step.overturned or step.peak_abs_x_m == pytest.approx(grown, rel=rel)


def steady_state(amp: float, omega: float) -> tuple[float, float, float, float]:
    """The unstepped steady state under A cos(ωt): its amplitude [m], the initial state (x, ẋ)
    [m, m/s] on it, and the ground acceleration at its positive crest [m/s²]."""
    h = 1.0 / complex(
        FRAME.omega_1_rad_s**2 - omega**2, 2 * FRAME.xi_1 * FRAME.omega_1_rad_s * omega
    )
    x = -FRAME.p_1 * amp * h
    # x(t) = |x| cos(ωt + arg x) peaks at ωt = -arg x, where A cos(ωt) = A cos(arg x).
    return abs(x), x.real, (1j * omega * x).real, amp * math.cos(np.angle(x))


@settings(max_examples=60, deadline=None)
@given(delta=deltas)
def test_portal_frame_grazing_its_switching_surface(delta: float) -> None:
    omega = 7.854
    graze = steady_state(1.0, omega)[0]
    amp = FRAME.x_c_m / graze * (1.0 + delta)
    size, x0, v0, ag_crest = steady_state(amp, omega)
    run = simulate_harmonic(FRAME, amp, omega, 10 * 2 * math.pi / omega, x0_m=x0, v0_m_s=v0)
    assert run.status == "ok" and not run.overturned and np.all(np.isfinite(run.x_m))
    # Stepping across the run's 640 output samples (each restarts the closed form at a time
    # rounded to its ulp) moves the steady state by up to ~3e-13 of its size: within that of
    # the threshold, a rounding-level lift-off is as right as none.
    if delta < -1e-11:
        assert run.n_liftoffs == 0
        assert run.peak_abs_x_m == pytest.approx(size, rel=1e-9)
        return
    # Crossing x_c at the speed ωX√(2δ) against the stepped phase's pull back there,
    # γ₁ - ω₂²x_c + P₂ẍ_g, it rises δω²X²/pull beyond x_c; the impact on return takes
    # (1 - C_r) of that speed, a transient of relative size (1 - C_r)√(2δ) that later crests
    # add to δ (the square-root law of grazing impacts).
    pull = FRAME.gamma_1_m_s2 - FRAME.omega_2_rad_s**2 * FRAME.x_c_m + FRAME.p_2 * ag_crest
    assert pull > 0
    excess = max(delta, 3e-13)
    excess += 2.0 * (1.0 - FRAME.c_r) * math.sqrt(2.0 * excess)
    assert run.peak_abs_x_m <= FRAME.x_c_m + 2.0 * excess * omega**2 * size**2 / pull


@settings(max_examples=60, deadline=None)
@given(delta=deltas)
def test_portal_frame_step_from_rest(delta: float) -> None:
    # ẍ + 2ξωẋ + ω²x = -P₁a from rest overshoots to x_s(1 + e^{-ξπ/√(1-ξ²)}), x_s = P₁a/ω².
    w, xi, p1 = FRAME.omega_1_rad_s, FRAME.xi_1, FRAME.p_1
    overshoot = 1.0 + math.exp(-xi * math.pi / math.sqrt(1 - xi * xi))
    threshold = FRAME.x_c_m * w * w / (p1 * overshoot)
    a = -threshold * (1.0 + delta)
    dt = 0.01
    run = simulate(FRAME, np.full(301, a), dt, tail_s=0.0, record_history=False).summary
    assert run.status == "ok"
    # Once stepped, this frame cannot hold the load: the pull back at x_c is negative, so the
    # step threshold is an overturning threshold (either outcome within the rounding of x).
    assert FRAME.gamma_1_m_s2 - FRAME.omega_2_rad_s**2 * FRAME.x_c_m + FRAME.p_2 * a < 0
    if delta < -1e-13:
        assert run.n_stepping_episodes == 0 and not run.overturned
        assert run.peak_abs_x_m == pytest.approx(-p1 * a / (w * w) * overshoot, rel=1e-9)
    elif delta > 1e-13:
        assert run.overturned and run.peak_abs_x_m == FRAME.x_cap_m


@settings(max_examples=60, deadline=None)
@given(delta=deltas)
def test_aframe_step_from_rest(delta: float) -> None:
    # The hysteretic A-frame loads with stiffness ω₁²(1 + πξ₁): a step a from rest reaches
    # 2P₁a/(ω₁²(1 + πξ₁)), and there it sticks (πξ₁ ≥ 1/3) or turns back.
    from stepframe.structure.aframe_hysteretic import simulate_aframe
    from stepframe.structure.frame import AFrame

    frame = AFrame(
        omega_1_rad_s=6.0, omega_2_rad_s=1.5, p_1=1.1, p_2=1.2, gamma_1_m_s2=2.0, xi_1=0.15,
        theta_rad=0.2, x_c_m=0.04, c_r=0.85, x_cap_m=0.8,
    )  # fmt: skip
    k_load = frame.omega_1_rad_s**2 * (1.0 + math.pi * frame.xi_1)
    a = frame.x_c_m * k_load / (2.0 * frame.p_1) * (1.0 + delta)
    run = simulate_aframe(frame, np.full(301, a), 0.01, tail_s=0.0)
    assert run.status == "ok" and not run.overturned
    if delta < -1e-13:
        assert run.n_liftoffs == 0 and run.n_sticks == 1
        assert run.peak_abs_x_m == pytest.approx(2 * frame.p_1 * a / k_load, rel=1e-12)
    else:
        # Crossing x_c at ω√(2 x_s δ x_c)-ish speed against the stepped phase's pull back:
        # a rise of at most 2δ x_c·k_load·x_c/pull beyond x_c (the ratio of the two stiffnesses).
        w2, g1, p2 = frame.stepped_constants
        pull = g1 - w2 * w2 * frame.x_c_m - p2 * a
        assert pull > 0
        rise = 2.0 * max(delta, 1e-13) * k_load * frame.x_c_m**2 / pull
        assert run.peak_abs_x_m <= frame.x_c_m + 2.0 * rise
