"""The exact integrator's fast path (``_exact._fast_step``): what it claims holds on the true
solution, it never skips a crossing of x_c or a new peak between samples, and whole runs through it
agree with closed forms and the DOP853 reference.

The true solution of one interval is computed here afresh, by the matrix exponential of the
augmented linear system z = (x, ẋ, 1, σ), ż = A·z (exact for linear forcing), never by the
kernel's formulas.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from scipy.linalg import expm

from stepframe.records.examples import fema_p695
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure import _exact
from stepframe.structure.frame import PortalFrame
from stepframe.structure.simulator import simulate

W1, P1 = 6.4581, 1.0901  # Example 4's unstepped phase
N_GRID = 400


def frame(**changes: Any) -> PortalFrame:
    base = {
        "omega_1_rad_s": W1, "omega_2_rad_s": 0.6445, "p_1": P1, "p_2": 1.2680,
        "gamma_1_m_s2": 0.1387, "xi_1": 0.05, "xi_2": 0.0, "x_c_m": 0.05, "c_r": 0.9,
    }  # fmt: skip
    return PortalFrame(**{**base, **changes})


def true_path(x: float, v: float, beta: float, k: float, q0: float, q1: float,
              dt: float) -> np.ndarray:  # fmt: skip
    """x on N_GRID + 1 equal steps of [0, dt] of ẍ + 2βẋ + k·x = q₀ + q₁σ."""
    a = np.zeros((4, 4))
    a[0, 1] = 1.0
    a[1] = (-k, -2.0 * beta, q0, q1)
    a[3, 2] = 1.0
    step = expm(a * (dt / N_GRID))
    z = np.array([x, v, 1.0, 0.0])
    out = np.empty(N_GRID + 1)
    for j in range(N_GRID + 1):
        out[j] = z[0]
        z = step @ z
    return out


def fast_step(x: float, v: float, ag_a: float, slope: float, xi: float, dt: float,
              lim_x: float, peak: float) -> tuple[float, float, int]:  # fmt: skip
    """The kernel's test of the unstepped phase, with the constants integrate derives."""
    beta, k = xi * W1, W1 * W1
    disc = W1 * W1 * (xi - 1.0) * (xi + 1.0)
    bound = _exact._bound_constants(beta, k, disc, dt)
    return _exact._fast_step(x, v, -P1 * ag_a, -P1 * slope, beta, k, bound, -lim_x, lim_x, peak)


@pytest.mark.parametrize("xi", [0.0, 0.05, 1.0, 2.0])
@pytest.mark.parametrize("dt", [0.005, 0.02, 0.1])
def test_fast_step_claims_hold_on_the_true_solution(xi: float, dt: float) -> None:
    """Random states and forcing; x_c and the running peak put just above or just below the
    interval's true largest |x| (the grazing and the new-peak traps) or well clear of it."""
    rng = np.random.default_rng(29)
    kinds = np.zeros(3, dtype=int)
    for _ in range(150):
        x, v = rng.normal(0.0, 0.02), rng.normal(0.0, 0.02 * W1)
        ag_a, slope = rng.normal(0.0, 0.5), rng.normal(0.0, 0.5 / dt)
        path = true_path(x, v, xi * W1, W1 * W1, -P1 * ag_a, -P1 * slope, dt)
        top = float(np.max(np.abs(path)))
        ends = max(abs(path[0]), abs(path[-1]))
        for lim_x, peak in (
            (top * (1.0 - 1e-7), 10.0),  # grazes x_c between samples (if not at an end)
            (top * (1.0 + 1e-3), top * (1.0 - 1e-7)),  # a new peak, by a hair
            (top * 1.5, top * 1.1),  # clear of both
            (top * 1.5, ends * (1.0 + 1e-9)),  # peak at the larger end: interior max above?
        ):
            x_b, _, kind = fast_step(x, v, ag_a, slope, xi, dt, lim_x, peak)
            assert x_b == pytest.approx(path[-1], rel=1e-9, abs=1e-15)
            kinds[kind] += 1
            if kind == 0:
                continue
            # Never past x_c, nor (kind 1) past the peak, anywhere inside.
            assert top < lim_x
            if kind == 1:
                assert top < peak
            else:
                steps = np.diff(path)
                assert np.all(steps >= 0.0) or np.all(steps <= 0.0)
                assert top == ends
    # Each kind is exercised: the test cannot pass by always declining.
    assert np.all(kinds > 0), kinds


