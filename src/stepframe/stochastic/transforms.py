"""Time-frequency transforms of a record: short-time Fourier and Morlet wavelet power.

The transforms only; nothing here fits a model, so the feature estimators
(:mod:`stepframe.stochastic.features`), the fit (:mod:`stepframe.stochastic.fit`) and the
evolutionary spectra (:mod:`stepframe.stochastic.spectra`, whose parametric method fits) all import
this module and none of them imports another to reach a transform. Conventions (the two-sided S on
ω ≥ 0, the normalisation of each transform) are stated in :mod:`stepframe.stochastic.spectra`.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

if TYPE_CHECKING:
    from obspy import Trace
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError

FftBackend = Literal["pyfftw", "scipy"]
StftEngine = Literal["batched", "shorttimefft"]

#: Default STFT window length [s]: resolves 2π/2 s ≈ 3 rad/s, tracks changes over ~1 s.
DEFAULT_WINDOW_S = 2.0
#: Default spacing of frames [s].
DEFAULT_HOP_S = 0.1
#: Half-width of the bins a Morlet band keeps, in its standard deviations σ = ω/q: the Gaussian
#: gain beyond is below e⁻⁵⁰ ≈ 2e-22, far under the rounding of the bins it keeps.
_GAIN_REACH = 10.0


def record_samples(
    record_or_array: Trace | ArrayLike, dt_s: float | None
) -> tuple[NDArray[np.float64], float]:
    """Samples [m/s²] and dt [s] of an ``obspy.Trace`` or an array, validated.

    Raises
    ------
    InputError
        Not 1-D, fewer than 8 samples, NaN/inf values, all equal (constant or zero), missing or
        bad dt.
    """
    stats = getattr(record_or_array, "stats", None)
    if stats is not None:
        trace: Any = record_or_array  # an obspy Trace (obspy ships no types)
        data = np.asarray(trace.data, dtype=np.float64)
        dt = float(stats.delta) if dt_s is None else float(dt_s)
        # Name the record in error messages by its file (when a reader set one) and channel.
        source = (stats.get("stepframe") or {}).get("source_file")
        name = f"{source or ''} {stats.channel}".strip() or "record"
    else:
        if dt_s is None:
            raise InputError("dt_s missing, expected the sampling interval of the array [s]")
        data = np.asarray(record_or_array, dtype=np.float64)
        dt = float(dt_s)
        name = "record"
    if data.ndim != 1 or data.size < 8:
        raise InputError(f"{name}: {data.size} samples in shape {data.shape}, expected ≥ 8 in 1-D")
    if not (math.isfinite(dt) and dt > 0):
        raise InputError(f"{name}: dt = {dt} s, expected a positive number")
    bad = ~np.isfinite(data)
    if bad.any():
        first = int(np.argmax(bad))
        raise InputError(
            f"{name}: {int(bad.sum())} NaN/inf samples (first at sample {first}), "
            "expected finite values"
        )
    if np.ptp(data) == 0:
        raise InputError(f"{name}: all samples equal {data[0]}, expected a varying accelerogram")
    return data, dt


def fft_backend(fft: FftBackend) -> AbstractContextManager[Any]:
    """Context in which scipy.fft (and so ``ShortTimeFFT``) uses pyFFTW or its own FFT."""
    if fft == "scipy":
        return nullcontext()
    if fft != "pyfftw":
        raise InputError(f"fft = {fft!r}, expected 'pyfftw' or 'scipy'")
    import pyfftw.interfaces.cache
    import pyfftw.interfaces.scipy_fft
    import scipy.fft

    pyfftw.interfaces.cache.enable()  # keep FFTW plans between frames and records
    return scipy.fft.set_backend(pyfftw.interfaces.scipy_fft)  # type: ignore[no-any-return]


def window_samples(window_s: float, dt_s: float, npts: int) -> int:
    """Window length in samples (≥ 16), checked against the record length."""
    if not (math.isfinite(window_s) and window_s > 0):
        raise InputError(f"window_s = {window_s}, expected a positive number of seconds")
    m = round(window_s / dt_s)
    if m < 16:
        raise InputError(
            f"window_s = {window_s} s is {m} samples at dt = {dt_s} s, expected ≥ 16 samples"
        )
    if m > npts:
        raise InputError(
            f"record of {npts} samples ({npts * dt_s:.3g} s) is shorter than the "
            f"{window_s} s window, expected a record at least one window long"
        )
    return m


#: Memory of one block of STFT frames in :func:`stft_power_blocks` [bytes]: the windowed
#: frames, their complex spectra and the power of a block are about this much, whatever the
#: record's length (a whole 1.5·10⁷-sample record's took 8 GB at once).
STFT_BLOCK_BYTES = 32 * 1024**2


@dataclass(frozen=True)
class StftGrid:
    """The frames of an STFT: their centres, the frequencies, the window and the blocks.

    Attributes
    ----------
    time_s
        Frame centres [s] from the record start (0, hop, ..., covering the record).
    omega_rad_s
        Frequencies 0 ... π/dt [rad/s].
    window
        The Hann window (samples).
    hop
        Frame spacing [samples].
    mfft
        FFT length [samples].
    mid
        Index of the window's centre sample.
    """

    time_s: NDArray[np.float64]
    omega_rad_s: NDArray[np.float64]
    window: NDArray[np.float64]
    hop: int
    mfft: int
    mid: int

    @property
    def frames_per_block(self) -> int:
        """Frames transformed at once (:data:`STFT_BLOCK_BYTES` of work)."""
        per_frame = 8 * self.window.size + 16 * (self.mfft // 2 + 1) + 24 * self.omega_rad_s.size
        return max(1, STFT_BLOCK_BYTES // per_frame)


def stft_grid(npts: int, dt_s: float, *, window_s: float, hop_s: float) -> StftGrid:
    """The frame grid of :func:`stft_power` for a record of ``npts`` samples at ``dt_s``."""
    from scipy.signal import ShortTimeFFT
    from scipy.signal.windows import hann

    m = window_samples(window_s, dt_s, npts)
    hop = max(1, round(hop_s / dt_s))
    win = hann(m, sym=False) if m % 2 == 0 else hann(m, sym=True)
    mfft = 1 << max(math.ceil(math.log2(m)), 4)
    stft = ShortTimeFFT(win, hop, 1.0 / dt_s, fft_mode="onesided", mfft=mfft)
    p1 = (npts - 1) // hop + 1
    time_s = np.arange(p1, dtype=np.float64) * hop * dt_s
    omega = 2 * math.pi * np.asarray(stft.f, dtype=np.float64)
    return StftGrid(time_s, omega, np.asarray(win, dtype=np.float64), hop, mfft, stft.m_num_mid)


def stft_power_blocks(
    data: NDArray[np.float64], dt_s: float, grid: StftGrid, *, fft: FftBackend = "scipy"
) -> Iterator[tuple[slice, NDArray[np.float64]]]:
    """The STFT power of :func:`stft_power`, a block of frames at a time: ``(frames, psd)``
    with ``psd`` of shape (frames, omega), each block holding :data:`STFT_BLOCK_BYTES` or so.

    Frame p is centred on sample p·hop (zeros outside the record), as in scipy's
    ``ShortTimeFFT``; each frame's values and FFT are those of the whole-record transform.
    """
    import scipy.fft as sfft

    m, hop, win = grid.window.size, grid.hop, grid.window
    scale = dt_s / float(np.sum(win**2))
    n_frames, step = grid.time_s.size, grid.frames_per_block
    with fft_backend(fft):
        for p0 in range(0, n_frames, step):
            p1 = min(n_frames, p0 + step)
            # The samples of frames p0..p1-1: from p0·hop - mid, padded with zeros at the ends.
            start = p0 * hop - grid.mid
            stop = (p1 - 1) * hop - grid.mid + m
            segment = np.zeros(stop - start)
            lo, hi = max(start, 0), min(stop, data.size)
            if hi > lo:
                segment[lo - start : hi - start] = data[lo:hi]
            frames = np.lib.stride_tricks.sliding_window_view(segment, m)[::hop][: p1 - p0]
            spec = sfft.rfft(frames * win, n=grid.mfft, axis=-1)
            yield slice(p0, p1), scale * (spec.real**2 + spec.imag**2)


def stft_power(
    data: NDArray[np.float64],
    dt_s: float,
    *,
    window_s: float = DEFAULT_WINDOW_S,
    hop_s: float = DEFAULT_HOP_S,
    fft: FftBackend = "scipy",
    engine: StftEngine = "batched",
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """STFT evolutionary spectrum as arrays.

    Both engines use the window, frequencies and slice positions of one scipy ``ShortTimeFFT``
    (slice p centred on sample p·hop, zeros outside the record) and FFTs through ``scipy.fft``
    (so pyFFTW or scipy's own per ``fft``). ``"shorttimefft"`` calls ``ShortTimeFFT.stft``,
    which transforms one slice per Python call; ``"batched"`` (default) transforms the slices
    a block at a time (:func:`stft_power_blocks`) in one ``scipy.fft.rfft`` call each on a
    strided view, 5-10x faster on records of a few thousand samples; the two agree to
    rounding (tests/stochastic/test_spectra.py). The whole PSD is (frames × frequencies):
    what needs only a reduction of each frame (the features) reads the blocks instead.

    Returns
    -------
    time_s : numpy.ndarray
        Frame centres [s] from the record start (0, hop, ..., covering the record).
    omega_rad_s : numpy.ndarray
        Frequencies 0 ... π/dt [rad/s].
    psd : numpy.ndarray
        S, shape (time, omega) [(m/s²)²·s/rad].
    window : numpy.ndarray
        The Hann window used (for its known spectral spread).
    """
    if engine not in ("batched", "shorttimefft"):
        raise InputError(f"engine = {engine!r}, expected 'batched' or 'shorttimefft'")
    grid = stft_grid(data.size, dt_s, window_s=window_s, hop_s=hop_s)
    psd = np.empty((grid.time_s.size, grid.omega_rad_s.size))
    if engine == "shorttimefft":
        from scipy.signal import ShortTimeFFT

        stft = ShortTimeFFT(grid.window, grid.hop, 1.0 / dt_s, fft_mode="onesided", mfft=grid.mfft)
        with fft_backend(fft):
            spec = stft.stft(data, p0=0, p1=grid.time_s.size).T
        psd[:] = (dt_s / float(np.sum(grid.window**2))) * (spec.real**2 + spec.imag**2)
    else:
        for frames, block in stft_power_blocks(data, dt_s, grid, fft=fft):
            psd[frames] = block
    return grid.time_s, grid.omega_rad_s, psd, grid.window


def wavelet_power(
    data: NDArray[np.float64],
    dt_s: float,
    *,
    hop_s: float = DEFAULT_HOP_S,
    omega_rad_s: ArrayLike | None = None,
    morlet_q: float = 6.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
    """Morlet-wavelet evolutionary spectrum (time, omega, S) on frames every ``hop_s``.

    The default bands (96, log-spaced) run from the lowest frequency outside the cone of
    influence anywhere in the record, 2√2·q/T (:func:`cone_of_influence`; at least 0.2 rad/s),
    to 0.8 × Nyquist. Cost: one FFT of the record, the bins of every band's Gaussian folded in
    one compiled loop (:mod:`stepframe.stochastic._wavelet_kernel`), and one inverse FFT of
    about 2·npts/hop points per band, all bands in one call (docs/benchmarks.md, issue 26).
    """
    import scipy.fft as sfft

    from stepframe.stochastic._wavelet_kernel import band_powers, folded_bands

    npts = data.size
    nyquist = math.pi / dt_s
    if omega_rad_s is None:
        low = max(2 * math.sqrt(2.0) * morlet_q / (npts * dt_s), 0.2)
        omega = np.geomspace(low, 0.8 * nyquist, 96)
    else:
        omega = np.asarray(omega_rad_s, dtype=np.float64)
        if omega.ndim != 1 or omega.size == 0 or not np.all(np.isfinite(omega)):
            raise InputError(
                f"omega_rad_s of shape {omega.shape}, expected at least one finite frequency "
                "[rad/s]"
            )
        if np.any(omega <= 0) or np.any(omega >= nyquist):
            raise InputError(
                f"omega_rad_s must be positive frequencies below Nyquist {nyquist:.4g} rad/s"
            )
    if not (math.isfinite(morlet_q) and morlet_q >= 2):
        raise InputError(f"morlet_q = {morlet_q}, expected ≥ 2 (a band-pass wavelet)")
    hop = max(1, round(hop_s / dt_s))
    n_frames = -(-npts // hop)
    # Only the frames, every hop samples, are wanted. With nfft = hop·m the inverse transform at
    # those samples is the m-point inverse FFT of the band's spectrum folded modulo m (exact:
    # e^{2πik·l·hop/nfft} depends on k mod m only), and each band keeps the bins within 10σ_j
    # of its centre (the Gaussian gain beyond is below e⁻⁵⁰). nfft = hop·m with m the fast
    # length ≥ 2·npts/hop (zero padding against wrap-around): both transforms fast. (m rounded
    # up from a fast nfft could be prime: 2,300 samples at hop 10 gave m = 461 and a spectrum
    # 6 times slower.) The extra zeros change the wrap-around of the longest bands, inside the
    # cone of influence, only.
    m = sfft.next_fast_len(-(-2 * npts // hop))
    nfft = m * hop
    spectrum = sfft.rfft(data, nfft)
    step = 2 * math.pi / (nfft * dt_s)  # bin spacing [rad/s]
    sigmas = omega / morlet_q
    folded = folded_bands(spectrum, omega, sigmas, step, m, _GAIN_REACH)
    psd = band_powers(sfft.ifft(folded, axis=-1, overwrite_x=True), n_frames, hop, sigmas)
    frames = np.arange(n_frames) * hop
    return np.asarray(frames * dt_s, dtype=np.float64), omega, psd


def cone_of_influence(
    time_s: NDArray[np.float64], duration_s: float, morlet_q: float
) -> NDArray[np.float64]:
    """Lowest frequency [rad/s] of the Morlet spectrum of :func:`wavelet_power` outside the cone
    of influence at each time [s] of a record ``duration_s`` long.

    The band at ω has the power envelope exp(-(ω t/q)²) in time, which falls by e⁻² at
    √2·q/ω: the edge effects of a band reach that far into the record (the e-folding time of
    Torrence and Compo 1998, "A practical guide to wavelet analysis", BAMS 79, 61-78, for the
    Morlet wavelet). At a time d from the nearer end the bands down to √2·q/d are clear of them
    (infinite at the ends).
    """
    edge = np.clip(np.minimum(time_s, duration_s - time_s), 0.0, None)
    with np.errstate(divide="ignore"):
        return np.asarray(math.sqrt(2.0) * morlet_q / edge)


def hann_kernel(length_s: float, spacing_s: float) -> NDArray[np.float64]:
    """Unit-sum Hann kernel of ``length_s`` sampled every ``spacing_s`` (odd length ≥ 3)."""
    half = max(1, round(length_s / spacing_s / 2))
    x = np.arange(-half, half + 1) / (half + 1)
    k = np.cos(0.5 * math.pi * x) ** 2
    return np.asarray(k / k.sum())


def crossing_positions(data: NDArray[np.float64]) -> NDArray[np.float64]:
    """Zero crossings (both directions) in samples from the first, interpolated linearly
    between the two samples either side."""
    sign = data >= 0
    idx = np.flatnonzero(sign[:-1] != sign[1:])
    a, b = data[idx], data[idx + 1]
    return np.asarray(idx + a / (a - b))


__all__ = [
    "DEFAULT_HOP_S",
    "DEFAULT_WINDOW_S",
    "STFT_BLOCK_BYTES",
    "FftBackend",
    "StftEngine",
    "StftGrid",
    "cone_of_influence",
    "crossing_positions",
    "fft_backend",
    "hann_kernel",
    "record_samples",
    "stft_grid",
    "stft_power",
    "stft_power_blocks",
    "wavelet_power",
    "window_samples",
]
