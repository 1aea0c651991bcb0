"""Housner's nonlinear rocking block: energy, the quarter period in closed form, the uplift
threshold, and the one-cosine pulse's overturning edges against an independent solve_ivp."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.special import ellipkinc

from stepframe.errors import InputError
from stepframe.structure.frame import RockingBlock
from stepframe.structure.harmonic import simulate_harmonic, simulate_pulse
from stepframe.structure.ida import IdaSettings, ida_pulse
from stepframe.structure.rocking_block import block_harmonic, block_pulse, simulate_block
from stepframe.structure.simulator import simulate
from stepframe.structure.status import small_angle_note

from .block_reference import block_pulse_reference

BLOCK = RockingBlock(0.25, 1.0)
P, ALPHA = BLOCK.p_rad_s, BLOCK.alpha_rad


def quarter_period(theta0: float) -> float:
    """Time from rest at θ₀ (0 < θ₀ < α) to the impact, in closed form.

    ½θ̇² = p²[cos(α - θ₀) - cos(α - θ)]; with ψ = α - θ, sin(ψ/2) = s the time is
    (1/p)∫ ds/√((1 - s²)(s² - k₀²)) from k₀ = sin(ψ₀/2) to sin(α/2), which is F(φ, k)/p with
    k² = 1 - k₀² and sin²φ = (y² - k₀²)/(y²(1 - k₀²)), y = sin(α/2) (Byrd and Friedman 217.00).
    The linearised block's is arccosh(1/(1 - θ₀/α))/p.
    """
    k0 = math.sin(0.5 * (ALPHA - theta0))
    y = math.sin(0.5 * ALPHA)
    phi = math.asin(math.sqrt((y * y - k0 * k0) / (y * y * (1 - k0 * k0))))
    return float(ellipkinc(phi, 1 - k0 * k0)) / P


def first_impact_s(theta0: float) -> float:
    """The kernel's time of the first impact from rest at θ₀, by bisection on the run length."""
    lo, hi = 0.0, 4.0 * quarter_period(theta0)
    for _ in range(55):
        mid = 0.5 * (lo + hi)
        run = simulate_block(BLOCK, np.zeros(2), mid, tail_s=0.0, theta0_rad=theta0)
        lo, hi = (lo, mid) if run.n_impacts else (mid, hi)
    return hi


@pytest.mark.parametrize("fraction", [0.05, 0.5, 0.9, 0.999])
def test_quarter_period_matches_the_elliptic_closed_form(fraction: float) -> None:
    theta0 = fraction * ALPHA
    # Close to the top the time grows like log(1/(α - θ₀)): the tolerance amplifies by as much.
    assert first_impact_s(theta0) == pytest.approx(quarter_period(theta0), rel=5e-9)


def test_energy_is_conserved_between_impacts_and_scaled_by_c_r_squared_at_one() -> None:
    theta0 = 0.8 * ALPHA
    t4 = quarter_period(theta0)
    energy0 = P * P * math.cos(ALPHA - theta0)
    for t in (0.3 * t4, 0.7 * t4, 0.95 * t4):
        run = simulate_block(BLOCK, np.zeros(2), t, tail_s=0.0, theta0_rad=theta0)
        th, w = run.residual_rotation_rad, run.residual_rate_rad_s
        energy = 0.5 * w * w + P * P * math.cos(ALPHA - th)
        assert run.n_impacts == 0 and energy == pytest.approx(energy0, rel=1e-11)
    # Past the impact the kinetic part at θ = 0 is C_r² of what it was.
    run = simulate_block(BLOCK, np.zeros(2), 1.5 * t4, tail_s=0.0, theta0_rad=theta0)
    th, w = run.residual_rotation_rad, run.residual_rate_rad_s
    kinetic_after = 0.5 * w * w + P * P * (math.cos(-ALPHA - th) - math.cos(ALPHA))
    kinetic_before = energy0 - P * P * math.cos(ALPHA)
    assert run.n_impacts == 1 and th < 0
    assert kinetic_after == pytest.approx(BLOCK.restitution**2 * kinetic_before, rel=1e-10)


def minimum_overturning(omega: float, lo: float, hi: float) -> tuple[float, float]:
    """Bracket [survives, overturns] of the kernel's minimum overturning amplitude [g·tan α]."""
    unit = BLOCK.uplift_acceleration_m_s2
    assert not block_pulse(BLOCK, lo * unit, omega).overturned
    assert block_pulse(BLOCK, hi * unit, omega).overturned
    while hi - lo > 1e-7 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if block_pulse(BLOCK, mid * unit, omega).overturned else (mid, hi)
    return lo, hi


@pytest.mark.parametrize(
    ("ratio", "lo", "hi"), [(2.0, 1.3, 1.5), (4.0, 3.2, 3.5), (6.0, 40.0, 46.0)]
)
def test_overturning_edges_of_a_one_cosine_pulse_match_solve_ivp(
    ratio: float, lo: float, hi: float
) -> None:
    survive, overturn = minimum_overturning(ratio * P, lo, hi)
    unit = BLOCK.uplift_acceleration_m_s2
    below = block_pulse_reference(0.25, 1.0, survive * (1 - 1e-5) * unit, ratio * P)
    above = block_pulse_reference(0.25, 1.0, overturn * (1 + 1e-5) * unit, ratio * P)
    assert not below[0] and above[0]
    # The surviving pulse's peak rotation, from both.
    ours = block_pulse(BLOCK, survive * (1 - 1e-5) * unit, ratio * P)
    assert ours.peak_rotation_rad == pytest.approx(below[1], rel=1e-8)


