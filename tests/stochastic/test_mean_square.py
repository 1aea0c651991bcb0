"""Mean-square response: closed forms, a second ODE solver, the three methods against each other."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy import integrate

from stepframe.errors import InputError
from stepframe.stochastic.amplification import response_amplification
from stepframe.stochastic.envelope import default_envelope
from stepframe.stochastic.mean_square import (
    Constant,
    FrameDriven,
    Given,
    Tracking,
    analysis_grid,
    mean_square_response,
    white_noise_response,
)
from stepframe.stochastic.model import GroundMotionModel

SITE = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)
# Constant ground parameters: ω_g ≡ ω_p when ω_s = ω_p, α_g ≡ ω_p ξ_p when ω_r ξ_r = ω_p ξ_p.
STEADY = GroundMotionModel(20.0, 20.0, 10.0, 0.1, 0.2, t_max_s=5.0, t_dur_s=20.0)


def _unit(t: np.ndarray) -> np.ndarray:
    return np.ones_like(t)


def _stationary_by_quadrature(w: float, b: float, wg: float, a: float) -> float:
    def integrand(x: float) -> float:
        s = 4 * a * wg**2 / ((x * x - wg * wg) ** 2 + 4 * a * a * x * x)
        return s / ((w * w - x * x) ** 2 + 4 * b * b * x * x)

    opts = {"limit": 2000, "epsabs": 0.0, "epsrel": 1e-13}
    pieces = [0.0, *sorted({w, wg}), 5 * max(w, wg), np.inf]
    total = sum(
        integrate.quad(integrand, lo, hi, **opts)[0] for lo, hi in itertools.pairwise(pieces)
    )
    return total / math.pi


# ---------------------------------------------------------------- white noise: closed forms


def test_white_noise_stationary_variance_q_over_4_zeta_omega_cubed() -> None:
    w, zeta, q = 12.0, 0.05, 3.0
    t = np.linspace(0.0, 40.0, 401)  # e^{-2ζωt} = 1e-21 at the end
    xx, xv, vv = white_noise_response(w, zeta, q, t)
    assert xx[-1] == pytest.approx(q / (4 * zeta * w**3), rel=1e-10)
    assert vv[-1] == pytest.approx(q / (4 * zeta * w), rel=1e-10)
    assert abs(xv[-1]) < 1e-12


def _caughey_stumpf(t: np.ndarray, w: float, zeta: float, q: float) -> np.ndarray:
    b = zeta * w
    wd = w * math.sqrt(1 - zeta**2)
    decay = np.exp(-2 * b * t)
    bracket = 1 + (b / wd) * np.sin(2 * wd * t) + 2 * (b / wd) ** 2 * np.sin(wd * t) ** 2
    return np.asarray(q / (4 * b * w**2) * (1 - decay * bracket))


@pytest.mark.parametrize(("w", "zeta"), [(12.0, 0.05), (3.0, 0.3), (40.0, 1e-6)])
def test_white_noise_transient_from_rest_is_caughey_stumpf(w: float, zeta: float) -> None:
    q = 2.0
    t = np.linspace(0.0, 6.0, 301)  # ω h up to 0.8 rad: the step is exact for frozen ω
    xx, _, _ = white_noise_response(w, zeta, q, t)
    expected = _caughey_stumpf(t, w, zeta, q)
    np.testing.assert_allclose(xx[1:], expected[1:], rtol=1e-7)
    # the closed form itself, against q ∫_0^t h(u)² du
    b, wd = zeta * w, w * math.sqrt(1 - zeta**2)
    for k in (7, 120, 300):
        value = integrate.quad(
            lambda u: (math.exp(-b * u) * math.sin(wd * u) / wd) ** 2, 0, t[k], limit=400
        )[0]
        assert expected[k] == pytest.approx(q * value, rel=1e-9)


# ------------------------------------------------------ filtered input, constant parameters


@pytest.mark.parametrize(("f_hz", "xi0"), [(1.5, 0.05), (20.0 / (2 * math.pi), 0.02), (6.0, 0.3)])
def test_filtered_input_stationary_variance_covariance_and_scalar(f_hz: float, xi0: float) -> None:
    """Eq. 6.12 input (second-order filter) with frozen parameters: both methods against the
    frequency-domain quadrature of S|H|², to 1e-6."""
    w = 2 * math.pi * f_hz
    t = np.linspace(0.0, 60.0 / (xi0 * w) + 1.0, 3001)
    expected = _stationary_by_quadrature(w, xi0 * w, 20.0, 2.0)
    for method in ("covariance", "scalar"):
        result = mean_square_response(STEADY, w, xi0, method=method, time_s=t, envelope=_unit)
        assert result.mean_square_m2[0, -1] == pytest.approx(expected, rel=1e-6), method
        assert result.omega_path == "constant"


@pytest.mark.parametrize("w", [1e3, 1e4, 1e5])
def test_stiff_oscillator_on_a_coarse_grid_reaches_the_stationary_value(w: float) -> None:
    """ω h = 10-1000 (a stiff structure on a 0.01 s grid): the covariance step is exact for
    frozen coefficients and eq. 6.4 exact in the stationary limit, whatever h. Before, the
    4-point coupling quadrature gave 3.75 times the variance at ω = 1e4 rad/s and eq. 6.4's
    3-point rule 0.93 (0.0004 at 1e5)."""
    xi0 = 0.05
    t = np.linspace(0.0, 2.0, 201)
    expected = _stationary_by_quadrature(w, xi0 * w, 20.0, 2.0)
    assert expected * w**4 == pytest.approx(1.0, rel=1e-3)  # quasi-static: E[y²]/ω⁴
    for method in ("covariance", "scalar"):
        result = mean_square_response(STEADY, w, xi0, method=method, time_s=t, envelope=_unit)
        # scaled by ω⁴: approx's default abs = 1e-12 would pass any variance of order 1/ω⁴
        assert result.mean_square_m2[0, -1] * w**4 == pytest.approx(expected * w**4, rel=1e-9)


@pytest.mark.parametrize(("w", "xi0"), [(300.0, 0.01), (1e3, 0.05), (2e3, 1.5)])
def test_covariance_transient_of_a_stiff_oscillator_is_the_matrix_exponential(
    w: float, xi0: float
) -> None:
    """Frozen coefficients from rest on a 0.01 s grid (ω h = 3-20): E[x²](t) against
    P(t) = e^{At}(P_0 - P_∞)e^{Aᵀt} + P_∞ of the 4-state system by scipy's expm and Lyapunov
    solver. Before, the 4-point coupling block was up to 9 % wrong in the transient."""
    from scipy import linalg

    wg, a, b = 20.0, 2.0, xi0 * w
    t = np.linspace(0.0, 1.0, 101)
    result = mean_square_response(STEADY, w, xi0, time_s=t, envelope=_unit)
    system = np.array(
        [[0, 1, 0, 0], [-(wg**2), -2 * a, 0, 0], [0, 0, 0, 1], [-1, 0, -(w**2), -2 * b]]
    )
    noise = np.zeros((4, 4))
    noise[1, 1] = 4 * a * wg**2
    p_inf = linalg.solve_continuous_lyapunov(system, -noise)
    p_0 = np.diag([1.0, wg**2, 0.0, 0.0])
    expected = [
        (phi @ (p_0 - p_inf) @ phi.T + p_inf)[2, 2]
        for phi in (linalg.expm(system * time) for time in t)
    ]
    np.testing.assert_allclose(result.mean_square_m2[0] * w**4, np.multiply(expected, w**4),
                               rtol=3e-7, atol=0)  # fmt: skip


def test_overdamped_oscillator_covariance_reaches_the_stationary_value() -> None:
    w, xi0 = 8.0, 1.5
    t = np.linspace(0.0, 30.0, 1501)
    result = mean_square_response(STEADY, w, xi0, time_s=t, envelope=_unit)
    expected = _stationary_by_quadrature(w, xi0 * w, 20.0, 2.0)
    assert result.mean_square_m2[0, -1] == pytest.approx(expected, rel=1e-6)
    critical = mean_square_response(STEADY, w, 1.0, time_s=t, envelope=_unit)
    expected = _stationary_by_quadrature(w, w, 20.0, 2.0)
    assert critical.mean_square_m2[0, -1] == pytest.approx(expected, rel=1e-6)
    with pytest.raises(InputError, match="underdamped"):
        mean_square_response(STEADY, w, xi0, method="scalar", time_s=t, envelope=_unit)


# --------------------------------------------------- time-varying: a second solver, invariants


def _liapunov_reference(omega_0: float, xi0: float, t_eval: np.ndarray) -> np.ndarray:
    """E[x²] from solve_ivp of the full 4×4 Liapunov ODE (tracking ω, default envelope)."""
    wp = SITE.omega_p_rad_s

    def rhs(t: float, p: np.ndarray) -> np.ndarray:
        wg, ag = float(SITE.omega_g(t)), float(SITE.alpha_g(t))
        ig = float(default_envelope(t, SITE.t_max_s, SITE.t_dur_s))
        w = omega_0 * wg / wp
        big_a = np.array(
            [
                [0, 1, 0, 0],
                [-(wg**2), -2 * ag, 0, 0],
                [0, 0, 0, 1],
                [-ig, 0, -(w**2), -2 * xi0 * omega_0],
            ]
        )
        mat = p.reshape(4, 4)
        dp = big_a @ mat + mat @ big_a.T
        dp[1, 1] += 4 * ag * wg**2
        return dp.ravel()

    p0 = np.zeros((4, 4))
    p0[0, 0], p0[1, 1] = 1.0, float(SITE.omega_g(0.0)) ** 2
    sol = integrate.solve_ivp(
        rhs, (0, t_eval[-1]), p0.ravel(), method="DOP853", rtol=1e-10, atol=1e-14, t_eval=t_eval
    )
    return np.asarray(sol.y[10])


def test_covariance_matches_a_fine_ode_solution_of_the_liapunov_equation() -> None:
    omegas = 2 * math.pi * np.array([1.0, 7.43])
    grid = np.linspace(0.0, 16.0, 3201)
    result = mean_square_response(SITE, Tracking(omegas), 0.05, time_s=grid)
    for i, w0 in enumerate(omegas):
        ref = _liapunov_reference(w0, 0.05, grid[::200])
        got = result.mean_square_m2[i, ::200]
        np.testing.assert_allclose(got[1:], ref[1:], rtol=1e-5, atol=1e-6 * ref.max())
    assert result.omega_path == "tracking"
    assert result.alpha_reading == "eq-6-11"


def test_given_array_and_callable_reproduce_tracking() -> None:
    grid = np.linspace(0.0, 12.0, 1201)
    w0 = 2 * math.pi * 3.0
    tracking = mean_square_response(SITE, Tracking(w0), 0.05, time_s=grid)
    path = w0 * SITE.omega_g(grid) / SITE.omega_p_rad_s
    by_callable = mean_square_response(
        SITE, lambda t: w0 * SITE.omega_g(t) / SITE.omega_p_rad_s, 0.05, time_s=grid
    )
    by_array = mean_square_response(SITE, Given(path), 0.05, time_s=grid)
    np.testing.assert_allclose(by_callable.mean_square_m2, tracking.mean_square_m2, rtol=1e-12)
    # linear interpolation of the samples at the step midpoints: O(h²) in ω
    np.testing.assert_allclose(by_array.mean_square_m2, tracking.mean_square_m2, rtol=2e-4)


def test_scalar_equation_conserves_q11_omega_without_damping_and_input() -> None:
    """Eq. 6.4 with ξ0 = 0 and no input: d(q11 ω)/dt = 0 (adiabatic invariant)."""
    grid = np.linspace(0.0, 10.0, 2001)

    def envelope(t: np.ndarray) -> np.ndarray:
        return np.where(t < 2.0, 1.0, 0.0)

    def omega(t: np.ndarray) -> np.ndarray:
        return 15.0 / (1 + np.maximum(t - 2.0, 0.0) ** 2 / 4)  # falls from 15 to 0.88 rad/s

    result = mean_square_response(
        SITE, Given(omega), 0.0, method="scalar", time_s=grid, envelope=envelope
    )
    action = result.mean_square_m2[0] * result.omega_rad_s[0]
    after = grid > 2.0 + grid[1]
    assert np.ptp(action[after]) < 1e-12 * action[after].max()
    assert result.omega_rad_s[0, -1] < 0.2 * result.omega_rad_s[0, 0]
    assert result.mean_square_m2[0, -1] > 5 * result.mean_square_m2[0, 400]


# ------------------------------------------------------------- the three methods together


def test_three_methods_agree_in_the_stationary_case() -> None:
    w = 2 * math.pi * 2.0
    grid = np.linspace(0.0, 12.0, 241)
    kwargs = {"time_s": grid, "envelope": _unit}
    cov = mean_square_response(STEADY, w, 0.1, **kwargs)
    sca = mean_square_response(STEADY, w, 0.1, method="scalar", **kwargs)
    mc = mean_square_response(
        STEADY, w, 0.1, method="monte-carlo", n_realisations=1500, seed=11, **kwargs
    )
    late = grid > 8.0  # e^{-2βt} < 1e-8: stationary
    np.testing.assert_allclose(sca.mean_square_m2[0, late], cov.mean_square_m2[0, late], rtol=1e-6)
    assert mc.lower_m2 is not None and mc.upper_m2 is not None
    inside = (mc.lower_m2 <= cov.mean_square_m2) & (cov.mean_square_m2 <= mc.upper_m2)
    assert inside[0, late].mean() > 0.8
    assert mc.mean_square_m2[0, late].mean() == pytest.approx(cov.mean_square_m2[0, -1], rel=0.03)


def test_three_methods_agree_in_a_slowly_varying_case() -> None:
    """Tracking ω(t) under the paper's site at 2 and 5 Hz: scalar within 2 %, Monte Carlo band."""
    omegas = 2 * math.pi * np.array([2.0, 5.0])
    grid = np.linspace(0.0, 20.0, 401)
    cov = mean_square_response(SITE, Tracking(omegas), 0.05, time_s=grid)
    sca = mean_square_response(SITE, Tracking(omegas), 0.05, method="scalar", time_s=grid)
    mc = mean_square_response(
        SITE, Tracking(omegas), 0.05, method="monte-carlo", time_s=grid, n_realisations=800, seed=3
    )
    np.testing.assert_allclose(sca.peak_rms_m, cov.peak_rms_m, rtol=0.02)
    peak = np.argmax(cov.mean_square_m2, axis=1)
    assert mc.lower_m2 is not None and mc.upper_m2 is not None
    for i, k in enumerate(peak):
        assert mc.lower_m2[i, k] <= cov.mean_square_m2[i, k] <= mc.upper_m2[i, k]
    assert mc.n_realisations == 800 and mc.seed == 3
    again = mean_square_response(
        SITE, Tracking(omegas), 0.05, method="monte-carlo", time_s=grid, n_realisations=800, seed=3
    )
    np.testing.assert_array_equal(again.mean_square_m2, mc.mean_square_m2)


