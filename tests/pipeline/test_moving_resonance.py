"""The moving-resonance index on motions whose frequency path is known: a chirp that leads the
frame down its backbone, one that runs the other way, a sine at ω_1; the closeness against the
resonator bank's gain for a tone; the picture."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure

from stepframe.errors import InputError
from stepframe.pipeline.dynamics.resonance import (
    NEAR_LN,
    BandPower,
    band_power,
    band_spectrum,
    closeness,
    moving_resonance,
    resonance_index,
)
from stepframe.pipeline.dynamics.resonator_bank import window_rate
from stepframe.pipeline.selection.band import frame_band
from stepframe.structure.frame import PortalFrame
from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping
from stepframe.structure.period_amplitude import period_amplitude
from stepframe.structure.simulator import simulate

DT = 0.02
DURATION = 200.0
AMPLITUDE_M_S2 = 1.5


def wide_frame() -> PortalFrame:
    """The frame template's physical inputs with l = L_F/2: x* = 34 x_c, room to step."""
    tables = tomllib.loads(FRAME_TEMPLATE)
    del tables["constants"]
    return frame_from_mapping(tables)


def path_motion(omega_rad_s: np.ndarray) -> np.ndarray:
    """A sine of AMPLITUDE_M_S2 whose frequency follows ``omega_rad_s``, with 3-s ramps."""
    t = np.arange(omega_rad_s.size) * DT
    ramp = np.clip(t / 3, 0, 1) * np.clip((t[-1] - t) / 3, 0, 1)
    return AMPLITUDE_M_S2 * ramp * np.sin(np.cumsum(omega_rad_s) * DT)


@pytest.fixture(scope="module")
def indices() -> dict[str, float]:
    frame = wide_frame()
    band = frame_band(frame)
    low, high = band.omega_low_rad_s, band.omega_1_rad_s
    t = np.arange(0, DURATION, DT)
    # Down the backbone: ω(A(t)) with A rising from x_c to x*/2 after 10 s at ω_1.
    amplitude = frame.x_c_m + (0.5 * frame.x_star_m - frame.x_c_m) * np.clip(
        (t - 10) / (DURATION - 15), 0, 1
    )
    follow = 2 * math.pi / period_amplitude(frame, amplitude)
    # Up through the band: from its bottom to 2 ω_1 at a constant rate in ln ω.
    opposite = np.exp(np.log(low) + np.log(2 * high / low) * t / DURATION)
    stationary = np.full(t.size, frame.omega_1_rad_s)
    out = {}
    for name, path in (("follow", follow), ("opposite", opposite), ("stationary", stationary)):
        run = moving_resonance(frame, path_motion(path), DT)
        assert run.measures.status == "ok"
        out[name] = run.measures.moving_resonance_index
        out[name + " share"] = run.measures.moving_resonance_share
        out[name + " depth"] = run.measures.work_depth
    return out


def test_a_chirp_down_the_backbone_scores_near_the_maximum(indices: dict[str, float]) -> None:
    # The frame is captured and led down its band: the record's energy is where the frame is.
    assert indices["follow"] >= 0.95
    assert indices["follow depth"] >= 0.4


def test_a_chirp_the_other_way_scores_near_the_minimum(indices: dict[str, float]) -> None:
    assert indices["opposite"] <= 0.3
    assert indices["opposite share"] <= 0.01


def test_a_sine_at_omega_1_scores_in_between(indices: dict[str, float]) -> None:
    # Entrained near ω_1, the frame rarely moves down its band (depth ≈ 0.001), and when it does
    # the sine's energy is partly within reach; the share of all the work that arrived by moving
    # resonance is nil, as for the chirp the other way.
    assert indices["opposite"] + 0.2 <= indices["stationary"] <= 0.85
    assert indices["stationary depth"] <= 0.01
    assert indices["stationary share"] <= 0.01


