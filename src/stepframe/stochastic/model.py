"""The Beck-Papadimitriou fully nonstationary ground-motion model (paper eqs. 6.10-6.12).

Conventions of the project (DESIGN.md, The paper):

- ``S(ω, t)`` is two-sided in ω [rad/s]: ``I_g(t)² = (1/2π) ∫_{-∞}^{∞} S(ω, t) dω``; eq. 6.12 as
  printed satisfies this.
- The process is the unit-variance output ``y`` of the second-order filter
  ``ÿ + 2 α_g(t) ẏ + ω_g(t)² y = √q(t) w(t)``, with ``w`` white noise of unit two-sided spectral
  density (``E[w(t) w(t+τ)] = δ(τ)``) and ``q = 4 α_g ω_g²``
  (:meth:`GroundMotionModel.noise_intensity`),
  multiplied by the RMS envelope ``I_g(t)``. Its spectrum is eq. 6.12; its zero up-crossing rate is
  ``ω_g/2π`` whatever the bandwidth. Eq. 6.3 (cascaded filters fed with ÿ) is a different process
  whose spectrum does not decay; it is not used (docs/paper-notes.md).
- Time ``t`` in eqs. 6.10-6.11 is measured from ``t0_s`` (the P-wave onset when picked, else the
  record start, 0). Before ``t0_s`` the parameters hold their starting values; ``α_g`` is held at
  ``ω_r ξ_r`` after the end of its ramp.
- ``alpha_reading`` says where the ramp of eq. 6.11 ends: ``"eq-6-11"`` at ``t_dur`` (as printed) or
  ``"paper"`` at ``t_max`` (the paper's use of ``α_g(t_max) = ω_r ξ_r`` in eqs. 6.15-6.18).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError

AlphaReading = Literal["eq-6-11", "paper"]
ALPHA_READINGS: tuple[AlphaReading, ...] = ("eq-6-11", "paper")


#: The numeric fields of a fitted ground-motion model, in order (table columns use these names).
MODEL_FIELDS = (
    "omega_p_rad_s",
    "omega_s_rad_s",
    "omega_r_rad_s",
    "xi_p",
    "xi_r",
    "t_max_s",
    "t_dur_s",
    "t0_s",
)


@dataclass(frozen=True)
class GroundMotionModel:
    """Parameters of the Beck-Papadimitriou model (eqs. 6.10-6.11).

    Attributes
    ----------
    omega_p_rad_s, omega_s_rad_s, omega_r_rad_s
        Dominant frequencies of the P, S and surface waves [rad/s]; ω_p ≥ ω_s ≥ ω_r > 0, ω_p > ω_r.
    xi_p, xi_r
        Bandwidth ratios around ω_p and ω_r (ξ > 0; ξ ≥ 1, α_g ≥ ω_g, is a broadband motion, the
        overdamped filter of eq. 6.12): α_g runs from ω_p ξ_p to ω_r ξ_r [rad/s].
    t_max_s
        Time of peak intensity after ``t0_s`` [s]; ω_g(t_max) = ω_s.
    t_dur_s
        Strong-motion duration after ``t0_s`` [s] (end of the α_g ramp as printed); t_max ≤ t_dur.
    t0_s
        Time origin in record time [s]: P onset when picked, else 0 (record start).
    alpha_reading
        ``"eq-6-11"`` (ramp ends at t_dur) or ``"paper"`` (ramp ends at t_max).
    omega_c_rad_s
        Optional source corner frequency [rad/s] (None: no corner filter). When set,
        :meth:`psd` applies the high-pass ``ω⁴/(ω² + ω_c²)²`` to eq. 6.12 (as estimated by
        ``fit_model(..., fit_corner=True)``); ω_g(t) and α_g(t) do not depend on it, and
        :func:`stepframe.stochastic.synthetic.synthetic_motions` refuses it (it simulates
        eq. 6.12 without the corner).
    """

    omega_p_rad_s: float
    omega_s_rad_s: float
    omega_r_rad_s: float
    xi_p: float
    xi_r: float
    t_max_s: float
    t_dur_s: float
    t0_s: float = 0.0
    alpha_reading: AlphaReading = "eq-6-11"
    omega_c_rad_s: float | None = None

    def __post_init__(self) -> None:
        for name in MODEL_FIELDS:
            value = getattr(self, name)
            if not isinstance(value, int | float) or not math.isfinite(value):
                raise InputError(f"{name} = {value!r}, expected a finite number")
        p, s, r = self.omega_p_rad_s, self.omega_s_rad_s, self.omega_r_rad_s
        if not r > 0:
            raise InputError(f"omega_r_rad_s = {r}, expected > 0")
        if not (p >= s >= r and p > r):
            raise InputError(
                f"omega_p, omega_s, omega_r = {p}, {s}, {r} rad/s, expected p ≥ s ≥ r with p > r"
            )
        for name in ("xi_p", "xi_r"):
            if not getattr(self, name) > 0:  # ξ ≥ 1 (α_g ≥ ω_g) is an overdamped filter: valid
                raise InputError(f"{name} = {getattr(self, name)}, expected > 0")
        if not 0 < self.t_max_s <= self.t_dur_s:
            raise InputError(
                f"t_max_s = {self.t_max_s}, t_dur_s = {self.t_dur_s}, expected 0 < t_max ≤ t_dur"
            )
        if self.alpha_reading not in ALPHA_READINGS:
            raise InputError(
                f"alpha_reading = {self.alpha_reading!r}, expected one of {ALPHA_READINGS}"
            )
        if self.omega_c_rad_s is not None and not (
            math.isfinite(self.omega_c_rad_s) and self.omega_c_rad_s > 0
        ):
            raise InputError(
                f"omega_c_rad_s = {self.omega_c_rad_s}, expected a positive number or None"
            )

    @classmethod
    def from_hz(
        cls,
        f_p_hz: float,
        f_s_hz: float,
        f_r_hz: float,
        xi_p: float,
        xi_r: float,
        t_max_s: float,
        t_dur_s: float,
        **kwargs: Any,
    ) -> GroundMotionModel:
        """Build from frequencies in Hz (the paper quotes ω_p = 7.43 Hz, meaning f_p)."""
        two_pi = 2 * math.pi
        return cls(
            two_pi * f_p_hz,
            two_pi * f_s_hz,
            two_pi * f_r_hz,
            xi_p,
            xi_r,
            t_max_s,
            t_dur_s,
            **kwargs,
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary of the fields (TOML/JSON ready)."""
        return asdict(self)

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> GroundMotionModel:
        """Inverse of :meth:`to_dict`; unknown keys are an error."""
        unknown = set(data) - set(cls.__dataclass_fields__)
        if unknown:
            raise InputError(
                f"unknown ground-motion model keys {sorted(unknown)}, "
                f"expected {sorted(cls.__dataclass_fields__)}"
            )
        return cls(**data)

    def _elapsed(self, t: ArrayLike) -> NDArray[np.float64]:
        return np.maximum(np.asarray(t, dtype=np.float64) - self.t0_s, 0.0)

    def omega_g(self, t: ArrayLike) -> NDArray[np.float64]:
        """Dominant frequency ω_g(t) [rad/s], eq. 6.10 (t in record time [s])."""
        p, s, r = self.omega_p_rad_s, self.omega_s_rad_s, self.omega_r_rad_s
        ratio = (s - r) / (p - r)  # p > r is validated; ratio in [0, 1]
        return np.asarray(r + (p - r) * np.power(ratio, self._elapsed(t) / self.t_max_s))

    def alpha_g(self, t: ArrayLike) -> NDArray[np.float64]:
        """Bandwidth α_g(t) [rad/s], eq. 6.11, held at ω_r ξ_r after its ramp ends."""
        start = self.omega_p_rad_s * self.xi_p
        end = self.omega_r_rad_s * self.xi_r
        ramp = self.t_dur_s if self.alpha_reading == "eq-6-11" else self.t_max_s
        fraction = np.minimum(self._elapsed(t) / ramp, 1.0)
        return np.asarray(start + (end - start) * fraction)

    def noise_intensity(self, t: ArrayLike) -> NDArray[np.float64]:
        """q(t) = 4 α_g ω_g² [rad³/s³]: white-noise intensity giving the filter unit variance."""
        return 4.0 * self.alpha_g(t) * self.omega_g(t) ** 2

    def psd(
        self, omega: ArrayLike, t: ArrayLike, intensity: ArrayLike = 1.0
    ) -> NDArray[np.float64]:
        """Evolutionary spectrum S(ω, t), eq. 6.12, two-sided in ω.

        Parameters
        ----------
        omega
            Frequencies [rad/s] (broadcast against ``t``).
        t
            Record times [s].
        intensity
            RMS intensity I_g(t) [m/s²] (1 gives the unit-variance spectrum).

        Returns
        -------
        numpy.ndarray
            S [(m/s²)²·s/rad], so that (1/2π)∫S dω = I_g² without a corner; with
            ``omega_c_rad_s`` set, S times ``ω⁴/(ω² + ω_c²)²`` (less than I_g²).
        """
        w = np.asarray(omega, dtype=np.float64)
        wg = self.omega_g(t)
        ag = self.alpha_g(t)
        i2 = np.asarray(intensity, dtype=np.float64) ** 2
        value = 4 * ag * wg**2 * i2 / ((w**2 - wg**2) ** 2 + 4 * w**2 * ag**2)
        if self.omega_c_rad_s is not None:
            value = value * (w**2 / (w**2 + self.omega_c_rad_s**2)) ** 2
        return np.asarray(value)
