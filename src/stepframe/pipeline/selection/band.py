"""The frame's band: the frequencies its period-amplitude law sweeps as it is pushed harder.

A stepping frame oscillating at amplitude A has the free-vibration frequency
ω(A) = 2π/T(A) (:func:`stepframe.structure.period_amplitude.period_amplitude`): ω_1 up to the
onset of stepping x_c, then falling towards 0 as A approaches the unstable equilibrium x*. The
band a record should sweep is [ω(A_max), ω_1]; A_max is, in order of precedence, a value the user
gives, the quasi-dynamic design displacement δ* (when the caller has the design inputs), or a
stated fraction of x* (default 0.8: at x* the period is infinite and the band would be unbounded).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from stepframe.errors import InputError
from stepframe.structure.frame import PortalFrame
from stepframe.structure.period_amplitude import amplitude_for_period, period_amplitude

AmplitudeSource = Literal["user", "design", "fraction-of-x-star"]
DEFAULT_X_STAR_FRACTION = 0.8


@dataclass(frozen=True)
class FrameBand:
    """The band [ω(A_max), ω_1] of a frame and the backbone levels inside it.

    Attributes
    ----------
    omega_1_rad_s
        Small-amplitude frequency ω_1 [rad/s] (top of the band).
    omega_low_rad_s
        ω(A_max) [rad/s] (bottom of the band).
    a_max_m
        The amplitude limit A_max [m].
    a_max_source
        Where A_max came from: ``"user"``, ``"design"`` or ``"fraction-of-x-star"``.
    x_c_m, x_star_m
        Onset of stepping and unstable equilibrium [m].
    level_amplitudes_m, level_omegas_rad_s
        The backbone levels used by the physics scores: amplitudes from x_c to A_max whose
        frequencies are equally spaced in log frequency over the band, ω_1 first [m], [rad/s].
    """

    omega_1_rad_s: float
    omega_low_rad_s: float
    a_max_m: float
    a_max_source: AmplitudeSource
    x_c_m: float
    x_star_m: float
    level_amplitudes_m: NDArray[np.float64]
    level_omegas_rad_s: NDArray[np.float64]
    frame: PortalFrame = field(repr=False, compare=False)

    @property
    def period_1_s(self) -> float:
        """T_1 = 2π/ω_1 [s]."""
        return 2.0 * math.pi / self.omega_1_rad_s

    @property
    def log_width(self) -> float:
        """ln(ω_1/ω(A_max)), the band's width in log frequency."""
        return math.log(self.omega_1_rad_s / self.omega_low_rad_s)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dictionary."""
        return {
            "omega_1_rad_s": self.omega_1_rad_s,
            "omega_low_rad_s": self.omega_low_rad_s,
            "band_rad_s": [self.omega_low_rad_s, self.omega_1_rad_s],
            "a_max_m": self.a_max_m,
            "a_max_source": self.a_max_source,
            "x_c_m": self.x_c_m,
            "x_star_m": self.x_star_m,
            "level_amplitudes_m": self.level_amplitudes_m.tolist(),
            "level_omegas_rad_s": self.level_omegas_rad_s.tolist(),
        }

    def reach_rad_s(self, amplitude_m: float) -> float:
        """ω(A) for an amplitude the record's intensity reaches: how deep into the band a given
        response amplitude takes the frame (A ≥ x* gives 0: the frame overturns) [rad/s]."""
        amplitude = max(float(amplitude_m), 0.0)
        if amplitude >= self.x_star_m:
            return 0.0
        return 2.0 * math.pi / float(period_amplitude(self.frame, amplitude))


def band_levels(
    frame: PortalFrame, omega_1_rad_s: float, omega_low_rad_s: float, a_max_m: float, n_levels: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """``n_levels`` amplitudes from x_c to A_max whose frequencies ω(A) are equally spaced in
    ln ω from ω_1 down to ω(A_max), and those frequencies: ``(amplitudes [m], omegas [rad/s])``.

    The inner amplitudes invert the period-amplitude law (:func:`amplitude_for_period`); the
    ends are x_c and A_max themselves. The one home of the band's levels: the physics scores'
    (:func:`frame_band`) and the substitute structure's
    (:func:`stepframe.pipeline.selection.substitute.substitute_levels`).
    """
    omegas = np.exp(np.linspace(math.log(omega_1_rad_s), math.log(omega_low_rad_s), n_levels))
    amplitudes = np.empty(n_levels)
    amplitudes[0] = frame.x_c_m
    amplitudes[1:-1] = amplitude_for_period(frame, 2.0 * math.pi / omegas[1:-1])
    amplitudes[-1] = a_max_m
    return amplitudes, omegas


def frame_band(
    frame: PortalFrame,
    *,
    a_max_m: float | None = None,
    design_displacement_m: float | None = None,
    x_star_fraction: float = DEFAULT_X_STAR_FRACTION,
    n_levels: int = 6,
) -> FrameBand:
    """The band [ω(A_max), ω_1] of ``frame`` and ``n_levels`` backbone levels in it.

    Parameters
    ----------
    frame
        The frame (its ω_1, ω_2, γ_1 and x_c define T(A)).
    a_max_m
        Amplitude limit given by the user [m]; overrides the others.
    design_displacement_m
        Quasi-dynamic design displacement δ* [m] (:func:`stepframe.structure.quasi_dynamic.
        design_displacement`), used when ``a_max_m`` is None.
    x_star_fraction
        A_max = fraction · x* when neither is given (0 < fraction < 1).
    n_levels
        Number of backbone levels (≥ 2): ω_1 and n_levels - 1 frequencies equally spaced in
        ln ω down to ω(A_max).

    Raises
    ------
    InputError
        A_max not in (x_c, x*) (no elongation, or no periodic orbit), bad fraction or n_levels.
    """
    if not 0 < x_star_fraction < 1:
        raise InputError(f"x_star_fraction = {x_star_fraction}, expected 0 < fraction < 1")
    if not (isinstance(n_levels, int) and n_levels >= 2):
        raise InputError(f"n_levels = {n_levels!r}, expected an integer ≥ 2")
    source: AmplitudeSource
    if a_max_m is not None:
        a_max, source = float(a_max_m), "user"
    elif design_displacement_m is not None:
        a_max, source = float(design_displacement_m), "design"
    else:
        a_max, source = x_star_fraction * frame.x_star_m, "fraction-of-x-star"
    if not (math.isfinite(a_max) and frame.x_c_m < a_max < frame.x_star_m):
        # the default's fix: a fraction of x* above x_c/x* (a frame with little room to step)
        hint = (
            f"; x_c is {frame.x_c_m / frame.x_star_m:.4g} x*: give --a-max-m between them or a "
            "--x-star-fraction above that"
            if source == "fraction-of-x-star"
            else ""
        )
        raise InputError(
            f"A_max = {a_max:.6g} m ({source}), expected x_c = {frame.x_c_m:.6g} m < A_max < "
            f"x* = {frame.x_star_m:.6g} m (below x_c the frame does not step; at x* it "
            f"overturns){hint}"
        )
    omega_1 = frame.omega_1_rad_s
    omega_low = 2.0 * math.pi / float(period_amplitude(frame, a_max))
    amplitudes, omegas = band_levels(frame, omega_1, omega_low, a_max, n_levels)
    return FrameBand(
        omega_1, omega_low, a_max, source, frame.x_c_m, frame.x_star_m, amplitudes, omegas, frame
    )