# ---------------------------------------------------------------------- frame-driven ω(t)


def _period_law(amplitude_m: float) -> float:
    return 0.4 * math.sqrt(1.0 + amplitude_m / 0.05)  # elongates with amplitude


def test_frame_driven_frequency_is_self_consistent() -> None:
    grid = np.linspace(0.0, 20.0, 2001)
    spec = FrameDriven(_period_law)
    result = mean_square_response(SITE, spec, 0.05, time_s=grid, peak_intensity=3.0)
    assert result.omega_path == "frame" and result.status == "ok"
    sigma = np.sqrt(result.mean_square_m2[0])
    expected = np.array([2 * math.pi / _period_law(math.sqrt(2) * s) for s in sigma])
    np.testing.assert_allclose(result.omega_rad_s[0], expected, rtol=1e-12)
    assert result.omega_rad_s[0].min() < 0.75 * result.omega_0_rad_s[0]  # it softened
    # the scalar method follows the same law; peaks within 2 %
    scalar = mean_square_response(
        SITE, spec, 0.05, method="scalar", time_s=grid, peak_intensity=3.0
    )
    assert scalar.peak_rms_m[0] == pytest.approx(result.peak_rms_m[0], rel=0.02)
    # a constant period law is the constant-frequency oscillator
    flat = mean_square_response(SITE, FrameDriven(lambda a: 0.4), 0.05, time_s=grid)
    const = mean_square_response(SITE, 2 * math.pi / 0.4, 0.05, time_s=grid)
    np.testing.assert_allclose(flat.mean_square_m2, const.mean_square_m2, rtol=1e-12)


