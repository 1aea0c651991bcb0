"""R_g, I_c, I_s (eqs. 6.5-6.9, 6.14-6.16): closed forms against quadrature and a Lyapunov solve."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from scipy import integrate, linalg

from stepframe.errors import InputError
from stepframe.stochastic.correlation import (
    autocorrelation,
    correlation_integrals,
    r_g,
    stationary_moments,
)

# (ω, β, ω_g, α): light damping, resonance ω = ω_g, overdamped oscillator (β > ω),
# overdamped input (α > ω_g), critically damped oscillator (β = ω)
CASES = [
    (12.0, 0.6, 20.0, 3.0),
    (20.0, 1.0, 20.0, 1.9),
    (19.6, 0.98, 46.7, 4.48),
    (5.0, 7.0, 20.0, 3.0),
    (10.0, 0.5, 6.0, 9.0),
    (8.0, 8.0, 20.0, 2.0),
]


def _spectrum(x: float, wg: float, a: float) -> float:
    return 4 * a * wg**2 / ((x * x - wg * wg) ** 2 + 4 * a * a * x * x)


def _quad_integrals(w: float, b: float, wg: float, a: float) -> tuple[float, float]:
    """Eqs. 6.6-6.7 by adaptive quadrature over [0, T] (integrand below 1e-17 beyond T)."""
    wd2 = w * w - b * b
    root = math.sqrt(abs(wd2))

    def c(t: float) -> float:
        if wd2 >= 0:
            return math.cos(root * t)
        return math.cosh(root * t)

    def s(t: float) -> float:
        if root * t < 1e-12:
            return t
        return (math.sin(root * t) if wd2 >= 0 else math.sinh(root * t)) / root

    # slowest decay of e^{-βτ} r(τ) times cosh(ω_d τ)
    nu = math.sqrt(max(a * a - wg * wg, 0.0))
    decay = b + a - nu - (root if wd2 < 0 else 0.0)
    t_end = 40.0 / decay

    def f_c(t: float) -> float:
        return float(math.exp(-b * t) * autocorrelation(t, wg, a) * c(t))

    def f_s(t: float) -> float:
        return float(math.exp(-b * t) * autocorrelation(t, wg, a) * s(t))

    opts = {"limit": 4000, "epsabs": 0.0, "epsrel": 1e-12}
    return integrate.quad(f_c, 0, t_end, **opts)[0], integrate.quad(f_s, 0, t_end, **opts)[0]


@pytest.mark.parametrize(("w", "b", "wg", "a"), CASES)
def test_closed_forms_match_quadrature_of_eqs_6_6_and_6_7(
    w: float, b: float, wg: float, a: float
) -> None:
    i_c, i_s = correlation_integrals(w, b, wg, a)
    q_c, q_s = _quad_integrals(w, b, wg, a)
    assert float(i_c) == pytest.approx(q_c, rel=1e-8)
    assert float(i_s) == pytest.approx(q_s, rel=1e-8)


@pytest.mark.parametrize(("w", "b", "wg", "a"), CASES)
def test_stationary_variance_matches_frequency_domain_quadrature(
    w: float, b: float, wg: float, a: float
) -> None:
    """E[x²] = R_g/(4βω²) against (1/2π)∫ S(ν)|H(ν)|² dν for ẍ + 2βẋ + ω²x = -y."""

    def integrand(x: float) -> float:
        return _spectrum(x, wg, a) / ((w * w - x * x) ** 2 + 4 * b * b * x * x)

    peaks = sorted({w, wg})
    opts = {"limit": 2000, "epsabs": 0.0, "epsrel": 1e-13}
    pieces = [0.0, *peaks, 4 * max(peaks)]
    var = sum(integrate.quad(integrand, lo, hi, **opts)[0] for lo, hi in itertools.pairwise(pieces))
    var += integrate.quad(integrand, pieces[-1], np.inf, **opts)[0]
    var /= math.pi  # (1/2π) ∫_{-∞}^{∞} = (1/π) ∫_0^∞ for an even integrand
    assert float(r_g(w, b, wg, a)) / (4 * b * w * w) == pytest.approx(var, rel=1e-9)
    assert float(stationary_moments(w, b, wg, a)["xx"]) == pytest.approx(var, rel=1e-9)


@pytest.mark.parametrize(("w", "b", "wg", "a"), CASES)
def test_stationary_moments_match_lyapunov_solve(w: float, b: float, wg: float, a: float) -> None:
    """All second moments of (y, ẏ, x, ẋ) against scipy's algebraic Lyapunov solver."""
    big_a = np.array(
        [[0, 1, 0, 0], [-(wg**2), -2 * a, 0, 0], [0, 0, 0, 1], [-1.0, 0, -(w**2), -2 * b]]
    )
    noise = np.zeros((4, 4))
    noise[1, 1] = 4 * a * wg**2
    p = linalg.solve_continuous_lyapunov(big_a, -noise)
    m = stationary_moments(w, b, wg, a)
    expected = {"xy": p[2, 0], "xy'": p[2, 1], "vy": p[3, 0], "vy'": p[3, 1]}
    expected |= {"xx": p[2, 2], "vv": p[3, 3]}
    scale = math.sqrt(p[2, 2] * p[0, 0]), math.sqrt(p[2, 2] * p[1, 1])
    for key, value in expected.items():
        tol = 1e-9 * (p[2, 2] if key == "xx" else p[3, 3] if key == "vv" else max(scale))
        assert float(m[key]) == pytest.approx(value, abs=tol), key
    assert abs(p[2, 3]) < 1e-9 * math.sqrt(p[2, 2] * p[3, 3])  # E[xẋ] = 0