def test_uplift_is_at_g_tan_alpha_not_g_alpha() -> None:
    lift = BLOCK.uplift_acceleration_m_s2
    assert lift == pytest.approx(9.81 * math.tan(ALPHA))
    below = block_pulse(BLOCK, lift * (1 - 1e-9), 2 * P)
    above = block_pulse(BLOCK, lift * (1 + 1e-6), 2 * P)
    assert (below.n_liftoffs, below.peak_rotation_rad) == (0, 0.0)
    assert above.n_liftoffs >= 1 and 0 < above.peak_rotation_rad < 1e-12
    # The linearised block lifts from g·α, 2 % lower for this block.
    linear = simulate_pulse(BLOCK.linearised(), lift * (1 - 1e-9), 2 * P)
    assert linear.peak_abs_x_m > 0


@settings(max_examples=40, deadline=None)
@given(u=st.floats(-15.0, -3.0), side=st.sampled_from([-1.0, 1.0]), ratio=st.floats(1.0, 8.0))
def test_no_impossible_answer_near_uplift(u: float, side: float, ratio: float) -> None:
    delta = side * 10.0**u
    amp = BLOCK.uplift_acceleration_m_s2 * (1 + delta)
    run = block_pulse(BLOCK, amp, ratio * P)
    assert run.status == "ok" and not run.overturned
    if delta < 0:
        assert run.peak_rotation_rad == 0.0 and run.n_liftoffs == 0
    else:
        # The ground pushes it out by at most p²·sin α·δ (at θ = 0) for at most the window
        # 2√(2δ)/ω where the crest is above g·tan α, and it returns within twice that.
        push = P * P * math.sin(ALPHA) * delta
        window = 2 * math.sqrt(2 * delta) / (ratio * P)
        assert run.peak_rotation_rad <= 0.5 * push * (2 * window) ** 2 + 1e-15


def test_a_record_and_a_harmonic_run_and_the_escape_verdicts() -> None:
    from stepframe.records.examples import fema_p695

    trace = fema_p695()[0][2]
    pga = float(np.max(np.abs(trace.data)))
    for level, overturns in ((0.5, False), (0.6, True)):
        scale = level * 9.81 / pga
        run = simulate_block(BLOCK, trace.data, trace.stats.delta, scale=scale, record_history=True)
        assert run.status == "ok" and run.overturned is overturns
        assert run.history_rad is not None and run.history_rad.size == trace.data.size + 1000
        if not overturns:
            assert 0 < run.peak_over_alpha < 1
    steady = block_harmonic(BLOCK, 0.3 * 9.81, 16.0, 20 * 2 * math.pi / 16.0)
    assert steady.status == "ok" and not steady.overturned and steady.n_impacts > 10
    # Free from beyond the top moving out: it overturns; moving in slowly enough: it survives.
    out = simulate_block(BLOCK, np.zeros(2), 0.01, tail_s=0.0, theta0_rad=1.2 * ALPHA)
    assert out.overturned
    back = simulate_block(
        BLOCK, np.zeros(2), 0.01, tail_s=0.0, theta0_rad=0.5 * ALPHA, rate0_rad_s=-0.1 * P
    )
    assert not back.overturned and back.status == "ok"
    with pytest.raises(InputError):
        simulate_block(BLOCK, np.zeros(2), 0.01, theta0_rad=2.0)


def test_ida_of_the_nonlinear_block_brackets_the_edge() -> None:
    settings_ = IdaSettings(
        start=1.0, step=0.5, step_increment=0.25, resolution=1e-3, max_intensity=10.0
    )
    (item,) = ida_pulse(BLOCK, [2 * P], settings=settings_)
    survive, overturn = minimum_overturning(2 * P, 1.3, 1.5)
    assert item.last_survival_below is not None and item.first_overturning is not None
    assert item.last_survival_below <= overturn and survive <= item.first_overturning


def test_linearised_results_say_when_rotations_are_not_small() -> None:
    lin = BLOCK.linearised()
    run = simulate_harmonic(lin, 0.3 * 9.81, 16.0, 20 * 2 * math.pi / 16.0)
    assert run.status == "ok" and "peak rotation" in run.message and "= 0.133 α" in run.message
    t = np.arange(0, 10, 0.01)
    sim = simulate(lin, 0.3 * 9.81 * np.cos(16 * t), 0.01).summary
    assert sim.status == "ok" and "linearised rocking block" in sim.message
    # A slender block rocking to half its α: cos(α/2... ) ≈ 1 within 1 %, no note.
    slender = RockingBlock(0.05, 1.0).linearised()
    assert small_angle_note(0.0, slender.x_star_m, 1.0, 0.5 * slender.x_star_m) == ""
    assert small_angle_note(0.0, slender.x_star_m, 1.0, 4.0 * slender.x_star_m)
    assert small_angle_note(0.05, 0.3, 10.0, 0.29) == ""  # a portal frame: no note
