"""What the amplification report's headlines may claim, each checked before it is stated.

- :func:`curve_maxima`: a maximum of the response amplification is one only where the curve
  falls on both sides; at an edge of the f0 grid where it still rises, :func:`extend_past_edges`
  continues the grid (same log spacing, at most :data:`EXTENSION_FACTOR` beyond the edge) until
  it turns, or the edge is reported as "at the edge of the range, rising".
- :func:`frame_stepping`: whether the frame-driven run stepped (its amplitude A = √2 σ_x reached
  the uplift amplitude x_c), and the site intensity at which it would: below x_c the frame is a
  linear oscillator at ω_1, so its response is the fixed oscillator's and scales with the
  intensity, and the onset is I · x_c / (√2 max σ_x,fixed).
- :func:`design_limits`: the design displacement δ* and its adjusted values against x_c (below
  it the frame does not step) and x* (at or beyond it the frame overturns).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

Floats = NDArray[np.float64]


@dataclass
class ReportNumbers:
    """What the report states, filled step by step: the summary's lines, ``numbers.json``, and
    the warnings shown above the summary."""

    summary: list[tuple[str, str]] = field(default_factory=list)
    numbers: dict[str, Any] = field(default_factory=dict)
    warnings: list[str] = field(default_factory=list)


#: How far past an edge of the f0 grid the search for a maximum goes (a factor on the edge).
EXTENSION_FACTOR = 10.0

#: Frequencies added per step of the search past an edge.
EXTENSION_BATCH = 6


@dataclass(frozen=True)
class CurveMaximum:
    """One maximum of a curve over f0, or an edge where it still rises.

    Attributes
    ----------
    f0_hz, value
        Where and how large.
    kind
        ``"interior"`` (lower values on both sides), ``"low-edge"`` or ``"high-edge"`` (at the
        first or last f0 computed, rising towards it: not a maximum).
    """

    f0_hz: float
    value: float
    kind: Literal["interior", "low-edge", "high-edge"]

    @property
    def interior(self) -> bool:
        """Whether it is a maximum (not an edge)."""
        return self.kind == "interior"

    def describe(self) -> str:
        """``14.7 at 10.6 Hz`` or ``5.91 at 0.1 Hz (at the edge of the range, rising)``."""
        text = f"{self.value:.3g} at {self.f0_hz:.3g} Hz"
        return text if self.interior else text + " (at the edge of the range, rising)"


def curve_maxima(f0_hz: Floats, values: Floats) -> list[CurveMaximum]:
    """The interior local maxima of a curve and the edges where it rises, largest first.

    A plateau of equal values counts once (at its first point). NaN values are skipped.
    """
    f = np.asarray(f0_hz, dtype=np.float64)
    v = np.asarray(values, dtype=np.float64)
    keep = np.isfinite(v)
    f, v = f[keep], v[keep]
    found: list[CurveMaximum] = []
    if v.size == 0:
        return found
    if v.size == 1:
        return [CurveMaximum(float(f[0]), float(v[0]), "low-edge")]
    if v[0] > v[1]:
        found.append(CurveMaximum(float(f[0]), float(v[0]), "low-edge"))
    if v[-1] > v[-2]:
        found.append(CurveMaximum(float(f[-1]), float(v[-1]), "high-edge"))
    for i in range(1, v.size - 1):
        if v[i] > v[i - 1] and v[i] >= v[i + 1]:
            # a plateau ending higher is no maximum: look past it
            j = i
            while j + 1 < v.size and v[j + 1] == v[i]:
                j += 1
            if j + 1 == v.size or v[j + 1] < v[i]:
                found.append(CurveMaximum(float(f[i]), float(v[i]), "interior"))
    return sorted(found, key=lambda m: -m.value)


@dataclass(frozen=True)
class ExtendedCurve:
    """A curve over the f0 grid asked for, with the points added past its edges.

    Attributes
    ----------
    f0_hz, values
        Every point, in increasing f0.
    on_grid
        Whether each point is on the grid asked for (False: added past an edge).
    """

    f0_hz: Floats
    values: Floats
    on_grid: NDArray[np.bool_]

    @property
    def added(self) -> int:
        """Points added past the edges."""
        return int(np.count_nonzero(~self.on_grid))


def extend_past_edges(
    f0_hz: Floats,
    values: Floats,
    evaluate: Callable[[Floats], Floats],
    *,
    factor: float = EXTENSION_FACTOR,
    batch: int = EXTENSION_BATCH,
) -> ExtendedCurve:
    """Continue a log-spaced curve past each edge where it still rises, until it turns.

    Parameters
    ----------
    f0_hz, values
        The curve on its grid (log-spaced, increasing, at least two points).
    evaluate
        f0 [Hz] → values, for the added points.
    factor
        The search stops ``factor`` beyond the edge (f_min/factor, f_max·factor).
    batch
        Points added per step (the grid's log spacing).
    """
    f = np.asarray(f0_hz, dtype=np.float64)
    v = np.asarray(values, dtype=np.float64)
    on_grid = np.ones(f.size, dtype=bool)
    if f.size < 2:
        return ExtendedCurve(f, v, on_grid)
    ratio = float(f[1] / f[0])
    low_limit, high_limit = float(f[0]) / factor, float(f[-1]) * factor
    # the low edge: rising towards it while below the limit
    while v[0] > v[1] and f[0] / ratio >= low_limit * (1 - 1e-9):
        steps = np.arange(batch, 0, -1)
        new = f[0] / ratio**steps
        new = new[new >= low_limit * (1 - 1e-9)]
        f = np.concatenate([new, f])
        v = np.concatenate([np.asarray(evaluate(new), dtype=np.float64), v])
        on_grid = np.concatenate([np.zeros(new.size, dtype=bool), on_grid])
    while v[-1] > v[-2] and f[-1] * ratio <= high_limit * (1 + 1e-9):
        new = f[-1] * ratio ** np.arange(1, batch + 1)
        new = new[new <= high_limit * (1 + 1e-9)]
        f = np.concatenate([f, new])
        v = np.concatenate([v, np.asarray(evaluate(new), dtype=np.float64)])
        on_grid = np.concatenate([on_grid, np.zeros(new.size, dtype=bool)])
    return ExtendedCurve(f, v, on_grid)


@dataclass(frozen=True)
class Stepping:
    """Whether the frame-driven run stepped, and the intensity at which it would.

    Attributes
    ----------
    stepped
        The run's amplitude A = √2 σ_x reached x_c (the frame's period changed).
    overturned
        The run stopped: the period law gave no finite period (A reached x*).
    peak_amplitude_m
        max A of the run [m] (up to where it stopped).
    linear_amplitude_m
        max A of the frame held linear at ω_1 under the same motion [m] (the fixed oscillator).
    x_c_m
        The uplift amplitude [m].
    intensity_m_s2
        The site's peak intensity I_g of the run [m/s²] (before the participation factor).
    onset_intensity_m_s2
        The site's peak I_g at which the linear response reaches x_c [m/s²]: the frame steps
        above it (and not below).
    """

    stepped: bool
    overturned: bool
    peak_amplitude_m: float
    linear_amplitude_m: float
    x_c_m: float
    intensity_m_s2: float
    onset_intensity_m_s2: float

    @property
    def onset_factor(self) -> float:
        """The onset intensity over the run's."""
        return self.onset_intensity_m_s2 / self.intensity_m_s2

    def describe(self) -> str:
        """One sentence for the page."""
        onset = (
            f"it steps from a peak intensity I_g = {self.onset_intensity_m_s2:.3g} m/s² "
            f"({self.onset_factor:.3g} × the run's {self.intensity_m_s2:.3g} m/s²)"
        )
        if self.overturned:
            return f"The frame stepped and overturned (reached x*) in the run; {onset}."
        if self.stepped:
            return (
                f"The frame stepped: its amplitude √2·σ_x reached {self.peak_amplitude_m:.3g} m, "
                f"above x_c = {self.x_c_m:.3g} m; {onset}."
            )
        return (
            f"The frame did not step: its amplitude √2·σ_x stayed at {self.peak_amplitude_m:.3g} "
            f"m, below x_c = {self.x_c_m:.3g} m, so it stayed a linear oscillator at f_1 and its "
            f"amplification is 1 by construction; {onset}."
        )


