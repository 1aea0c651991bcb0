"""Frame parameters of the stepping portal frame (paper eqs. 4.6-4.12).

The equations of motion integrated by the simulator, for the dominant lateral displacement x [m]
relative to the ground (eqs. 4.11-4.12)::

    unstepped, |x| < x_c:  ẍ + 2ξ₁ω₁ẋ + ω₁²x              = -P₁ ẍ_g
    stepped,   |x| ≥ x_c:  ẍ + 2ξ₂ω₂ẋ - ω₂²x + sign(x)γ₁ = -P₂ ẍ_g

with impact at touchdown (|x| returning to x_c from outside) multiplying the velocity by the
velocity ratio C_r (eq. 4.3; Housner's energy ratio r is C_r²). x* = γ₁/ω₂² is the unstable
equilibrium of the stepped phase.

:class:`PortalFrame` holds these model constants. It is built from model constants directly or
from physical inputs (``from_physical``); every convention the paper leaves open is an explicit
argument with a documented default.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

from stepframe.errors import InputError


@dataclass(frozen=True)
class PortalFrame:
    """Model constants of a stepping portal frame (SI units).

    Attributes
    ----------
    omega_1_rad_s
        Unstepped (fixed-base) circular frequency ω₁ [rad/s].
    omega_2_rad_s
        Stepped-phase frequency parameter ω₂ [rad/s] (negative stiffness -ω₂²).
    p_1, p_2
        Participation factors of the ground acceleration in each phase [-].
    gamma_1_m_s2
        Stepped-phase restoring term γ₁ [m/s²]; x* = γ₁/ω₂².
    xi_1, xi_2
        Viscous damping ratios of the two phases [-] (fractions, ≥ 0).
    x_c_m
        Displacement at the onset of stepping x_c [m] (eq. 4.10); 0 < x_c < x*.
    c_r
        Velocity ratio at impact C_r (eq. 4.3), 0 ≤ C_r ≤ 1; Housner's energy ratio is C_r².
    x_cap_m
        Displacement beyond which the frame is declared overturned [m] (None: the geometric
        overturning displacement set by the builder, or no cap).
    """

    omega_1_rad_s: float
    omega_2_rad_s: float
    p_1: float
    p_2: float
    gamma_1_m_s2: float
    xi_1: float
    xi_2: float
    x_c_m: float
    c_r: float
    x_cap_m: float | None = None

    def __post_init__(self) -> None:
        for name, value in asdict(self).items():
            if value is None and name == "x_cap_m":
                continue
            if not isinstance(value, int | float) or not math.isfinite(value):
                raise InputError(f"{name} = {value!r}, expected a finite number")
        for name in ("omega_1_rad_s", "omega_2_rad_s", "p_1", "p_2", "gamma_1_m_s2", "x_c_m"):
            if not getattr(self, name) > 0:
                raise InputError(f"{name} = {getattr(self, name)}, expected > 0")
        for name in ("xi_1", "xi_2"):
            if not getattr(self, name) >= 0:
                raise InputError(f"{name} = {getattr(self, name)}, expected ≥ 0")
        if not 0 <= self.c_r <= 1:
            raise InputError(f"c_r = {self.c_r}, expected 0 ≤ c_r ≤ 1 (a velocity ratio)")
        if not self.x_c_m < self.x_star_m:
            raise InputError(
                f"x_c_m = {self.x_c_m} m ≥ x* = gamma_1/omega_2² = {self.x_star_m:.6g} m, "
                "expected x_c < x* (otherwise the frame overturns as soon as it steps)"
            )
        if self.x_cap_m is not None and not self.x_cap_m > self.x_c_m:
            raise InputError(f"x_cap_m = {self.x_cap_m} m, expected > x_c_m = {self.x_c_m} m")

    @property
    def x_star_m(self) -> float:
        """Unstable equilibrium of the stepped phase x* = γ₁/ω₂² [m]."""
        return self.gamma_1_m_s2 / self.omega_2_rad_s**2

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary of the model constants."""
        return asdict(self)