def _paper_eq_6_8_and_6_9(w: float, b: float, wg: float, a: float) -> tuple[float, float]:
    wd2 = w * w - b * b
    ab = a + b
    den = (w**2 - wg**2) ** 2 + 4 * w * wg * ab * ((a / wg) * w + (b / w) * wg)
    i_c = (ab * (ab**2 + wd2 + wg**2 - a**2) + a * (ab**2 - wd2 + wg**2 - a**2)) / den
    i_s = (ab**2 * (wd2 - wg**2 + a**2) + 2 * ab * a) / den
    return i_c, i_s


@pytest.mark.parametrize(("w", "b", "wg", "a"), CASES)
def test_paper_eq_6_8_agrees_and_eq_6_9_does_not(w: float, b: float, wg: float, a: float) -> None:
    i_c, i_s = correlation_integrals(w, b, wg, a)
    paper_c, paper_s = _paper_eq_6_8_and_6_9(w, b, wg, a)
    assert paper_c == pytest.approx(float(i_c), rel=1e-12)
    assert abs(paper_s / float(i_s) - 1) > 0.2


def test_eq_6_9_is_not_dimensionally_consistent() -> None:
    """Scaling every frequency by λ must scale I_s by λ⁻² (it is in s²); eq. 6.9 does not."""
    w, b, wg, a = CASES[0]
    lam = 3.0
    ours = [float(correlation_integrals(*(lam**k * v for v in (w, b, wg, a)))[1]) for k in (0, 1)]
    assert ours[1] / ours[0] == pytest.approx(lam**-2, rel=1e-12)
    paper = [_paper_eq_6_8_and_6_9(*(lam**k * v for v in (w, b, wg, a)))[1] for k in (0, 1)]
    assert abs(paper[1] / paper[0] - lam**-2) > 0.1


def test_r_g_at_zero_damping_is_the_spectrum_eq_6_16_and_6_15() -> None:
    wg, a = 19.6, 4.76
    for w in (3.0, 12.0, 19.6, 40.0):
        assert float(r_g(w, 0.0, wg, a)) == pytest.approx(_spectrum(w, wg, a), rel=1e-13)
    assert float(r_g(wg, 0.0, wg, a)) == pytest.approx(1 / a, rel=1e-13)  # eq. 6.15


def test_r_g_at_resonance_and_the_printed_eq_6_14() -> None:
    """At ω = ω_g: R_g = (ω_g² + 4αβ)/((α + β)ω_g²); the printed eq. 6.14 differs when β > 0."""
    wg, a, b = 19.6, 4.76, 0.98
    ours = float(r_g(wg, b, wg, a))
    assert ours == pytest.approx((wg**2 + 4 * a * b) / ((a + b) * wg**2), rel=1e-13)
    printed = (10 * b * a + 4 * wg**2 + b * (b + a) * (a**2 + b**2)) / (4 * a * wg**2)
    assert abs(printed / ours - 1) > 0.1
    assert (4 * wg**2) / (4 * a * wg**2) == pytest.approx(float(r_g(wg, 0.0, wg, a)), rel=1e-13)


@pytest.mark.parametrize(("wg", "a"), [(20.0, 3.0), (6.0, 9.0), (10.0, 10.0)])
def test_autocorrelation_is_the_transform_of_eq_6_12(wg: float, a: float) -> None:
    """r(τ) = (1/π) ∫_0^∞ S(ν) cos(ντ) dν for the unit-variance spectrum."""
    for tau in (0.0, 0.05, 0.2, 0.7):
        if tau == 0.0:
            value = integrate.quad(_spectrum, 0, np.inf, args=(wg, a), epsrel=1e-12)[0]
        else:
            value = integrate.quad(
                _spectrum, 0, np.inf, args=(wg, a), weight="cos", wvar=tau, epsrel=1e-12
            )[0]
        assert float(autocorrelation(tau, wg, a)) == pytest.approx(value / math.pi, abs=1e-9)


def test_bad_inputs_raise_one_line_errors() -> None:
    with pytest.raises(InputError, match="no finite spectral value"):
        r_g(20.0, 0.0, 20.0, 0.0)
    with pytest.raises(InputError, match="expected > 0"):
        r_g(0.0, 0.5, 20.0, 2.0)
    with pytest.raises(InputError, match="no stationary state"):
        stationary_moments(10.0, 0.0, 20.0, 2.0)
    # α_g → 0 with damping: finite, and the limit of small α
    near = float(r_g(20.0, 0.5, 20.0, 1e-12))
    assert math.isfinite(near)
    assert near == pytest.approx(float(r_g(20.0, 0.5, 20.0, 0.0)), rel=1e-9)