def test_closeness_of_a_tone_follows_the_banks_gain() -> None:
    # A tone A sin(ω₀t) reaches band j through the window's gain 2s/(s² + (ω₀ - ω_j)²) (and
    # its mirror at -ω₀ through 2s/(s² + (ω₀ + ω_j)²)), so away from the motion's ends S_j has
    # the mean s_j A²(g₊² + g₋²)/(8π) and swings by 2g₋/g₊ about it at 2ω₀ (averaged out over
    # 400 frames; 1 % for the linear interpolation between samples and the decimation, and
    # 1e-5 of the peak for the tone's abrupt ends, 40 s away). The closeness reads the largest
    # of these within a third of an octave of each band, interpolated in ln ω at ω_f: to 3 %.
    omega_0, band = 3.0, (0.5, 6.0)
    t = np.arange(0, 120, 0.01)
    spectrum = band_spectrum(np.sin(omega_0 * t), 0.01, band)
    frames, grid = spectrum["time"].values, spectrum["omega"].values
    mid = (frames > 40) & (frames < 80)
    s = window_rate() * grid
    gain = 2 * s / (s**2 + (omega_0 - grid) ** 2), 2 * s / (s**2 + (omega_0 + grid) ** 2)
    mean_s = s * (gain[0] ** 2 + gain[1] ** 2) / (8 * math.pi)
    measured = spectrum.sel(time=frames[mid]).values.mean(axis=0)
    assert np.allclose(measured, mean_s, rtol=0.01, atol=1e-5 * mean_s.max())
    for omega_f in (omega_0, omega_0 * math.exp(0.9 * NEAR_LN)):  # the tone within reach
        near, ridge = closeness(spectrum, frames[mid], np.full(mid.sum(), omega_f))
        assert np.allclose(near, 1.0, rtol=0, atol=1e-12)
        assert np.all(np.abs(np.log(ridge / omega_0)) <= math.log(2) / 18 + 1e-12)
    reach = round(NEAR_LN / math.log(grid[1] / grid[0]))
    windowed = [mean_s[max(0, j - reach) : j + reach + 1].max() for j in range(grid.size)]
    far = omega_0 * math.exp(2 * NEAR_LN)
    expected = np.interp(math.log(far), np.log(grid), np.array(windowed) / mean_s.max())
    near, _ = closeness(spectrum, frames[mid], np.full(mid.sum(), far))
    assert near.mean() == pytest.approx(expected, rel=0.03)
    assert 0.05 < expected < 0.5  # the tone is out of reach, its neighbour within


def closeness_from_the_definition(
    psd: np.ndarray, frames: np.ndarray, omega: np.ndarray, t: float, omega_f: float
) -> float:
    """c at one time, straight from docs/selection.md step 3, independently of the kernel: the
    largest S of the bands within NEAR_LN (in ln ω, on the grid) of each band, over the frame's
    largest, read bilinearly in (t, ln ω) with ω_f held at the grid's edges."""
    log_w = np.log(omega)
    reach = round(NEAR_LN / (log_w[1] - log_w[0]))
    windowed = np.array(
        [[row[max(0, j - reach) : j + reach + 1].max() / row.max() for j in range(omega.size)]
         for row in psd]
    )  # fmt: skip
    at_time = np.array([np.interp(t, frames, windowed[:, j]) for j in range(omega.size)])
    return float(np.interp(np.log(np.clip(omega_f, omega[0], omega[-1])), log_w, at_time))


def test_closeness_kernel_reproduces_the_definition_on_a_random_spectrum() -> None:
    rng = np.random.default_rng(7)
    acc = rng.standard_normal(1500) * np.hanning(1500)
    spectrum = band_power(acc, 0.01, (0.6, 6.0))
    times = rng.uniform(0.0, spectrum.time_s[-1], 200)
    omega_f = np.exp(rng.uniform(math.log(0.2), math.log(12.0), 200))  # some beyond the grid
    near, _ = closeness(spectrum, times, omega_f)
    expected = [
        closeness_from_the_definition(spectrum.psd, spectrum.time_s, spectrum.omega_rad_s, t, w)
        for t, w in zip(times, omega_f, strict=True)
    ]
    assert np.allclose(near, expected, rtol=1e-12, atol=1e-14)


