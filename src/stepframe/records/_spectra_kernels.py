"""Compiled loops of :mod:`stepframe.records.spectra` (numba, cached on disk where a folder is
writable: :mod:`stepframe.core.jit`).

Kept apart so that importing :mod:`stepframe.records.spectra` does not import numba. Each kernel
runs the Nigam-Jennings recurrence with time outer and periods inner: the periods are independent,
so the inner loop vectorises (SIMD) instead of waiting on one oscillator's dependency chain, which
measured 3-7 times faster than periods outer on the 111-period PEER grid.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from stepframe.core.jit import njit


@njit(cache=True, fastmath=True)
def peak_displacements(
    acc: NDArray[np.float64], coeffs: NDArray[np.float64]
) -> NDArray[np.float64]:
    """Peak |u| per period for the recurrence rows ``coeffs`` (P, 8), starting from rest."""
    nper = coeffs.shape[0]
    c = np.ascontiguousarray(coeffs.T)
    u = np.zeros(nper)
    v = np.zeros(nper)
    peak = np.zeros(nper)
    for i in range(1, acc.size):
        previous = acc[i - 1]
        current = acc[i]
        for j in range(nper):
            u_next = c[0, j] * u[j] + c[1, j] * v[j] + c[4, j] * previous + c[5, j] * current
            v[j] = c[2, j] * u[j] + c[3, j] * v[j] + c[6, j] * previous + c[7, j] * current
            u[j] = u_next
            peak[j] = max(peak[j], abs(u_next))
    return peak


@njit(cache=True, fastmath=True)
def displacement_histories(
    acc: NDArray[np.float64], coeffs: NDArray[np.float64]
) -> NDArray[np.float64]:
    """u(t) per period, shape (N, P), starting from rest (for RotD of two components)."""
    nper = coeffs.shape[0]
    c = np.ascontiguousarray(coeffs.T)
    out = np.zeros((acc.size, nper))
    v = np.zeros(nper)
    for i in range(1, acc.size):
        previous = acc[i - 1]
        current = acc[i]
        for j in range(nper):
            u = out[i - 1, j]
            out[i, j] = c[0, j] * u + c[1, j] * v[j] + c[4, j] * previous + c[5, j] * current
            v[j] = c[2, j] * u + c[3, j] * v[j] + c[6, j] * previous + c[7, j] * current
    return out
