"""Synthetic motions: the exact step against expm and quadrature, a Liapunov ODE, and statistics."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import integrate, linalg

from stepframe.errors import InputError
from stepframe.stochastic.envelope import default_envelope
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.synthetic import synthetic_motions, transition

SITE = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)


def _a_matrix(w: float, a: float) -> np.ndarray:
    return np.array([[0.0, 1.0], [-(w**2), -2 * a]])


@pytest.mark.parametrize(
    ("w", "a"), [(20.0, 1.0), (20.0, 19.9999), (20.0, 20.0), (20.0, 20.00001), (5.0, 30.0)]
)
def test_transition_matches_expm_and_quadrature(w: float, a: float) -> None:
    h = 0.02
    phi, chol = transition([w], [a], h)
    big_a = _a_matrix(w, a)
    np.testing.assert_allclose(phi[0], linalg.expm(big_a * h), rtol=1e-9, atol=1e-12)
    q = 4 * a * w**2

    def integrand(s: float, i: int, j: int) -> float:
        e = linalg.expm(big_a * s)
        return float(q * e[i, 1] * e[j, 1])

    expected = np.array(
        [
            [integrate.quad(integrand, 0, h, args=(i, j), epsabs=0)[0] for j in (0, 1)]
            for i in (0, 1)
        ]
    )
    np.testing.assert_allclose(chol[0] @ chol[0].T, expected, rtol=1e-6, atol=1e-12)


def test_covariance_of_scheme_converges_to_liapunov_ode() -> None:
    """The scheme's covariance (midpoint-frozen steps) against Ṗ = AP + PAᵀ + q BBᵀ."""

    def rhs(t: float, p: np.ndarray) -> np.ndarray:
        big_a = _a_matrix(float(SITE.omega_g(t)), float(SITE.alpha_g(t)))
        mat = p.reshape(2, 2)
        dp = big_a @ mat + mat @ big_a.T
        dp[1, 1] += float(SITE.noise_intensity(t))
        return dp.ravel()

    w0 = float(SITE.omega_g(0.0))
    p0 = np.diag([1.0, w0**2])
    t_end = 8.0
    ref = integrate.solve_ivp(rhs, (0, t_end), p0.ravel(), rtol=1e-11, atol=1e-12).y[:, -1]
    errors = []
    for h in (0.01, 0.005):
        n = round(t_end / h)
        mid = (np.arange(n) + 0.5) * h
        phi, chol = transition(SITE.omega_g(mid), SITE.alpha_g(mid), h)
        p = p0.copy()
        for k in range(n):
            p = phi[k] @ p @ phi[k].T + chol[k] @ chol[k].T
        errors.append(abs(p[0, 0] - ref[0]))
    # Measured 2.7e-8 (h = 0.01 s) and 1.5e-9 (h = 0.005 s): the stated accuracy, with margin.
    assert errors[0] < 1e-7
    assert errors[1] < errors[0] / 4  # at least second order: halving h divides it by ≥ 4


def test_unit_variance_and_envelope_by_monte_carlo() -> None:
    n = 4000
    t, acc = synthetic_motions(SITE, duration_s=30.0, dt_s=0.01, n_realisations=n, seed=1)
    env = default_envelope(t, SITE.t_max_s, SITE.t_dur_s)
    for t_check in (0.0, 2.0, 5.0, 15.0, 29.0):
        k = round(t_check / 0.01)
        if env[k] == 0:
            assert np.all(acc[:, k] == 0)
            continue
        var = float(np.mean((acc[:, k] / env[k]) ** 2))
        assert var == pytest.approx(1.0, abs=5 * math.sqrt(2 / n))


def test_zero_upcrossing_rate_is_omega_g_over_two_pi() -> None:
    """Frozen parameters (nearly constant model): up-crossing rate ω_g/2π whatever α."""
    flat = GroundMotionModel(20.0001, 20.0, 19.9999, 0.5, 0.5, t_max_s=1.0, t_dur_s=2.0)
    t, acc = synthetic_motions(
        flat, duration_s=200.0, dt_s=0.005, n_realisations=8, seed=3, envelope=np.ones(40001)
    )
    ups = np.sum((acc[:, :-1] < 0) & (acc[:, 1:] >= 0))
    rate = ups / (8 * t[-1])
    assert rate * 2 * math.pi == pytest.approx(20.0, rel=0.03)


def test_seed_reproducible_and_shapes() -> None:
    t1, a1 = synthetic_motions(SITE, duration_s=10.0, dt_s=0.01, n_realisations=3, seed=7)
    _, a2 = synthetic_motions(SITE, duration_s=10.0, dt_s=0.01, n_realisations=3, seed=7)
    _, a3 = synthetic_motions(SITE, duration_s=10.0, dt_s=0.01, n_realisations=3, seed=8)
    assert t1.shape == (1001,) and a1.shape == (3, 1001)
    assert t1[-1] == pytest.approx(10.0)
    np.testing.assert_array_equal(a1, a2)
    assert not np.allclose(a1, a3)


def test_rest_start_and_peak_intensity_scaling() -> None:
    _, a = synthetic_motions(
        SITE, duration_s=5.0, dt_s=0.01, seed=2, envelope=np.ones(501), initial="rest"
    )
    assert a[0, 0] == 0.0
    _, b1 = synthetic_motions(SITE, duration_s=5.0, dt_s=0.01, seed=2, peak_intensity=1.0)
    _, b2 = synthetic_motions(SITE, duration_s=5.0, dt_s=0.01, seed=2, peak_intensity=2.5)
    np.testing.assert_allclose(b2, 2.5 * b1)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"duration_s": -1.0, "dt_s": 0.01},
        {"duration_s": 10.0, "dt_s": 0.0},
        {"duration_s": 10.0, "dt_s": 0.1},  # Nyquist 31 rad/s < ω_p = 46.7 rad/s
        {"duration_s": 10.0, "dt_s": 0.01, "n_realisations": 0},
        {"duration_s": 10.0, "dt_s": 0.01, "envelope": np.ones(5)},
        {"duration_s": 0.02, "dt_s": 0.01, "envelope": [1.0, np.nan, 1.0]},
    ],
    ids=["duration", "dt-zero", "dt-coarse", "realisations", "envelope-shape", "envelope-nan"],
)
def test_bad_input(kwargs: dict[str, object]) -> None:
    with pytest.raises(InputError):
        synthetic_motions(SITE, **kwargs)  # type: ignore[arg-type]


def test_model_with_a_corner_is_refused() -> None:
    cornered = GroundMotionModel(**{**SITE.to_dict(), "omega_c_rad_s": 3.0})
    with pytest.raises(InputError, match=r"omega_c_rad_s = 3\.0"):
        synthetic_motions(cornered, duration_s=10.0, dt_s=0.01)


def test_realisations_are_vectorised_and_independent() -> None:
    """One call with 400 realisations: sample correlation between realisations ~ 0."""
    _, acc = synthetic_motions(SITE, duration_s=20.0, dt_s=0.01, n_realisations=400, seed=6)
    k = round(5.0 / 0.01)  # at t_max
    x, y = acc[0::2, k], acc[1::2, k]
    corr = float(np.corrcoef(x, y)[0, 1])
    assert abs(corr) < 4 / math.sqrt(x.size)