@pytest.mark.parametrize("xi_2", [0.0, 0.1])
@pytest.mark.parametrize("dt", [0.005, 0.02])
def test_stepped_phase_claims_hold_on_the_true_solution(xi_2: float, dt: float) -> None:
    """The stepped phase on side +1 (k = -ω₂², forcing -γ₁ - P₂ẍ_g): touchdown at x_c and the
    cap a hair inside or outside the interval's true range, the episode's peak likewise."""
    w2, p2, g1 = 0.6445, 1.2680, 0.1387
    beta, k = xi_2 * w2, -(w2**2)
    bound = _exact._bound_constants(beta, k, w2 * w2 * (xi_2 * xi_2 + 1.0), dt)
    rng = np.random.default_rng(5)
    kinds = np.zeros(3, dtype=int)
    for _ in range(100):
        x, v = rng.uniform(0.06, 0.5), rng.normal(0.0, 0.1)
        ag_a, slope = rng.normal(0.0, 1.0), rng.normal(0.0, 1.0 / dt)
        q0, q1 = -g1 - p2 * ag_a, -p2 * slope
        path = true_path(x, v, beta, k, q0, q1, dt)
        low, high = float(path.min()), float(path.max())
        ends = (min(path[0], path[-1]), max(path[0], path[-1]))
        for lo, hi, top in (
            (low * 0.5, 10.0, 10.0),  # clear of the thresholds and the peak
            (low * (1 + 1e-7), 10.0, 10.0),  # a touchdown grazed between samples
            (0.0, high * (1 - 1e-7), 10.0),  # the cap reached between samples
            (0.0, 10.0, high * (1 - 1e-7)),  # a new episode peak, by a hair
            (0.0, 10.0, ends[1] * (1 + 1e-9)),  # peak at the larger end
        ):
            x_b, _, kind = _exact._fast_step(x, v, q0, q1, beta, k, bound, lo, hi, top)
            assert x_b == pytest.approx(path[-1], rel=1e-9, abs=1e-15)
            kinds[kind] += 1
            if kind == 0:
                continue
            assert lo < low and high < hi
            if kind == 1:
                assert high < top
            else:
                steps = np.diff(path)
                assert np.all(steps >= 0.0) or np.all(steps <= 0.0)
                assert (low, high) == ends
    assert np.all(kinds > 0), kinds


def test_chord_bound_passes_what_the_envelope_did_not() -> None:
    """Near a (decayed) extremum, 1 % below the running peak, at ω₁dt = 0.13: the envelope
    |x_p| + amplitude reaches the peak; the chord bound (slack ω₁²·amplitude·dt²/8, 0.2 % of it)
    does not. Free vibration, no forcing: x = A·cos(ω₁σ) about the extremum at σ = dt/2."""
    dt, amp = 0.02, 0.01
    xi = 0.0
    x = amp * math.cos(W1 * dt / 2)
    v = amp * W1 * math.sin(W1 * dt / 2)
    _, _, kind = fast_step(x, v, 0.0, 0.0, xi, dt, 0.05, amp * 1.01)
    assert kind == 1
    # The slack is ω₁²A·dt²/8: a peak that close above the end values is declined.
    slack = W1**2 * amp * dt**2 / 8
    _, _, kind = fast_step(x, v, 0.0, 0.0, xi, dt, 0.05, x + 0.99 * slack)
    assert kind == 0
    _, _, kind = fast_step(x, v, 0.0, 0.0, xi, dt, 0.05, x + 1.01 * slack)
    assert kind == 1


@pytest.mark.parametrize("dt", [0.005, 0.02])
def test_decaying_free_vibration_peak_between_samples(dt: float) -> None:
    """x = (v₀/ω_d)e^{-βt}sin(ω_d t): the largest |x| is the first extremum, at
    tan(ω_d t) = ω_d/β, between samples; every later one is lower (the near-peak intervals the
    chord bound lets through)."""
    xi, v0 = 0.05, 0.2
    f = frame(xi_1=xi, x_c_m=0.3)
    beta, wd = xi * W1, W1 * math.sqrt(1 - xi**2)
    t_top = math.atan(wd / beta) / wd
    top = v0 / wd * math.exp(-beta * t_top) * math.sin(wd * t_top)
    result = simulate(f, np.zeros(2), dt, v0_m_s=v0, tail_s=10.0)
    assert result.summary.n_stepping_episodes == 0
    assert result.summary.peak_abs_x_m == pytest.approx(top, rel=1e-13)
    assert result.summary.peak_time_s == pytest.approx(t_top, abs=1e-10)
    assert abs(t_top / dt - round(t_top / dt)) > 0.1  # the peak is between samples


