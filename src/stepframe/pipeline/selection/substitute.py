"""The substitute structure of a stepping frame, and the record-based score built on it.

Priestley, Evison and Carr (1978, "Seismic response of structures free to rock on their
foundations", Bull. N.Z. Natl Soc. Earthquake Eng. 11(3):141-150) estimate the peak response of
a rocking structure with an equivalent linear oscillator: at response amplitude A it vibrates
with its free-vibration period T(A) and an equivalent damping ξ(A), and its peak displacement is
read from the record's displacement spectrum, D(A) = P(A) · SD(T(A), ξ(A)). A response
amplitude is consistent when D(A) = A. Here (docs/selection.md, "The substitute structure"):

- T(A): the frame's period-amplitude law (:func:`stepframe.structure.period_amplitude`);
- ξ(A) (:func:`stepping_damping`): the equivalent viscous ratio that loses, per cycle, the
  energy the conservative two-phase cycle at amplitude A loses to viscous damping in each
  phase (first order in ξ_1, ξ_2) and to the two touchdowns (C_r² of the kinetic energy kept);
- P(A): the participation factors P_1, P_2 weighted by the time spent in each phase.

At the confirmation's equal intensity (scale s with P_1·SD(T_1, ξ_1)·s = x_c), the demand ratio
r(A) = s·D(A)/A is 1 at A = x_c. Scaled by λ more, the substitute structure finds no consistent
amplitude in (x_c, A_max] when λ·r(A) > 1 for all of them: it runs away, the frame overturns;
below λ = 1 it stays linear. So λ* = max(1, 1/min_{A>x_c} r(A)) estimates the overturning
intensity (as a multiple of the onset intensity), and ``substitute_demand_ratio`` =
min_{A>x_c} r(A) ranks records by how easily they overturn the frame at equal PSA(T_1) (above 1:
by how much the demand exceeds every amplitude once the frame steps).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from stepframe.pipeline.selection.band import FrameBand, band_levels
from stepframe.structure.frame import PortalFrame
from stepframe.structure.period_amplitude import quarter_periods_s

Floats = NDArray[np.float64]
#: Backbone levels of the substitute structure: equally spaced in ln ω over the band.
N_SUBSTITUTE_LEVELS = 16
#: Damping ratios are rounded to this step so that levels share spectrum calls (one kernel
#: call per distinct damping); 1e-4 changes SD by well under 0.1 %.
DAMPING_STEP = 1e-4


def stepping_damping(frame: PortalFrame, amplitude_m: Floats) -> Floats:
    """Equivalent viscous damping ratio ξ(A) of the free stepping cycle at amplitude A.

    The conservative cycle at amplitude A (:func:`stepframe.structure.period_amplitude.
    quarter_periods_s`) has energy E = ω_1²B²/2 with B² = x_c² + v_c²/ω_1² (v_c: speed at
    x = ±x_c). Per cycle, to first order in the damping ratios, it loses

    - in the unstepped phase (x = B sin ω_1t, four arcs of phase θ_c = ω_1t_1):
      2ξ_1ω_1∮ẋ²dt = ξ_1E(8θ_c + 4 sin 2θ_c) (4πξ_1E for θ_c = π/2, the linear cycle);
    - in the stepped phase (x - x* = (A - x*)cosh ω_2t, four arcs of u = ω_2t_2):
      2ξ_2ω_2∮ẋ²dt = 4ξ_2ω_2²(x* - A)²(sinh 2u - 2u);
    - at the two touchdowns, each (1 - C_r²)v_c²/2 (C_r a velocity ratio).

    The linear oscillator that keeps the same share of its energy per cycle, e^{-4πξ}, has
    ξ = [η_viscous - 2 ln(1 - (1 - C_r²)v_c²/(2E))]/(4π), η_viscous the viscous share above.
    Limits: ξ_1 for A ≤ x_c; -ln(C_r)/π for a rigid block (x_c = 0) without viscous damping.

    Parameters
    ----------
    frame
        The frame (ω_1, ω_2, x_c, x*, ξ_1, ξ_2, C_r).
    amplitude_m
        Amplitudes 0 ≤ A < x* [m].

    Returns
    -------
    numpy.ndarray
        ξ(A), a fraction, shaped like ``amplitude_m``.
    """
    a = np.asarray(amplitude_m, dtype=np.float64)
    w1, w2 = frame.omega_1_rad_s, frame.omega_2_rad_s
    x_c, x_star = frame.x_c_m, frame.x_star_m
    t1, t2 = quarter_periods_s(frame, a)
    steps = a > x_c
    gap_a = np.where(steps, x_star - a, x_star - x_c)
    v_c_sq = np.where(steps, w2**2 * ((x_star - x_c) ** 2 - gap_a**2), 0.0)
    two_e = w1**2 * x_c**2 + v_c_sq
    if x_c == 0.0 and not np.all(steps):
        two_e = np.where(steps, two_e, 1.0)  # a rigid block at rest: no cycle, no loss
    theta = w1 * t1
    unstepped = frame.xi_1 * (8.0 * theta + 4.0 * np.sin(2.0 * theta))
    u = w2 * t2
    stepped = 8.0 * frame.xi_2 * w2**2 * gap_a**2 * (np.sinh(2.0 * u) - 2.0 * u) / two_e
    kept = 1.0 - (1.0 - frame.c_r**2) * v_c_sq / two_e
    with np.errstate(divide="ignore"):
        impact = -2.0 * np.log(kept)
    return np.asarray((unstepped + stepped + impact) / (4.0 * math.pi))


@dataclass(frozen=True)
class SubstituteLevels:
    """The substitute structure at backbone levels A_k (x_c first).

    Attributes
    ----------
    amplitudes_m
        A_k [m], from x_c to A_max, equally spaced in ln ω(A).
    periods_s
        T(A_k) [s].
    damping
        ξ(A_k) (:func:`stepping_damping`), rounded to :data:`DAMPING_STEP`.
    participation
        P(A_k) = (t_1P_1 + t_2P_2)/(t_1 + t_2), t_1 and t_2 the quarter period's times in each
        phase.
    """

    amplitudes_m: Floats
    periods_s: Floats
    damping: Floats
    participation: Floats

    def to_dict(self) -> dict[str, list[float]]:
        """JSON-ready dictionary."""
        return {
            "amplitudes_m": self.amplitudes_m.tolist(),
            "periods_s": self.periods_s.tolist(),
            "damping": self.damping.tolist(),
            "participation": self.participation.tolist(),
        }

    def spectrum_groups(self) -> list[tuple[Floats, float]]:
        """(periods, damping) groups, one per distinct damping, in level order of first use."""
        groups: list[tuple[Floats, float]] = []
        for value in dict.fromkeys(self.damping.tolist()):
            groups.append((self.periods_s[self.damping == value], float(value)))
        return groups

    def gather(self, sd_by_group: list[Floats]) -> Floats:
        """SD at every level [m] from the SD of each of :meth:`spectrum_groups`."""
        out = np.empty(self.periods_s.size)
        for value, sd in zip(dict.fromkeys(self.damping.tolist()), sd_by_group, strict=True):
            out[self.damping == value] = sd
        return out


def substitute_levels(band: FrameBand, n_levels: int = N_SUBSTITUTE_LEVELS) -> SubstituteLevels:
    """The substitute structure at ``n_levels`` amplitudes from x_c to the band's A_max."""
    frame = band.frame
    amplitudes, _ = band_levels(
        frame, band.omega_1_rad_s, band.omega_low_rad_s, band.a_max_m, n_levels
    )
    t1, t2 = quarter_periods_s(frame, amplitudes)
    periods = 4.0 * (t1 + t2)
    periods[0] = band.period_1_s  # A = x_c: the linear frame exactly
    with np.errstate(invalid="ignore"):  # a rigid block at A = x_c = 0 has no cycle
        participation = (t1 * frame.p_1 + t2 * frame.p_2) / (t1 + t2)
    participation[0] = frame.p_1  # A = x_c: the linear frame exactly
    damping = np.round(stepping_damping(frame, amplitudes) / DAMPING_STEP) * DAMPING_STEP
    damping[0] = frame.xi_1
    return SubstituteLevels(amplitudes, periods, damping, participation)