def index_from_the_definition(
    result: object, spectrum: object, band: tuple[float, float]
) -> dict[str, float]:
    """The measures straight from docs/selection.md steps 3-6 with numpy, independently of the
    index's kernel: ω_f, the interval work and the zero crossings from the simulation's history
    (tested on their own in tests/structure/test_frame_frequency.py), c from
    :func:`closeness_from_the_definition`, the half-cycles' sums with ``np.add.reduceat``."""
    from stepframe.structure.frame_frequency import (
        felt_ground_acc,
        interval_work,
        motion_frequency,
        zero_crossings,
    )

    omega_f = motion_frequency(result)[0]  # type: ignore[arg-type]
    n = omega_f.size
    raw, model, dt = result.raw, result.model, result.dt_s  # type: ignore[attr-defined]
    x, v, phase = raw.hist_x[:n], raw.hist_v[:n], raw.hist_p[:n]
    work = interval_work(x, v, phase, felt_ground_acc(result)[:n], dt, model.p_1, model.p_2)  # type: ignore[arg-type]
    psd, frames, omega = spectrum.psd, spectrum.time_s, spectrum.omega_rad_s  # type: ignore[attr-defined]
    # c at each sample: the definition's table once, read at the samples the same way.
    log_w = np.log(omega)
    reach = round(NEAR_LN / (log_w[1] - log_w[0]))
    windowed = np.array(
        [[row[max(0, j - reach) : j + reach + 1].max() / row.max() for j in range(omega.size)]
         for row in psd]
    )  # fmt: skip
    times = np.arange(n) * dt
    at_band = np.log(np.clip(omega_f, omega[0], omega[-1]))
    columns = np.array([np.interp(times, frames, windowed[:, j]) for j in range(omega.size)])
    near = np.array([np.interp(at_band[i], log_w, columns[:, i]) for i in range(n)])
    hop = round((frames[1] - frames[0]) / dt)  # frames on the samples, every hop of them
    nearest = (2 * np.arange(n) + hop) // (2 * hop)  # halfway: the later frame
    ridge = omega[np.argmax(psd, axis=1)][nearest]
    low, high = band
    depth = np.clip(
        (np.log(high / np.maximum(omega_f, 1e-300)) - NEAR_LN) / (math.log(high / low) - NEAR_LN),
        0.0, 1.0,
    )  # fmt: skip
    offset_sq = np.log(ridge / np.clip(omega_f, low, high)) ** 2
    starts = np.concatenate(([0], zero_crossings(x, v, dt)[0] + 1))
    starts = starts[starts < n - 1]
    counts = np.diff(np.append(starts, n - 1))

    def mean(values: np.ndarray) -> np.ndarray:
        return np.add.reduceat(0.5 * (values[:-1] + values[1:]), starts) / counts

    pumped = np.maximum(np.add.reduceat(work, starts), 0.0)
    moved = mean(depth) * pumped
    return {
        "moving_resonance_index": float(moved @ mean(near) / moved.sum()),
        "work_depth": float(moved.sum() / pumped.sum()),
        "resonant_work_share": float(pumped @ mean(near) / pumped.sum()),
        "ridge_log_offset": math.sqrt(float(moved @ mean(offset_sq) / moved.sum())),
        "n_half_cycles": starts.size,
        "n_stepping_half_cycles": int(
            (np.add.reduceat((phase[:-1] != 0) | (phase[1:] != 0), starts) > 0).sum()
        ),
        "input_energy_m2_s2": float(work.sum()),
        "lowest_omega_f_rad_s": float(omega_f.min()),
    }


