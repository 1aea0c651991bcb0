"""The hysteretic A-frame sticks (eq. 4.1 at ẋ = 0): closed forms and an independent integrator.

At ẋ = 0 the hysteretic force πξ₁ω₁² sign(ẋ)|x| of eq. 4.1 can take any value within ±W,
W = πξ₁ω₁²|x|, so the frame stays at rest while the rest of the force, F = -ω₁²x - P₁ẍ_g, stays
within that window (the Filippov sliding state). Under a constant ground acceleration the
motion is a chain of half cycles in closed form that ends stuck; under a slow harmonic the frame
sticks at each reversal of the ground. Both are checked here, the second against the solve_ivp
integrator of :mod:`aframe_reference`, written from the equations with its own event finder,
which the previous integrator (no stick state: it moved on with the damping's sign flipped)
agreed with only up to the first stick.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.structure.aframe_hysteretic import simulate_aframe
from stepframe.structure.frame import AFrame

from .aframe_reference import aframe_reference

#: A frame whose stepped phase holds about 1.6 m/s² (x* = 0.89 m), with strong hysteresis.
STRONG = AFrame(
    omega_1_rad_s=6.0, omega_2_rad_s=1.5, p_1=1.1, p_2=1.2, gamma_1_m_s2=2.0, xi_1=0.15,
    theta_rad=0.2, x_c_m=0.04, c_r=0.85, x_cap_m=0.8,
)  # fmt: skip
#: The frame of test_aframe_hysteretic (weak stepped phase: it holds 0.11 m/s²).
WEAK = AFrame(
    omega_1_rad_s=6.0, omega_2_rad_s=0.7, p_1=1.1, p_2=1.2, gamma_1_m_s2=0.15, xi_1=0.05,
    theta_rad=0.2, x_c_m=0.04, c_r=0.9, x_cap_m=0.6,
)  # fmt: skip


def constant_load(frame: AFrame, a: float, t: np.ndarray) -> tuple[np.ndarray, float, float, float]:
    """x(t) [m] of the unstepped A-frame from rest at 0 under ẍ_g = a, the time it sticks [s],
    where [m] and the largest |x| at its turning points [m]: half cycles in closed form.

    At rest at x_n the frame moves the way F = -ω₁²x_n - P₁a points if |F| > W, with stiffness
    k = ω₁²(1 + πξ₁ d·sign x) (d the direction) about e = -P₁a/k: x = e + (x_n - e)cos(√k τ)
    until it stops again at 2e - x_n. Crossing x = 0 changes k; the motion then continues from
    (0, v₀) about the new e' until ẋ = 0. It stays (|x| < x_c here) once |F| ≤ W.
    """
    w1, p1, h = frame.omega_1_rad_s, frame.p_1, math.pi * frame.xi_1
    pieces = []  # (start time, x0, v0, k, e) of each closed-form piece
    t0, x, peak = 0.0, 0.0, 0.0
    for _ in range(200):
        peak = max(peak, abs(x))
        f = -w1 * w1 * x - p1 * a
        if abs(f) <= h * w1 * w1 * abs(x):
            break
        d = math.copysign(1.0, f)
        sx = math.copysign(1.0, x) if x != 0.0 else d
        k = w1 * w1 * (1.0 + h * d * sx)
        e = -p1 * a / k
        w = math.sqrt(k)
        pieces.append((t0, x, 0.0, k, e))
        x_turn = 2.0 * e - x
        if x != 0.0 and x_turn * x < 0.0:
            # Through x = 0 first: cos(wτ₀) = -e/(x - e).
            tau0 = math.acos(-e / (x - e)) / w
            v0 = -(x - e) * w * math.sin(w * tau0)
            t0 += tau0
            k2 = w1 * w1 * (1.0 + h * d * -sx)
            e2, w2 = -p1 * a / k2, math.sqrt(k2)
            pieces.append((t0, 0.0, v0, k2, e2))
            # 0 = e₂ + R cos(-φ): x - e₂ = R cos(w₂τ - φ), R cos φ = -e₂, R sin φ = v₀/w₂.
            phi = math.atan2(v0 / w2, -e2) % (2.0 * math.pi)
            t0 += (phi if phi > 0 else math.pi) / w2
            x = e2 + math.hypot(e2, v0 / w2) * d
        else:
            t0 += math.pi / w
            x = x_turn
    x_t = np.empty_like(t)
    for j, tj in enumerate(t):
        start = [p for p in pieces if p[0] <= tj]
        if tj >= t0:
            x_t[j] = x
            continue
        ts, xs, vs, k, e = start[-1]
        w = math.sqrt(k)
        tau = tj - ts
        x_t[j] = e + (xs - e) * math.cos(w * tau) + vs / w * math.sin(w * tau)
    return x_t, t0, x, peak


@pytest.mark.parametrize(("frame", "a"), [(STRONG, 0.6), (STRONG, -0.9), (WEAK, 0.5)])
def test_a_constant_load_ends_stuck_where_the_closed_form_says(frame: AFrame, a: float) -> None:
    dt = 0.01
    t = np.arange(0.0, 6.0 + dt / 2, dt)
    x_closed, t_stick, x_stick, peak = constant_load(frame, a, t)
    run = simulate_aframe(frame, np.full(t.size, a), dt, tail_s=0.0, record_history=True)
    assert run.status == "ok" and run.n_liftoffs == 0 and t_stick < 6.0
    assert run.n_sticks == 1
    assert run.first_stick_s == pytest.approx(t_stick, rel=1e-12)
    assert run.residual_x_m == pytest.approx(x_stick, rel=1e-12)
    np.testing.assert_allclose(run.history_x_m, x_closed, rtol=0, atol=1e-14)
    assert run.peak_abs_x_m == pytest.approx(peak, rel=1e-12)


def test_free_decay_with_hysteresis_beyond_its_spring_sticks_at_once() -> None:
    # πξ₁ ≥ 1: released from rest at x₀ the spring force ω₁²x₀ is within the window, it stays.
    frame = AFrame(**{**STRONG.to_dict(), "xi_1": 0.4})
    run = simulate_aframe(frame, np.zeros(101), 0.01, tail_s=0.0, x0_m=0.03)
    assert run.status == "ok" and run.residual_x_m == 0.03 and run.peak_abs_x_m == 0.03
    with pytest.raises(Exception, match="1/π"):
        simulate_aframe(AFrame(**{**STRONG.to_dict(), "xi_1": 1 / math.pi}), np.zeros(3), 0.01)


def slow_harmonic(amplitude: float, burst: float, burst_hz: float) -> tuple[np.ndarray, float]:
    """0.25 Hz ground motion for 8 s with a one-cycle-pair burst at 2 s (ẍ_g [m/s²], dt [s])."""
    dt = 0.01
    t = np.arange(0.0, 8.0 + dt / 2, dt)
    window = (t > 2.0) & (t < 2.0 + 2.0 / burst_hz)
    ag = amplitude * np.sin(0.5 * math.pi * t)
    ag += np.where(window, burst * np.sin(2 * math.pi * burst_hz * (t - 2.0)), 0.0)
    return ag, dt


@pytest.mark.parametrize(
    ("amplitude", "burst", "burst_hz", "sticks", "episodes"),
    [(1.0, 0.0, 1.0, 4, 0), (1.0, 1.0, 1.5, 5, 1), (1.5, 0.5, 1.5, 3, 3), (1.0, 1.25, 1.0, 2, 3)],
)
def test_through_several_sticks_against_an_independent_integrator(
    amplitude: float, burst: float, burst_hz: float, sticks: int, episodes: int
) -> None:
    ag, dt = slow_harmonic(amplitude, burst, burst_hz)
    ref = aframe_reference(STRONG, ag, dt)
    run = simulate_aframe(STRONG, ag, dt, tail_s=0.0, record_history=True)
    assert run.status == "ok" and not run.overturned and not ref.overturned
    assert (run.n_sticks, run.n_liftoffs, run.n_impacts) == (sticks, episodes, episodes)
    assert (len(ref.stick_times_s), ref.n_liftoffs, ref.n_impacts) == (sticks, episodes, episodes)
    assert run.first_stick_s == pytest.approx(ref.stick_times_s[0], abs=1e-9)
    t = np.arange(ag.size) * dt
    before = t < ref.stick_times_s[0]
    diff = np.abs(run.history_x_m - ref.x_m)
    # Before the first stick both are the same smooth solution (the previous integrator too,
    # to 1e-17 m); after it the previous one parted by 1.3e-3 to 9.7e-3 m on these runs.
    assert diff[before].max() < 1e-15
    assert diff[~before].max() < 1e-10
    assert run.peak_abs_x_m == pytest.approx(ref.peak_abs_x_m, rel=1e-10)


def test_peak_while_stepping_is_the_extremum_of_the_phase_solution() -> None:
    # A real record that steps three times: the previous integrator read the stepped peak at the
    # end of its pieces (8e-5 low); the extremum is located as a zero of ẋ.
    from stepframe.records.examples import fema_p695

    trace = fema_p695()[0][2]
    ag = trace.data.astype(float) * 0.5
    ref = aframe_reference(WEAK, ag, trace.stats.delta)
    run = simulate_aframe(WEAK, ag, trace.stats.delta, tail_s=0.0)
    assert run.status == "ok" and run.n_liftoffs == ref.n_liftoffs == 3
    assert run.peak_abs_x_m == pytest.approx(ref.peak_abs_x_m, rel=1e-9)
