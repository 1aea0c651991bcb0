"""Intensity measures of one acceleration component: peaks, Arias, durations, CAV, Fourier spectrum.

The record is read as piecewise linear between samples, the same reading as the exact
response-spectrum recurrence, and every integral is exact for that reading: velocity and
displacement by exact integration of the linear pieces, ∫a² and ∫|a| in closed form per step
(zero crossings inside a step included). Nothing is filtered or baseline-corrected here: PGV and
PGD of an unprocessed record carry its baseline drift (see :mod:`stepframe.records.processing`).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError
from stepframe.records.integration import check_record, displacement_m, velocity_m_s
from stepframe.records.processing import ProcessingWarning as ProcessingWarning  # re-exported
from stepframe.records.units import STANDARD_GRAVITY_M_S2

if TYPE_CHECKING:
    from obspy import Trace

#: Unit-named keys of :func:`intensity_measures`, with unit and meaning (the column dictionary).
MEASURES: dict[str, tuple[str, str]] = {
    "pga_g": ("g", "peak absolute ground acceleration (standard gravity 9.80665 m/s²)"),
    "pga_m_s2": ("m/s²", "peak absolute ground acceleration"),
    "pgv_m_s": ("m/s", "peak absolute ground velocity, acceleration integrated as recorded"),
    "pgd_m": ("m", "peak absolute ground displacement, acceleration integrated twice as recorded"),
    "arias_m_s": ("m/s", "Arias intensity π/(2g)∫a²dt"),
    "d5_75_s": ("s", "significant duration between 5 % and 75 % of the Arias intensity"),
    "d5_95_s": ("s", "significant duration between 5 % and 95 % of the Arias intensity"),
    "cav_m_s": ("m/s", "cumulative absolute velocity ∫|a|dt"),
    "pgv_pga_s": ("s", "PGV/PGA, frequency-content indicator"),
    "ts_low_s": ("s", "characteristic period T_s, lower estimate 4·PGV/PGA (paper §5)"),
    "ts_high_s": ("s", "characteristic period T_s, upper estimate 5·PGV/PGA (paper §5)"),
}

#: Multipliers of PGV/PGA that the paper (Example 4) uses to bracket the characteristic period.
TS_MULTIPLIERS = (4.0, 5.0)


def cumulative_arias_m_s(acc_m_s2: ArrayLike, dt_s: float) -> NDArray[np.float64]:
    """Arias intensity accumulated up to each sample, π/(2g)∫₀ᵗa²dt [m/s]."""
    acc = check_record(acc_m_s2, dt_s)
    a0, a1 = acc[:-1], acc[1:]
    # ∫ of a linear piece squared over one step, exactly.
    step = dt_s * (a0 * a0 + a0 * a1 + a1 * a1) / 3.0
    out = np.zeros(acc.size)
    np.cumsum(step, out=out[1:])
    result: NDArray[np.float64] = out * (math.pi / (2.0 * STANDARD_GRAVITY_M_S2))
    return result


def arias_intensity_m_s(acc_m_s2: ArrayLike, dt_s: float) -> float:
    """Arias intensity π/(2g)∫a²dt [m/s], g the standard gravity."""
    return float(cumulative_arias_m_s(acc_m_s2, dt_s)[-1])


def arias_times_s(
    husid_m_s: NDArray[np.float64], dt_s: float, fractions: ArrayLike
) -> NDArray[np.float64]:
    """Times [s] at which the Husid curve (:func:`cumulative_arias_m_s`) reaches each fraction of
    its total, interpolated linearly between samples: the one reading of D5-75 and D5-95."""
    time = np.arange(husid_m_s.size) * dt_s
    targets = np.asarray(fractions, dtype=np.float64) * husid_m_s[-1]
    return np.asarray(np.interp(targets, husid_m_s, time), dtype=np.float64)


def significant_duration_s(
    acc_m_s2: ArrayLike, dt_s: float, start: float = 0.05, end: float = 0.95
) -> float:
    """Time [s] between ``start`` and ``end`` fractions of the Arias intensity (D5-95 default).

    The normalised Husid curve is interpolated linearly between samples. A record without
    energy (all zeros) has no duration: :class:`InputError`.
    """
    if not 0.0 <= start < end <= 1.0:
        raise InputError(f"fractions {start}, {end}, expected 0 <= start < end <= 1")
    husid = cumulative_arias_m_s(acc_m_s2, dt_s)
    total = husid[-1]
    if not total > 0.0:
        raise InputError("record is all zeros, expected a record with some motion")
    t_start, t_end = arias_times_s(husid, dt_s, [start, end])
    return float(t_end - t_start)


def cav_m_s(acc_m_s2: ArrayLike, dt_s: float) -> float:
    """Cumulative absolute velocity ∫|a|dt [m/s], exact for linear pieces with sign changes."""
    acc = check_record(acc_m_s2, dt_s)
    a0, a1 = np.abs(acc[:-1]), np.abs(acc[1:])
    crossing = np.sign(acc[:-1]) * np.sign(acc[1:]) < 0
    step = 0.5 * dt_s * (a0 + a1)
    # Across a zero crossing the two triangles have area Δt(a0² + a1²)/(2(|a0| + |a1|)).
    cross = crossing.nonzero()
    step[cross] = dt_s * (a0[cross] ** 2 + a1[cross] ** 2) / (2.0 * (a0[cross] + a1[cross]))
    return float(np.sum(step))


def fourier_amplitude(
    acc_m_s2: ArrayLike, dt_s: float
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Fourier amplitude spectrum |∫a e^{-iωt}dt| ≈ Δt·|DFT(a)|.

    Returns
    -------
    frequency_hz : numpy.ndarray
        Frequencies [Hz] from 0 to the Nyquist frequency.
    amplitude_m_s : numpy.ndarray
        Fourier amplitude [m/s].
    """
    acc = check_record(acc_m_s2, dt_s)
    amplitude: NDArray[np.float64] = np.abs(np.fft.rfft(acc)) * dt_s
    frequency = np.fft.rfftfreq(acc.size, dt_s).astype(np.float64)
    return frequency, amplitude