def frame_stepping(
    x_c_m: float, driven: Any, intensity_m_s2: float, amplitude_factor: float = math.sqrt(2.0)
) -> Stepping:
    """Stepping of a frame-driven run (:func:`stepframe.stochastic.amplification.
    response_amplification` with ``frame=``) at the site intensity ``intensity_m_s2`` [m/s²],
    for a frame of uplift amplitude ``x_c_m`` [m].

    ``amplitude_factor`` is the one the frame's period law was given, A = factor·σ_x
    (:class:`stepframe.stochastic.mean_square.FrameDriven`, √2 by default).
    """
    factor = float(amplitude_factor)
    moving = float(np.sqrt(np.nanmax(driven.moving.mean_square_m2)))
    fixed = float(driven.fixed.peak_rms_m[0])
    x_c = float(x_c_m)
    overturned = driven.moving.status != "ok"
    linear = factor * fixed
    return Stepping(
        stepped=overturned or factor * moving > x_c,
        overturned=overturned,
        peak_amplitude_m=factor * moving,
        linear_amplitude_m=linear,
        x_c_m=x_c,
        intensity_m_s2=float(intensity_m_s2),
        onset_intensity_m_s2=float(intensity_m_s2) * x_c / linear,
    )


@dataclass(frozen=True)
class DesignLimit:
    """One design displacement against the frame's x_c and x*.

    Attributes
    ----------
    name
        Which value (``delta_star``, or the factor that adjusted it).
    displacement_m
        The value [m].
    state
        ``"below x_c"`` (the frame does not step at it), ``"between x_c and x*"`` or
        ``"at or beyond x*"`` (the frame overturns: not a design).
    """

    name: str
    displacement_m: float
    state: Literal["below x_c", "between x_c and x*", "at or beyond x*"]

    @property
    def overturns(self) -> bool:
        """At or beyond x*."""
        return self.state == "at or beyond x*"


def design_limits(values: Mapping[str, float], x_c_m: float, x_star_m: float) -> list[DesignLimit]:
    """Each displacement of ``values`` (name → [m]) placed against x_c and x* [m]."""
    out = []
    for name, value in values.items():
        state: Literal["below x_c", "between x_c and x*", "at or beyond x*"]
        if value >= x_star_m:
            state = "at or beyond x*"
        elif value < x_c_m:
            state = "below x_c"
        else:
            state = "between x_c and x*"
        out.append(DesignLimit(name, float(value), state))
    return out


__all__ = [
    "EXTENSION_FACTOR",
    "CurveMaximum",
    "DesignLimit",
    "ExtendedCurve",
    "ReportNumbers",
    "Stepping",
    "curve_maxima",
    "design_limits",
    "extend_past_edges",
    "frame_stepping",
]
