"""R_g and its integrals I_c, I_s (paper eqs. 6.5-6.7) in closed form, and stationary moments.

The input is the project's unit-variance eq. 6.12 process ``y`` (:mod:`stepframe.stochastic.model`):
``ÿ + 2α ẏ + ω_g² y = √(4αω_g²) w``. Its autocorrelation and the Laplace transform of it are::

    r(τ) = e^{-α|τ|} [cos ν τ + (α/ν) sin ν|τ|],   ν² = ω_g² - α²  (cosh/sinh when α > ω_g),
    J(s) = ∫_0^∞ e^{-sτ} r(τ) dτ = (s + 2α) / (s² + 2α s + ω_g²).

With β = ξ_0 ω_0 (the oscillator's decay rate [1/s]) and ω_d² = ω² - β², the integrals of eqs.
6.6-6.7 are the real and imaginary parts of J at s = β + iω_d::

    I_c = Re J(β + iω_d),   I_s = -Im J(β + iω_d) / ω_d,

which, written with W = ω_d² (so that they hold for an overdamped oscillator too, W < 0), are::

    D   = (ω_g² - ω²)² + 4(α + β)(β ω_g² + α ω²)
    I_c = [(β + 2α)(ω_g² - ω² + 2β(α + β)) + 2(α + β) W] / D
    I_s = [ω² - ω_g² + 4α(α + β)] / D

Eq. 6.8 (I_c) agrees with this; eq. 6.9 (I_s) does not (it is not dimensionally consistent); see
docs/paper-notes.md. R_g = 2 I_c + 2β I_s (eq. 6.5) makes the stationary limit of eq. 6.4 exact:
the stationary variance of ``ẍ + 2βẋ + ω²x = -I y`` is ``I² R_g / (4 β ω²)``.

Units: ω, ω_g, α in rad/s, β in 1/s; I_c and R_g in s, I_s in s², so that I² R_g / ω² is a mean
square [m²] for an intensity I in m/s².
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError


def _arrays(
    omega_rad_s: ArrayLike, beta_1_s: ArrayLike, omega_g_rad_s: ArrayLike, alpha_g_rad_s: ArrayLike
) -> tuple[NDArray[np.float64], ...]:
    w, b, wg, a = (
        np.asarray(v, dtype=np.float64)
        for v in (omega_rad_s, beta_1_s, omega_g_rad_s, alpha_g_rad_s)
    )
    if np.any(~np.isfinite(w)) or np.any(w <= 0):
        raise InputError("oscillator frequency omega has values ≤ 0 or not finite, expected > 0")
    if np.any(~np.isfinite(wg)) or np.any(wg <= 0):
        raise InputError("omega_g has values ≤ 0 or not finite, expected > 0")
    if np.any(~np.isfinite(b)) or np.any(b < 0):
        raise InputError("beta = xi0·omega0 has negative or non-finite values, expected ≥ 0")
    if np.any(~np.isfinite(a)) or np.any(a < 0):
        raise InputError("alpha_g has negative or non-finite values, expected ≥ 0")
    return w, b, wg, a


def _denominator(
    w: NDArray[np.float64], b: NDArray[np.float64], wg: NDArray[np.float64], a: NDArray[np.float64]
) -> NDArray[np.float64]:
    d = (wg**2 - w**2) ** 2 + 4 * (a + b) * (b * wg**2 + a * w**2)
    if np.any(d <= 0):
        raise InputError(
            "alpha_g = 0 and beta = 0 with omega = omega_g: undamped resonance with a pure "
            "sinusoid has no finite spectral value, expected alpha_g > 0 or xi0 > 0"
        )
    return np.asarray(d)


def correlation_integrals(
    omega_rad_s: ArrayLike,
    beta_1_s: ArrayLike,
    omega_g_rad_s: ArrayLike,
    alpha_g_rad_s: ArrayLike,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Closed forms of I_c and I_s (eqs. 6.6-6.7) for the unit-variance eq. 6.12 process.

    Parameters
    ----------
    omega_rad_s
        Oscillator frequency ω(t) [rad/s] (> 0).
    beta_1_s
        Oscillator decay rate β = ξ_0 ω_0 [1/s] (≥ 0); ω_d² = ω² - β² may be negative.
    omega_g_rad_s, alpha_g_rad_s
        Ground-motion parameters ω_g(t) [rad/s] (> 0) and α_g(t) [rad/s] (≥ 0).

    Returns
    -------
    i_c, i_s : numpy.ndarray
        I_c [s] and I_s [s²] (broadcast shape of the inputs).
    """
    w, b, wg, a = _arrays(omega_rad_s, beta_1_s, omega_g_rad_s, alpha_g_rad_s)
    d = _denominator(w, b, wg, a)
    big_a = wg**2 - w**2 + 2 * b * (a + b)
    i_c = ((b + 2 * a) * big_a + 2 * (a + b) * (w**2 - b**2)) / d
    i_s = (w**2 - wg**2 + 4 * a * (a + b)) / d
    return np.asarray(i_c), np.asarray(i_s)