def intensity_measures(acc_m_s2: ArrayLike, dt_s: float) -> dict[str, float]:
    """Every scalar measure of :data:`MEASURES` for one component.

    Parameters
    ----------
    acc_m_s2
        Ground acceleration [m/s²].
    dt_s
        Sampling interval [s].

    Returns
    -------
    dict
        Keys of :data:`MEASURES` (unit in the name). Durations are NaN for an all-zero record.
    """
    acc = check_record(acc_m_s2, dt_s)
    # One record-long array at a time beside the record (a long record's measures held five).
    pga = float(np.max(np.abs(acc)))
    pgv = float(np.max(np.abs(velocity_m_s(acc, dt_s))))
    husid = cumulative_arias_m_s(acc, dt_s)
    total = float(husid[-1])
    if total > 0.0:
        t5, t75, t95 = arias_times_s(husid, dt_s, [0.05, 0.75, 0.95])
        d5_75, d5_95 = float(t75 - t5), float(t95 - t5)
    else:
        d5_75 = d5_95 = math.nan
    del husid
    ratio = pgv / pga if pga > 0 else math.nan
    return {
        "pga_g": pga / STANDARD_GRAVITY_M_S2,
        "pga_m_s2": pga,
        "pgv_m_s": pgv,
        "pgd_m": float(np.max(np.abs(displacement_m(acc, dt_s)))),
        "arias_m_s": total,
        "d5_75_s": d5_75,
        "d5_95_s": d5_95,
        "cav_m_s": cav_m_s(acc, dt_s),
        "pgv_pga_s": ratio,
        "ts_low_s": TS_MULTIPLIERS[0] * ratio,
        "ts_high_s": TS_MULTIPLIERS[1] * ratio,
    }


def trace_intensity_measures(trace: Trace) -> dict[str, float]:
    """:func:`intensity_measures` of a record (``obspy.Trace`` in m/s²).

    A record made from raw counts (response, sensitivity or a header calibration applied by the
    reader) and not high-passed since is measured after
    :func:`stepframe.records.processing.standard_processing` (offset and linear trend removed,
    5 % taper, 0.1 Hz high-pass), on a copy, with a :class:`ProcessingWarning` saying so
    (:func:`stepframe.records.processing.measured`): as read, its offset integrates into PGV of
    metres per second (CE.68150 HNN: PGV 37 m/s and PGD 2,200 m as read, 0.55 m/s and 0.15 m
    processed).
    """
    from stepframe.records.processing import measured

    trace = measured(trace)
    return intensity_measures(trace.data, float(trace.stats.delta))