def test_frame_driven_monte_carlo_uses_the_ensemble_rms() -> None:
    grid = np.linspace(0.0, 12.0, 241)
    spec = FrameDriven(_period_law)
    cov = mean_square_response(SITE, spec, 0.05, time_s=grid, peak_intensity=3.0)
    mc = mean_square_response(
        SITE,
        spec,
        0.05,
        method="monte-carlo",
        time_s=grid,
        peak_intensity=3.0,
        n_realisations=600,
        seed=5,
    )
    k = int(np.argmax(cov.mean_square_m2[0]))
    assert mc.lower_m2 is not None and mc.upper_m2 is not None
    assert mc.lower_m2[0, k] <= cov.mean_square_m2[0, k] <= mc.upper_m2[0, k]
    assert mc.omega_rad_s[0, k] == pytest.approx(cov.omega_rad_s[0, k], rel=0.05)


def test_overturning_frame_stops_with_a_status_not_a_silent_nan() -> None:
    def law(amplitude_m: float) -> float:
        return 0.4 if amplitude_m < 0.01 else math.inf

    grid = np.linspace(0.0, 20.0, 401)
    result = mean_square_response(SITE, FrameDriven(law), 0.05, time_s=grid, peak_intensity=3.0)
    assert result.status == "lower_bound"
    assert result.message.startswith("stopped at t =")
    assert "overturning" in result.message
    assert np.isnan(result.mean_square_m2[0, -1])
    mc = mean_square_response(
        SITE,
        FrameDriven(law),
        0.05,
        method="monte-carlo",
        time_s=grid[:161],
        peak_intensity=3.0,
        n_realisations=50,
        seed=1,
    )
    assert mc.status == "lower_bound" and mc.message.startswith("stopped at t =")
    reached = np.isfinite(mc.mean_square_m2[0])
    assert not reached[-1] and reached[:10].all()
    assert np.all(mc.mean_square_m2[0, 1:][reached[1:]] > 0)  # no zeros left where it stopped