def test_growing_resonance_new_peak_between_samples() -> None:
    """Undamped, forced at ω₁: each extremum is a new peak, reached between samples after
    intervals the monotone test passes. Peak and its time against the DOP853 reference."""
    f = frame(xi_1=0.0, x_c_m=0.3)
    dt = 0.02
    t = np.arange(800) * dt
    ag = 0.05 * np.sin(W1 * t)
    exact = simulate(f, ag, dt, tail_s=1.0)
    ref = simulate(f, ag, dt, tail_s=1.0, method="DOP853", rtol=1e-12, atol=1e-15)
    assert exact.summary.n_stepping_episodes == ref.summary.n_stepping_episodes == 0
    assert exact.summary.peak_abs_x_m == pytest.approx(ref.summary.peak_abs_x_m, rel=1e-9)
    assert exact.summary.peak_time_s == pytest.approx(ref.summary.peak_time_s, abs=1e-8)
    assert abs(exact.summary.peak_time_s / dt - round(exact.summary.peak_time_s / dt)) > 1e-3
    assert exact.history is not None and ref.history is not None
    np.testing.assert_allclose(exact.history["x"], ref.history["x"], rtol=0, atol=1e-10)


@pytest.mark.parametrize("where", [0.1, 0.5, 0.9])
@pytest.mark.parametrize(("excess", "lifts"), [(1e-6, True), (-1e-6, False)])
def test_grazing_x_c_between_samples_at_a_fine_dt(where: float, excess: float, lifts: bool) -> None:
    """Undamped free vibration x = A·sin(ω₁(t - t₀)) with A = x_c(1 ± 10⁻⁶) and its extremum at
    ``where`` of an interval of 0.01 s, both samples below x_c: just over x_c lifts off at the
    closed-form time; just under does not, and its peak is A."""
    dt = 0.01
    f = frame(xi_1=0.0, c_r=1.0)
    amp = f.x_c_m * (1.0 + excess)
    t_top = (40 + where) * dt  # the extremum, inside interval 40
    phase0 = math.pi / 2 - W1 * t_top
    x0, v0 = amp * math.sin(phase0), amp * W1 * math.cos(phase0)
    # Both samples of the interval below x_c: the excursion lies between them.
    assert amp * max(math.cos(W1 * where * dt), math.cos(W1 * (1 - where) * dt)) < f.x_c_m
    result = simulate(f, np.zeros(2), dt, x0_m=x0, v0_m_s=v0, tail_s=0.8)
    if lifts:
        assert result.summary.n_stepping_episodes == 1
        t_lift = t_top - math.acos(f.x_c_m / amp) / W1
        assert result.switching_times_s[0] == pytest.approx(t_lift, abs=1e-10)
        assert result.summary.peak_abs_x_m > f.x_c_m
    else:
        assert result.summary.n_stepping_episodes == 0
        assert result.summary.peak_abs_x_m == pytest.approx(amp, rel=1e-12)
        assert result.summary.peak_time_s == pytest.approx(t_top, abs=1e-9)


@pytest.fixture(scope="module")
def records() -> Any:
    stream, _ = fema_p695()
    return stream


# (catalogue index, scale, what happens): elastic runs (RSN 169 a peaks at 0.86 x_c: many
# intervals near x_c), runs that step and impact (RSN 960 a at dt 0.01 s, RSN 174 b at 0.005 s),
# and one that overturns past the cap after five impacts (RSN 960 b).
RUNS = [
    (2, 0.02, "elastic"), (8, 0.05, "elastic"), (2, 0.1, "step"), (11, 0.1, "step"),
    (3, 0.25, "overturn"),
]  # fmt: skip


@pytest.mark.parametrize(("index", "scale", "what"), RUNS)
def test_fema_runs_agree_with_dop853(records: Any, index: int, scale: float, what: str) -> None:
    trace = records[index]
    ag, dt = trace.data.astype(float) * STANDARD_GRAVITY_M_S2, float(trace.stats.delta)
    f = frame(x_cap_m=0.6)
    exact = simulate(f, ag, dt, scale=scale, tail_s=3.0)
    ref = simulate(f, ag, dt, scale=scale, tail_s=3.0, method="DOP853", rtol=1e-12, atol=1e-15)
    assert exact.summary.status == ref.summary.status == "ok"
    assert (exact.summary.n_stepping_episodes > 0) is (what != "elastic")
    assert exact.summary.overturned is ref.summary.overturned is (what == "overturn")
    assert exact.summary.peak_abs_x_m == pytest.approx(ref.summary.peak_abs_x_m, rel=1e-9)
    assert exact.summary.n_impacts == ref.summary.n_impacts
    np.testing.assert_allclose(exact.switching_times_s, ref.switching_times_s, rtol=0, atol=1e-8)
    if what == "overturn":
        assert exact.summary.overturn_time_s == pytest.approx(ref.summary.overturn_time_s, abs=1e-8)
    else:
        # (Past the cap the peak is the cap, wherever the reference dates it.)
        assert exact.summary.peak_time_s == pytest.approx(ref.summary.peak_time_s, abs=1e-8)
    if what != "elastic":
        assert exact.summary.n_impacts > 0
