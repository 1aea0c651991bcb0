"""The chosen set's scaled spectra: one spectrum per unit (a component, or a record's pair).

A record's two horizontal components make one spectrum by the rule the run states
(``pair_spectrum``): RotD50 (the median over rotation angles, Boore 2010), RotD100 (the maximum
direction) or the geometric mean of the two components' spectra
(:func:`stepframe.records.rotd.rotd_spectrum`). Both components of a record carry one scale
factor, so the pair's spectrum scales with it. The same spectra serve the code's suite check,
the report's figure and the exported ``spectra.csv``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from stepframe.records.units import STANDARD_GRAVITY_M_S2

Floats = NDArray[np.float64]
Samples = tuple[Floats, float]

#: Periods of the set's spectra [s] (report figure, spectra.csv, the check's grid).
SET_PERIODS_S = np.geomspace(0.02, 10.0, 80)
#: Rotation-angle step of RotD spectra [deg].
ANGLE_STEP_DEG = 1.0


@dataclass(frozen=True)
class SetSpectra:
    """Scaled spectra of the chosen units.

    Attributes
    ----------
    names
        Each unit's name (the record, or ``file [component]``).
    periods_s
        Periods [s].
    psa_g
        Scaled PSA [g], shape (units, periods), at ``damping``.
    pga_g
        Scaled PGA of each unit [g] (of the pair by the same rule).
    scales
        Each unit's scale factor.
    damping
        Damping ratio.
    measure
        What a unit's spectrum is (``component``, ``rotd50``, ``geomean``, ``rotd100``).
    notes
        Anything the rule could not do as stated (a pair sampled differently: geometric mean).
    """

    names: list[str]
    periods_s: Floats
    psa_g: Floats
    pga_g: Floats
    scales: Floats
    damping: float
    measure: str
    notes: tuple[str, ...] = ()

    @property
    def mean_psa_g(self) -> Floats:
        """Arithmetic mean over units (the codes' "average" spectrum) [g]."""
        return np.asarray(np.mean(self.psa_g, axis=0))


def _pair(a: Samples, b: Samples, periods: Floats, damping: float, measure: str) -> Floats | None:
    """PSA [m/s²] of a pair by ``measure``; None when the two are sampled differently."""
    from stepframe.records.rotd import rotd_spectrum

    (acc1, dt1), (acc2, dt2) = a, b
    if not math.isclose(dt1, dt2, rel_tol=1e-9):
        return None
    result = rotd_spectrum(acc1, acc2, dt1, periods, damping, angle_step_deg=ANGLE_STEP_DEG)
    values: Floats = getattr(result, f"{measure}_m_s2")
    return values


def _pair_pga(a: Samples, b: Samples, measure: str) -> float:
    """The pair's PGA [m/s²] by ``measure`` (rotated accelerations for RotD)."""
    from stepframe.records.rotd import rotated_peaks

    n = min(a[0].size, b[0].size)
    if measure == "geomean" or not math.isclose(a[1], b[1], rel_tol=1e-9):
        return float(np.sqrt(np.max(np.abs(a[0])) * np.max(np.abs(b[0]))))
    angles = np.deg2rad(np.arange(0.0, 180.0 - 1e-9, ANGLE_STEP_DEG))
    peaks = rotated_peaks(a[0][:n], b[0][:n], angles)
    return float(np.max(peaks) if measure == "rotd100" else np.median(peaks))


def set_spectra(
    units: list[tuple[str, list[Samples], float]],
    periods_s: Floats,
    damping: float,
    measure: str,
) -> SetSpectra:
    """The scaled spectra of ``units`` = (name, its components' samples, scale factor).

    A unit of one component is that component's spectrum; a unit of two is the pair's by
    ``measure`` (``rotd50``, ``geomean``, ``rotd100``).
    """
    from stepframe.records.spectra import response_spectrum

    rows, pgas, notes = [], [], []
    for name, members, scale in units:
        if len(members) == 1:
            acc, dt = members[0]
            psa = response_spectrum(acc, dt, periods_s, damping).psa_m_s2
            pga = float(np.max(np.abs(acc)))
        else:
            a, b = members[:2]
            pair = None if measure == "geomean" else _pair(a, b, periods_s, damping, measure)
            if pair is None:
                if measure != "geomean":
                    notes.append(f"{name}: components sampled differently, geometric mean used")
                one = response_spectrum(a[0], a[1], periods_s, damping).psa_m_s2
                two = response_spectrum(b[0], b[1], periods_s, damping).psa_m_s2
                pair = np.sqrt(one * two)
            psa, pga = pair, _pair_pga(a, b, measure)
        rows.append(np.asarray(psa) * scale / STANDARD_GRAVITY_M_S2)
        pgas.append(pga * scale / STANDARD_GRAVITY_M_S2)
    is_pairs = any(len(members) > 1 for _, members, _ in units)
    return SetSpectra(
        [name for name, _, _ in units],
        np.asarray(periods_s, dtype=np.float64),
        np.vstack(rows) if rows else np.empty((0, len(periods_s))),
        np.asarray(pgas, dtype=np.float64),
        np.array([scale for _, _, scale in units], dtype=np.float64),
        damping,
        measure if is_pairs else "component",
        tuple(notes),
    )


def pair_psa(
    members: list[Samples], periods_s: Floats, damping: float, measure: str
) -> Floats | None:
    """PSA [m/s²] of one record's pair by ``measure`` (scale 1); None for fewer than two."""
    if len(members) < 2:
        return None
    spectra = set_spectra([("", members, 1.0)], periods_s, damping, measure)
    return np.asarray(spectra.psa_g[0] * STANDARD_GRAVITY_M_S2)
