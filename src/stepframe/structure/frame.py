"""Frame parameters of stepping frames (paper eqs. 4.1-4.16).

The equations of motion integrated by the simulator, for the dominant lateral displacement x [m]
relative to the ground (eqs. 4.11-4.12)::

    unstepped, |x| < x_c:  ẍ + 2ξ₁ω₁ẋ + ω₁²x              = -P₁ ẍ_g
    stepped,   |x| ≥ x_c:  ẍ + 2ξ₂ω₂ẋ - ω₂²x + sign(x)γ₁ = -P₂ ẍ_g

with impact at touchdown (|x| returning to x_c from outside) multiplying the velocity by the
velocity ratio C_r (eq. 4.3; Housner's energy ratio r is C_r²). x* = γ₁/ω₂² is the unstable
equilibrium of the stepped phase.

:class:`PortalFrame` holds these model constants. It is built from model constants
(:meth:`PortalFrame.from_constants`), from physical inputs (:meth:`PortalFrame.from_physical`,
eqs. 4.6, 4.7, 4.10, 4.15-4.16) or as the linearised rigid (Housner) block
(:meth:`PortalFrame.housner_block`, x_c = 0: impact at x = 0). Every convention the paper leaves
open is an explicit argument with a documented default:

- ``w_col_convention``: the symbol W_col in eqs. 4.6-4.7 is the weight of both columns
  (``"total"``, default: it reproduces Example 4's printed ω₁ = 6.4581 rad/s, ω₂ = 0.6445 rad/s
  and P₂ = 1.2680 from Example 2's weights) or of one column (``"per-column"``). Eq. 4.10 (the
  axial force in one footing, "half of the weight of the superstructure and the column's weight")
  and eqs. 4.15-4.16 (I_o = (2/3 m̄_col H_r + m̄_s L_F) H_r², which is the inertia of two columns
  only if m̄_col is one column's mass per length) always use one column's weight.
- ``l_m``: the length l in γ₁ (eq. 4.7) is not defined by the paper. Default L_F/2, the lever arm
  of the weight about the pivot footing, for which x* → L_F/2 as the columns get light, as eq.
  5.13 assumes.
- ``c_r`` is the velocity ratio of eq. 4.3, never Housner's energy ratio.

:class:`AFrame` holds the stepping A-frame of eqs. 4.1-4.2 (hysteretic damping in the unstepped
phase, leg inclination θ).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import Any, Literal, get_args

from stepframe.core.validation import damping_fraction, in_range
from stepframe.core.validation import finite as _finite
from stepframe.core.validation import non_negative as _non_negative
from stepframe.core.validation import positive as _positive
from stepframe.errors import InputError

WColConvention = Literal["total", "per-column"]
W_COL_CONVENTIONS: tuple[str, ...] = get_args(WColConvention)

#: Gravity used by the paper's worked examples [m/s²].
PAPER_G_M_S2 = 9.81


#: Plausible range of the model's circular frequencies [rad/s] (periods from 63 µs to 6,000 s):
#: beyond it a value is a typing or unit error, and the integrator's step would underflow.
OMEGA_RANGE_RAD_S = (1e-3, 1e5)
#: Largest damping ratio a frame object takes (over-damped phases are modelled; a frame FILE
#: takes fractions below 1 only, where 5 is far more likely a percentage than a ratio).
MAX_DAMPING = 5.0
#: Plausible range of the participation factors P₁, P₂ [-] (about 1 for real frames).
P_RANGE = (1e-3, 1e3)


def _omega(name: str, value: object) -> float:
    low, high = OMEGA_RANGE_RAD_S
    return in_range(name, _positive(name, value), low, high, unit="rad/s")


def _participation(name: str, value: object) -> float:
    return in_range(name, _positive(name, value), *P_RANGE)


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
        Displacement at the onset of stepping x_c [m] (eq. 4.10); 0 ≤ x_c < x*. x_c = 0 is the
        rigid-block limit: no unstepped phase, impact at x = 0.
    c_r
        Velocity ratio at impact C_r (eq. 4.3), 0 ≤ C_r ≤ 1; Housner's energy ratio is C_r².
    x_cap_m
        Displacement beyond which the frame is declared overturned [m] (None: no cap). The
        physical constructors set it to the geometric overturning displacement.
    h_r_m
        Height of the superstructure above the footings H_r [m], for drift ratios (None:
        unknown, drift ratios are not available).
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
    h_r_m: float | None = None

    def __post_init__(self) -> None:
        for name, value in asdict(self).items():
            if value is None and name in ("x_cap_m", "h_r_m"):
                continue
            _finite(name, value)
        for name in ("omega_1_rad_s", "omega_2_rad_s"):
            _omega(name, getattr(self, name))
        for name in ("p_1", "p_2"):
            _participation(name, getattr(self, name))
        _positive("gamma_1_m_s2", self.gamma_1_m_s2)
        for name in ("xi_1", "xi_2"):
            damping_fraction(name, getattr(self, name), high=MAX_DAMPING)
        _non_negative("x_c_m", self.x_c_m)
        if not 0 <= self.c_r <= 1:
            raise InputError(f"c_r = {self.c_r}, expected 0 ≤ c_r ≤ 1 (a velocity ratio)")
        if not self.x_c_m < self.x_star_m:
            raise InputError(
                f"x_c_m = {self.x_c_m} m ≥ x* = gamma_1/omega_2² = {self.x_star_m:.6g} m, "
                "expected x_c < x* (otherwise the frame overturns as soon as it steps)"
            )
        if self.x_cap_m is not None and not self.x_cap_m > self.x_c_m:
            raise InputError(f"x_cap_m = {self.x_cap_m} m, expected > x_c_m = {self.x_c_m} m")
        if self.h_r_m is not None:
            _positive("h_r_m", self.h_r_m)

    # ----------------------------------------------------------------- derived quantities
    @property
    def x_star_m(self) -> float:
        """Unstable equilibrium of the stepped phase x* = γ₁/ω₂² [m]."""
        return self.gamma_1_m_s2 / self.omega_2_rad_s**2

    @property
    def is_rigid_block(self) -> bool:
        """True for x_c = 0: no unstepped phase, impact at x = 0 (Housner block)."""
        return self.x_c_m == 0.0

    @property
    def uplift_acceleration_m_s2(self) -> float:
        """Static ground acceleration that starts stepping, ω₁² x_c / P₁ [m/s²].

        A constant ground acceleration a deflects the unstepped frame by P₁ a / ω₁² (eq. 4.11 at
        rest); stepping starts when that reaches x_c.
        """
        return self.omega_1_rad_s**2 * self.x_c_m / self.p_1

    @property
    def drift_ratio_per_m(self) -> float | None:
        """Drift ratio per metre of x, 1/H_r [1/m] (None when H_r is unknown)."""
        return None if self.h_r_m is None else 1.0 / self.h_r_m

    @property
    def unstepped_period_s(self) -> float:
        """Small-amplitude (fixed-base) period 2π/ω₁ [s]."""
        return 2.0 * math.pi / self.omega_1_rad_s

    # ----------------------------------------------------------------- dictionaries
    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary of the model constants (the keys of :meth:`from_dict`)."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> PortalFrame:
        """Inverse of :meth:`to_dict`; unknown keys raise :class:`InputError` naming them."""
        names = [f.name for f in fields(cls)]
        unknown = sorted(set(data) - set(names))
        if unknown:
            raise InputError(f"unknown key(s) {', '.join(unknown)}, expected some of {names}")
        required = [f.name for f in fields(cls) if f.name not in ("x_cap_m", "h_r_m")]
        missing = [name for name in required if name not in data]
        if missing:
            raise InputError(f"missing key(s) {', '.join(missing)}")
        return cls(**data)

    # ----------------------------------------------------------------- constructors
    @classmethod
    def from_constants(
        cls,
        *,
        omega_1_rad_s: float,
        omega_2_rad_s: float,
        p_1: float,
        p_2: float,
        gamma_1_m_s2: float,
        xi_1: float,
        xi_2: float,
        x_c_m: float | None = None,
        c_r: float | None = None,
        x_cap_m: float | None = None,
        h_r_m: float | None = None,
        w_s_n: float | None = None,
        w_col_n: float | None = None,
        l_f_m: float | None = None,
        k_a_n_m: float | None = None,
        g_m_s2: float = PAPER_G_M_S2,
    ) -> PortalFrame:
        """A frame from its model constants, deriving x_c, C_r and the cap when not given.

        Example 4 of the paper gives ω₁, ω₂, P₁, P₂, γ₁, ξ₁, ξ₂ but leaves x_c and C_r implicit;
        they follow from the physical inputs through eq. 4.10 and eqs. 4.15-4.16.

        Parameters
        ----------
        omega_1_rad_s, omega_2_rad_s, p_1, p_2, gamma_1_m_s2, xi_1, xi_2
            Model constants (see the class attributes).
        x_c_m
            Onset of stepping [m]; None: solved from eq. 4.10 (needs ``k_a_n_m``, ``h_r_m``,
            ``w_s_n``, ``w_col_n``).
        c_r
            Velocity ratio at impact; None: eqs. 4.15-4.16 (needs ``w_s_n``, ``w_col_n``,
            ``h_r_m``, ``l_f_m``).
        x_cap_m
            Overturning cap [m]; None: the geometric overturning displacement when ``w_s_n``,
            ``w_col_n``, ``h_r_m`` and ``l_f_m`` are given, else no cap.
        h_r_m, w_s_n, w_col_n, l_f_m, k_a_n_m
            Optional physical inputs [m, N, N, m, N/m]: H_r, W_S, the total weight of both
            columns, L_F, and the axial stiffness K_a of one leg.
        g_m_s2
            Gravity [m/s²] (the paper's examples use 9.81).
        """
        g = _positive("g_m_s2", g_m_s2)
        phys = {
            "w_s_n": w_s_n,
            "w_col_n": w_col_n,
            "h_r_m": h_r_m,
            "l_f_m": l_f_m,
            "k_a_n_m": k_a_n_m,
        }
        for name, value in phys.items():
            if value is not None:
                (_non_negative if name == "w_col_n" else _positive)(name, value)

        def need(purpose: str, names: tuple[str, ...]) -> list[float]:
            missing = [name for name in names if phys[name] is None]
            if missing:
                raise InputError(f"{purpose} not given and cannot be derived: missing {missing}")
            return [float(phys[name]) for name in names]  # type: ignore[arg-type]

        if x_c_m is None:
            k_a, h_r, w_s, w_col = need("x_c_m", ("k_a_n_m", "h_r_m", "w_s_n", "w_col_n"))
            x_c_m = onset_of_stepping_m(k_a, h_r, w_s, w_col / 2.0)
        if c_r is None:
            w_s, w_col, h_r, l_f = need("c_r", ("w_s_n", "w_col_n", "h_r_m", "l_f_m"))
            c_r = restitution_velocity_ratio(w_s, w_col / 2.0, h_r, l_f, g_m_s2=g)
        if x_cap_m is None and all(phys[n] is not None for n in ("w_s_n", "w_col_n", "l_f_m")):
            w_s, w_col, h_r, l_f = need("x_cap_m", ("w_s_n", "w_col_n", "h_r_m", "l_f_m"))
            x_cap_m = overturning_displacement_m(w_s, w_col, h_r, l_f)
        return cls(
            omega_1_rad_s=omega_1_rad_s,
            omega_2_rad_s=omega_2_rad_s,
            p_1=p_1,
            p_2=p_2,
            gamma_1_m_s2=gamma_1_m_s2,
            xi_1=xi_1,
            xi_2=xi_2,
            x_c_m=x_c_m,
            c_r=c_r,
            x_cap_m=x_cap_m,
            h_r_m=h_r_m,
        )

    @classmethod
    def from_physical(
        cls,
        *,
        w_s_n: float,
        w_col_n: float,
        h_r_m: float,
        l_f_m: float,
        k_a_n_m: float,
        k_b_n_m: float,
        xi_1: float,
        xi_2: float,
        l_m: float | None = None,
        c_r: float | None = None,
        x_c_m: float | None = None,
        x_cap_m: float | None = None,
        g_m_s2: float = PAPER_G_M_S2,
        w_col_convention: WColConvention = "total",
    ) -> PortalFrame:
        """A frame from its physical inputs through eqs. 4.6, 4.7, 4.10 and 4.15-4.16.

        Parameters
        ----------
        w_s_n
            Weight of the superstructure W_S [N].
        w_col_n
            Total weight of both columns [N] (W_T - W_S in the paper's examples).
        h_r_m
            Height of the superstructure above the footings H_r [m].
        l_f_m
            Distance between the footings L_F [m].
        k_a_n_m, k_b_n_m
            Resultant axial and bending stiffness of each leg K_a, K_b [N/m].
        xi_1, xi_2
            Viscous damping ratios of the unstepped and stepped phases [-].
        l_m
            The length l in γ₁ (eq. 4.7) [m]; None: L_F/2 (see the module docstring).
        c_r
            Velocity ratio at impact; None: eqs. 4.15-4.16 with one column's weight.
        x_c_m
            Onset of stepping [m]; None: the smallest root of eq. 4.10 with one column's weight.
        x_cap_m
            Overturning cap [m]; None: :func:`overturning_displacement_m`.
        g_m_s2
            Gravity [m/s²] (the paper's examples use 9.81).
        w_col_convention
            What W_col stands for in eqs. 4.6-4.7: ``"total"`` (both columns, default) or
            ``"per-column"``.
        """
        w_s = _positive("w_s_n", w_s_n)
        w_col_total = _non_negative("w_col_n", w_col_n)
        h_r = _positive("h_r_m", h_r_m)
        l_f = _positive("l_f_m", l_f_m)
        k_a = _positive("k_a_n_m", k_a_n_m)
        k_b = _positive("k_b_n_m", k_b_n_m)
        g = _positive("g_m_s2", g_m_s2)
        lever = l_f / 2.0 if l_m is None else _positive("l_m", l_m)
        if w_col_convention == "total":
            w_col = w_col_total
        elif w_col_convention == "per-column":
            w_col = w_col_total / 2.0
        else:
            raise InputError(
                f"w_col_convention = {w_col_convention!r}, expected one of {W_COL_CONVENTIONS}"
            )
        # eq. 4.6
        omega_1_sq = 2.0 * k_b * g / (w_s + 2.0 / 3.0 * w_col)
        p_1 = (w_s + w_col) / (w_s + 2.0 / 3.0 * w_col)
        # eq. 4.7
        denominator = w_s + 5.0 / 9.0 * w_col
        omega_2_sq = (w_s + w_col) / denominator * g / h_r
        gamma_1 = (w_s + 2.0 * w_col) / denominator * g / h_r * lever
        p_2 = (w_s + w_col) / denominator
        if x_c_m is None:
            x_c_m = onset_of_stepping_m(k_a, h_r, w_s, w_col_total / 2.0)
        if c_r is None:
            c_r = restitution_velocity_ratio(w_s, w_col_total / 2.0, h_r, l_f, g_m_s2=g)
        if x_cap_m is None:
            x_cap_m = overturning_displacement_m(w_s, w_col_total, h_r, l_f)
        return cls(
            omega_1_rad_s=math.sqrt(omega_1_sq),
            omega_2_rad_s=math.sqrt(omega_2_sq),
            p_1=p_1,
            p_2=p_2,
            gamma_1_m_s2=gamma_1,
            xi_1=xi_1,
            xi_2=xi_2,
            x_c_m=x_c_m,
            c_r=c_r,
            x_cap_m=x_cap_m,
            h_r_m=h_r,
        )

    @classmethod
    def housner_block(
        cls,
        *,
        half_width_m: float,
        half_height_m: float,
        g_m_s2: float = PAPER_G_M_S2,
        c_r: float | None = None,
        xi: float = 0.0,
    ) -> PortalFrame:
        """The linearised rigid rectangular block of Housner (1963) on a rigid base.

        With θ the rotation and α = atan(b/h), I_o = (4/3) m R² and p² = 3g/(4R), the
        linearised equation θ̈ - p²θ + p²α sign θ = -p² ẍ_g/g, written for the horizontal
        displacement of the centre of mass x = h θ, is the stepped phase of eq. 4.12 with
        ω₂ = p, γ₁ = p² α h, P₂ = p² h / g (so x* = α h and the free-rocking quarter period
        from rest at x₀ is arccosh(1/(1 - x₀/x*))/p). There is no unstepped phase (x_c = 0):
        impact happens at x = 0. ω₁ and P₁ are set to p and P₂ and never used.

        Parameters
        ----------
        half_width_m, half_height_m
            b and h of the block [m].
        g_m_s2
            Gravity [m/s²].
        c_r
            Velocity ratio at impact; None: Housner's 1 - 1.5 sin²α (angular momentum
            conservation about the new pivot).
        xi
            Viscous damping ratio of the rocking phase [-] (0 in Housner's model).
        """
        b = _positive("half_width_m", half_width_m)
        h = _positive("half_height_m", half_height_m)
        g = _positive("g_m_s2", g_m_s2)
        alpha = math.atan2(b, h)
        radius = math.hypot(b, h)
        p = math.sqrt(3.0 * g / (4.0 * radius))
        if c_r is None:
            c_r = 1.0 - 1.5 * math.sin(alpha) ** 2
            if c_r < 0:  # sin²α > 2/3: Housner's formula has no meaning for so squat a block
                raise InputError(
                    f"a block of b = {b:g} m, h = {h:g} m is too squat for Housner's C_r = "
                    f"1 - 1.5 sin²α = {c_r:.3g} (b/h > √2), expected a slender block (b/h < "
                    "√2) or c_r given (a [block] table's c_r; --block cannot give it)"
                )
        return cls(
            omega_1_rad_s=p,
            omega_2_rad_s=p,
            p_1=p * p * h / g,
            p_2=p * p * h / g,
            gamma_1_m_s2=p * p * alpha * h,
            xi_1=xi,
            xi_2=xi,
            x_c_m=0.0,
            c_r=c_r,
            x_cap_m=None,
            h_r_m=h,
        )


@dataclass(frozen=True)
class RockingBlock:
    """A rigid rectangular block on a rigid base (SI units), for the full nonlinear rocking
    equation of :mod:`stepframe.structure.rocking_block` (its small-angle model:
    :meth:`linearised`, :meth:`PortalFrame.housner_block`).

    Attributes
    ----------
    half_width_m, half_height_m
        b and h [m].
    g_m_s2
        Gravity [m/s²] (9.81, the paper's value, as
        :meth:`~stepframe.structure.frame.PortalFrame.housner_block`).
    c_r
        Velocity ratio at impact (None: Housner's 1 - (3/2)sin²α); Housner's energy ratio r is
        its square.
    """

    half_width_m: float
    half_height_m: float
    g_m_s2: float = PAPER_G_M_S2
    c_r: float | None = None

    def __post_init__(self) -> None:
        for name in ("half_width_m", "half_height_m", "g_m_s2"):
            _positive(name, getattr(self, name))
        if self.c_r is not None:
            in_range("c_r", self.c_r, 0.0, 1.0)

    @property
    def alpha_rad(self) -> float:
        """Slenderness α = atan(b/h) [rad]."""
        return math.atan2(self.half_width_m, self.half_height_m)

    @property
    def p_rad_s(self) -> float:
        """Frequency parameter p = √(3g/(4R)) [rad/s]."""
        return math.sqrt(
            3.0 * self.g_m_s2 / (4.0 * math.hypot(self.half_width_m, self.half_height_m))
        )

    @property
    def restitution(self) -> float:
        """C_r used at impacts (the given one, or Housner's 1 - (3/2)sin²α)."""
        return 1.0 - 1.5 * math.sin(self.alpha_rad) ** 2 if self.c_r is None else self.c_r

    @property
    def uplift_acceleration_m_s2(self) -> float:
        """Ground acceleration that lifts the block off at rest, g·tan α [m/s²]."""
        return self.g_m_s2 * self.half_width_m / self.half_height_m

    def linearised(self) -> PortalFrame:
        """The small-angle model of the same block (x = hθ, uplift at g·α)."""
        return PortalFrame.housner_block(
            half_width_m=self.half_width_m, half_height_m=self.half_height_m,
            g_m_s2=self.g_m_s2, c_r=self.restitution,
        )  # fmt: skip


# --------------------------------------------------------------------- physical relations
def onset_of_stepping_m(k_a_n_m: float, h_r_m: float, w_s_n: float, w_col_one_n: float) -> float:
    """x_c: the smallest root of eq. 4.10, W_S/2 + W_col = ½ K_a x_c sin(2 x_c / H_r).

    Parameters
    ----------
    k_a_n_m
        Axial stiffness of one leg K_a [N/m].
    h_r_m
        Height H_r [m].
    w_s_n
        Weight of the superstructure W_S [N] (each footing carries half).
    w_col_one_n
        Weight of one column [N].

    Returns
    -------
    float
        x_c [m]. The right-hand side rises from 0 to its maximum at 2x/H_r = u_max (the root of
        tan u = -u, u_max ≈ 2.0288); a footing load above that maximum never lifts off and
        raises :class:`InputError`.
    """
    k_a = _positive("k_a_n_m", k_a_n_m)
    h_r = _positive("h_r_m", h_r_m)
    load = _positive("w_s_n", w_s_n) / 2.0 + _non_negative("w_col_n", w_col_one_n)

    def excess(x: float) -> float:
        return 0.5 * k_a * x * math.sin(2.0 * x / h_r) - load

    def slope(x: float) -> float:
        u = 2.0 * x / h_r
        return 0.5 * k_a * (math.sin(u) + u * math.cos(u))

    x_max = _U_MAX * h_r / 2.0
    if excess(x_max) <= 0:
        raise InputError(
            f"k_a_n_m = {k_a:.6g} N/m cannot lift a footing carrying {load:.6g} N (eq. 4.10 "
            f"peaks at {load + excess(x_max):.6g} N), expected a stiffer leg"
        )
    # excess is increasing on [0, x_max]: Newton from the small-angle root, kept inside a
    # shrinking bracket (bisection when a step leaves it). Plain Python: no scipy import at
    # frame construction, which the command line pays for on every run.
    low, high = 0.0, x_max
    x = min(math.sqrt(h_r * load / k_a), 0.5 * x_max)
    for _ in range(200):
        value = excess(x)
        if value > 0:
            high = x
        else:
            low = x
        step = value / slope(x) if slope(x) > 0 else math.inf
        candidate = x - step
        if not low < candidate < high:
            candidate = 0.5 * (low + high)
        if abs(candidate - x) <= 4e-16 * x or high - low <= 4e-16 * high:
            return candidate
        x = candidate
    return x


#: Root of tan u = -u in (π/2, π): 2x/H_r at the maximum of the right side of eq. 4.10.
_U_MAX = 2.028757838110434


def restitution_velocity_ratio(
    w_s_n: float, w_col_one_n: float, h_r_m: float, l_f_m: float, g_m_s2: float = PAPER_G_M_S2
) -> float:
    """C_r of eqs. 4.15-4.16 (a velocity ratio) from angular momentum about the new pivot.

    C_r = 1 - (m̄_col H_r L_F² + m̄_s L_F³/3) / I_o, I_o = (2/3 m̄_col H_r + m̄_s L_F) H_r²,
    m̄_col = W_col/(g H_r) (one column), m̄_s = W_S/(g L_F). Equals the paper's
    1 - c₂² (3 + c₁)/(2 + 3c₁) for W_S = c₁ W_col and L_F = c₂ H_r.

    Returns
    -------
    float
        C_r in [0, 1); a squat frame for which the formula is negative raises
        :class:`InputError` (the momentum model does not apply; give C_r).
    """
    w_s = _positive("w_s_n", w_s_n)
    w_col = _non_negative("w_col_n", w_col_one_n)
    h_r = _positive("h_r_m", h_r_m)
    l_f = _positive("l_f_m", l_f_m)
    g = _positive("g_m_s2", g_m_s2)
    m_col = w_col / (g * h_r)
    m_s = w_s / (g * l_f)
    inertia = (2.0 / 3.0 * m_col * h_r + m_s * l_f) * h_r**2
    c_r = 1.0 - (m_col * h_r * l_f**2 + m_s * l_f**3 / 3.0) / inertia
    if c_r < 0:
        raise InputError(
            f"c_r from eqs. 4.15-4.16 = {c_r:.4g} for L_F/H_r = {l_f / h_r:.4g}, expected ≥ 0 "
            "(the frame is too squat for the momentum model: give c_r)"
        )
    return c_r


def overturning_displacement_m(w_s_n: float, w_col_n: float, h_r_m: float, l_f_m: float) -> float:
    """Geometric overturning displacement of the deck [m]: the default x_cap.

    The frame, rocking rigidly about one footing, topples when its centre of mass (at L_F/2
    from the pivot and at height h_cm = H_r (W_S + W_col/2)/(W_S + W_col), W_col the total column
    weight) is above the pivot, at rotation φ = atan(L_F / (2 h_cm)). The deck's centre has then
    moved (L_F/2)(1 - cos φ) + H_r sin φ sideways. Elastic drift at uplift shortens the lever arm
    and the rotation needed by the same amount to first order, so it is not added.
    """
    w_s = _positive("w_s_n", w_s_n)
    w_col = _non_negative("w_col_n", w_col_n)
    h_r = _positive("h_r_m", h_r_m)
    half = _positive("l_f_m", l_f_m) / 2.0
    h_cm = h_r * (w_s + w_col / 2.0) / (w_s + w_col)
    phi = math.atan2(half, h_cm)
    return half * (1.0 - math.cos(phi)) + h_r * math.sin(phi)


# --------------------------------------------------------------------- A-frame
class EquivalentViscousWarning(UserWarning):
    """The A-frame's hysteretic damping replaced by viscous damping: results carry its error."""


#: The equivalent-viscous route's error on the peak, measured against the hysteretic A-frame
#: (``python bench/bench_structure_models.py``, docs/structure-dynamics.md).
EQUIVALENT_VISCOUS_NOTE = (
    "equivalent-viscous damping in place of the A-frame's hysteretic damping (eq. 4.1): against "
    "the exact hysteretic model (stepframe.structure.aframe_hysteretic.simulate_aframe) the peak "
    "|x| erred by a median 8.1 % and up to +567 % over 3 frames × 100 FEMA P695 records × 4 "
    "intensities, and the overturning verdict differed in 97 of 1200 runs"
)


@dataclass(frozen=True)
class AFrame:
    """Lateral model of the stepping A-frame, eqs. 4.1-4.2 (vertical coordinates omitted).

    ::

        unstepped, |x| ≤ x_c:  ẍ + πξ₁ω₁² sign(ẋ)|x| + ω₁²x        = -P₁ ẍ_g
        stepped,   |x| > x_c:  ẍ - ω₂² sec θ x + γ₁ sec θ sign(x)  = -P₂ sec θ ẍ_g

    The hysteretic term dissipates 2πξ₁ω₁²A² per cycle of amplitude A, as much as viscous
    damping ξ₁ at resonance, independent of frequency. The vertical coordinates x₃, x₄ of eqs.
    4.1-4.2 decouple without vertical excitation and are not modelled. Impact at touchdown
    multiplies the velocity by C_r (eq. 4.3).

    Attributes
    ----------
    omega_1_rad_s, omega_2_rad_s
        ω₁, ω₂ [rad/s] as defined by Beck and Skinner (1974).
    p_1, p_2
        Participation factors [-].
    gamma_1_m_s2
        γ₁ [m/s²].
    xi_1
        Hysteretic damping factor of the unstepped phase [-].
    theta_rad
        Inclination θ of the legs from the vertical [rad], 0 ≤ θ < π/2 (θ = 0: portal frame).
    x_c_m
        Onset of stepping [m], 0 < x_c < x*.
    c_r
        Velocity ratio at impact, 0 ≤ C_r ≤ 1.
    x_cap_m
        Overturning cap [m] or None.
    """

    omega_1_rad_s: float
    omega_2_rad_s: float
    p_1: float
    p_2: float
    gamma_1_m_s2: float
    xi_1: float
    theta_rad: float
    x_c_m: float
    c_r: float
    x_cap_m: float | None = None

    def __post_init__(self) -> None:
        for name, value in asdict(self).items():
            if value is None and name == "x_cap_m":
                continue
            _finite(name, value)
        for name in ("omega_1_rad_s", "omega_2_rad_s"):
            _omega(name, getattr(self, name))
        for name in ("p_1", "p_2"):
            _participation(name, getattr(self, name))
        for name in ("gamma_1_m_s2", "x_c_m"):
            _positive(name, getattr(self, name))
        damping_fraction("xi_1", self.xi_1, high=MAX_DAMPING)
        if not 0 <= self.theta_rad < math.pi / 2:
            raise InputError(f"theta_rad = {self.theta_rad}, expected 0 ≤ theta_rad < π/2")
        if not 0 <= self.c_r <= 1:
            raise InputError(f"c_r = {self.c_r}, expected 0 ≤ c_r ≤ 1 (a velocity ratio)")
        if not self.x_c_m < self.x_star_m:
            raise InputError(
                f"x_c_m = {self.x_c_m} m ≥ x* = gamma_1/omega_2² = {self.x_star_m:.6g} m, "
                "expected x_c < x*"
            )
        if self.x_cap_m is not None and not self.x_cap_m > self.x_c_m:
            raise InputError(f"x_cap_m = {self.x_cap_m} m, expected > x_c_m = {self.x_c_m} m")

    @property
    def x_star_m(self) -> float:
        """Unstable equilibrium of the stepped phase, γ₁/ω₂² [m] (sec θ cancels)."""
        return self.gamma_1_m_s2 / self.omega_2_rad_s**2

    @property
    def stepped_constants(self) -> tuple[float, float, float]:
        """(ω₂ √sec θ [rad/s], γ₁ sec θ [m/s²], P₂ sec θ): eq. 4.2 in the form of eq. 4.12."""
        sec = 1.0 / math.cos(self.theta_rad)
        return self.omega_2_rad_s * math.sqrt(sec), self.gamma_1_m_s2 * sec, self.p_2 * sec

    def acceleration_m_s2(
        self, x_m: float, v_m_s: float, ground_acc_m_s2: float, *, stepped: bool
    ) -> float:
        """ẍ of eq. 4.1 (``stepped=False``) or eq. 4.2 (``stepped=True``) [m/s²]."""
        if not stepped:
            w1 = self.omega_1_rad_s
            hysteretic = math.pi * self.xi_1 * w1 * w1 * math.copysign(abs(x_m), v_m_s)
            if v_m_s == 0.0:
                hysteretic = 0.0
            return -hysteretic - w1 * w1 * x_m - self.p_1 * ground_acc_m_s2
        w2, gamma, p2 = self.stepped_constants
        return w2 * w2 * x_m - gamma * math.copysign(1.0, x_m) - p2 * ground_acc_m_s2

    def to_portal_frame(
        self, hysteretic: Literal["refuse", "equivalent-viscous"] = "refuse"
    ) -> PortalFrame:
        """The same lateral model in the form of eqs. 4.11-4.12, for the portal-frame tools.

        The stepped phase maps exactly (:attr:`stepped_constants`, ξ₂ = 0). The unstepped phase
        maps exactly only without hysteretic damping (ξ₁ = 0).

        Parameters
        ----------
        hysteretic
            ``"refuse"`` (default): raise :class:`InputError` when ξ₁ > 0.
            ``"equivalent-viscous"``: replace the hysteretic term by viscous damping ξ₁, which
            dissipates the same energy per cycle at ω = ω₁ (and more above, less below it), and
            cannot stick; it warns (:class:`EquivalentViscousWarning`) with the error measured
            over records and frames (:data:`EQUIVALENT_VISCOUS_NOTE`). The exact route is
            :func:`stepframe.structure.aframe_hysteretic.simulate_aframe`.
        """
        if hysteretic not in ("refuse", "equivalent-viscous"):
            raise InputError(
                f"hysteretic = {hysteretic!r}, expected 'refuse' or 'equivalent-viscous'"
            )
        if self.xi_1 > 0 and hysteretic == "refuse":
            raise InputError(
                f"xi_1 = {self.xi_1} is hysteretic damping (eq. 4.1), expected 0 for an exact "
                "portal-frame form, or hysteretic='equivalent-viscous'"
            )
        if self.xi_1 > 0:
            import warnings

            warnings.warn(EQUIVALENT_VISCOUS_NOTE, EquivalentViscousWarning, stacklevel=2)
        omega_2, gamma_1, p_2 = self.stepped_constants
        return PortalFrame(
            omega_1_rad_s=self.omega_1_rad_s,
            omega_2_rad_s=omega_2,
            p_1=self.p_1,
            p_2=p_2,
            gamma_1_m_s2=gamma_1,
            xi_1=self.xi_1,
            xi_2=0.0,
            x_c_m=self.x_c_m,
            c_r=self.c_r,
            x_cap_m=self.x_cap_m,
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary of the constants."""
        return asdict(self)