# ----------------------------------------------------------------------- numerical extremes


def test_extremes_are_finite_or_clear_errors() -> None:
    grid = np.linspace(0.0, 20.0, 801)
    # ω(t) = ω_g(t) exactly (tracking at ω_0 = ω_p)
    exact = mean_square_response(SITE, Tracking(SITE.omega_p_rad_s), 0.05, time_s=grid)
    np.testing.assert_allclose(exact.omega_rad_s[0], SITE.omega_g(grid), rtol=1e-14)
    assert np.all(np.isfinite(exact.mean_square_m2)) and exact.peak_rms_m[0] > 0
    # α_g → 0: finite, continuous in α_g
    narrow = [
        GroundMotionModel.from_hz(7.43, 3.12, 1.11, xi, xi, t_max_s=5.0, t_dur_s=20.0)
        for xi in (1e-9, 2e-9)
    ]
    peaks = [
        mean_square_response(m, 2 * math.pi * 3.0, 0.05, time_s=grid).peak_rms_m[0] for m in narrow
    ]
    assert all(math.isfinite(p) for p in peaks)
    assert peaks[0] == pytest.approx(peaks[1], rel=1e-6)
    # ξ0 → 0: the covariance method down to 1e-6, a clear error at 0; the scalar one at 0
    small = mean_square_response(SITE, 2 * math.pi * 3.0, 1e-6, time_s=grid)
    zero = mean_square_response(SITE, 2 * math.pi * 3.0, 0.0, method="scalar", time_s=grid)
    assert np.all(np.isfinite(small.mean_square_m2))
    assert small.peak_rms_m[0] == pytest.approx(zero.peak_rms_m[0], rel=0.05)
    with pytest.raises(InputError, match=r"xi0 = 0\.0, expected ≥ 1e-06"):
        mean_square_response(SITE, 2 * math.pi * 3.0, 0.0, time_s=grid)
    # ω_p = ω_s: ω_g constant until the end
    flat = GroundMotionModel.from_hz(5.0, 5.0, 1.0, 0.1, 0.5, t_max_s=5.0, t_dur_s=20.0)
    result = mean_square_response(flat, Tracking(2 * math.pi * 5.0), 0.05, time_s=grid)
    np.testing.assert_allclose(result.omega_rad_s[0], 2 * math.pi * 5.0, rtol=1e-14)
    assert np.all(np.isfinite(result.mean_square_m2))


