"""Scores of a candidate record for a frame, each named for what it measures (docs/selection.md).

Cheap scores, closed forms vectorised over a whole features table:

- ``band_coverage``: the share of the frame's band [ω(A_max), ω_1], in log frequency, that the
  fitted ω_g(t) sweeps (downwards: eq. 6.10 is monotone) during the strong-motion window;
- ``enters_from_above``: whether ω_g at the start of the window is above ω_1 (the sweep enters
  the band from the frame's small-amplitude frequency, as the frame starts to step);
- ``spectral_ratio_eq_6_18``: the paper's eq. 6.18 at ω_0 = ω_1, with α_g(t_max) from eq. 6.11 as
  printed (the array form of :func:`stepframe.stochastic.amplification.spectral_ratio_eq_6_18`);
- ``omega_p_over_s_sq``: (ω_p/ω_s)², eq. 6.19's last approximation.

Physics scores, from the exact covariance (Liapunov) method of
:func:`stepframe.stochastic.mean_square.mean_square_response`, per candidate (a few ms each), on
the record's fitted model at unit peak intensity (so every record and intensity gives a finite
number: they are ratios of RMS responses under the same input):

- ``backbone_amplification``: the geometric mean over the band's backbone levels ω(A_k) of
  max σ_x(ω(A_k)) / max σ_x(ω_1): how much more response the record's evolving spectrum gives
  the frame's equivalent-linear oscillator at each stepping amplitude than at its
  small-amplitude frequency, whose response is what equal PSA at T_1 fixes;
- ``descent_amplification``: max σ_x of an oscillator whose frequency descends along the
  backbone from ω_1 to ω(A_max) during the strong-motion window (log-linear in time), over the
  largest max σ_x of the same oscillator held at any backbone level (same decay rate
  β = ξ_1ω_1 for all, the mean-square module's convention for a moving oscillator): the
  moving-resonance gain of following the backbone over sitting at its best fixed frequency.
  Above 1 only when ω_g(t) falls through the band as the oscillator does.

Record score, from the record's own response spectrum (not the fit):
:mod:`stepframe.pipeline.selection.substitute` (``substitute_demand_ratio``).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.pipeline.selection.band import FrameBand
from stepframe.pipeline.selection.names import RANKABLE
from stepframe.pipeline.selection.path import Paths, model_of_row

Floats = NDArray[np.float64]

#: Score name → (unit, meaning); higher means more of what the name says.
SCORES: dict[str, tuple[str, str]] = {
    "band_coverage": (
        "",
        "share of the frame's band (log frequency) swept downward by omega_g during strong motion",
    ),
    "spectral_ratio_eq_6_18": ("", "the paper's spectral ratio (eq. 6.18) at omega_0 = omega_1"),
    "omega_p_over_s_sq": ("", "(omega_p/omega_s)^2, eq. 6.19's last approximation"),
    "backbone_amplification": (
        "",
        "geometric mean over backbone levels of peak RMS response at omega(A_k) over that at "
        "omega_1 (exact covariance, fitted model, unit intensity)",
    ),
    "descent_amplification": (
        "",
        "peak RMS response of an oscillator descending the backbone from omega_1 to "
        "omega(A_max) during strong motion, over the best of the same held at a backbone level",
    ),
    "substitute_demand_ratio": (
        "",
        "min over amplitudes x_c < A <= A_max of the substitute structure's demand "
        "P(A)*SD(T(A), xi(A))/A of the record at equal PSA(T_1) (max(1, 1/it): predicted "
        "overturning onset ratio)",
    ),
}
assert tuple(SCORES) == RANKABLE


def band_coverage(paths: Paths, band: FrameBand) -> Floats:
    """Share of [ω(A_max), ω_1] in ln ω that [ω_end, ω_start] covers, per row (NaN kept)."""
    top = np.minimum(paths.omega_start_rad_s, band.omega_1_rad_s)
    bottom = np.maximum(paths.omega_end_rad_s, band.omega_low_rad_s)
    with np.errstate(divide="ignore", invalid="ignore"):
        overlap = np.log(top / bottom)
    return np.asarray(
        np.where(np.isnan(overlap), np.nan, np.maximum(overlap, 0.0) / band.log_width)
    )


def enters_from_above(paths: Paths, band: FrameBand) -> NDArray[np.bool_]:
    """ω_g at the start of strong motion is above ω_1 and falls below it by the end."""
    return np.asarray(
        (paths.omega_start_rad_s > band.omega_1_rad_s)
        & (paths.omega_end_rad_s < band.omega_1_rad_s)
    )


def spectral_ratio_eq_6_18(table: Any, omega_0_rad_s: float) -> Floats:
    """Eq. 6.18 at ``omega_0_rad_s`` for every row, α_g(t_max) by eq. 6.11 as printed (ramp to
    t_dur): [(ω_0² - ω_p²)² + 4(ω_pξ_p)²ω_0²] / [4 α_g(t_max) ω_pξ_p ω_p²] · (ω_0/ω_s)²."""
    wp = np.asarray(table["omega_p_rad_s"], dtype=np.float64)
    ws = np.asarray(table["omega_s_rad_s"], dtype=np.float64)
    wr = np.asarray(table["omega_r_rad_s"], dtype=np.float64)
    alpha_p = wp * np.asarray(table["xi_p"], dtype=np.float64)
    alpha_r = wr * np.asarray(table["xi_r"], dtype=np.float64)
    t_max = np.asarray(table["t_max_s"], dtype=np.float64)
    t_dur = np.asarray(table["t_dur_s"], dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        alpha_t_max = alpha_p + (alpha_r - alpha_p) * np.minimum(t_max / t_dur, 1.0)
        w0 = omega_0_rad_s
        numerator = (w0**2 - wp**2) ** 2 + 4 * alpha_p**2 * w0**2
        return np.asarray(numerator / (4 * alpha_t_max * alpha_p * wp**2) * (w0 / ws) ** 2)


def omega_p_over_s_sq(table: Any) -> Floats:
    """(ω_p/ω_s)² per row."""
    wp = np.asarray(table["omega_p_rad_s"], dtype=np.float64)
    ws = np.asarray(table["omega_s_rad_s"], dtype=np.float64)
    return np.asarray((wp / ws) ** 2)


def equivalent_damping(xi_2: float, c_r: float) -> float:
    """Damping ratio of the equivalent-linear oscillator on the stepping branch.

    Two impacts per cycle each keep the fraction C_r of the velocity (C_r² of the energy), so a
    cycle keeps C_r⁴ of its energy; a viscous oscillator keeps e^{-4πξ}: ξ_impact = -ln(C_r)/π.
    The stepped phase's own viscous ξ_2 adds to it. A floor of 0.005 keeps the covariance
    method's stationary covariance (∝ 1/ξ) well conditioned for a perfectly elastic frame.
    """
    impact = -math.log(c_r) / math.pi if 0 < c_r < 1 else 0.0
    return max(xi_2 + impact, 0.005)


def physics_scores(
    row: Any,
    band: FrameBand,
    xi_1: float,
    xi_levels: float,
    window: tuple[float, float],
    n_steps: int = 150,
) -> tuple[float, float]:
    """``(backbone_amplification, descent_amplification)`` of one features row.

    Parameters
    ----------
    row
        A features row (eq. 6.10-6.11 parameters).
    band
        The frame's band and backbone levels.
    xi_1
        Damping ratio at ω_1 (the frame's unstepped phase).
    xi_levels
        Damping ratio on the stepping branch (:func:`equivalent_damping`).
    window
        Strong-motion window (start, end) after t0 [s].
    n_steps
        Steps of the analysis grid over [0, t0 + 2 t_dur] (150: within 3e-4 of 1,000 steps).
    """
    from stepframe.stochastic.mean_square import (
        Constant,
        Given,
        analysis_grid,
        mean_square_response,
    )

    model = model_of_row(row)
    grid = analysis_grid(model, n_steps=n_steps)
    omega_1 = band.omega_1_rad_s
    levels = band.level_omegas_rad_s
    switch = float(grid[1])
    start = model.t0_s + window[0]
    length = max(window[1] - window[0], 1e-9)
    log_ratio = math.log(band.omega_low_rad_s / omega_1)

    def paths(t: Floats) -> Floats:
        # Rows: each level held (from the first step on; ω_1 at the first time, where the
        # input is zero, so that every row has the decay rate β = ξ_1 ω_1), then the descent.
        held = np.where(t[None, :] < switch, omega_1, levels[:, None])
        share = np.clip((t - start) / length, 0.0, 1.0)
        return np.vstack([held, omega_1 * np.exp(log_ratio * share)])

    same_beta = mean_square_response(model, Given(paths), xi_1, time_s=grid)
    peaks = np.sqrt(np.max(same_beta.mean_square_m2, axis=1))
    sigma_1, held_best, descent = peaks[0], float(np.max(peaks[:-1])), float(peaks[-1])
    stepping = mean_square_response(model, Constant(levels[1:]), xi_levels, time_s=grid)
    sigma_k = np.sqrt(np.max(stepping.mean_square_m2, axis=1))
    backbone = float(np.exp(np.mean(np.log(sigma_k / sigma_1))))
    return backbone, descent / held_best