@pytest.mark.parametrize(
    ("scale", "overturns", "dt"), [(16.0, False, 0.01), (32.0, True, 0.01), (16.0, False, 0.02)]
)
def test_the_index_kernel_reproduces_the_definition(
    scale: float, overturns: bool, dt: float
) -> None:
    # A record-like motion (filtered noise under an envelope) that makes the wide frame step
    # for many half-cycles, and at a larger scale overturn it; at 0.02 s the frames are five
    # samples apart (an odd number: no sample halfway between two frames).
    rng = np.random.default_rng(11)
    t = np.arange(0, 30, 0.01)
    noise = np.convolve(rng.standard_normal(t.size), np.hanning(25), mode="same")
    acc = noise * np.exp(-(((t - 10) / 6) ** 2))
    acc = acc[:: round(dt / 0.01)] / np.abs(acc).max()
    frame = wide_frame()
    band = (frame_band(frame).omega_low_rad_s, frame.omega_1_rad_s)
    result = simulate(frame, acc, dt, scale=scale, tail_s=10.0)
    assert result.summary.overturned is overturns
    spectrum = band_power(acc, dt, band, n_samples=result.raw.hist_x.size)
    measures = resonance_index(result, spectrum, band)
    expected = index_from_the_definition(result, spectrum, band)
    assert measures.n_stepping_half_cycles >= 6
    assert measures.work_depth > 0.0
    for key, value in expected.items():
        assert getattr(measures, key) == pytest.approx(value, rel=1e-11, abs=1e-14), key
    assert measures.moving_resonance_share == pytest.approx(
        expected["moving_resonance_index"] * expected["work_depth"], rel=1e-11
    )


def test_a_spectrum_off_the_history_s_samples_or_too_short_is_an_input_error() -> None:
    # The index reads frame f of the spectrum at sample f·hop of the history: a spectrum of
    # another sampling, or one that ends before the history, cannot be read; it is refused.
    t = np.arange(0, 20, 0.01)
    acc = np.sin(2.0 * t) * np.exp(-(((t - 8) / 4) ** 2))
    frame = wide_frame()
    band = (frame_band(frame).omega_low_rad_s, frame.omega_1_rad_s)
    result = simulate(frame, acc, 0.01, scale=2.0, tail_s=5.0)
    assert not result.summary.overturned  # the motion runs to the tail's end
    n = result.raw.hist_x.size
    good = band_power(acc, 0.01, band, n_samples=n)
    assert resonance_index(result, good, band).status == "ok"
    cases = {
        "whole number": BandPower(good.time_s * 1.037, good.omega_rad_s, good.psd),
        "from 0 s": BandPower(good.time_s + 0.05, good.omega_rad_s, good.psd),
        "cover": band_power(acc, 0.01, band),  # the record without the tail
    }
    for expected, spectrum in cases.items():
        with pytest.raises(InputError, match=expected):
            resonance_index(result, spectrum, band)


def test_band_power_is_the_band_spectrum_without_labels() -> None:
    acc = np.random.default_rng(3).standard_normal(2300)
    arrays = band_power(acc, 0.01, (0.65, 6.46), n_samples=2400)
    labelled = band_spectrum(acc, 0.01, (0.65, 6.46), n_samples=2400)
    assert np.array_equal(arrays.psd, labelled.transpose("time", "omega").values)
    assert np.array_equal(arrays.omega_rad_s, labelled["omega"].values)
    assert np.array_equal(arrays.time_s, labelled["time"].values)


def test_without_history_or_with_a_failed_run_the_index_says_why() -> None:
    frame = wide_frame()
    acc = np.sin(np.arange(0, 20, 0.01))
    result = simulate(frame, acc, 0.01, record_history=False)
    spectrum = band_spectrum(acc, 0.01, (1.0, 6.0), n_samples=2000 + 1000)
    measures = resonance_index(result, spectrum, (1.0, 6.0))
    assert measures.status == "failed"
    assert "record_history" in measures.message
    assert math.isnan(measures.moving_resonance_index)


def test_the_picture_draws_the_spectrum_the_path_and_the_work() -> None:
    frame = wide_frame()
    t = np.arange(0, 60, DT)
    run = moving_resonance(frame, 3.0 * np.sin(frame.omega_1_rad_s * t), DT, title="sine")
    figure = run.figure()
    assert isinstance(figure, Figure)
    top, below = figure.axes[0], figure.axes[1]  # the colour bar is axes[2]
    assert top.get_yscale() == "log"
    omega_f = run.result.frame_frequency
    work = run.result.input_energy
    assert omega_f is not None and work is not None
    drawn = next(line for line in top.get_lines() if line.get_label() == "frame's ω_f(t)")
    assert np.allclose(drawn.get_ydata(), omega_f.values / (2 * math.pi), equal_nan=True)
    assert np.allclose(below.get_lines()[0].get_ydata(), work.values)
    assert "R_m" in top.get_title()


