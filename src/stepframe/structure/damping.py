"""Damping of the equivalent linear oscillator: ξ_eq from C_r and spectral reduction factors β.

The quasi-dynamic design scales the 5 %-damped spectrum by β (paper eq. 1.3). β is either given,
or computed from an equivalent viscous damping ratio ξ through a named damping-reduction formula.
For a stepping frame ξ may come from the velocity ratio at impact C_r (eq. 4.3) through the
paper's eq. 4.17, ξ ≈ 0.48 (1 - C_r²), quoted from Priestley et al.; note that C_r is a velocity
ratio, so 1 - C_r² is the fraction of kinetic energy lost per impact (Housner's r = C_r²).

Reduction formulas (all give β = 1 at ξ = 0.05):

- ``"ec8"`` (default): Eurocode 8 (EN 1998-1:2004, 3.2.2.2), η = √(10/(5 + 100ξ)) ≥ 0.55.
- ``"ec8-1998"``: the earlier ENV 1998 form η = √(7/(2 + 100ξ)), used by Priestley, Calvi and
  Kowalsky (2007) for displacement-based design; no lower bound.
- ``"aashto-isolation"``: AASHTO Guide Specifications for Seismic Isolation Design,
  β = 1/B_L with B_L = (ξ/0.05)^0.3 ≤ 1.7 (the cap binds from ξ ≈ 0.29).
"""

from __future__ import annotations

import math
from typing import Literal, get_args

from stepframe.errors import InputError

DampingMethod = Literal["ec8", "ec8-1998", "aashto-isolation"]
DAMPING_METHODS: tuple[str, ...] = get_args(DampingMethod)

#: Coefficient of eq. 4.17 (Priestley et al.): ξ_eq = 0.48 (1 - C_r²).
EQ_4_17_COEFFICIENT = 0.48


def equivalent_damping_from_cr(c_r: float) -> float:
    """Equivalent viscous damping ratio of eq. 4.17, ξ = 0.48 (1 - C_r²).

    Parameters
    ----------
    c_r
        Velocity ratio at impact C_r (eq. 4.3), 0 ≤ C_r ≤ 1 (not Housner's energy ratio C_r²).

    Returns
    -------
    float
        ξ as a fraction (0 for C_r = 1, 0.48 for C_r = 0).
    """
    if isinstance(c_r, bool) or not isinstance(c_r, int | float) or not 0 <= c_r <= 1:
        raise InputError(f"c_r = {c_r!r}, expected a velocity ratio 0 ≤ c_r ≤ 1")
    return EQ_4_17_COEFFICIENT * (1.0 - c_r * c_r)


def damping_reduction(xi: float, method: DampingMethod = "ec8") -> float:
    """Spectral reduction factor β for viscous damping ratio ``xi`` (a fraction, not a percent).

    Parameters
    ----------
    xi
        Damping ratio ξ ≥ 0 (``"aashto-isolation"`` needs ξ > 0).
    method
        ``"ec8"`` (default), ``"ec8-1998"`` or ``"aashto-isolation"``; see the module docstring.

    Returns
    -------
    float
        β, the factor on the 5 %-damped pseudo-acceleration.
    """
    if isinstance(xi, bool) or not isinstance(xi, int | float) or not math.isfinite(xi):
        raise InputError(f"xi = {xi!r}, expected a finite damping ratio")
    if xi < 0:
        raise InputError(f"xi = {xi}, expected a damping ratio ≥ 0 (a fraction, 0.05 = 5 %)")
    if method == "ec8":
        return max(math.sqrt(10.0 / (5.0 + 100.0 * xi)), 0.55)
    if method == "ec8-1998":
        return math.sqrt(7.0 / (2.0 + 100.0 * xi))
    if method == "aashto-isolation":
        if xi <= 0:
            raise InputError(
                "xi = 0 with method 'aashto-isolation', expected xi > 0 (B_L = (xi/0.05)^0.3)"
            )
        b_l = min(float((xi / 0.05) ** 0.3), 1.7)
        return 1.0 / b_l
    raise InputError(f"damping method {method!r}, expected one of {', '.join(DAMPING_METHODS)}")


def beta_from_cr(c_r: float, method: DampingMethod = "ec8") -> float:
    """β from the velocity ratio C_r: eq. 4.17 then :func:`damping_reduction`."""
    return damping_reduction(equivalent_damping_from_cr(c_r), method)