def demand_ratios(sd_levels_m: Floats, levels: SubstituteLevels) -> Floats:
    """r(A_k) = s·P(A_k)·SD(T(A_k), ξ(A_k))/A_k at equal intensity, per row of ``sd_levels_m``.

    ``sd_levels_m`` has shape (n_records, n_levels), its first column SD(T_1, ξ_1): the equal
    intensity scale is s = x_c/(P_1·SD(T_1, ξ_1)), so r(x_c) = 1. NaN for a rigid block
    (x_c = 0), which has no onset intensity.
    """
    sd = np.atleast_2d(np.asarray(sd_levels_m, dtype=np.float64))
    if not levels.amplitudes_m[0] > 0:
        # A rigid block (x_c = 0) has no onset intensity to hold equal: no ratio to speak of.
        return np.full(sd.shape, np.nan)
    with np.errstate(divide="ignore", invalid="ignore"):
        scale = levels.amplitudes_m[0] / (levels.participation[0] * sd[:, :1])
        return np.asarray(scale * levels.participation * sd / levels.amplitudes_m)


def substitute_demand_ratio(sd_levels_m: Floats, levels: SubstituteLevels) -> Floats:
    """min over the stepping levels A_k > x_c of r(A_k), per record (NaN where any is not
    finite). max(1, 1/it) estimates the overturning onset ratio: below 1 the frame stays
    linear, so cannot overturn; a ratio above 1 says by how much the demand of the frame once
    stepping exceeds its amplitude at every level, at the onset intensity."""
    ratios = demand_ratios(sd_levels_m, levels)[:, 1:]
    out = np.min(ratios, axis=1)
    out[~np.all(np.isfinite(ratios), axis=1)] = np.nan
    return np.asarray(out)


def predicted_overturn_ratio(demand_ratio: Floats) -> Floats:
    """max(1, 1/``demand_ratio``): the substitute structure's lowest P_1·SD(T_1)/x_c that
    overturns the frame (the frame cannot overturn before it steps)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(np.maximum(1.0, 1.0 / np.asarray(demand_ratio, dtype=np.float64)))