def test_bad_arguments_raise_input_errors() -> None:
    grid = np.linspace(0.0, 10.0, 101)
    with pytest.raises(InputError, match="method"):
        mean_square_response(SITE, 10.0, 0.05, method="exact", time_s=grid)  # type: ignore[arg-type]
    with pytest.raises(InputError, match="xi0"):
        mean_square_response(SITE, 10.0, -0.1, time_s=grid)
    with pytest.raises(InputError, match="omega_0_rad_s"):
        mean_square_response(SITE, Constant([-1.0]), 0.05, time_s=grid)
    with pytest.raises(InputError, match=r"expected \(101,\) or"):
        mean_square_response(SITE, Given(np.ones(7)), 0.05, time_s=grid)
    with pytest.raises(InputError, match="uniform"):
        mean_square_response(SITE, 10.0, 0.05, time_s=np.array([0.0, 1.0, 3.0]))
    with pytest.raises(InputError, match="n_realisations"):
        mean_square_response(SITE, 10.0, 0.05, method="monte-carlo", time_s=grid, n_realisations=1)


def test_monte_carlo_step_that_cannot_apply_or_is_too_coarse_is_refused() -> None:
    """mc_dt_s above the grid's step was silently the grid's step (0.05, 0.1 and 0.5 s gave the
    same numbers), and at max(ω, ω_p)·h = 2.3 E[x²] came out 17 % low with a 95 % band that
    excluded the exact value, marked ok."""
    grid = np.linspace(0.0, 10.0, 201)  # step 0.05 s
    w = 2 * math.pi * 3.12
    mc = {"method": "monte-carlo", "time_s": grid, "n_realisations": 4, "seed": 1}
    with pytest.raises(InputError, match=r"mc_dt_s = 0\.5 s is coarser than the analysis grid's"):
        mean_square_response(SITE, w, 0.05, mc_dt_s=0.5, **mc)  # type: ignore[arg-type]
    with pytest.raises(
        InputError, match=r"max\(omega, omega_p\)·mc_dt_s = 2\.33 rad, expected ≤ 1"
    ):
        mean_square_response(SITE, w, 0.05, mc_dt_s=0.05, **mc)  # type: ignore[arg-type]
    # at the limit it runs; a fine grid with the default step (coarser than the grid) too
    limit = 1.0 / SITE.omega_p_rad_s
    assert mean_square_response(SITE, w, 0.05, mc_dt_s=limit, **mc).status == "ok"  # type: ignore[arg-type]
    fine = np.linspace(0.0, 0.2, 201)  # step 0.001 s < 0.1/ω_p
    result = mean_square_response(SITE, w, 0.05, method="monte-carlo", time_s=fine,
                                  n_realisations=4, seed=1, envelope=_unit)  # fmt: skip
    assert np.all(np.isfinite(result.mean_square_m2))


