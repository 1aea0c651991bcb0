"""Code design spectra: ASCE 7-22's two-period spectrum and Eurocode 8's elastic spectra.

Both give ``sa_m_s2(period_s)``, ``branch(period_s)`` and ``to_dict()`` (the
:class:`~stepframe.structure.design_spectrum.Spectrum` protocol), so either can be a selection
target or a design spectrum. The equations are the standards' own, written here from them:

**ASCE/SEI 7-22 §11.4.5.2, two-period design response spectrum** (5 % damping; the same shape
as ASCE 7-16 §11.4.6, Fig. 11.4-1), with T_0 = 0.2 S_D1/S_DS and T_s = S_D1/S_DS:

- T < T_0: S_a = S_DS (0.4 + 0.6 T/T_0)
- T_0 ≤ T ≤ T_s: S_a = S_DS
- T_s < T ≤ T_L: S_a = S_D1/T
- T > T_L: S_a = S_D1 T_L/T²

(unlike :class:`~stepframe.structure.design_spectrum.TwoPeriodSpectrum`, the paper's shape,
which holds the plateau down to T = 0). ASCE 7-22's multi-period spectrum (§11.4.5.1) is a table
of ordinates from the USGS Seismic Design Geodatabase: a
:class:`~stepframe.structure.design_spectrum.TabulatedSpectrum`.

**EN 1998-1:2004 §3.2.2.2, horizontal elastic response spectrum**, eqs. 3.2-3.5, with
a_g = γ_I a_gR, the soil factor S and corner periods T_B, T_C, T_D of Table 3.2 (Type 1) or
Table 3.3 (Type 2), and the damping correction η = √(10/(5 + ξ)) ≥ 0.55 (eq. 3.6, ξ in percent):

- 0 ≤ T ≤ T_B: S_e = a_g S [1 + (T/T_B)(2.5 η - 1)]
- T_B ≤ T ≤ T_C: S_e = 2.5 a_g S η
- T_C ≤ T ≤ T_D: S_e = 2.5 a_g S η T_C/T
- T_D ≤ T ≤ 4 s: S_e = 2.5 a_g S η T_C T_D/T²

The standard defines the spectrum up to 4 s (longer periods: its informative Annex A); beyond
4 s this class continues the last branch (constant spectral displacement), which a stepping
frame's elongated period can reach: the output says so where it matters.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Literal

from stepframe.core import validation
from stepframe.errors import InputError
from stepframe.structure.design_spectrum import Branch
from stepframe.structure.frame import PAPER_G_M_S2

#: EN 1998-1 Tables 3.2 (Type 1) and 3.3 (Type 2): ground type → (S, T_B [s], T_C [s], T_D [s]).
EC8_PARAMETERS: dict[str, dict[str, tuple[float, float, float, float]]] = {
    "type1": {
        "A": (1.0, 0.15, 0.4, 2.0),
        "B": (1.2, 0.15, 0.5, 2.0),
        "C": (1.15, 0.20, 0.6, 2.0),
        "D": (1.35, 0.20, 0.8, 2.0),
        "E": (1.4, 0.15, 0.5, 2.0),
    },
    "type2": {
        "A": (1.0, 0.05, 0.25, 1.2),
        "B": (1.35, 0.05, 0.25, 1.2),
        "C": (1.5, 0.10, 0.25, 1.2),
        "D": (1.8, 0.10, 0.30, 1.2),
        "E": (1.6, 0.05, 0.25, 1.2),
    },
}
#: The period up to which EN 1998-1 §3.2.2.2 defines the elastic spectrum [s].
EC8_LAST_PERIOD_S = 4.0


@dataclass(frozen=True)
class Asce7TwoPeriod:
    """ASCE 7-22 §11.4.5.2 two-period design response spectrum.

    Attributes
    ----------
    s_ds_g, s_d1_g
        Design spectral accelerations S_DS (short periods) and S_D1 (at 1 s) [g].
    t_l_s
        Long-period transition period T_L [s] (None: the S_D1/T branch continues).
    g_m_s2
        Gravity converting g to m/s² (default the paper's 9.81, as every g_m_s2 of
        :mod:`stepframe.structure`; the selection passes standard gravity 9.80665).
    """

    s_ds_g: float
    s_d1_g: float
    t_l_s: float | None = None
    g_m_s2: float = PAPER_G_M_S2

    def __post_init__(self) -> None:
        validation.positive("s_ds_g", self.s_ds_g)
        validation.positive("s_d1_g", self.s_d1_g)
        if self.t_l_s is not None and not self.t_l_s > self.t_s_s:
            raise InputError(
                f"t_l_s = {self.t_l_s} s, expected > T_s = S_D1/S_DS = {self.t_s_s:.6g} s"
            )

    @property
    def t_s_s(self) -> float:
        """T_s = S_D1/S_DS [s]."""
        return self.s_d1_g / self.s_ds_g

    @property
    def t_0_s(self) -> float:
        """T_0 = 0.2 S_D1/S_DS [s]."""
        return 0.2 * self.t_s_s

    def branch(self, period_s: float) -> Branch:
        """``"short"`` up to T_s (the ramp and the plateau), ``"long"`` to T_L, then
        ``"very-long"``."""
        if period_s <= self.t_s_s:
            return "short"
        if self.t_l_s is None or period_s <= self.t_l_s:
            return "long"
        return "very-long"

    def sa_g(self, period_s: float) -> float:
        """S_a(T) [g]."""
        if period_s < self.t_0_s:
            return self.s_ds_g * (0.4 + 0.6 * period_s / self.t_0_s)
        branch = self.branch(period_s)
        if branch == "short":
            return self.s_ds_g
        if branch == "long":
            return self.s_d1_g / period_s
        assert self.t_l_s is not None
        return self.s_d1_g * self.t_l_s / period_s**2

    def sa_m_s2(self, period_s: float) -> float:
        """S_a(T) [m/s²]."""
        return self.sa_g(period_s) * self.g_m_s2

    def describe(self) -> str:
        """The spectrum in words, for the output."""
        t_l = "" if self.t_l_s is None else f", T_L {self.t_l_s:g} s"
        return (
            f"ASCE 7-22 two-period spectrum (§11.4.5.2): S_DS {self.s_ds_g:g} g, "
            f"S_D1 {self.s_d1_g:g} g{t_l}"
        )

    def to_dict(self) -> dict[str, Any]:
        """``kind``, the standard and the parameters."""
        return {
            "kind": "asce7-22-two-period",
            "standard": "ASCE/SEI 7-22 §11.4.5.2",
            "s_ds_g": self.s_ds_g,
            "s_d1_g": self.s_d1_g,
            "t_l_s": self.t_l_s,
            "damping": 0.05,
        }


@dataclass(frozen=True)
class Ec8Elastic:
    """EN 1998-1:2004 §3.2.2.2 horizontal elastic response spectrum.

    Attributes
    ----------
    spectrum_type
        ``"type1"`` (Table 3.2, M_s > 5.5) or ``"type2"`` (Table 3.3).
    ground
        Ground type ``"A"`` to ``"E"``.
    a_gr_g
        Reference peak ground acceleration on type A ground a_gR [g].
    importance
        Importance factor γ_I (a_g = γ_I a_gR).
    damping
        Viscous damping ratio (a fraction; the code's ξ is in percent).
    g_m_s2
        Gravity converting g to m/s² (default the paper's 9.81, as every g_m_s2 of
        :mod:`stepframe.structure`; the selection passes standard gravity 9.80665).
    """

    spectrum_type: Literal["type1", "type2"]
    ground: Literal["A", "B", "C", "D", "E"]
    a_gr_g: float
    importance: float = 1.0
    damping: float = 0.05
    g_m_s2: float = PAPER_G_M_S2

    def __post_init__(self) -> None:
        if self.spectrum_type not in EC8_PARAMETERS:
            raise InputError(f"spectrum type {self.spectrum_type!r}, expected type1 or type2")
        if self.ground not in EC8_PARAMETERS[self.spectrum_type]:
            raise InputError(f"ground type {self.ground!r}, expected one of A, B, C, D, E")
        validation.positive("a_gr_g", self.a_gr_g)
        validation.positive("importance", self.importance)
        if not 0 < self.damping < 1:
            raise InputError(f"damping = {self.damping}, expected a fraction in (0, 1)")

    @property
    def parameters(self) -> tuple[float, float, float, float]:
        """(S, T_B, T_C, T_D) of the type and ground."""
        return EC8_PARAMETERS[self.spectrum_type][self.ground]

    @property
    def a_g_g(self) -> float:
        """Design ground acceleration on type A ground a_g = γ_I a_gR [g]."""
        return self.importance * self.a_gr_g

    @property
    def eta(self) -> float:
        """Damping correction η = √(10/(5 + ξ[%])) ≥ 0.55 (eq. 3.6)."""
        return max(math.sqrt(10.0 / (5.0 + 100.0 * self.damping)), 0.55)

    @property
    def pga_g(self) -> float:
        """The zero-period ordinate a_g S [g] (the mean PGA the suite must reach)."""
        return self.a_g_g * self.parameters[0]

    def branch(self, period_s: float) -> Branch:
        """``"short"`` up to T_C, ``"long"`` to T_D, ``"very-long"`` beyond."""
        _, _, t_c, t_d = self.parameters
        if period_s <= t_c:
            return "short"
        return "long" if period_s <= t_d else "very-long"

    def sa_g(self, period_s: float) -> float:
        """S_e(T) [g] (eqs. 3.2-3.5; the last branch continued beyond 4 s)."""
        s, t_b, t_c, t_d = self.parameters
        top = 2.5 * self.a_g_g * s * self.eta
        if period_s <= t_b:
            return self.a_g_g * s * (1.0 + period_s / t_b * (2.5 * self.eta - 1.0))
        if period_s <= t_c:
            return top
        if period_s <= t_d:
            return top * t_c / period_s
        return top * t_c * t_d / period_s**2

    def sa_m_s2(self, period_s: float) -> float:
        """S_e(T) [m/s²]."""
        return self.sa_g(period_s) * self.g_m_s2

    def describe(self) -> str:
        """The spectrum in words, for the output."""
        number = self.spectrum_type[-1]
        return (
            f"Eurocode 8 Type {number} elastic spectrum (EN 1998-1 §3.2.2.2), ground "
            f"{self.ground}, a_gR {self.a_gr_g:g} g, γ_I {self.importance:g}, "
            f"{self.damping:.0%} damping"
        )

    def to_dict(self) -> dict[str, Any]:
        """``kind``, the standard and the parameters."""
        s, t_b, t_c, t_d = self.parameters
        return {
            "kind": f"ec8-{self.spectrum_type}",
            "standard": "EN 1998-1:2004 §3.2.2.2",
            "ground": self.ground,
            "a_gr_g": self.a_gr_g,
            "importance": self.importance,
            "damping": self.damping,
            "s": s,
            "t_b_s": t_b,
            "t_c_s": t_c,
            "t_d_s": t_d,
            "eta": self.eta,
        }
