"""Compiled kernel of the Morlet spectrum (:func:`stepframe.stochastic.transforms.wavelet_power`):
each band's Gaussian-weighted bins folded modulo the length of the frames' inverse FFT.

Compiled because the fold is a short loop per band: written with numpy it costs some ten calls
per band, which for the 30-50 bands of a frame's band was most of the spectrum's time, and laid
end to end over all bands it doubles the memory traffic of the 96 default bands of a long record
(docs/benchmarks.md, issue 26).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from stepframe.core.jit import njit


@njit(cache=True)
def folded_bands(
    spectrum: NDArray[np.complex128],
    omega: NDArray[np.float64],
    sigma: NDArray[np.float64],
    step: float,
    m: int,
    reach: float,
) -> NDArray[np.complex128]:
    """Each band's analytic spectrum 2·X(ω_k)·exp(-½((ω_k - ω_j)/σ_j)²) over the bins k within
    ``reach``·σ_j of ω_j, summed modulo ``m`` (bands × m).

    Parameters
    ----------
    spectrum
        One-sided FFT X(ω_k) of the zero-padded record, bins every ``step`` [rad/s].
    omega, sigma
        Band centres ω_j and Gaussian widths σ_j [rad/s].
    step
        Bin spacing [rad/s].
    m
        Length of each band's folded spectrum (the frames' inverse FFT).
    reach
        Half-width of the bins kept, in σ_j.
    """
    folded = np.zeros((omega.size, m), dtype=np.complex128)
    for j in range(omega.size):
        first = max(0, math.floor((omega[j] - reach * sigma[j]) / step))
        last = min(spectrum.size, math.ceil((omega[j] + reach * sigma[j]) / step) + 1)
        for k in range(first, last):
            z = (k * step - omega[j]) / sigma[j]
            # Analytic signal: positive frequencies only, hence the factor 2.
            folded[j, k % m] += 2.0 * math.exp(-0.5 * z * z) * spectrum[k]
    return folded


@njit(cache=True)
def band_powers(
    analytic: NDArray[np.complex128], n_frames: int, hop: int, sigma: NDArray[np.float64]
) -> NDArray[np.float64]:
    """The power density √π·|u_j(t_l)|²/(2σ_j) of each band's analytic signal at the first
    ``n_frames`` frames (frames × bands), u = the inverse FFT of the folded spectrum over
    ``hop`` (the m-point transform of every hop-th sample).

    One pass instead of numpy's slice, scaling, squares, division and transposition, each a
    temporary the size of the table (docs/benchmarks.md, issue 26).
    """
    n_bands = analytic.shape[0]
    psd = np.empty((n_frames, n_bands))
    root_pi = math.sqrt(math.pi)
    for j in range(n_bands):
        width = 2.0 * sigma[j]
        for f in range(n_frames):
            re = analytic[j, f].real / hop
            im = analytic[j, f].imag / hop
            psd[f, j] = root_pi * (re * re + im * im) / width
    return psd