def test_a_grid_that_misses_the_motion_is_refused_for_what_it_is() -> None:
    """A grid over 0-0.2 s (the peak is at 5 s) was refused with "t_dur - t_max = 15 s: more
    time steps, or a t_max further from t_dur", advice that does not apply."""
    with pytest.raises(
        InputError,
        match=r"time_s runs from 0 to 0\.2 s, which misses the envelope.s peak at t0 \+ t_max = 5",
    ):
        mean_square_response(SITE, 10.0, 0.05, time_s=np.linspace(0.0, 0.2, 201))


def test_an_envelope_between_the_grid_times_is_refused() -> None:
    """t_max 1 ms before t_dur: the envelope's exponent, ln 0.1 / (ln r + 1 - r) with r =
    t_dur/t_max, is about 2·10⁹, a pulse of some 2 ms that no time of a 0.01-s grid samples at
    strength; the response (~1e-19 m) and any ratio of two of them would be rounding noise."""
    spike = GroundMotionModel(20.0, 20.0, 10.0, 0.1, 0.2, t_max_s=19.999, t_dur_s=20.0)
    grid = np.linspace(0.0, 40.0, 4001)
    sampled = default_envelope(grid, 19.999, 20.0)
    assert np.count_nonzero(sampled >= 0.1) < 2  # the strong motion between the grid's times
    with pytest.raises(InputError, match=r"holds [01] of the analysis's 4000 time steps of 0\.01"):
        mean_square_response(spike, 10.0, 0.05, time_s=grid)
    # 0.1 s before t_dur: 20 samples of strong motion on that grid, too few (at 100 Hz the
    # amplification was 8 % off, and with 2 samples, at t_max = 19.99 s, 2.5 times: 16.4 for
    # 6.67, status ok); on 16,000 steps, 80 samples: within 0.1 % of 64,000 steps
    short = GroundMotionModel(20.0, 20.0, 10.0, 0.1, 0.2, t_max_s=19.9, t_dur_s=20.0)
    with pytest.raises(InputError, match=r"holds 20 of the analysis's 4000 time steps"):
        mean_square_response(short, 10.0, 0.05, time_s=grid)
    paper = GroundMotionModel(
        2 * math.pi * 7.43, 2 * math.pi * 3.12, 2 * math.pi * 1.11, 0.096, 0.655,
        t_max_s=19.9, t_dur_s=20.0, alpha_reading="paper",
    )  # fmt: skip
    fine, finest = (
        response_amplification(
            paper, [2 * math.pi * 100.0], 0.05, time_s=analysis_grid(paper, n_steps=n)
        ).vs_fixed[0]
        for n in (16_000, 64_000)
    )
    assert fine == pytest.approx(finest, rel=1e-3)
