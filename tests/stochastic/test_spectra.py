"""Evolutionary spectra: the mean-square identity, FFT backends, eq. 6.12 and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal.windows import hann

from stepframe.errors import InputError
from stepframe.records.trace import make_trace
from stepframe.stochastic.model import GroundMotionModel
from stepframe.stochastic.spectra import evolutionary_spectrum, mean_square
from stepframe.stochastic.synthetic import synthetic_motions
from stepframe.stochastic.transforms import stft_power

SITE = GroundMotionModel.from_hz(7.43, 3.12, 1.11, 0.096, 0.655, t_max_s=5.0, t_dur_s=20.0)
#: Nearly constant parameters: a stationary eq. 6.12 process (ω_g = 20 rad/s, α_g = 4 rad/s).
FLAT = GroundMotionModel(20.0001, 20.0, 19.9999, 0.2, 0.2, t_max_s=1.0, t_dur_s=2.0)


@pytest.fixture(scope="module")
def motion() -> tuple[np.ndarray, np.ndarray]:
    t, acc = synthetic_motions(SITE, duration_s=30.0, dt_s=0.01, seed=11, peak_intensity=2.0)
    return t, acc[0]


def _weighted_mean_square(x: np.ndarray, centre: int, m: int) -> float:
    """Σ w² x² / Σ w² with the Hann window centred on sample ``centre`` (zeros outside)."""
    w = hann(m, sym=False)
    start = centre - m // 2
    total = 0.0
    for i in range(m):
        n = start + i
        if 0 <= n < x.size:
            total += w[i] ** 2 * x[n] ** 2
    return total / float(np.sum(w**2))


@pytest.mark.parametrize("fft", ["pyfftw", "scipy"])
def test_stft_mean_square_identity_at_each_time(
    motion: tuple[np.ndarray, np.ndarray], fft: str
) -> None:
    _, x = motion
    spec = evolutionary_spectrum(x, 0.01, window_s=2.0, hop_s=0.5, fft=fft)  # type: ignore[arg-type]
    ms = mean_square(spec)
    for j in (0, 3, 10, 20, 40, spec.sizes["time"] - 1):
        centre = round(float(spec["time"][j]) / 0.01)
        assert ms[j] == pytest.approx(_weighted_mean_square(x, centre, 200), rel=1e-10)


def test_pyfftw_matches_scipy_fft(motion: tuple[np.ndarray, np.ndarray]) -> None:
    _, x = motion
    a = evolutionary_spectrum(x, 0.01, fft="pyfftw").values
    b = evolutionary_spectrum(x, 0.01, fft="scipy").values
    np.testing.assert_allclose(a, b, rtol=1e-8, atol=1e-12 * float(b.max()))


@pytest.mark.parametrize("dt", [0.005, 0.01, 0.02])
def test_batched_engine_equals_shorttimefft(
    motion: tuple[np.ndarray, np.ndarray], dt: float
) -> None:
    _, x = motion
    batched = stft_power(x, dt, engine="batched", fft="scipy")
    reference = stft_power(x, dt, engine="shorttimefft", fft="scipy")
    for a, b in zip(batched, reference, strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-14 * float(np.max(np.abs(b))))


def test_dims_coords_units(motion: tuple[np.ndarray, np.ndarray]) -> None:
    t, x = motion
    spec = evolutionary_spectrum(make_trace(x, 0.01))
    assert spec.dims == ("time", "omega")
    assert spec["omega"].attrs["units"] == "rad/s" and spec["time"].attrs["units"] == "s"
    assert float(spec["omega"][0]) == 0.0
    assert float(spec["omega"][-1]) == pytest.approx(math.pi / 0.01)
    assert float(spec["time"][-1]) <= t[-1] + 1e-9
    assert spec.attrs["units"] == "(m/s2)2 s/rad"


def test_stationary_stft_and_wavelet_match_eq_6_12() -> None:
    """Time-averaged estimates of a stationary eq. 6.12 process against the model spectrum."""
    npts = 24001
    _, acc = synthetic_motions(
        FLAT, duration_s=240.0, dt_s=0.01, seed=5, envelope=np.ones(npts), n_realisations=1
    )
    for method in ("stft", "wavelet"):
        spec = evolutionary_spectrum(acc[0], 0.01, method=method, window_s=4.0)  # type: ignore[arg-type]
        omega = spec["omega"].values
        mean = spec.values[5:-5].mean(axis=0)
        band = (omega > 10) & (omega < 30)
        truth = FLAT.psd(omega[band], 0.0)
        ratio = float(np.median(mean[band] / truth))
        assert ratio == pytest.approx(1.0, abs=0.15), method
        # The identity: mean square of the estimate against the record's, time-averaged.
        assert float(np.mean(mean_square(spec)[5:-5])) == pytest.approx(
            float(np.mean(acc[0] ** 2)), rel=0.08
        ), method


def test_wavelet_energy_identity_on_a_nonstationary_record(
    motion: tuple[np.ndarray, np.ndarray],
) -> None:
    """∫(1/π)∫_0^∞ S dω dt of the Morlet estimate equals ∫x² dt (measured 1.0006); frame by
    frame it follows the 2-s STFT mean square only roughly (median 0.96), since each band has
    its own time support 6/ω (docs/stochastic-features.md)."""
    _, x = motion
    wavelet = mean_square(evolutionary_spectrum(x, 0.01, method="wavelet"))  # frames 0.1 s apart
    assert float(np.sum(wavelet)) * 0.1 == pytest.approx(float(np.sum(x**2)) * 0.01, rel=0.02)
    stft = mean_square(evolutionary_spectrum(x, 0.01))
    strong = stft > 0.1 * stft.max()
    assert float(np.median(wavelet[strong] / stft[strong])) == pytest.approx(1.0, abs=0.08)


def test_wavelet_pure_tone_peak() -> None:
    t = np.arange(0, 30, 0.01)
    x = np.sin(2 * math.pi * 2.5 * t)
    spec = evolutionary_spectrum(x, 0.01, method="wavelet")
    omega = spec["omega"].values
    ridge = omega[np.argmax(spec.values[100:-100], axis=1)]
    assert float(np.median(ridge)) == pytest.approx(2 * math.pi * 2.5, rel=0.04)


def test_parametric_integrates_to_record_intensity(motion: tuple[np.ndarray, np.ndarray]) -> None:
    _, x = motion
    stft = evolutionary_spectrum(x, 0.01)
    para = evolutionary_spectrum(x, 0.01, method="parametric")
    assert para.attrs["method"] == "parametric"
    strong = mean_square(stft) > 0.1 * mean_square(stft).max()
    # eq. 6.12 integrates to I_g² (up to the tail beyond Nyquist, ~1 %): same as the STFT's.
    np.testing.assert_allclose(mean_square(para)[strong], mean_square(stft)[strong], rtol=0.03)


@pytest.mark.parametrize(
    ("data", "dt", "match"),
    [
        (np.ones(3000), 0.01, "all samples equal"),
        (np.zeros(3000), 0.01, "all samples equal"),
        (np.r_[np.sin(np.arange(3000.0)), np.nan], 0.01, "NaN"),
        (np.sin(np.arange(100.0)), 0.01, "shorter than"),
        (np.sin(np.arange(100.0)), None, "dt_s missing"),
        (np.sin(np.arange(4.0)), 0.01, "expected ≥ 8"),
    ],
)
def test_bad_records(data: np.ndarray, dt: float | None, match: str) -> None:
    with pytest.raises(InputError, match=match):
        evolutionary_spectrum(data, dt)


def test_bad_options(motion: tuple[np.ndarray, np.ndarray]) -> None:
    _, x = motion
    with pytest.raises(InputError, match="method"):
        evolutionary_spectrum(x, 0.01, method="fourier")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="16 samples"):
        evolutionary_spectrum(x, 0.01, window_s=0.1)
    with pytest.raises(InputError, match="fft"):
        evolutionary_spectrum(x, 0.01, fft="numpy")  # type: ignore[arg-type]
    with pytest.raises(InputError, match="≥ 0"):
        evolutionary_spectrum(x, 0.01, method="parametric", omega_rad_s=[-1.0, 2.0])
    with pytest.raises(InputError, match="below Nyquist"):
        evolutionary_spectrum(x, 0.01, method="wavelet", omega_rad_s=[1.0, 400.0])


def test_wavelet_cone_of_influence_against_the_gaussian_edge_loss() -> None:
    """A tone at the band's centre: the band's amplitude at a distance d from the record start
    is Φ(σd) of its value inside (σ = ω/q; the wavelet's Gaussian time envelope cut by the
    edge), so its power is Φ(√2)² = 0.849 at the cone of influence d = √2 q/ω, where the
    ``omega_floor`` coordinate says the band becomes clear, and Φ(0)² = 1/4 at the start."""
    from scipy.stats import norm

    omega, q, dt = 1.0, 6.0, 0.01
    t = np.arange(0, 120, dt)
    spec = evolutionary_spectrum(np.cos(omega * t), dt, method="wavelet", omega_rad_s=[omega])
    power = spec.values[:, 0]
    time = spec["time"].values
    inside = float(np.median(power[(time > 40) & (time < 80)]))
    d_coi = math.sqrt(2) * q / omega
    at_coi = power[np.argmin(np.abs(time - d_coi))] / inside
    assert at_coi == pytest.approx(norm.cdf(math.sqrt(2)) ** 2, rel=0.01)
    assert power[0] / inside == pytest.approx(0.25, rel=0.02)
    # The coordinate: √2 q/d from the nearer end, crossing the band's ω at d = √2 q/ω.
    floor = spec["omega_floor"].values
    assert floor[np.argmin(np.abs(time - d_coi))] == pytest.approx(omega, rel=0.01)
    assert floor[np.argmin(np.abs(time - 60.0))] == pytest.approx(math.sqrt(2) * q / 60, rel=0.01)
    # The default bands start at the lowest frequency clear anywhere, 2√2 q/T (at least
    # 0.2 rad/s): 0.283 rad/s on 60 s, where 6 cycles in the record (the old floor) gave 0.63.
    default = evolutionary_spectrum(np.cos(omega * t[:6000]), dt, method="wavelet")
    assert float(default["omega"][0]) == pytest.approx(2 * math.sqrt(2) * q / 60.0, rel=1e-3)


def test_stft_floor_is_one_cycle_per_window(motion: tuple[np.ndarray, np.ndarray]) -> None:
    _, x = motion
    spec = evolutionary_spectrum(x, 0.01, window_s=4.0)
    np.testing.assert_allclose(spec["omega_floor"].values, 2 * math.pi / 4.0)
    assert spec["omega_floor"].attrs["units"] == "rad/s"


def test_an_empty_wavelet_grid_is_one_line() -> None:
    """omega_rad_s=[] was a numpy reduction error from deep in the transform."""
    from stepframe.stochastic.spectra import evolutionary_spectrum

    acc = np.sin(np.linspace(0.0, 60.0, 6001))
    with pytest.raises(InputError, match=r"omega_rad_s of shape \(0,\), expected at least one"):
        evolutionary_spectrum(acc, 0.01, "wavelet", omega_rad_s=[])
