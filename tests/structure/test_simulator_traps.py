"""Known traps of stepping simulation: events on sample times, grazing, C_r = 0 and 1, ξ = 0
and ξ ≥ 1, very stiff K_a, dt from 1e-4 to 0.02 s, a 10⁶-sample record, escape near the
separatrix, bad input. Expected values are closed forms or the solve_ivp reference."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.records.examples import fema_p695
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure.frame import PortalFrame
from stepframe.structure.simulator import simulate, simulate_batch

BASE = {
    "omega_1_rad_s": 6.4581,
    "omega_2_rad_s": 0.6445,
    "p_1": 1.0901,
    "p_2": 1.2680,
    "gamma_1_m_s2": 0.1387,
    "xi_1": 0.05,
    "xi_2": 0.0,
    "x_c_m": 0.05,
    "c_r": 0.9,
}


def frame(**changes: Any) -> PortalFrame:
    return PortalFrame(**{**BASE, **changes})


@pytest.fixture(scope="module")
def motion() -> tuple[np.ndarray, float]:
    """RSN 960 component a (FEMA P695 far-field set), first 12 s, in m/s²."""
    stream, _ = fema_p695()
    trace = stream[2]
    return trace.data[:1201].astype(float) * STANDARD_GRAVITY_M_S2, float(trace.stats.delta)


def _reference_check(f: PortalFrame, ag: np.ndarray, dt: float, scale: float) -> Any:
    exact = simulate(f, ag, dt, scale=scale, tail_s=2.0)
    ref = simulate(f, ag, dt, scale=scale, tail_s=2.0, method="DOP853", rtol=1e-12, atol=1e-15)
    assert exact.summary.n_stepping_episodes > 0
    assert exact.summary.overturned == ref.summary.overturned
    assert exact.summary.peak_abs_x_m == pytest.approx(ref.summary.peak_abs_x_m, rel=1e-9)
    assert exact.switching_times_s.size == ref.switching_times_s.size
    np.testing.assert_allclose(exact.switching_times_s, ref.switching_times_s, atol=1e-8, rtol=0)
    return exact


def test_lift_off_at_time_zero_from_the_surface() -> None:
    f = frame()
    ag = np.zeros(3)
    result = simulate(f, ag, 0.01, x0_m=f.x_c_m, v0_m_s=0.1, tail_s=5.0)
    assert result.events["kind"].iloc[0] == "liftoff"
    assert result.events["time_s"].iloc[0] == 0.0
    # Unforced stepped phase, ξ₂ = 0: touchdown when x* + (x_c - x*)cosh(ω₂t) + (v₀/ω₂)sinh(ω₂t)
    # returns to x_c, i.e. tanh(ω₂t/2) = v₀/(ω₂(x* - x_c)).
    w2 = f.omega_2_rad_s
    t_td = 2.0 * math.atanh(0.1 / (w2 * (f.x_star_m - f.x_c_m))) / w2
    assert result.switching_times_s[1] == pytest.approx(t_td, rel=1e-12)
    assert result.impact_velocities_m_s[0] == pytest.approx(-0.1, rel=1e-12)


def test_event_exactly_on_a_sample_time_is_found_once() -> None:
    f = frame(xi_1=0.0)
    w1 = f.omega_1_rad_s
    v0 = w1 * f.x_c_m / math.sin(w1 * 0.1)  # x = (v0/ω₁) sin(ω₁t) reaches x_c at t = 0.1 s
    result = simulate(f, np.zeros(2), 0.01, v0_m_s=v0, tail_s=0.5)
    lifts = result.events[result.events["kind"] == "liftoff"]["time_s"].to_numpy()
    assert lifts[0] == pytest.approx(0.1, abs=1e-13)
    assert np.all(np.diff(result.switching_times_s) > 1e-3)


def test_grazing_excursion_between_samples_is_not_missed() -> None:
    f = frame(xi_1=0.0)
    w1 = f.omega_1_rad_s
    amplitude = f.x_c_m * (1.0 + 1e-6)
    # Coarse dt: samples at 0.2 and 0.4 s straddle the peak at π/(2ω₁) = 0.243 s, both below x_c.
    result = simulate(f, np.zeros(2), 0.2, v0_m_s=amplitude * w1, tail_s=0.4)
    assert result.history is not None
    assert np.all(np.abs(result.history["x"].to_numpy()[:3]) < f.x_c_m)
    assert result.summary.n_stepping_episodes == 1 and result.summary.n_impacts == 1
    t_lift = math.asin(f.x_c_m / amplitude) / w1
    assert result.switching_times_s[0] == pytest.approx(t_lift, abs=1e-10)
    # ξ₂ = 0, no forcing: the stepped phase returns with the velocity it left with.
    v_lift = amplitude * w1 * math.cos(w1 * t_lift)
    assert result.impact_velocities_m_s[0] == pytest.approx(-v_lift, rel=1e-6)
    assert result.summary.peak_abs_x_m > f.x_c_m


def test_c_r_zero_comes_to_rest_on_the_surface_then_rings_down() -> None:
    f = frame(c_r=0.0)
    x0 = 0.1
    result = simulate(f, np.zeros(2), 0.01, x0_m=x0, tail_s=6.0)
    w2, xs = f.omega_2_rad_s, f.x_star_m
    t_td = math.acosh((xs - f.x_c_m) / (xs - x0)) / w2
    assert result.summary.n_impacts == 1
    assert result.switching_times_s[0] == pytest.approx(t_td, rel=1e-12)
    assert result.events["v_out_m_s"].iloc[0] == 0.0
    # Afterwards: damped free vibration of the unstepped phase from rest at x_c.
    w1, xi = f.omega_1_rad_s, f.xi_1
    wd = w1 * math.sqrt(1 - xi**2)
    assert result.history is not None
    times = result.history["time"].to_numpy()
    late = times > t_td + 0.05
    tau = times[late] - t_td
    closed = f.x_c_m * np.exp(-xi * w1 * tau) * (np.cos(wd * tau) + xi * w1 / wd * np.sin(wd * tau))
    np.testing.assert_allclose(result.history["x"].to_numpy()[late], closed, atol=1e-12)


def test_c_r_one_and_no_damping_conserve_the_orbit() -> None:
    f = frame(c_r=1.0, xi_1=0.0)
    result = simulate(f, np.zeros(2), 0.01, x0_m=0.1, tail_s=40.0)
    complete = result.episodes[np.isfinite(result.episodes["end_s"])]
    peaks = complete["peak_abs_x_m"].to_numpy()
    assert peaks.size >= 4
    np.testing.assert_allclose(peaks, 0.1, rtol=1e-9)
    starts = complete["start_s"].to_numpy()
    np.testing.assert_allclose(np.diff(np.diff(starts)), 0.0, atol=1e-9)


@pytest.mark.parametrize("xi_1", [1.0, 2.0])
def test_over_and_critically_damped_unstepped_phase(motion: Any, xi_1: float) -> None:
    ag, dt = motion
    _reference_check(frame(xi_1=xi_1, xi_2=0.3), ag, dt, scale=0.35)


def test_continuity_through_critical_damping(motion: Any) -> None:
    ag, dt = motion
    peaks = [
        simulate(frame(xi_1=xi), ag, dt, scale=0.35, record_history=False).summary.peak_abs_x_m
        for xi in (1.0 - 1e-9, 1.0, 1.0 + 1e-9)
    ]
    np.testing.assert_allclose(peaks, peaks[1], rtol=1e-6)


def test_very_stiff_unstepped_phase(motion: Any) -> None:
    ag, dt = motion
    # ω₁ = 2000 rad/s: about 3 undamped periods per sample interval.
    stiff = frame(omega_1_rad_s=2000.0, x_c_m=1e-7, xi_1=0.02)
    _reference_check(stiff, ag[:400], dt, scale=0.1)


@pytest.mark.parametrize(("scale", "overturns"), [(0.1, False), (0.2, True)])
def test_same_motion_at_dt_from_1e_4_to_0_02(motion: Any, scale: float, overturns: bool) -> None:
    ag, _ = motion
    coarse = ag[::2]  # a piecewise-linear motion on a 0.02 s grid
    t_coarse = np.arange(coarse.size) * 0.02
    # With a cap the overturn is located exactly; without one the verdict falls on the sample
    # at which escape became certain, which depends on dt by construction.
    capped = frame(x_cap_m=0.6)
    runs = []
    for dt in (0.02, 0.01, 1e-3, 1e-4):
        n = round(t_coarse[-1] / dt) + 1
        fine = np.interp(np.arange(n) * dt, t_coarse, coarse)
        runs.append(simulate(capped, fine, dt, scale=scale, tail_s=0.0, record_history=False))
    first = runs[0]
    assert first.summary.n_stepping_episodes > 0
    assert first.summary.overturned is overturns
    for run in runs[1:]:
        assert run.summary.overturned is overturns
        assert run.summary.peak_abs_x_m == pytest.approx(first.summary.peak_abs_x_m, rel=1e-9)
        np.testing.assert_allclose(run.switching_times_s, first.switching_times_s, atol=1e-8)
        if overturns:
            assert run.summary.overturn_time_s == pytest.approx(
                first.summary.overturn_time_s, abs=1e-8
            )


def test_million_sample_harmonic_steady_state() -> None:
    f = frame(x_c_m=0.2)
    dt, n = 1e-3, 1_000_000
    omega = 3.0
    t = np.arange(n) * dt
    amp = 0.5
    result = simulate(f, amp * np.sin(omega * t), dt, tail_s=0.0)
    assert result.summary.status == "ok" and result.summary.n_stepping_episodes == 0
    w1, xi = f.omega_1_rad_s, f.xi_1
    steady = f.p_1 * amp / math.hypot(w1**2 - omega**2, 2 * xi * w1 * omega)
    assert result.history is not None
    tail = np.abs(result.history["x"].to_numpy()[-100_000:])
    assert tail.max() == pytest.approx(steady, rel=1e-5)


@pytest.mark.parametrize("xi_2", [0.0, 0.1])
@pytest.mark.parametrize(("offset", "expect"), [(1 - 1e-6, True), (1 + 1e-6, False)])
def test_escape_verdict_at_the_separatrix(xi_2: float, offset: float, expect: bool) -> None:
    """Just beyond x* moving inward: it escapes iff ẋ > λ₂(x - x*) (λ₂ < 0 the stable root).

    With ẋ inward and E = ẋ² - ω₂²(x - x*)² < 0 (for the escaping case) the state still escapes:
    the verdict without a cap must agree with running on to a cap.
    """
    f = frame(xi_2=xi_2)
    w2 = f.omega_2_rad_s
    lam2 = -w2 * (xi_2 + math.sqrt(1 + xi_2**2))
    u = 0.01
    v0 = lam2 * u * offset  # inward (negative), just slower or faster than the separatrix
    no_cap = simulate(f, np.zeros(2), 0.01, x0_m=f.x_star_m + u, v0_m_s=v0, tail_s=20.0)
    capped = simulate(
        frame(xi_2=xi_2, x_cap_m=0.6), np.zeros(2), 0.01, x0_m=f.x_star_m + u, v0_m_s=v0,
        tail_s=20.0,
    )  # fmt: skip
    assert no_cap.summary.overturned is expect
    assert capped.summary.overturned is expect
    if expect:
        # No ground motion ahead: escape is certain from t = 0 (the test during the record uses
        # the largest |ẍ_g| still to come, here 0).
        assert no_cap.summary.overturn_time_s == 0.0
        assert capped.summary.overturn_time_s is not None and capped.summary.overturn_time_s > 1


def test_batch_equals_single_runs(motion: Any) -> None:
    ag, dt = motion
    scales = [0.1, 0.3, 0.6]
    table = simulate_batch(frame(x_cap_m=0.6), [(ag, dt), (ag[:600], dt)], scales, tail_s=3.0)
    assert len(table) == 6
    for row in table.itertuples():
        series = ag if row.record == 0 else ag[:600]
        one = simulate(frame(x_cap_m=0.6), series, dt, scale=row.scale, tail_s=3.0,
                       record_history=False).summary  # fmt: skip
        assert row.peak_abs_x_m == one.peak_abs_x_m
        assert row.n_impacts == one.n_impacts
        assert row.overturned == one.overturned


@pytest.mark.parametrize(
    ("ag", "dt", "match"),
    [
        ([0.0, math.nan, 1.0], 0.01, r"ground_acc_m_s2\[1\] = nan"),
        ([0.0, math.inf], 0.01, "non-finite"),
        ([0.0, 1.0], 0.0, "dt_s = 0.0"),
        ([0.0, 1.0], -0.01, "dt_s = -0.01"),
        ([0.0, 1.0], math.nan, "dt_s = nan"),
        ([[0.0, 1.0]], 0.01, "1-D series"),
        ([1.0], 0.01, "≥ 2 samples"),
    ],
)
def test_bad_input_raises_one_line_input_error(ag: Any, dt: float, match: str) -> None:
    with pytest.raises(InputError, match=match) as info:
        simulate(frame(), ag, dt)
    assert "\n" not in str(info.value)


def test_bad_method_and_tail() -> None:
    with pytest.raises(InputError, match="method = 'Euler'"):
        simulate(frame(), [0.0, 1.0], 0.01, method="Euler")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="tail_s = -1"):
        simulate(frame(), [0.0, 1.0], 0.01, tail_s=-1.0)
