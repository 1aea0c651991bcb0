"""A record's evolutionary spectrum over a frame's band from a bank of two-sided resonators: the
spectrum the moving-resonance index reads and its picture draws (docs/selection.md, "Moving
resonance, measured", step 1).

Band j filters the ground acceleration with the two-sided exponential window
e^{-s_j|t - τ|} e^{iω_j(t - τ)}, s_j = ω_j · :func:`window_rate` (q):

    W_j(t) = ∫ e^{-s_j|t - τ|} e^{iω_j(t - τ)} a(τ) dτ,      S(ω_j, t) = s_j |W_j(t)|² / (2π)

[(m/s²)²·s/rad]. Its gain is 2s/(s² + Δ²) at a distance Δ from ω_j, so under white noise of
density S₀, E|W|² = S₀ ∫ 4s²/(s² + Δ²)² dΔ = 2π S₀/s and S is unbiased; a tone A cos ω_j t
gives A²/(2π s_j). s_j = (2/√π) ω_j/q gives the window the equivalent noise bandwidth
(∫|gain|² over the peak's square) of the project's Morlet wavelet of the same q, whose power
spectrum the index was first defined on: the gain exp(-(Δ q/ω)²) of that wavelet and the
squared Lorentzian here have equal areas, πs/2 = √π ω/q. Like the Morlet's, the window is
symmetric in time (no lag: the index compares the record's energy with the frame's frequency
at the same time), its power falls by e⁻² at 1/s_j from its centre (so within 1/s of either end
of the motion the lowest bands lean on the zeros beyond it, ``omega_floor``,
:func:`cone_floor_rad_s`), and its spectral tail falls as Δ⁻⁴ in power, so the 2-10 Hz of a
record do not leak into the bands at 0.1 Hz. A causal bank (ordinary oscillators, issue 26's
first attempt) lags the record by some q/ω, 10-20 s at the bottom of Example 4's band, and
turned the sufficiency study's answer around (docs/benchmarks.md).

Computation: W = W⁺ + W⁻, the causal part W⁺(t) = ∫_{τ<t} and the anticausal W⁻(t) = ∫_{τ>t},
each a complex one-pole recursion stepped exactly for a motion linear between samples
(:func:`step_weights`), W⁺ forwards in time and W⁻ backwards, ``hop`` samples at a time (only the
frames are wanted: the samples between two frames enter as one weighted sum, :func:`_frame_step`).
Before it the record is smoothed by a centred triangle of 2D - 1 samples and decimated by D, the
largest divisor of the hop with D·dt at most :data:`DECIMATED_PERIOD_FRACTION` of the top band's
period: the triangle's aliases reach the band below (f/f_s)⁴ of their power, and its passband
droop and that of the coarser linear interpolation are divided out (:func:`decimation_gain`).
The decimated bank runs in single precision: its S is within 3e-5 of each frame's largest S of
the same bank in double precision on the example catalogue (the decimation itself moves it by
up to 0.03), for a third less time (the recursions' tables are half the memory and twice the
values a vector instruction).

Cost (docs/benchmarks.md, issue 26): some 0.1 ms a record and frame for the example catalogue,
against 0.8-1.3 ms for the Morlet spectrum (one FFT of the record padded to twice its length and
an inverse FFT per band).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError

Floats = NDArray[np.float64]
Complexes = NDArray[np.complex128]

#: Quality factor of the bank: its equivalent noise bandwidth is the Morlet wavelet's of this q.
BANK_Q = 6.0
#: The decimated bank's step is at most this fraction of the top band's period: 20 steps a
#: period (module docstring).
DECIMATED_PERIOD_FRACTION = 0.05


def window_rate(q: float = BANK_Q) -> float:
    """s/ω of the two-sided window with the equivalent noise bandwidth of a Morlet wavelet of
    quality ``q`` (module docstring): 2/(√π q), 0.188 for q = 6."""
    return 2.0 / (math.sqrt(math.pi) * q)


def bank_grid_rad_s(band_rad_s: Sequence[float], widen_ln: float, per_octave: int) -> Floats:
    """Centres ``per_octave`` to the octave from the band's bottom lowered by ``widen_ln`` (in
    ln ω) up to the first at or above its top raised by as much [rad/s] (a new array)."""
    low, high = float(band_rad_s[0]), float(band_rad_s[1])
    if not (math.isfinite(low) and math.isfinite(high) and 0 < low < high):
        raise InputError(f"band_rad_s = {tuple(band_rad_s)}, expected 0 < low < high [rad/s]")
    return _grid(low, high, widen_ln, per_octave).copy()


@functools.lru_cache(maxsize=64)
def _grid(low: float, high: float, widen_ln: float, per_octave: int) -> Floats:
    """:func:`bank_grid_rad_s` of a checked band, remembered (a selection asks it of every
    record)."""
    octaves = math.log2(high / low) + 2 * widen_ln / math.log(2.0)
    count = max(2, math.ceil(per_octave * octaves - 1e-9) + 1)
    return low * math.exp(-widen_ln) * 2.0 ** (np.arange(count) / per_octave)


def step_weights(pole: Complexes, dt_s: float) -> tuple[Complexes, Complexes, Complexes]:
    """One exact step of z' = p z + a(t) with a linear between samples dt apart:
    z_{i+1} = E z_i + b₀ a_i + b₁ a_{i+1}, E = e^{p dt}, b₀ = I₀ - I₁/dt, b₁ = I₁/dt with
    I₀ = ∫₀^dt e^{p(dt - u)} du = (E - 1)/p and I₁ = ∫₀^dt e^{p(dt - u)} u du = (E - 1 - p dt)/p²
    (their Taylor series where |p dt| < 0.1, where the closed forms cancel digits)."""
    x = np.asarray(pole, dtype=np.complex128) * dt_s
    exponential = np.exp(x)
    small = np.abs(x) < 0.1
    safe = np.where(small, 1.0, x)
    first = np.where(small, 0.0, (exponential - 1.0) / safe)
    second = np.where(small, 0.0, (exponential - 1.0 - x) / safe**2)
    if np.any(small):  # 16 terms: exact to rounding for |x| < 0.1
        xs = x[small]
        first[small] = sum(xs**k / math.factorial(k + 1) for k in range(16))
        second[small] = sum(xs**k / math.factorial(k + 2) for k in range(16))
    integral_0, integral_1 = dt_s * first, dt_s * second  # I₀ and I₁/dt
    return (
        np.asarray(exponential, dtype=np.complex128),
        np.asarray(integral_0 - integral_1, dtype=np.complex128),
        np.asarray(integral_1, dtype=np.complex128),
    )


def _blocked(
    exponential: Complexes, from_start: Complexes, from_end: Complexes, hop: int
) -> tuple[Complexes, Complexes]:
    """``hop`` steps at once: z_{i₀+h} = Eʰ z_{i₀} + Σ_k w_k a_{i₀+k}, w_0 = Eʰ⁻¹ b₀,
    w_k = Eʰ⁻¹⁻ᵏ b₀ + Eʰ⁻ᵏ b₁ (0 < k < h), w_h = b₁; returns (w, shape (hop + 1, P), and Eʰ)."""
    weights = np.zeros((hop + 1, exponential.size), dtype=np.complex128)
    weights[hop] = from_end
    power = np.ones(exponential.size, dtype=np.complex128)  # E^(h-1-k), from k = h - 1 down
    for k in range(hop - 1, -1, -1):
        weights[k] = power * from_start + (power * exponential * from_end if k >= 1 else 0.0)
        power = power * exponential
    return weights, power


@functools.lru_cache(maxsize=32)
def _frame_step(
    omega_bytes: bytes, rate: float, dt_s: float, hop: int, factor: int, real: str = "f8"
) -> tuple[NDArray[np.floating], NDArray[np.floating], NDArray[np.floating]]:
    """The bank's weights over ``hop`` samples ``dt_s`` apart for
    :func:`stepframe.pipeline.dynamics._resonance_kernel.bank_energies`, remembered (a selection
    asks the same grid of every record, and records share a few sampling intervals).

    Returns
    -------
    weights : numpy.ndarray, shape (hop + 1, 4P)
        Real and imaginary parts of the causal pass's w_k (columns 0..2P-1), then of the
        anticausal pass's (2P..4P-1), by the sample's place k in the frame interval.
    powers : numpy.ndarray, shape (4, P)
        Real and imaginary parts of Eʰ of the causal pass, then of the anticausal pass.
    scale : numpy.ndarray
        s_j/(2π) times the :func:`decimation_gain` of a record decimated by ``factor``.

    All three computed in double precision and given in ``real`` ("f4" for the decimated
    bank, :func:`bank_power`).
    """
    omega = np.frombuffer(omega_bytes, dtype=np.float64)
    rate_s = rate * omega
    # W⁺ steps forwards with p = -s + iω. W⁻(t_i) = e^{q dt} W⁻(t_{i+1}) + ∫₀^dt e^{q u} a(t_i + u)
    # du, q = -s - iω: the forward step run backwards in time (its first sample is a_{i+1}), so
    # its weights, blocked over the samples in reverse order, are reversed to the samples' own.
    causal = _blocked(*step_weights(-rate_s + 1j * omega, dt_s), hop)
    reversed_weights, anticausal_power = _blocked(*step_weights(-rate_s - 1j * omega, dt_s), hop)
    anticausal = (reversed_weights[::-1], anticausal_power)
    weights = np.concatenate(
        [causal[0].real, causal[0].imag, anticausal[0].real, anticausal[0].imag], axis=1
    )
    powers = np.stack([causal[1].real, causal[1].imag, anticausal[1].real, anticausal[1].imag])
    scale = rate_s / (2 * math.pi)
    if factor > 1:
        scale = scale * decimation_gain(omega, dt_s / factor, factor)
    return (
        np.ascontiguousarray(weights, dtype=real),
        np.ascontiguousarray(powers, dtype=real),
        np.ascontiguousarray(scale, dtype=real),
    )


@functools.lru_cache(maxsize=64)
def decimation_factor(dt_s: float, hop: int, top_rad_s: float) -> int:
    """The largest factor D dividing ``hop`` (so frames stay on decimated samples) with D·dt
    at most :data:`DECIMATED_PERIOD_FRACTION` of the top band's period (1: none)."""
    limit = max(DECIMATED_PERIOD_FRACTION * 2 * math.pi / top_rad_s / dt_s, 1.0)
    return max(d for d in range(1, hop + 1) if hop % d == 0 and d <= limit)


