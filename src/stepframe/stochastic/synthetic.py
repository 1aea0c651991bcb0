"""Synthetic ground motions of the Beck-Papadimitriou model (eq. 6.12 process times an envelope).

The unit-variance process ``y`` solves ``ÿ + 2 α_g(t) ẏ + ω_g(t)² y = √q(t) w(t)`` with
``q = 4 α_g ω_g²`` (:meth:`GroundMotionModel.noise_intensity`), so that for frozen parameters
``E[y²] = 1`` and ``E[ẏ²] = ω_g²``; its spectrum is eq. 6.12 with I_g = 1. The motion is
``I_g(t) · y(t)``.

Scheme (stated accuracy): over each step ``[t_k, t_k + h]`` the parameters are frozen at the step's
midpoint and the linear SDE is advanced exactly in distribution (covariance matched): the state
``x = (y, ẏ)`` maps as ``x_{k+1} = Φ x_k + L z_k`` with ``Φ = exp(A h)`` and
``L Lᵀ = Q = P - Φ P Φᵀ``, ``P = diag(1, ω_g²)`` the stationary covariance of the frozen filter,
``z_k`` standard normal. For constant parameters the samples are exact whatever ``h``; for
time-varying parameters the covariance of the samples differs from that of the continuous
time-varying filter by O(h²) (midpoint freezing), checked against a Liapunov ODE in
``tests/stochastic/test_synthetic.py``: for the paper's site parameters over 0-8 s the variance
of y is within 7e-6 of the ODE's at h = 0.02 s, 4e-7 at h = 0.01 s and 2.4e-8 at h = 0.005 s
(the slow parameter change makes the h² term small; the error falls about 16x per halving).
``h`` must still resolve the band of interest
(``ω_p h < π`` is enforced: the Nyquist frequency must lie above ω_p).

Initial state: drawn from the stationary distribution of the filter frozen at ``t = 0``
(``y ~ N(0, 1)``, ``ẏ ~ N(0, ω_g(0)²)``), so ``E[y²] = 1`` at every time, which is what
"unit-variance process" means; with the default envelope (0 at ``t0_s``) the motion itself still
starts from rest. ``initial="rest"`` starts ``y`` at exactly 0 instead.
"""

from __future__ import annotations

import math
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError
from stepframe.stochastic.envelope import default_envelope
from stepframe.stochastic.model import GroundMotionModel

InitialState = Literal["stationary", "rest"]


