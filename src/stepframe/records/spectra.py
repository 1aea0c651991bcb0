"""Response spectra of one component: SD, PSV and PSA of linear oscillators at any damping.

Two methods, chosen by name (``method=``), both vectorised over periods:

``"nigam_jennings"`` (default)
    The exact state-transition recurrence for ground acceleration that is linear between samples
    (Nigam and Jennings 1969), run by a small compiled kernel over all periods. Cost O(N·P); exact
    for the piecewise-linear reading of the record.
``"frequency_domain"``
    The oscillator's transfer function applied to the FFT of the zero-padded record (the record
    read as band-limited). Cost O(P·M log M) with M the padded length; needs damping > 0 (the
    padding must hold the free-vibration decay). A cross-check of the first.

Short periods: the peak of an oscillator whose period spans only a few samples falls between
samples. Both methods first interpolate the record band-limitedly (FFT zero padding) by an integer
factor so that every period spans at least ``points_per_period`` samples (default 10), each period
using the smallest factor it needs.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.core.memory import check_memory
from stepframe.core.validation import damping_fraction, finite_array, in_range, non_negative
from stepframe.errors import InputError
from stepframe.records.integration import check_record
from stepframe.records.units import STANDARD_GRAVITY_M_S2

SpectrumMethod = Literal["nigam_jennings", "frequency_domain"]

#: Default period grid [s]: 91 log-spaced periods from 0.01 s to 10 s (30 per decade).
DEFAULT_PERIODS_S: NDArray[np.float64] = np.logspace(-2.0, 1.0, 91)

#: Largest band-limited upsampling factor (a period of 0.01 s at dt = 0.02 s needs 20).
MAX_UPSAMPLING = 64


@dataclass(frozen=True)
class ResponseSpectrum:
    """Peak responses of damped linear oscillators to one ground-acceleration component.

    Attributes
    ----------
    period_s
        Oscillator periods [s].
    damping
        Damping ratio (fraction of critical).
    sd_m
        Peak relative displacement [m].
    psv_m_s
        Pseudo-spectral velocity ω·SD [m/s].
    psa_m_s2
        Pseudo-spectral acceleration ω²·SD [m/s²].
    """

    period_s: NDArray[np.float64]
    damping: float
    sd_m: NDArray[np.float64]
    psv_m_s: NDArray[np.float64]
    psa_m_s2: NDArray[np.float64]

    @property
    def psa_g(self) -> NDArray[np.float64]:
        """Pseudo-spectral acceleration in units of standard gravity [g]."""
        return self.psa_m_s2 / STANDARD_GRAVITY_M_S2


#: Oscillator periods accepted [s]: a 1 kHz oscillator is already far above any accelerograph's
#: band, and a shorter period would upsample the record without bound; 10⁴ s is far below the
#: longest period a record of finite length can constrain, yet keeps ω finite and non-zero.
PERIOD_RANGE_S = (1e-3, 1e4)


def check_periods(period_s: ArrayLike) -> NDArray[np.float64]:
    """Periods [s] as a 1-D float array within :data:`PERIOD_RANGE_S`; refuses anything else."""
    periods = finite_array("periods", period_s, positive_values=True)
    low, high = PERIOD_RANGE_S
    for period in periods:
        in_range("period", float(period), low, high, unit="s")
    return periods


def check_damping(damping: float) -> float:
    """Damping ratio as a float in [0, 1); a percentage (5 for 5 %) is refused with a hint."""
    return damping_fraction("damping", damping)


#: Below this ωΔt the coefficients come from a Taylor series (the closed form loses digits there:
#: its terms grow like 1/(ω³Δt) while the coefficients shrink like Δt²).
SERIES_BELOW_OMEGA_DT = 0.1


def nigam_jennings_coefficients(
    omega_rad_s: NDArray[np.float64], damping: float, dt_s: float
) -> NDArray[np.float64]:
    """Exact one-step coefficients of ü + 2ζωu̇ + ω²u = -a(t), a linear over each step.

    Closed form of Nigam and Jennings (1969) where ωΔt >= :data:`SERIES_BELOW_OMEGA_DT`; below
    it, the Taylor series of the same state-transition matrix (the closed form would cancel
    digits: 2e-4 relative error at T = 100 s, Δt = 1 ms). Both are within 1e-12 of a 40-digit
    evaluation on T = 0.01-100 s, Δt = 1-20 ms (tests).

    Returns
    -------
    numpy.ndarray, shape (P, 8)
        Rows ``(a11, a12, a21, a22, b11, b12, b21, b22)`` such that
        ``u' = a11 u + a12 v + b11 a_i + b12 a_{i+1}`` and
        ``v' = a21 u + a22 v + b21 a_i + b22 a_{i+1}`` (u [m], v [m/s], a [m/s²]).
    """
    w = np.ascontiguousarray(np.atleast_1d(np.asarray(omega_rad_s, dtype=np.float64)))
    # a copy: the cached array is shared by every later call with the same arguments
    return _coefficients(w.tobytes(), float(damping), float(dt_s)).copy()


@functools.lru_cache(maxsize=64)
def _coefficients(omega_bytes: bytes, damping: float, dt_s: float) -> NDArray[np.float64]:
    """:func:`nigam_jennings_coefficients` of the frequencies packed in ``omega_bytes``,
    remembered: a catalogue's records share a few sampling intervals and the selection asks
    the same periods of each, and these coefficients were a quarter of its spectra pass's
    time (docs/benchmarks.md, the responses stage's cost)."""
    w = np.frombuffer(omega_bytes, dtype=np.float64)
    out = _closed_form(w, damping, dt_s)
    small = w * dt_s < SERIES_BELOW_OMEGA_DT
    if np.any(small):
        out[small] = _series(w[small], damping, dt_s)
    return out


def _closed_form(w: NDArray[np.float64], z: float, dt_s: float) -> NDArray[np.float64]:
    root = math.sqrt(1.0 - z * z)
    wd = w * root
    e = np.exp(-z * w * dt_s)
    s = np.sin(wd * dt_s)
    c = np.cos(wd * dt_s)
    a11 = e * (z / root * s + c)
    a12 = e * s / wd
    a21 = -w / root * e * s
    a22 = e * (c - z / root * s)
    # The particular solutions for a constant and a linearly growing forcing, combined so that
    # the step starts from rest; see Nigam and Jennings (1969), eqs. 8-9.
    k1 = (2.0 * z * z - 1.0) / (w * w * dt_s)
    k2 = 2.0 * z / (w**3 * dt_s)
    b11 = e * ((k1 + z / w) * s / wd + (k2 + 1.0 / w**2) * c) - k2
    b12 = -e * (k1 * s / wd + k2 * c) - 1.0 / w**2 + k2
    dc = c - z / root * s
    ds = wd * s + z * w * c
    b21 = e * ((k1 + z / w) * dc - (k2 + 1.0 / w**2) * ds) + 1.0 / (w * w * dt_s)
    b22 = -e * (k1 * dc - k2 * ds) - 1.0 / (w * w * dt_s)
    return np.ascontiguousarray(np.stack([a11, a12, a21, a22, b11, b12, b21, b22], axis=1))


def _series(w: NDArray[np.float64], z: float, dt_s: float) -> NDArray[np.float64]:
    """Coefficients from exp(MΔt) by its Taylor series, state (u, v, a, ȧ) with ȧ constant.

    Every cycle through M multiplies by at most (ωΔt)² (u ↔ v), and the forcing enters through
    a nilpotent chain, so 24 terms are exact to rounding for ωΔt < 0.1.
    """
    m = np.zeros((w.size, 4, 4))
    m[:, 0, 1] = dt_s
    m[:, 1, 0] = -w * w * dt_s
    m[:, 1, 1] = -2.0 * z * w * dt_s
    m[:, 1, 2] = -dt_s
    m[:, 2, 3] = dt_s
    term = np.broadcast_to(np.eye(4), m.shape).copy()
    total = term.copy()
    for k in range(1, 25):
        term = term @ m / k
        total += term
    p = total
    return np.stack(
        [
            p[:, 0, 0],
            p[:, 0, 1],
            p[:, 1, 0],
            p[:, 1, 1],
            p[:, 0, 2] - p[:, 0, 3] / dt_s,
            p[:, 0, 3] / dt_s,
            p[:, 1, 2] - p[:, 1, 3] / dt_s,
            p[:, 1, 3] / dt_s,
        ],
        axis=1,
    )


def upsampling_factors(
    period_s: NDArray[np.float64], dt_s: float, points_per_period: float = 10.0
) -> NDArray[np.int64]:
    """Integer factor per period so that each period spans at least ``points_per_period`` samples.

    Capped at :data:`MAX_UPSAMPLING`; ``points_per_period`` 0 upsamples nothing (the record at
    its own rate); a negative or NaN value is refused (it upsampled nothing, silently).
    """
    non_negative("points_per_period", points_per_period)
    need = np.maximum(points_per_period * dt_s / period_s, 1.0)
    factors = np.ceil(need - 1e-9).astype(np.int64)
    return np.minimum(np.maximum(factors, 1), MAX_UPSAMPLING)


class _Upsampler:
    """Band-limited interpolation of one record by integer factors, sharing one forward FFT.

    The record is padded with zeros (a quarter of its length, rounded up to a fast FFT length)
    so that the interpolated end does not wrap onto the start; original samples are reproduced
    (to rounding).
    """

    def __init__(self, acc_m_s2: NDArray[np.float64]) -> None:
        self.acc = acc_m_s2
        self._spectrum: NDArray[np.complex128] | None = None
        self._nfft = 0

    def __call__(self, factor: int) -> NDArray[np.float64]:
        if factor == 1:
            return self.acc
        from scipy.fft import irfft, next_fast_len, rfft

        n = self.acc.size
        if self._spectrum is None:
            nfft = next_fast_len(n + n // 4 + 16, real=True)
            self._nfft = nfft + nfft % 2  # even: the last bin is the Nyquist bin handled below
            spectrum = rfft(self.acc, self._nfft)
            # The original Nyquist bin is shared by ±f_N; once it is no longer the Nyquist bin
            # of the longer series it must be halved to keep the same real cosine.
            spectrum[-1] *= 0.5
            self._spectrum = spectrum
        padded = np.zeros(self._nfft * factor // 2 + 1, dtype=complex)
        padded[: self._spectrum.size] = self._spectrum * factor
        fine = irfft(padded, self._nfft * factor, overwrite_x=True)
        return np.ascontiguousarray(fine[: (n - 1) * factor + 1])


def upsample(acc_m_s2: NDArray[np.float64], factor: int) -> NDArray[np.float64]:
    """Band-limited interpolation by an integer factor (FFT zero padding of the padded record).

    The record is padded with zeros (a quarter of its length, rounded up to a fast FFT length)
    so that the interpolated end does not wrap onto the start; original samples are reproduced
    (to rounding).
    """
    return _Upsampler(acc_m_s2)(factor)


def _kernels() -> tuple[Any, Any]:
    """The compiled kernels (numba imported on first use: the CLI stays fast to start)."""
    global _KERNELS
    if _KERNELS is None:
        from stepframe.records import _spectra_kernels

        _KERNELS = (_spectra_kernels.peak_displacements, _spectra_kernels.displacement_histories)
    return _KERNELS


_KERNELS: tuple[Any, Any] | None = None


def _groups(periods: NDArray[np.float64], dt_s: float, points_per_period: float) -> Any:
    factors = upsampling_factors(periods, dt_s, points_per_period)
    for factor in np.unique(factors):
        yield int(factor), np.flatnonzero(factors == factor)


#: Peak memory of a response spectrum per sample of the upsampled record [bytes], by method:
#: the record's spectrum padded, its inverse and the fine copy (measured 40 bytes for
#: nigam_jennings and 64 for frequency_domain on 1.5·10⁶ samples upsampled 5 and 25 times).
SPECTRUM_BYTES_PER_FINE_SAMPLE = {"nigam_jennings": 48.0, "frequency_domain": 80.0}


def _check_spectrum_memory(
    n_samples: int, factor: int, method: str, histories: int = 0, pad: int = 0
) -> None:
    """Refuse a response spectrum whose upsampled record (``factor`` times ``n_samples``, plus
    the free-vibration ``pad``) and ``histories`` kept would pass the memory budget."""
    fine = float(n_samples + pad) * factor
    check_memory(
        fine * (SPECTRUM_BYTES_PER_FINE_SAMPLE.get(method, 80.0) + 8.0 * histories),
        f"the response spectrum of {n_samples} samples upsampled {factor} times ({method})",
        "a shortest period nearer 10 dt (it sets the upsampling)",
    )


def peak_displacements_m(
    acc_m_s2: ArrayLike,
    dt_s: float,
    period_s: ArrayLike,
    damping: float = 0.05,
    *,
    method: SpectrumMethod = "nigam_jennings",
    points_per_period: float = 10.0,
) -> NDArray[np.float64]:
    """Peak relative displacement [m] of each oscillator (see :func:`response_spectrum`)."""
    acc = check_record(acc_m_s2, dt_s)
    periods = check_periods(period_s)
    zeta = check_damping(damping)
    _check_spectrum_memory(
        acc.size, int(upsampling_factors(periods, dt_s, points_per_period).max()), method
    )
    if method == "nigam_jennings":
        peak, _ = _kernels()
        out = np.empty(periods.size)
        upsampler = _Upsampler(acc)
        for factor, index in _groups(periods, dt_s, points_per_period):
            fine = upsampler(factor)
            coeffs = nigam_jennings_coefficients(2 * np.pi / periods[index], zeta, dt_s / factor)
            out[index] = peak(fine, coeffs)
        return out
    if method == "frequency_domain":
        return _frequency_domain_peaks(acc, dt_s, periods, zeta, points_per_period)
    raise InputError(f"unknown method {method!r}, expected 'nigam_jennings' or 'frequency_domain'")


def displacement_histories_m(
    acc_m_s2: NDArray[np.float64],
    dt_s: float,
    period_s: NDArray[np.float64],
    damping: float,
    factor: int,
) -> NDArray[np.float64]:
    """Relative displacement histories [m], shape ((N-1)·factor+1, P), at step dt_s/factor."""
    _, histories = _kernels()
    record = check_record(acc_m_s2, dt_s)
    _check_spectrum_memory(record.size, factor, "nigam_jennings", histories=np.size(period_s))
    fine = upsample(record, factor)
    coeffs = nigam_jennings_coefficients(
        2 * np.pi / period_s, check_damping(damping), dt_s / factor
    )
    result: NDArray[np.float64] = histories(fine, coeffs)
    return result


def _frequency_domain_peaks(
    acc: NDArray[np.float64],
    dt_s: float,
    periods: NDArray[np.float64],
    zeta: float,
    points_per_period: float,
) -> NDArray[np.float64]:
    if zeta <= 0.0:
        raise InputError(
            "damping 0 with method 'frequency_domain', expected damping > 0 (or 'nigam_jennings')"
        )
    from scipy.fft import irfft, next_fast_len, rfft

    n = acc.size
    out = np.empty(periods.size)
    for factor, index in _groups(periods, dt_s, points_per_period):
        omegas = 2 * np.pi / periods[index]
        # Zero padding holds the free vibration after the record (8 decay times ≈ e^-8).
        pad = math.ceil(8.0 / (zeta * omegas.min()) / dt_s)
        _check_spectrum_memory(n, factor, "frequency_domain", pad=pad)
        nfft = next_fast_len(n + pad, real=True)
        spectrum = rfft(acc, nfft)
        nfine = nfft * factor
        padded = np.zeros(nfine // 2 + 1, dtype=complex)
        padded[: spectrum.size] = spectrum
        if nfft % 2 == 0:
            padded[spectrum.size - 1] *= 0.5
        omega = 2 * np.pi * np.fft.rfftfreq(nfine, dt_s / factor)
        for j, w0 in zip(index, omegas, strict=True):
            transfer = -1.0 / (w0 * w0 - omega * omega + 2j * zeta * w0 * omega)
            u = irfft(padded * transfer, nfine) * factor
            out[j] = np.max(np.abs(u))
    return out


def psa_column(period_s: float) -> str:
    """The table column of the PSA [g] at one period, ``psa_0.2s_g``, ``psa_10s_g``: the one name
    of the records catalogue's and the measures stage's columns (docs/workflows.md)."""
    return f"psa_{period_s:g}s_g"


def pseudo_acceleration_m_s2(period_s: ArrayLike, sd_m: ArrayLike) -> NDArray[np.float64]:
    """PSA = ω²·SD [m/s²], ω = 2π/T, of peak displacements ``sd_m`` [m] at periods ``period_s``
    [s] (broadcast together): the one conversion of :func:`response_spectrum`, the RotD spectra
    and the selection's PSA(T_1) and peers."""
    omega = 2 * np.pi / np.asarray(period_s, dtype=np.float64)
    return np.asarray(omega * omega * np.asarray(sd_m, dtype=np.float64))


def response_spectrum(
    acc_m_s2: ArrayLike,
    dt_s: float,
    period_s: ArrayLike = DEFAULT_PERIODS_S,
    damping: float = 0.05,
    *,
    method: SpectrumMethod = "nigam_jennings",
    points_per_period: float = 10.0,
) -> ResponseSpectrum:
    """SD, PSV and PSA of one ground-acceleration component.

    Parameters
    ----------
    acc_m_s2
        Ground acceleration [m/s²], uniformly sampled.
    dt_s
        Sampling interval [s].
    period_s
        Oscillator periods [s] (default :data:`DEFAULT_PERIODS_S`).
    damping
        Damping ratio, a fraction of critical in [0, 1) (0.05, not 5).
    method
        ``"nigam_jennings"`` (exact recurrence, default) or ``"frequency_domain"`` (see module).
    points_per_period
        Minimum samples per oscillator period; shorter periods use a band-limited upsampled
        record.

    Returns
    -------
    ResponseSpectrum
        SD [m], PSV = ωSD [m/s], PSA = ω²SD [m/s²] at each period.
    """
    periods = check_periods(period_s)
    sd = peak_displacements_m(
        acc_m_s2, dt_s, periods, damping, method=method, points_per_period=points_per_period
    )
    omega = 2 * np.pi / periods
    return ResponseSpectrum(
        periods, float(damping), sd, omega * sd, pseudo_acceleration_m_s2(periods, sd)
    )
