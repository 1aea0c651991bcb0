"""Free-vibration period-amplitude law T(A) of the two-phase stepping model (closed form).

For the conservative model (ξ₁ = ξ₂ = 0, C_r = 1, no ground motion) released from rest at
amplitude A, the motion is symmetric and its period is four quarter periods, each the time to
fall from A to 0:

- A ≤ x_c (never steps): the linear unstepped phase, T = 2π/ω₁.
- x_c < A < x*: the stepped phase ẍ = ω₂²(x - x*) gives x - x* = (A - x*) cosh(ω₂t), reaching
  x_c after t₂ = arccosh((x* - x_c)/(x* - A))/ω₂ with speed v_c = ω₂ √((x* - x_c)² - (x* - A)²).
  The unstepped phase then moves as B sin(ω₁t + φ) with B = √(x_c² + v_c²/ω₁²), reaching 0
  after t₁ = arcsin(x_c/B)/ω₁. T = 4 (t₁ + t₂).
- A → x*: T grows like (4/ω₂) ln(1/(x* - A)) (the logarithmic elongation the paper quotes from
  Housner and Beck-Skinner); A ≥ x* has no periodic orbit (the frame overturns).

With x_c = 0 (rigid block) the law is Housner's, T = (4/p) arccosh(x*/(x* - A)).

The law is the backbone of the frame: the frame's damping ratios and C_r are not used. Record
selection and the mean-square analysis take it as the callable :func:`period_amplitude`.
"""

from __future__ import annotations

import math
from typing import Literal, Protocol, overload

import numpy as np
import numpy.typing as npt

from stepframe.errors import InputError

BeyondXStar = Literal["raise", "inf"]


class Backbone(Protocol):
    """What the law reads from a frame (SI units): a
    :class:`~stepframe.structure.frame.PortalFrame` is one, and so is the simulator's model
    (:func:`stepframe.structure.frame_frequency.backbone_of`)."""

    @property
    def omega_1_rad_s(self) -> float: ...
    @property
    def omega_2_rad_s(self) -> float: ...
    @property
    def x_c_m(self) -> float: ...
    @property
    def x_star_m(self) -> float: ...
    @property
    def is_rigid_block(self) -> bool: ...