def decimation_gain(omega_rad_s: Floats, dt_s: float, factor: int) -> Floats:
    """Power gain to multiply the decimated bank's S by, at each band, so that a tone reads as at
    the record's own rate: (sinc²(ω dt/2π) / (H_tri(ω) · sinc²(ω D dt/2π)))², with
    H_tri(ω) = (sin(ω D dt/2)/(D sin(ω dt/2)))² the triangle's gain and sinc² that of linear
    interpolation between samples dt (or D dt) apart."""
    half = 0.5 * omega_rad_s * dt_s
    triangle = (np.sin(half * factor) / (factor * np.sin(half))) ** 2
    own = np.sinc(omega_rad_s * dt_s / (2 * math.pi)) ** 2
    coarse = np.sinc(omega_rad_s * dt_s * factor / (2 * math.pi)) ** 2
    return np.asarray((own / (triangle * coarse)) ** 2)


def bank_power(
    ground_acc_m_s2: ArrayLike,
    dt_s: float,
    omega_rad_s: Floats,
    *,
    hop_s: float,
    q: float = BANK_Q,
    n_samples: int | None = None,
    decimate: bool = True,
) -> tuple[Floats, Floats]:
    """S(ω_j, t) of the module docstring at frames every ``hop_s`` from the first sample.

    Parameters
    ----------
    ground_acc_m_s2
        Ground acceleration [m/s²], finite (a motion a simulation accepted), any scale; linear
        between samples, nothing before the first, and zeros after the last (up to
        ``n_samples``: a ramp to zero over one step, as the simulation's tail).
    dt_s
        Sampling interval [s].
    omega_rad_s
        Band centres [rad/s], below the Nyquist frequency π/dt.
    hop_s
        Frame spacing [s], rounded to whole samples (at least one).
    q
        Quality factor (:func:`window_rate`).
    n_samples
        Samples to cover, the motion followed by zeros (default: the motion's own).
    decimate
        Run the bank on the record smoothed and decimated where the bands allow it, in single
        precision (module docstring); False runs it at the record's own rate in double precision
        (the reference the tests hold the decimated bank to).

    Returns
    -------
    time_s : numpy.ndarray
        Frame times [s]: 0, hop, 2 hop, ... up to the first at or after the last sample
        covered (the motion is followed by zeros up to it).
    psd : numpy.ndarray, shape (frames, len(omega_rad_s))
        S [(m/s²)²·s/rad].

    Raises
    ------
    InputError
        Fewer than two samples, or a band at or above the Nyquist frequency.
    """
    from stepframe.pipeline.dynamics._resonance_kernel import bank_energies, triangle_decimated

    data = np.ascontiguousarray(ground_acc_m_s2, dtype=np.float64)
    omega = np.ascontiguousarray(omega_rad_s, dtype=np.float64)
    top = float(omega.max()) if omega.size else 0.0
    if top >= math.pi / dt_s:
        raise InputError(
            f"band at {top:.4g} rad/s at or above the Nyquist frequency "
            f"{math.pi / dt_s:.4g} rad/s of dt = {dt_s:g} s, expected a record sampled finer"
        )
    hop = max(1, round(hop_s / dt_s))
    covered = max(data.size, n_samples or 0)
    if covered < 2:
        raise InputError(
            f"{covered} sample at {dt_s:g} s, expected ≥ 2 (a motion to put in frames of "
            f"{hop * dt_s:g} s)"
        )
    # The last frame at or after the last sample, so that every sample is felt.
    n_frames = -(-(covered - 1) // hop) + 1
    factor = decimation_factor(dt_s, hop, top) if decimate else 1
    if factor > 1:
        data = triangle_decimated(data, factor, (n_frames - 1) * (hop // factor) + 1)
    real = "f4" if decimate else "f8"
    weights, powers, scale = _frame_step(
        omega.tobytes(), window_rate(q), dt_s * factor, hop // factor, factor, real
    )
    psd = bank_energies(data.astype(real, copy=False), weights, powers, scale, n_frames)
    return np.arange(n_frames, dtype=np.float64) * (hop * dt_s), psd.astype(np.float64)


def cone_floor_rad_s(time_s: Floats, duration_s: float, q: float = BANK_Q) -> Floats:
    """Lowest band [rad/s] clear of the motion's ends at each time [s]: the window's power falls
    by e⁻² at 1/s = 1/(ω·rate) from its centre, so at a distance d from the nearer end the bands
    down to 1/(rate·d) are clear (infinite at the ends; the Morlet's cone of influence,
    Torrence and Compo 1998, drawn the same way)."""
    edge = np.clip(np.minimum(time_s, duration_s - np.asarray(time_s)), 0.0, None)
    with np.errstate(divide="ignore"):
        return np.asarray(1.0 / (window_rate(q) * edge))


__all__ = [
    "BANK_Q",
    "DECIMATED_PERIOD_FRACTION",
    "bank_grid_rad_s",
    "bank_power",
    "cone_floor_rad_s",
    "decimation_factor",
    "decimation_gain",
    "step_weights",
    "window_rate",
]