def r_g(
    omega_rad_s: ArrayLike,
    beta_1_s: ArrayLike,
    omega_g_rad_s: ArrayLike,
    alpha_g_rad_s: ArrayLike,
) -> NDArray[np.float64]:
    """R_g = 2 I_c + 2β I_s (eq. 6.5) [s], for a unit-variance eq. 6.12 input.

    With β = 0 it is the unit-intensity spectrum S(ω) of eq. 6.12 (eq. 6.16); at ω = ω_g it is
    (ω_g² + 4αβ)/((α + β) ω_g²), which is 1/α at β = 0 (eq. 6.15).
    """
    b = np.asarray(beta_1_s, dtype=np.float64)
    i_c, i_s = correlation_integrals(omega_rad_s, b, omega_g_rad_s, alpha_g_rad_s)
    return np.asarray(2 * i_c + 2 * b * i_s)


def autocorrelation(
    tau_s: ArrayLike, omega_g_rad_s: float, alpha_g_rad_s: float
) -> NDArray[np.float64]:
    """r(τ) of the unit-variance eq. 6.12 process (any α ≥ 0: under-, critically, over-damped)."""
    tau = np.abs(np.asarray(tau_s, dtype=np.float64))
    a, wg = alpha_g_rad_s, omega_g_rad_s
    nu2 = wg**2 - a**2
    nu = np.sqrt(abs(nu2))
    x = nu * tau
    if nu * float(np.max(tau, initial=0.0)) < 1e-6:
        c, s = np.ones_like(tau), tau  # series: cos → 1, sin(ντ)/ν → τ
    elif nu2 > 0:
        c, s = np.cos(x), np.sin(x) / nu
    else:
        # e^{-ατ}cosh(ντ) and e^{-ατ}sinh(ντ) written with e^{-(α∓ν)τ} so that they never overflow
        slow, fast = np.exp(-(a - nu) * tau), np.exp(-(a + nu) * tau)
        return np.asarray((slow + fast) / 2 + a * (slow - fast) / (2 * nu))
    return np.asarray(np.exp(-a * tau) * (c + a * s))


def stationary_moments(
    omega_rad_s: ArrayLike,
    beta_1_s: ArrayLike,
    omega_g_rad_s: ArrayLike,
    alpha_g_rad_s: ArrayLike,
) -> dict[str, NDArray[np.float64]]:
    """Stationary second moments of ``ẍ + 2βẋ + ω²x = -y`` driven by the unit eq. 6.12 process.

    Returns a dict with ``xx, vv`` (E[x²] [s⁴], E[ẋ²] [s²]; E[xẋ] = 0), and the cross moments
    ``xy, xy', vy, vy'`` (E[x y], E[x ẏ], E[ẋ y], E[ẋ ẏ]), for an input of unit RMS; multiply by
    I (cross) or I² (``xx``, ``vv``) for an input I·y. β must be > 0 (no stationary state without
    damping).

    Derivation: x(t) = -∫_0^∞ h(u) y(t-u) du with h(u) = e^{-βu} sin(ω_d u)/ω_d, so
    E[x y] = -∫h r = -I_s and E[ẋ y] = -∫h' r = -(I_c - β I_s); the ẏ moments use r' instead of r,
    whose transform is s J(s) - 1 = -ω_g²/(s² + 2αs + ω_g²). Then E[ẋ f] = 2β E[ẋ²] (energy balance)
    and E[ẋ²] = ω² E[x²] - E[x f] with f = -y give E[x²] = (I_c + β I_s)/(2βω²) = R_g/(4βω²).
    """
    w, b, wg, a = _arrays(omega_rad_s, beta_1_s, omega_g_rad_s, alpha_g_rad_s)
    if np.any(b <= 0):
        raise InputError("beta = xi0·omega0 = 0 has no stationary state, expected xi0 > 0")
    d = _denominator(w, b, wg, a)
    big_a = wg**2 - w**2 + 2 * b * (a + b)
    big_b = 2 * (a + b)
    i_c = ((b + 2 * a) * big_a + big_b * (w**2 - b**2)) / d
    i_s = (w**2 - wg**2 + 4 * a * (a + b)) / d
    m_c = -(wg**2) * big_a / d  # integrals of r' (E = 0, C = -ω_g² in the module's notation)
    m_s = -(wg**2) * big_b / d
    xx = (i_c + b * i_s) / (2 * b * w**2)
    return {
        "xx": np.asarray(xx),
        "vv": np.asarray(w**2 * xx - i_s),
        "xy": np.asarray(-i_s),
        "xy'": np.asarray(-m_s),
        "vy": np.asarray(-(i_c - b * i_s)),
        "vy'": np.asarray(-(m_c - b * m_s)),
    }