def transition(
    omega_rad_s: ArrayLike, alpha_rad_s: ArrayLike, h_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Exact one-step transition and noise covariance of the frozen unit-variance filter.

    Parameters
    ----------
    omega_rad_s, alpha_rad_s
        ω_g and α_g over the step [rad/s] (arrays of equal shape ``(n,)``); any α ≥ 0
        (under-, critically and over-damped).
    h_s
        Step [s].

    Returns
    -------
    phi : numpy.ndarray
        ``exp(A h)``, shape ``(n, 2, 2)``, with ``A = [[0, 1], [-ω², -2α]]``.
    chol : numpy.ndarray
        Lower Cholesky factor of ``Q = P - Φ P Φᵀ``, shape ``(n, 2, 2)``.
    """
    w = np.atleast_1d(np.asarray(omega_rad_s, dtype=np.float64))
    a = np.atleast_1d(np.asarray(alpha_rad_s, dtype=np.float64))
    d = w**2 - a**2
    root = np.sqrt(np.abs(d))
    x = root * h_s
    # exp(A h) = e^{-αh} [C I + S (A + αI)], C = cos(ω_d h), S = sin(ω_d h)/ω_d (cosh/sinh when
    # over-damped, 1 and h when critical); the series branch avoids 0/0 near critical damping.
    small = x < 1e-4
    safe_root = np.where(small, 1.0, root)
    osc = d > 0
    c = np.where(osc, np.cos(x), np.cosh(x))
    s = np.where(osc, np.sin(x), np.sinh(x)) / safe_root
    c = np.where(small, 1.0 - np.sign(d) * x**2 / 2, c)
    s = np.where(small, h_s * (1.0 - np.sign(d) * x**2 / 6), s)
    decay = np.exp(-a * h_s)
    phi = np.empty((w.size, 2, 2))
    phi[:, 0, 0] = decay * (c + a * s)
    phi[:, 0, 1] = decay * s
    phi[:, 1, 0] = -decay * w**2 * s
    phi[:, 1, 1] = decay * (c - a * s)
    p22 = w**2
    q11 = 1.0 - (phi[:, 0, 0] ** 2 + phi[:, 0, 1] ** 2 * p22)
    q12 = -(phi[:, 0, 0] * phi[:, 1, 0] + phi[:, 0, 1] * phi[:, 1, 1] * p22)
    q22 = p22 - (phi[:, 1, 0] ** 2 + phi[:, 1, 1] ** 2 * p22)
    l11 = np.sqrt(np.maximum(q11, 0.0))
    l21 = np.where(l11 > 0, q12 / np.where(l11 > 0, l11, 1.0), 0.0)
    l22 = np.sqrt(np.maximum(q22 - l21**2, 0.0))
    chol = np.zeros_like(phi)
    chol[:, 0, 0] = l11
    chol[:, 1, 0] = l21
    chol[:, 1, 1] = l22
    return phi, chol


def unit_process(
    model: GroundMotionModel,
    time_s: NDArray[np.float64],
    n_realisations: int,
    rng: np.random.Generator,
    initial: InitialState = "stationary",
) -> NDArray[np.float64]:
    """Samples of the unit-variance eq. 6.12 process at ``time_s`` (uniform), shape (n, npts)."""
    npts = time_s.size
    out = np.empty((n_realisations, npts))
    if npts == 0:
        return out
    h = float(time_s[1] - time_s[0]) if npts > 1 else 0.0
    mid = time_s[:-1] + h / 2
    phi, chol = transition(model.omega_g(mid), model.alpha_g(mid), h)
    if initial == "stationary":
        y = rng.standard_normal(n_realisations)
        v = rng.standard_normal(n_realisations) * float(model.omega_g(time_s[0]))
    else:
        y = np.zeros(n_realisations)
        v = np.zeros(n_realisations)
    out[:, 0] = y
    noise = rng.standard_normal((npts - 1, 2, n_realisations))
    for k in range(npts - 1):
        f, c, z = phi[k], chol[k], noise[k]
        y, v = (
            f[0, 0] * y + f[0, 1] * v + c[0, 0] * z[0],
            f[1, 0] * y + f[1, 1] * v + c[1, 0] * z[0] + c[1, 1] * z[1],
        )
        out[:, k + 1] = y
    return out


def synthetic_motions(
    model: GroundMotionModel,
    *,
    duration_s: float,
    dt_s: float,
    n_realisations: int = 1,
    seed: int | None = None,
    envelope: ArrayLike | None = None,
    peak_intensity: float = 1.0,
    initial: InitialState = "stationary",
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Realisations of the Beck-Papadimitriou ground motion ``I_g(t) · y(t)``.

    Parameters
    ----------
    model
        ω_g(t), α_g(t) (eqs. 6.10-6.11) and, for the default envelope, t_max, t_dur, t0.
    duration_s
        Length [s]; samples at ``0, dt, ..., ≤ duration_s``.
    dt_s
        Sampling interval [s]; must satisfy ``ω_p dt < π``.
    n_realisations
        Number of independent realisations (vectorised).
    seed
        Seed of ``numpy.random.default_rng``: equal seeds give equal motions.
    envelope
        RMS envelope I_g(t) at the sample times (shape ``(npts,)``) [units of the output]; None
        uses ``default_envelope(t, model.t_max_s, model.t_dur_s, peak_intensity,
        t0_s=model.t0_s)`` (needs t_max < t_dur).
    peak_intensity
        max I_g of the default envelope (ignored when ``envelope`` is given) [e.g. m/s²].
    initial
        ``"stationary"`` (default; E[y²] = 1 from t = 0) or ``"rest"`` (y = ẏ = 0 at t = 0).

    Returns
    -------
    time_s : numpy.ndarray
        Shape ``(npts,)`` [s].
    acceleration : numpy.ndarray
        Shape ``(n_realisations, npts)``, in the units of ``peak_intensity`` (or ``envelope``).

    Raises
    ------
    InputError
        Non-positive or non-finite duration/dt, dt too coarse for ω_p, bad envelope shape or
        values, n_realisations < 1, unknown ``initial``, a model with a corner ω_c.
    """
    if model.omega_c_rad_s is not None:
        raise InputError(
            f"model has a corner omega_c_rad_s = {model.omega_c_rad_s}, expected None: the "
            "synthetic motions are eq. 6.12 without the corner filter "
            "(dataclasses.replace(model, omega_c_rad_s=None))"
        )
    if not (math.isfinite(duration_s) and duration_s > 0):
        raise InputError(f"duration_s = {duration_s}, expected a positive number")
    if not (math.isfinite(dt_s) and 0 < dt_s < duration_s):
        raise InputError(f"dt_s = {dt_s}, expected 0 < dt_s < duration_s = {duration_s}")
    if model.omega_p_rad_s * dt_s >= math.pi:
        raise InputError(
            f"dt_s = {dt_s} puts the Nyquist frequency {math.pi / dt_s:.4g} rad/s below "
            f"omega_p = {model.omega_p_rad_s:.4g} rad/s, expected dt_s < pi / omega_p"
        )
    if not (isinstance(n_realisations, int) and n_realisations >= 1):
        raise InputError(f"n_realisations = {n_realisations!r}, expected an integer ≥ 1")
    if initial not in ("stationary", "rest"):
        raise InputError(f"initial = {initial!r}, expected 'stationary' or 'rest'")
    npts = math.floor(duration_s / dt_s + 1e-9) + 1
    time_s = np.arange(npts, dtype=np.float64) * dt_s
    if envelope is None:
        if not math.isfinite(peak_intensity):
            raise InputError(f"peak_intensity = {peak_intensity}, expected a finite number")
        env = default_envelope(
            time_s, model.t_max_s, model.t_dur_s, peak_intensity, t0_s=model.t0_s
        )
    else:
        env = np.asarray(envelope, dtype=np.float64)
        if env.shape != (npts,):
            raise InputError(
                f"envelope has shape {env.shape}, expected ({npts},) (one value per sample)"
            )
        if not np.all(np.isfinite(env)):
            raise InputError("envelope has NaN or infinite values, expected finite values")
    rng = np.random.default_rng(seed)
    unit = unit_process(model, time_s, n_realisations, rng, initial)
    return time_s, unit * env
