"""ω_f(t) and the ground's work from the simulated history, against closed forms."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

from stepframe.structure.frame import PortalFrame
from stepframe.structure.frame_frequency import (
    backbone_of,
    energy,
    potential,
    swing_frequency_rad_s,
)
from stepframe.structure.period_amplitude import quarter_periods_s
from stepframe.structure.simulator import simulate

# A conservative frame with room to step: x* = 4 x_c.
FREE = PortalFrame(omega_1_rad_s=6.4581, omega_2_rad_s=0.6445, p_1=1.1884, p_2=1.1884,
                   gamma_1_m_s2=0.3178, xi_1=0.0, xi_2=0.0, x_c_m=0.19, c_r=1.0)  # fmt: skip


def period_by_quadrature(frame: PortalFrame, amplitude: float) -> float:
    """T(A) = 4 ∫_0^A dx / √(2(V(A) - V(x))), by quadrature of the potential (independent of the
    law's closed form). On the stepped part V(A) - V(x) = (A - x)(γ₁ - ω₂²(A + x)/2): the
    (A - x)^(-1/2) singularity is quad's algebraic weight."""
    backbone = backbone_of(simulate(frame, np.zeros(2), 0.01, tail_s=0.0).model)  # type: ignore[arg-type]
    top = float(potential(np.array([amplitude]), backbone)[0])
    g1, w2 = frame.gamma_1_m_s2, frame.omega_2_rad_s

    def unstepped(y: float) -> float:
        return 1.0 / math.sqrt(2.0 * (top - 0.5 * frame.omega_1_rad_s**2 * y * y))

    def stepped(y: float) -> float:
        return 1.0 / math.sqrt(2.0 * (g1 - 0.5 * w2**2 * (amplitude + y)))

    inner = quad(unstepped, 0.0, frame.x_c_m, epsabs=0.0, epsrel=1e-12)[0]
    outer = quad(stepped, frame.x_c_m, amplitude, weight="alg", wvar=(0.0, -0.5),
                 epsabs=0.0, epsrel=1e-12)[0]  # fmt: skip
    return 4.0 * (inner + outer)


@pytest.mark.parametrize("ratio", [1.3, 2.0, 3.6])
def test_a_free_stepping_cycle_has_the_law_s_frequency(ratio: float) -> None:
    amplitude = ratio * FREE.x_c_m
    period = period_by_quadrature(FREE, amplitude)
    result = simulate(FREE, np.zeros(2), 0.01, x0_m=amplitude, tail_s=4.2 * period)
    omega = result.frame_frequency
    assert omega is not None
    # Every swing measured from its own zero crossings, and the law at the start.
    assert np.allclose(omega.values, 2 * math.pi / period, rtol=2e-7, atol=0.0)
    assert np.allclose(omega["omega_law"].values, 2 * math.pi / period, rtol=2e-7, atol=0.0)
    assert np.allclose(omega["amplitude"].values, amplitude, rtol=1e-7)
    assert omega.attrs["units"] == "rad/s"


def test_an_impact_lengthens_the_return_as_the_law_and_the_impact_rule_say() -> None:
    # C_r < 1, no damping: each stepping half-cycle goes out at amplitude A (quarter period
    # t₁(A) + t₂(A)) and comes back through a touchdown that multiplies the speed by C_r, so its
    # unstepped return takes arcsin(x_c/B')/ω₁ with B' = √(x_c² + (C_r v_c/ω₁)²).
    frame = PortalFrame(**{**FREE.to_dict(), "c_r": 0.9})
    result = simulate(frame, np.zeros(2), 0.01, x0_m=3.0 * frame.x_c_m, tail_s=40.0)
    omega = result.frame_frequency
    assert omega is not None
    w1, w2, x_c, x_star = 6.4581, 0.6445, frame.x_c_m, frame.x_star_m
    checked = 0
    for episode in result.episode_records()[:-1]:
        a = episode["peak_abs_x_m"]
        t_in, t_step = (float(part) for part in quarter_periods_s(frame, a))
        v_c = w2 * math.sqrt((a - x_c) * ((x_star - x_c) + (x_star - a)))
        back = math.asin(x_c / math.hypot(x_c, 0.9 * v_c / w1)) / w1
        expected = math.pi / (t_in + 2 * t_step + back)
        mid = 0.5 * (episode["start_s"] + episode["end_s"])
        assert omega.sel(time=mid, method="nearest").item() == pytest.approx(expected, rel=1e-6)
        checked += 1
    assert checked >= 3


def test_linear_motion_is_at_omega_1_however_it_is_forced() -> None:
    frame = PortalFrame(**{**FREE.to_dict(), "xi_1": 0.05, "c_r": 0.9})
    t = np.arange(0, 30, 0.01)
    for forcing in (0.8 * np.sin(2.0 * 6.4581 * t), 0.3 * np.sin(0.4 * t)):
        result = simulate(frame, forcing, 0.01)
        assert result.summary.n_stepping_episodes == 0
        assert result.summary.peak_abs_x_m < frame.x_c_m
        omega = result.frame_frequency
        assert omega is not None
        assert np.all(omega.values == frame.omega_1_rad_s)


def test_the_ground_s_work_balances_the_frame_s_energy_and_the_impacts() -> None:
    # Without damping, E(end) - E(0) = work of the ground - ½ Σ (v_in² - v_out²) at touchdowns.
    # The cubic through x and ẋ is exact between switches; an interval holding a lift-off or a
    # touchdown (a jump of ẍ, of ẋ at an impact, of P) is not, which the tolerance allows for.
    rng = np.random.default_rng(1)
    ground = np.convolve(rng.standard_normal(4000), np.hanning(40), "same") * 0.14
    for p_2, c_r, tolerance in ((1.1884, 1.0, 3e-3), (1.1884, 0.9, 3e-3), (1.268, 0.9, 3e-3)):
        frame = PortalFrame(**{**FREE.to_dict(), "p_2": p_2, "c_r": c_r,
                               "gamma_1_m_s2": 8 * 0.1387})  # fmt: skip
        result = simulate(frame, ground, 0.01, tail_s=5.0)
        assert result.summary.n_stepping_episodes >= 5
        assert not result.summary.overturned
        history, work = result.history, result.input_energy
        assert history is not None and work is not None and result.model is not None
        e = energy(history["x"].values, history["v"].values, backbone_of(result.model))
        touchdowns = result.events[result.events["kind"] == "touchdown"]
        lost = 0.5 * float(np.sum(touchdowns["v_in_m_s"] ** 2 - touchdowns["v_out_m_s"] ** 2))
        assert e[-1] - e[0] == pytest.approx(float(work.values[-1]) - lost, rel=tolerance)
        # Between switches the balance holds to rounding: before the first lift-off.
        first = int(result.events["time_s"].iloc[0] / 0.01)
        assert e[first] - e[0] == pytest.approx(float(work.values[first]), rel=1e-7)
        assert work.attrs["units"] == "m2/s2"


def test_after_overturning_there_is_no_frequency_and_no_more_work() -> None:
    t = np.arange(0, 20, 0.01)
    frame = PortalFrame(**{**FREE.to_dict(), "x_cap_m": 1.5})
    result = simulate(frame, 6.0 * np.sin(3.0 * t), 0.01)
    assert result.summary.overturned
    omega, work = result.frame_frequency, result.input_energy
    assert omega is not None and work is not None
    after = omega["time"].values > result.summary.overturn_time_s
    assert np.all(np.isnan(omega.values[after]))
    assert np.all(work.values[after] == work.values[after][0])
    # Before it, on the last excursion, the law's frequency falls to 0: no orbit to return on.
    assert np.nanmin(omega.values) == 0.0


def test_swing_frequency_needs_no_result() -> None:
    # The array function behind the property: a state released at rest at A in the unstepped
    # phase swings at ω₁.
    backbone = backbone_of(simulate(FREE, np.zeros(2), 0.01, tail_s=0.0).model)  # type: ignore[arg-type]
    t = np.arange(0, 5, 0.01)
    x, v = 0.1 * np.cos(6.4581 * t), -0.1 * 6.4581 * np.sin(6.4581 * t)
    omega, amplitude, law = swing_frequency_rad_s(x, v, np.zeros(t.size, np.int8), 0.01, backbone)
    assert np.all(omega == 6.4581)
    assert np.allclose(amplitude, 0.1, rtol=1e-8)
    assert np.allclose(law, 6.4581, rtol=1e-12)


def test_the_law_at_the_edges_only_gives_the_same_frequency() -> None:
    # law_everywhere=False (the index's path) evaluates A(t) and the law before the first zero
    # crossing and after the last only: ω_f must be the same to the bit, on a run that steps
    # many times and on one that overturns; A and the law are NaN between, given at the edges.
    rng = np.random.default_rng(1)
    ground = np.convolve(rng.standard_normal(4000), np.hanning(40), "same") * 0.14
    frame = PortalFrame(**{**FREE.to_dict(), "gamma_1_m_s2": 8 * 0.1387})
    for scale in (1.0, 6.0):
        result = simulate(frame, ground, 0.01, scale=scale, tail_s=5.0)
        assert result.model is not None and result.raw.hist_x.size
        raw, backbone = result.raw, backbone_of(result.model)
        n = (
            raw.hist_x.size
            if not result.summary.overturned
            else int(
                result.summary.overturn_time_s / 0.01  # type: ignore[operator]
            )
        )
        args = (raw.hist_x[:n], raw.hist_v[:n], raw.hist_p[:n], 0.01, backbone)
        full = swing_frequency_rad_s(*args, overturns=result.summary.overturned)
        edges = swing_frequency_rad_s(
            *args, overturns=result.summary.overturned, law_everywhere=False
        )
        assert np.array_equal(full[0], edges[0])
        given = ~np.isnan(edges[1])
        assert 0 < given.sum() < n
        assert np.array_equal(full[1][given], edges[1][given])
        assert np.array_equal(full[2][given], edges[2][given])


def crossings_by_numpy(x: np.ndarray, v: np.ndarray, dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Zero crossings written with numpy, independently of the kernel: the sign changes of
    x > 0, each at the linear interpolation refined by one Newton step on the Hermite cubic."""
    positive = x > 0.0
    i = np.flatnonzero(positive[:-1] != positive[1:])
    x0, x1, h0, h1 = x[i], x[i + 1], dt * v[i], dt * v[i + 1]
    s = x0 / (x0 - x1)
    cubic = ((2 * s**3 - 3 * s**2 + 1) * x0 + (s**3 - 2 * s**2 + s) * h0
             + (3 * s**2 - 2 * s**3) * x1 + (s**3 - s**2) * h1)  # fmt: skip
    slope = ((6 * s**2 - 6 * s) * (x0 - x1) + (3 * s**2 - 4 * s + 1) * h0
             + (3 * s**2 - 2 * s) * h1)  # fmt: skip
    with np.errstate(divide="ignore", invalid="ignore"):
        refined = s - cubic / slope
    s = np.where(np.isfinite(refined) & (refined >= 0.0) & (refined <= 1.0), refined, s)
    return i, (i + s) * dt


def turning_points_by_numpy(
    x: np.ndarray, v: np.ndarray, dt: float
) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """Turning points written with numpy: where ẋ changes sign strictly, the zero of the Hermite
    cubic's derivative inside the interval, by the quadratic formula."""
    i = np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0)
    x0, x1, h0, h1 = x[i], x[i + 1], dt * v[i], dt * v[i + 1]
    a = 6.0 * (x0 - x1) + 3.0 * (h0 + h1)
    b = -6.0 * (x0 - x1) - 4.0 * h0 - 2.0 * h1
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = np.sqrt(np.maximum(b * b - 4.0 * a * h0, 0.0))
        roots = np.stack([(-b + disc) / (2 * a), (-b - disc) / (2 * a)])
    inside = (roots >= 0.0) & (roots <= 1.0)
    linear = h0 / (h0 - h1)
    s = np.where(inside[0], roots[0], np.where(inside[1], roots[1], linear))
    value = ((2 * s**3 - 3 * s**2 + 1) * x0 + (s**3 - 2 * s**2 + s) * h0
             + (3 * s**2 - 2 * s**3) * x1 + (s**3 - s**2) * h1)  # fmt: skip
    return (i + s) * dt, np.abs(value)


def test_crossings_and_turning_points_match_a_numpy_computation() -> None:
    from stepframe.structure.frame_frequency import turning_points, zero_crossings

    # A swing with a hold (ẋ = 0 for 30 samples) and samples exactly at zero.
    t = np.arange(0.0, 20.0, 0.01)
    x = 0.3 * np.sin(1.7 * t) * np.exp(-0.05 * t) + 0.01 * np.sin(9.1 * t)
    v = 0.3 * (1.7 * np.cos(1.7 * t) - 0.05 * np.sin(1.7 * t)) * np.exp(-0.05 * t)
    v += 0.091 * np.cos(9.1 * t)
    v[700:730] = 0.0
    x[700:730] = x[700]
    x[[0, 400, 401]] = 0.0
    i, z = zero_crossings(x, v, 0.01)
    i_np, z_np = crossings_by_numpy(x, v, 0.01)
    assert np.array_equal(i, i_np) and i.size > 10
    assert np.allclose(z, z_np, rtol=1e-13, atol=1e-15)
    turns_t, turns_a = turning_points(x, v, 0.01)
    np_t, np_a = turning_points_by_numpy(x, v, 0.01)
    assert turns_t.size == np_t.size > 10
    assert np.allclose(turns_t, np_t, rtol=1e-10, atol=1e-12)
    assert np.allclose(turns_a, np_a, rtol=1e-10, atol=1e-12)


def test_the_amplitude_at_any_samples_reads_the_turning_points_either_side() -> None:
    # swing_amplitude_m looks for turning points only around the samples it is asked about (the
    # index asks for the two ends of a long history): at any set of samples, ascending or not,
    # it must equal the interpolation over every turning point, written here with numpy.
    from stepframe.structure.frame_frequency import energy_amplitude_m, swing_amplitude_m

    rng = np.random.default_rng(7)
    t = np.arange(0.0, 30.0, 0.01)
    x = 0.25 * np.sin(1.3 * t) * np.exp(-0.03 * t) + 0.004 * rng.standard_normal(t.size)
    v = np.gradient(x, 0.01)
    v[1200:1240] = 0.0  # a hold: no turning point inside it
    backbone = backbone_of(simulate(FREE, np.zeros(3), 0.01).model)  # type: ignore[arg-type]
    turns_t, turns_a = turning_points_by_numpy(x, v, 0.01)
    later = turns_t > 0.0
    start = min(float(energy_amplitude_m(x[:1], v[:1], backbone)[0]), backbone.x_star_m)
    knots_t, knots_a = np.r_[0.0, turns_t[later]], np.r_[start, turns_a[later]]
    head_and_tail = np.r_[np.arange(40), np.arange(2900, t.size)]
    sparse = np.sort(rng.choice(t.size, 50, replace=False))
    shuffled = rng.permutation(t.size)[:200]
    for at in (head_and_tail, sparse, shuffled, np.array([t.size - 1]), np.arange(t.size)):
        amplitude = swing_amplitude_m(x, v, 0.01, backbone, at=at)
        assert np.allclose(amplitude, np.interp(at * 0.01, knots_t, knots_a), rtol=1e-10)
