"""The Morlet transform evaluated only at its frames (folded inverse FFT) against a direct
time-domain convolution with the Morlet kernel."""

from __future__ import annotations

import math

import numpy as np

from stepframe.stochastic.transforms import wavelet_power


def test_frames_match_a_direct_convolution_with_the_morlet_kernel() -> None:
    # The gain exp(-½((ω - ω_j)/σ)²) on positive frequencies, doubled (analytic signal), is the
    # kernel 2·(σ/√(2π))·exp(-½σ²τ²)·e^{iω_jτ} in time (up to its negligible negative-frequency
    # tail at q = 6): convolve the samples with it directly, away from the record's ends.
    rng = np.random.default_rng(3)
    dt, q = 0.01, 6.0
    t = np.arange(6000) * dt
    data = np.sin(2.1 * t + 0.3) * np.exp(-(((t - 30) / 12) ** 2)) + 0.3 * rng.standard_normal(
        t.size
    )
    omega = np.array([1.0, 2.1, 4.0, 9.0])
    time_s, _, psd = wavelet_power(data, dt, hop_s=0.1, omega_rad_s=omega, morlet_q=q)
    for j, wj in enumerate(omega):
        sigma = wj / q
        for m in (200, 300, 400):  # frames at 20, 30, 40 s: 20 s clear of both ends
            tau = time_s[m] - t
            kernel = 2 * sigma / math.sqrt(2 * math.pi) * np.exp(-0.5 * (sigma * tau) ** 2)
            u = np.sum(data * kernel * np.exp(1j * wj * tau)) * dt
            direct = math.sqrt(math.pi) * abs(u) ** 2 / (2 * sigma)
            assert abs(psd[m, j] - direct) <= 1e-6 * psd[:, j].max()
    assert time_s.size == math.ceil(t.size / 10)
    assert np.allclose(np.diff(time_s), 0.1)
