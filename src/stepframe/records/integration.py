"""Exact integration of an acceleration record read as linear between samples.

The one home of the record check and of velocity and displacement from rest, used by the
intensity measures (:mod:`stepframe.records.intensity`), the baseline correction
(:mod:`stepframe.records.processing`) and the spectra.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError


def check_record(acc_m_s2: ArrayLike, dt_s: float) -> NDArray[np.float64]:
    """Samples as a contiguous 1-D float array; refuses NaN, fewer than 2 samples, bad dt."""
    acc = np.ascontiguousarray(acc_m_s2, dtype=np.float64)
    if acc.ndim != 1 or acc.size < 2:
        raise InputError(f"record of shape {acc.shape}, expected a 1-D series of >= 2 samples")
    if not np.all(np.isfinite(acc)):
        raise InputError("record holds NaN or infinite samples, expected finite values")
    if not (math.isfinite(dt_s) and dt_s > 0):
        raise InputError(f"sampling interval {dt_s} s, expected a positive number")
    return acc


def velocity_m_s(acc_m_s2: ArrayLike, dt_s: float) -> NDArray[np.float64]:
    """Ground velocity [m/s] from rest, exact for acceleration linear between samples."""
    acc = check_record(acc_m_s2, dt_s)
    out = np.zeros(acc.size)
    np.cumsum(0.5 * dt_s * (acc[1:] + acc[:-1]), out=out[1:])
    return out


def displacement_m(acc_m_s2: ArrayLike, dt_s: float) -> NDArray[np.float64]:
    """Ground displacement [m] from rest, exact for acceleration linear between samples.

    Per step, d_{i+1} = d_i + v_i Δt + Δt²(2a_i + a_{i+1})/6.
    """
    acc = check_record(acc_m_s2, dt_s)
    vel = velocity_m_s(acc, dt_s)
    step = vel[:-1] * dt_s + dt_s * dt_s * (2.0 * acc[:-1] + acc[1:]) / 6.0
    out = np.zeros(acc.size)
    np.cumsum(step, out=out[1:])
    return out
