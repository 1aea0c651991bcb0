"""Orientation-independent spectra of two horizontal components: geometric mean, RotD50, RotD100.

RotDnn (Boore 2010) is the nn-th percentile over rotation angles θ ∈ [0°, 180°) of the peak
oscillator displacement for the ground motion rotated to θ. The oscillator is linear, so the
response to the rotated motion is the rotated response, u_θ(t) = u₁(t) cos θ + u₂(t) sin θ: one
pair of response histories per period (exact Nigam-Jennings recurrence, upsampled at short
periods as in :mod:`stepframe.records.spectra`) serves every angle.

Peaks over angles are exact at every evaluated angle but cheap: a sample whose radius
|(u₁, u₂)| is below a lower bound B on every angle's peak cannot be any angle's peak, and B is
taken from the peak samples of a few angles, so only a small fraction of the samples is projected
on all angles.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError
from stepframe.records.integration import check_record
from stepframe.records.spectra import (
    DEFAULT_PERIODS_S,
    check_damping,
    check_periods,
    displacement_histories_m,
    pseudo_acceleration_m_s2,
    upsampling_factors,
)
from stepframe.records.units import STANDARD_GRAVITY_M_S2


@dataclass(frozen=True)
class RotDSpectrum:
    """Two-component pseudo-spectral accelerations [m/s²] at each period.

    Attributes
    ----------
    period_s
        Oscillator periods [s].
    damping
        Damping ratio (fraction of critical).
    psa1_m_s2, psa2_m_s2
        PSA of the first (h1) and second (h2) component as given.
    geomean_m_s2
        Geometric mean √(PSA₁·PSA₂).
    rotd50_m_s2, rotd100_m_s2
        Median and maximum over rotation angles of the rotated PSA.
    rotd0_m_s2
        Minimum over rotation angles.
    """

    period_s: NDArray[np.float64]
    damping: float
    psa1_m_s2: NDArray[np.float64]
    psa2_m_s2: NDArray[np.float64]
    geomean_m_s2: NDArray[np.float64]
    rotd0_m_s2: NDArray[np.float64]
    rotd50_m_s2: NDArray[np.float64]
    rotd100_m_s2: NDArray[np.float64]

    def in_g(self, name: str) -> NDArray[np.float64]:
        """The named field (``"rotd50"``, ``"geomean"``, ``"psa1"``...) in standard gravities."""
        values: NDArray[np.float64] = getattr(self, f"{name}_m_s2") / STANDARD_GRAVITY_M_S2
        return values


def rotated_peaks(
    u1: NDArray[np.float64], u2: NDArray[np.float64], angle_rad: NDArray[np.float64]
) -> NDArray[np.float64]:
    """max_t |u₁(t) cos θ + u₂(t) sin θ| at each angle θ (exact; see module)."""
    direction = np.stack([np.cos(angle_rad), np.sin(angle_rad)])
    points = np.stack([u1, u2], axis=1)
    # Peak samples at a few angles give every angle a lower bound B on its peak.
    probe = np.linspace(0.0, np.pi, 8, endpoint=False)
    probe_dir = np.stack([np.cos(probe), np.sin(probe)])
    extremes = points[np.argmax(np.abs(points @ probe_dir), axis=0)]
    bound = float(np.min(np.max(np.abs(extremes @ direction), axis=0)))
    radius = np.hypot(u1, u2)
    candidates = points[radius >= bound]
    peaks: NDArray[np.float64] = np.max(np.abs(candidates @ direction), axis=0)
    return peaks


def rotd_spectrum(
    acc1_m_s2: ArrayLike,
    acc2_m_s2: ArrayLike,
    dt_s: float,
    period_s: ArrayLike = DEFAULT_PERIODS_S,
    damping: float = 0.05,
    *,
    angle_step_deg: float = 1.0,
    points_per_period: float = 10.0,
) -> RotDSpectrum:
    """Geometric mean, RotD0, RotD50 and RotD100 of two horizontal components.

    Parameters
    ----------
    acc1_m_s2, acc2_m_s2
        The two horizontal ground accelerations [m/s²], same sampling; the first is h1
        (θ = 0). Records of different lengths are compared over the common length.
    dt_s
        Sampling interval [s].
    period_s
        Oscillator periods [s].
    damping
        Damping ratio, a fraction in [0, 1).
    angle_step_deg
        Rotation-angle step [deg]; angles 0, step, ... below 180°.
    points_per_period
        Minimum samples per period (shorter periods use an upsampled record).

    Returns
    -------
    RotDSpectrum
    """
    acc1 = check_record(acc1_m_s2, dt_s)
    acc2 = check_record(acc2_m_s2, dt_s)
    if not (0.0 < angle_step_deg <= 90.0):
        raise InputError(f"angle step {angle_step_deg} deg, expected a value in (0, 90]")
    n = min(acc1.size, acc2.size)
    acc1, acc2 = acc1[:n], acc2[:n]
    periods = check_periods(period_s)
    zeta = check_damping(damping)
    angles = np.deg2rad(np.arange(0.0, 180.0 - 1e-9, angle_step_deg))
    factors = upsampling_factors(periods, dt_s, points_per_period)
    sd = np.empty((periods.size, angles.size))
    for factor in np.unique(factors):
        index = np.flatnonzero(factors == factor)
        u1 = displacement_histories_m(acc1, dt_s, periods[index], zeta, int(factor))
        u2 = displacement_histories_m(acc2, dt_s, periods[index], zeta, int(factor))
        for k, j in enumerate(index):
            sd[j] = rotated_peaks(u1[:, k], u2[:, k], angles)
    psa = pseudo_acceleration_m_s2(periods[:, None], sd)
    psa1 = psa[:, 0]
    # θ = 90° is h2 when the step divides 90; otherwise compute it from the histories' peaks.
    from stepframe.records.spectra import peak_displacements_m

    sd2 = peak_displacements_m(acc2, dt_s, periods, zeta, points_per_period=points_per_period)
    psa2 = pseudo_acceleration_m_s2(periods, sd2)
    return RotDSpectrum(
        period_s=periods,
        damping=zeta,
        psa1_m_s2=psa1,
        psa2_m_s2=psa2,
        geomean_m_s2=np.sqrt(psa1 * psa2),
        rotd0_m_s2=np.min(psa, axis=1),
        rotd50_m_s2=np.median(psa, axis=1),
        rotd100_m_s2=np.max(psa, axis=1),
    )