def quarter_periods_s(
    frame: Backbone, amplitude_m: npt.ArrayLike
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The two parts of the quarter period: time in the unstepped and in the stepped phase [s].

    Parameters
    ----------
    frame
        The frame (its ω₁, ω₂, γ₁ and x_c are used).
    amplitude_m
        Amplitudes A with 0 ≤ A < x* [m] (not checked here; see :func:`period_amplitude`).

    Returns
    -------
    (t_unstepped_s, t_stepped_s)
        Arrays shaped like ``amplitude_m`` (the closed forms of the module docstring, evaluated
        by the compiled :func:`stepframe.structure._frequency_kernel.quarter_periods`, which
        the frame's frequency along a response also reads).
    """
    from stepframe.structure._frequency_kernel import quarter_periods

    a = np.asarray(amplitude_m, dtype=float)
    unstepped, stepped = quarter_periods(
        np.ascontiguousarray(a.ravel()),
        float(frame.omega_1_rad_s), float(frame.omega_2_rad_s), float(frame.x_c_m),
        float(frame.x_star_m),
    )  # fmt: skip
    return unstepped.reshape(a.shape), stepped.reshape(a.shape)


@overload
def period_amplitude(
    frame: Backbone, amplitude_m: float, *, beyond_x_star: BeyondXStar = "raise"
) -> float: ...
@overload
def period_amplitude(
    frame: Backbone, amplitude_m: npt.NDArray[np.float64], *, beyond_x_star: BeyondXStar = ...
) -> npt.NDArray[np.float64]: ...
@overload
def period_amplitude(
    frame: Backbone, amplitude_m: npt.ArrayLike, *, beyond_x_star: BeyondXStar = ...
) -> float | npt.NDArray[np.float64]: ...
def period_amplitude(
    frame: Backbone, amplitude_m: npt.ArrayLike, *, beyond_x_star: BeyondXStar = "raise"
) -> float | npt.NDArray[np.float64]:
    """Free-vibration period T(A) of the conservative two-phase model [s], vectorised.

    Parameters
    ----------
    frame
        The frame; only ω₁, ω₂, γ₁ (through x*) and x_c enter (the backbone ignores ξ and C_r).
    amplitude_m
        Peak displacement A ≥ 0 of the free oscillation [m] (scalar or array).
    beyond_x_star
        What A ≥ x* gives: ``"raise"`` (default) an :class:`InputError`, ``"inf"`` an infinite
        period (no periodic orbit: the frame overturns).

    Returns
    -------
    float or numpy.ndarray
        T [s], a float for scalar input, else an array shaped like ``amplitude_m``.

    Examples
    --------
    >>> from stepframe.structure.frame import PortalFrame
    >>> frame = PortalFrame(omega_1_rad_s=6.4581, omega_2_rad_s=0.6445, p_1=1.1884,
    ...                     p_2=1.268, gamma_1_m_s2=0.1387, xi_1=0.0, xi_2=0.0,
    ...                     x_c_m=0.19, c_r=1.0)
    >>> round(period_amplitude(frame, 0.1), 4)  # unstepped: 2π/ω₁
    0.9729
    >>> round(period_amplitude(frame, 0.3), 2)  # stepping: elongated
    14.11
    """
    if beyond_x_star not in ("raise", "inf"):
        raise InputError(f"beyond_x_star = {beyond_x_star!r}, expected 'raise' or 'inf'")
    a = np.asarray(amplitude_m, dtype=float)
    bad = ~np.isfinite(a) | (a < 0)
    if np.any(bad):
        first = a.reshape(-1)[np.flatnonzero(bad.reshape(-1))[0]]
        raise InputError(f"amplitude_m = {first}, expected a finite amplitude ≥ 0 m")
    x_star = frame.x_star_m
    escapes = a >= x_star
    if beyond_x_star == "raise" and np.any(escapes):
        first = a.reshape(-1)[np.flatnonzero(escapes.reshape(-1))[0]]
        raise InputError(
            f"amplitude_m = {first} m ≥ x* = {x_star:.6g} m, expected A < x* "
            "(no periodic orbit: the frame overturns)"
        )
    safe = np.where(escapes, 0.0, a)
    t_unstepped, t_stepped = quarter_periods_s(frame, safe)
    period = np.where(escapes, np.inf, 4.0 * (t_unstepped + t_stepped))
    if period.ndim == 0:
        return float(period)
    return period


@overload
def amplitude_for_period(frame: Backbone, period_s: float) -> float: ...
@overload
def amplitude_for_period(
    frame: Backbone, period_s: npt.NDArray[np.float64]
) -> npt.NDArray[np.float64]: ...
@overload
def amplitude_for_period(
    frame: Backbone, period_s: npt.ArrayLike
) -> float | npt.NDArray[np.float64]: ...
def amplitude_for_period(
    frame: Backbone, period_s: npt.ArrayLike
) -> float | npt.NDArray[np.float64]:
    """Inverse of :func:`period_amplitude` on the stepping branch: A with T(A) = period [m].

    T(A) rises monotonically from 2π/ω₁ at A = x_c to infinity at A = x*, so every period above
    the fixed-base period belongs to exactly one amplitude in (x_c, x*). Found by bisection
    (60 halvings of the interval, vectorised): amplitude to about 1e-16 (x* - x_c).

    Parameters
    ----------
    frame
        The frame.
    period_s
        Periods T > 2π/ω₁ [s] (scalar or array); a rigid block (x_c = 0) takes any T > 0.

    Returns
    -------
    float or numpy.ndarray
        A [m], shaped like ``period_s``.

    Raises
    ------
    InputError
        A period at or below the fixed-base period (no stepping amplitude has it) or non-finite.
    """
    periods = np.asarray(period_s, dtype=float)
    shortest = 0.0 if frame.is_rigid_block else 2.0 * math.pi / frame.omega_1_rad_s
    bad = ~np.isfinite(periods) | (periods <= shortest)
    if np.any(bad):
        first = periods.reshape(-1)[np.flatnonzero(bad.reshape(-1))[0]]
        raise InputError(
            f"period_s = {first}, expected a finite period > {shortest:.6g} s (the fixed-base "
            "period 2π/ω₁: shorter periods belong to no stepping amplitude)"
        )
    low = np.full(periods.shape, frame.x_c_m)
    high = np.full(periods.shape, frame.x_star_m)
    for _ in range(60):
        middle = 0.5 * (low + high)
        longer = period_amplitude(frame, middle) > periods
        high = np.where(longer, middle, high)
        low = np.where(longer, low, middle)
    amplitude: npt.NDArray[np.float64] = 0.5 * (low + high)
    if amplitude.ndim == 0:
        return float(amplitude)
    return amplitude