def test_simulate_plot_lines_up_the_response_and_the_spectrum(data_dir: Path) -> None:
    # `structure simulate --plot`: x(t) above, the record's band spectrum with ω_f(t) below, on
    # one time axis (the record plus the tail).
    from stepframe.pipeline.dynamics.response import simulate_component
    from stepframe.records import read

    stream = read(data_dir / "peer_nga_west2/RSN8883_14383980_13849360.AT2")
    simulated = simulate_component(wide_frame(), stream, name="rec.AT2", scale=6.0, tail_s=5.0)
    figure = simulated.figure()
    run = simulated.response.resonance
    end_s = float(run.spectrum["time"].values[-1])
    (spectrum_axes,) = [ax for ax in figure.axes if ax.get_yscale() == "log"]
    (x_axes,) = [ax for ax in figure.axes if ax.get_ylabel() == "x [m]"]
    assert x_axes.get_xlim() == pytest.approx((0.0, end_s))
    assert end_s == pytest.approx((run.result.raw.hist_x.size - 1) * run.result.dt_s, abs=0.1)
    assert "R_m" in spectrum_axes.get_title()


def test_site_band_spectrum_is_eq_6_12_under_the_envelope_and_draws_the_frame_path() -> None:
    # At ω = ω_g(t) eq. 6.12 is 4αω²I²/(4ω²α²) = I_g(t)²/α_g(t): place t where ω_g(t) is a node
    # of the band grid (eq. 6.10 inverted) and compare with the closed form.
    from stepframe.pipeline.amplification.time_frequency import (
        SITE_BANDS_PER_OCTAVE,
        model_band_spectrum,
        site_band_figure,
    )
    from stepframe.pipeline.dynamics.resonance import band_grid_rad_s
    from stepframe.stochastic.amplification import response_amplification
    from stepframe.stochastic.envelope import default_envelope
    from stepframe.stochastic.mean_square import FrameDriven, analysis_grid
    from stepframe.stochastic.model import GroundMotionModel

    model = GroundMotionModel(30.0, 8.0, 1.0, 0.3, 0.4, 6.0, 25.0)
    frame = wide_frame()
    band = (frame_band(frame).omega_low_rad_s, frame.omega_1_rad_s)
    node = band_grid_rad_s(band, per_octave=SITE_BANDS_PER_OCTAVE)[20]
    p, s, r = 30.0, 8.0, 1.0
    t_node = 6.0 * math.log((node - r) / (p - r)) / math.log((s - r) / (p - r))
    spectrum = model_band_spectrum(model, band, np.array([t_node - 1.0, t_node]))
    intensity = default_envelope(np.array([t_node]), 6.0, 25.0, 1.0)[0]
    expected = intensity**2 / float(model.alpha_g(t_node))
    assert float(spectrum.isel(time=1, omega=20)) == pytest.approx(expected, rel=1e-12)
    assert float(model.omega_g(t_node)) == pytest.approx(node, rel=1e-12)

    driven = response_amplification(
        model, None, frame.xi_1,
        frame=FrameDriven(lambda a: float(period_amplitude(frame, a, beyond_x_star="inf"))),
        peak_intensity=2.0 * frame.p_1, time_s=analysis_grid(model, n_steps=400),
    )  # fmt: skip
    figure = site_band_figure(model, band, driven.moving, title="site")
    top, below = figure.axes[0], figure.axes[1]
    drawn = next(ln for ln in top.get_lines() if str(ln.get_label()).startswith("frame's ω"))
    omega = np.asarray(driven.moving.omega_rad_s).reshape(-1)
    assert np.allclose(drawn.get_ydata(), omega / (2 * math.pi), equal_nan=True)
    sigma = np.sqrt(np.asarray(driven.moving.mean_square_m2).reshape(-1))
    assert np.allclose(below.get_lines()[0].get_ydata(), sigma, equal_nan=True)
