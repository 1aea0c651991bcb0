"""Moving resonance measured on a simulated response: the record's evolutionary energy at the
frame's instantaneous frequency, weighted by the work the ground does on the frame.

The steps of docs/selection.md, "Moving resonance, measured":

1. the record's spectrum S(ω, t) from a bank of two-sided resonators over the frame's band
   widened by a third of an octave either side (:func:`band_power`,
   :mod:`~stepframe.pipeline.dynamics.resonator_bank`: the ground acceleration the frame felt,
   record then the tail's zeros, nine bands per octave, frames every 0.1 s);
2. the frame's instantaneous frequency ω_f(t) and the ground's work per sample interval from the
   exact simulation's history (:mod:`stepframe.structure.frame_frequency`);
3. at each sample, the **closeness** c(t) = the largest S within a third of an octave of
   ω_f(t) over the largest S anywhere on the grid: 1 when the record's strongest energy in the
   frame's reach lies near the frame's frequency, 0 when it has none there;
4. the **depth** d(t) = (ln(ω_1/ω_f) - h)/(ln(ω_1/ω_low) - h) clipped to [0, 1], h a third of an
   octave: 0 while the frame's frequency is near ω_1 (where a record tuned to ω_1 reaches it), 1
   at the band's bottom or below;
5. the response cut into half-cycles at the zero crossings of x; each half-cycle's net work of
   the ground on the frame W_k, its mean closeness c_k and its mean depth d_k;
6. the **moving-resonance index** R_m = Σ c_k d_k W_k⁺ / Σ d_k W_k⁺, and the **moving-resonance
   share** M = Σ c_k d_k W_k⁺ / Σ W_k⁺ (:class:`MovingResonance`).

Cost: the band spectrum is one pass of the bank over the record at a decimated rate in single
precision (once per record and frame, at any scale; :func:`band_power` gives it without the
DataArray); the index is one compiled call over the history (:mod:`._resonance_kernel`, with
ω_f and the work from :mod:`stepframe.structure._frequency_kernel`; its sums of c, d and the
ridge offset taken a run of samples at a time; docs/benchmarks.md, issue 26). The index reads
frame f of the spectrum at sample f·hop of the history: the spectrum must be the record's own
(:func:`band_power` with ``n_samples`` the history's), which :func:`resonance_index` checks.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError
from stepframe.pipeline.dynamics.resonator_bank import (
    BANK_Q,
    bank_grid_rad_s,
    bank_power,
    cone_floor_rad_s,
)

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure, SubFigure

    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.simulator import SimulationResult

Floats = NDArray[np.float64]

#: Bands per octave of the band spectrum: three bands make :data:`NEAR_LN`, so the window of
#: "near ω_f" is whole bands; a tone halfway between two bands reads 8 % below its value on
#: one (the bank's gain 1/(1 + (Δ/s)²)², Δ/ω = 3.9 %, s/ω = 0.188).
BANDS_PER_OCTAVE = 9
#: Spacing of the band spectrum's frames [s].
HOP_S = 0.1
#: Half-width of "near ω_f" in ln ω: a third of an octave either side. The phase-locked frame of
#: an ideal moving resonance (a chirp that captures the frame and leads it down its backbone)
#: swings with an amplitude whose law frequency lies 12-29 % below the drive's (median 18 %, the
#: wide frame of docs/selection.md), so "near" must hold at least that.
NEAR_LN = math.log(2.0) / 3.0


def band_grid_rad_s(band_rad_s: Sequence[float], per_octave: int = BANDS_PER_OCTAVE) -> Floats:
    """Band centres ``per_octave`` to the octave (default the index's) from the bottom of the
    frame's band widened by :data:`NEAR_LN` (every frequency "near" a frequency of the band) up
    to the first at or above its widened top [rad/s]."""
    return bank_grid_rad_s(band_rad_s, NEAR_LN, per_octave)


@dataclass(frozen=True)
class BandPower:
    """The resonator bank's spectrum of a motion over a frame's band as plain arrays (what the
    index reads; :func:`band_spectrum` is the same numbers as a labelled DataArray, for the
    pictures).

    Attributes
    ----------
    time_s
        Frame times [s] from the record start, every ``hop_s``.
    omega_rad_s
        Band centres [rad/s] (:func:`band_grid_rad_s`).
    psd
        S(ω, t) [(m/s²)²·s/rad], frames × bands.
    """

    time_s: Floats
    omega_rad_s: Floats
    psd: Floats

    @classmethod
    def of(cls, spectrum: BandPower | xr.DataArray) -> BandPower:
        """The arrays of a :class:`BandPower` or of a (time, omega) DataArray."""
        if isinstance(spectrum, BandPower):
            return spectrum
        return cls(
            np.asarray(spectrum["time"].values, dtype=np.float64),
            np.asarray(spectrum["omega"].values, dtype=np.float64),
            np.asarray(spectrum.transpose("time", "omega").values, dtype=np.float64),
        )


def band_power(
    ground_acc_m_s2: ArrayLike,
    dt_s: float,
    band_rad_s: Sequence[float],
    *,
    n_samples: int | None = None,
    q: float = BANK_Q,
    hop_s: float = HOP_S,
) -> BandPower:
    """The record's spectrum over a frame's band from the resonator bank, as arrays (the index's
    input; :func:`band_spectrum` labels the same numbers for the pictures).

    Parameters
    ----------
    ground_acc_m_s2
        Ground acceleration [m/s²] (at any scale: the index uses ratios of S at one time).
    dt_s
        Sampling interval [s].
    band_rad_s
        The frame's band (low, high) [rad/s].
    n_samples
        Samples to cover (the simulation's record plus tail): the motion is followed by zeros,
        which is what the frame feels after the record.
    q, hop_s
        The bank's quality factor (:func:`~.resonator_bank.window_rate`) and the frame
        spacing [s].

    Raises
    ------
    InputError
        A band that is not 0 < low < high, a motion of fewer than two samples, or a widened
        band reaching the Nyquist frequency (:func:`~.resonator_bank.bank_power`).
    """
    grid = band_grid_rad_s(band_rad_s)
    time_s, psd = bank_power(ground_acc_m_s2, dt_s, grid, hop_s=hop_s, q=q, n_samples=n_samples)
    return BandPower(time_s, grid, psd)


def band_spectrum(
    ground_acc_m_s2: ArrayLike,
    dt_s: float,
    band_rad_s: Sequence[float],
    *,
    n_samples: int | None = None,
    q: float = BANK_Q,
    hop_s: float = HOP_S,
) -> xr.DataArray:
    """:func:`band_power` as a (time, omega) DataArray with ``omega_floor``, the lowest band
    clear of the motion's ends at each time (:func:`~.resonator_bank.cone_floor_rad_s`), which
    the pictures grey out below.

    Parameters, errors: as :func:`band_power`.
    """
    import xarray as xr

    arrays = band_power(ground_acc_m_s2, dt_s, band_rad_s, n_samples=n_samples, q=q, hop_s=hop_s)
    covered = max(np.size(ground_acc_m_s2), n_samples or 0)  # the motion and the zeros after it
    floor = cone_floor_rad_s(arrays.time_s, (covered - 1) * dt_s, q)
    floor_attrs = {"units": "rad/s", "long_name": "lowest frequency resolved"}
    return xr.DataArray(
        arrays.psd,
        dims=("time", "omega"),
        coords={
            "time": ("time", arrays.time_s, {"units": "s", "long_name": "time from record start"}),
            "omega": (
                "omega",
                arrays.omega_rad_s,
                {"units": "rad/s", "long_name": "angular frequency"},
            ),
            "omega_floor": ("time", floor, floor_attrs),
        },
        name="psd",
        attrs={
            "method": "two-sided resonator bank",
            "q": q,
            "units": "(m/s2)2 s/rad",
            "long_name": "two-sided evolutionary PSD of acceleration",
        },
    )


@dataclass(frozen=True)
class MovingResonance:
    """The moving-resonance measures of one simulated response (docs/selection.md).

    Attributes
    ----------
    moving_resonance_index
        R_m = Σ c_k d_k W_k⁺ / Σ d_k W_k⁺ [0-1]: of the ground's positive half-cycle work W_k⁺
        on the frame while its frequency had moved down its band (each half-cycle counted by how
        far, d_k), the share delivered while the record's energy lay near ω_f (c_k); NaN when
        the frame's frequency never left the neighbourhood of ω_1 (no moving resonance to judge).
    moving_resonance_share
        M = Σ c_k d_k W_k⁺ / Σ W_k⁺ = R_m · ``work_depth`` [0-1]: the share of all the ground's
        positive half-cycle work that arrived by moving resonance (0 when the frame never moved).
    work_depth
        Σ d_k W_k⁺ / Σ W_k⁺ [0-1]: how far down its band the frame was when the ground pumped
        it, on average (0: all near ω_1; 1: all at the band's bottom or below).
    resonant_work_share
        Σ c_k W_k⁺ / Σ W_k⁺ [0-1]: the closeness over every half-cycle's work, resonance at ω_1
        included; NaN without positive work.
    ridge_log_offset
        RMS of ln(ω_ridge/ω_f) over the half-cycles, weighted by d_k W_k⁺ [-], ω_ridge the band
        of the largest S at the frame nearest each sample (halfway: the later frame), ω_f held
        inside the band (0: the record's ridge follows ω_f; ln 2 = 0.69: a factor 2 away); NaN
        when the frame never moved.
    n_half_cycles, n_stepping_half_cycles
        Half-cycles of the response (up to overturning), and those in which the frame stepped.
    input_energy_m2_s2
        Net work of the ground on the frame over the response [m²/s², per unit mass].
    lowest_omega_f_rad_s
        Lowest ω_f reached before overturning [rad/s] (0: a state with no periodic orbit).
    band_rad_s
        The band the closeness was measured over [rad/s].
    status, message
        "ok", or "failed" with the reason (a simulation that failed, no history).
    """

    moving_resonance_index: float
    moving_resonance_share: float
    work_depth: float
    resonant_work_share: float
    ridge_log_offset: float
    n_half_cycles: int
    n_stepping_half_cycles: int
    input_energy_m2_s2: float
    lowest_omega_f_rad_s: float
    band_rad_s: tuple[float, float]
    status: str = "ok"
    message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary (JSON-ready; NaN stays NaN for core.jsonable to map; no
        ``band_rad_s`` when the frame has none, :func:`unmeasured`)."""
        data = asdict(self)
        data["band_rad_s"] = list(self.band_rad_s)
        if not all(math.isfinite(value) for value in self.band_rad_s):
            del data["band_rad_s"]
        return data


def _failed(band: tuple[float, float], message: str) -> MovingResonance:
    nan = math.nan
    return MovingResonance(nan, nan, nan, nan, nan, 0, 0, nan, nan, band, "failed", message)


def closeness(
    spectrum: BandPower | xr.DataArray, time_s: Floats, omega_f_rad_s: Floats
) -> tuple[Floats, Floats]:
    """c(t) = max S(·, t) within :data:`NEAR_LN` of ω_f(t) / max S(·, t) over the spectrum's
    bands, at the given times, and the record's ridge ω_ridge(t) [rad/s] there (the band of the
    largest S at the nearest frame; halfway, the later one).

    The windowed maximum is taken on the band grid (the bands within NEAR_LN of each band), then
    interpolated linearly in time and in ln ω between frames and bands; ω_f outside the grid is
    read at its nearer edge.
    """
    from stepframe.pipeline.dynamics._resonance_kernel import closeness_many

    arrays = _checked(spectrum)
    near, ridge = closeness_many(
        arrays.psd, arrays.time_s, arrays.omega_rad_s, _reach(arrays.omega_rad_s),
        np.ascontiguousarray(time_s, dtype=np.float64),
        np.ascontiguousarray(omega_f_rad_s, dtype=np.float64),
    )  # fmt: skip
    return np.asarray(near), np.asarray(ridge)


def _checked(spectrum: BandPower | xr.DataArray) -> BandPower:
    """The spectrum's arrays, contiguous and writable; at least two frames and two bands (the
    closeness interpolates between them)."""
    arrays = BandPower.of(spectrum)
    frames, omega = arrays.time_s, arrays.omega_rad_s
    if frames.size < 2 or omega.size < 2:
        raise InputError(
            f"band spectrum of {frames.size} frames × {omega.size} bands, expected ≥ 2 of each"
        )
    # Copies of the two short axes: a DataArray's coordinates are read-only, which the kernels'
    # compiled signatures (writable arrays) would not match.
    return BandPower(
        np.array(frames, dtype=np.float64),
        np.array(omega, dtype=np.float64),
        np.ascontiguousarray(arrays.psd, dtype=np.float64),
    )


def _frame_hop(frame_times_s: Floats, dt_s: float, n_samples: int) -> int:
    """Samples between two frames of a spectrum whose frames lie on a history's samples (a
    :func:`band_power` of the record the history was run with), checked to cover its n samples.

    Raises
    ------
    InputError
        Frames that do not start at the first sample, are not a whole number of samples
        apart, or end before the history.
    """
    spacing_s = float(frame_times_s[1] - frame_times_s[0])
    hop = round(spacing_s / dt_s)
    if frame_times_s[0] != 0.0 or hop < 1 or abs(spacing_s - hop * dt_s) > 1e-9 * spacing_s:
        raise InputError(
            f"band spectrum with frames every {spacing_s:g} s from {frame_times_s[0]:g} s, "
            f"expected frames from 0 s a whole number of the history's dt = {dt_s:g} s apart "
            "(band_power of the same record)"
        )
    if (frame_times_s.size - 1) * hop < n_samples - 1:
        raise InputError(
            f"band spectrum ending at {frame_times_s[-1]:g} s, expected it to cover the "
            f"history's {(n_samples - 1) * dt_s:g} s (band_power with n_samples=the history's)"
        )
    return hop


def _reach(omega_rad_s: Floats) -> int:
    """Bands either side within :data:`NEAR_LN` of a band, on the grid's ln ω spacing."""
    log_step = math.log(omega_rad_s[-1] / omega_rad_s[0]) / (omega_rad_s.size - 1)
    return round(NEAR_LN / log_step)


def resonance_index(
    result: SimulationResult, spectrum: BandPower | xr.DataArray, band_rad_s: Sequence[float]
) -> MovingResonance:
    """The moving-resonance measures of a simulation with history (module docstring).

    Parameters
    ----------
    result
        :func:`stepframe.structure.simulator.simulate` run with ``record_history=True``.
    spectrum
        :func:`band_power` (or :func:`band_spectrum`) of the same ground motion (any scale),
        covering the history.
    band_rad_s
        The band (low, high) [rad/s] the spectrum covers.
    """
    from stepframe.pipeline.dynamics._resonance_kernel import resonance_sums
    from stepframe.structure.frame_frequency import (
        backbone_constants,
        backbone_of,
        motion_samples,
    )

    band = (float(band_rad_s[0]), float(band_rad_s[1]))
    if result.summary.status != "ok":
        return _failed(band, f"simulation {result.summary.status}: {result.summary.message}")
    raw, model = result.raw, result.model
    if not raw.hist_x.size or model is None or result.ground_acc_m_s2 is None:
        return _failed(band, "no history, expected a simulation with record_history=True")
    n = motion_samples(result)
    if n < 2:
        return _failed(band, "fewer than two samples of motion before overturning")
    arrays = _checked(spectrum)
    hop = _frame_hop(arrays.time_s, result.dt_s, n)
    backbone = np.array(backbone_constants(backbone_of(model)))
    # One compiled call: the crossings, ω_f, the work and the sums (docs/benchmarks.md: the
    # calls one by one, each with its arguments checked and its arrays made, cost more than
    # the arithmetic on a short record).
    sums = resonance_sums(
        raw.hist_x[:n], raw.hist_v[:n], raw.hist_p[:n],
        np.asarray(result.ground_acc_m_s2, dtype=np.float64), result.dt_s, float(model.p_1),
        float(model.p_2), bool(result.summary.overturned), backbone, arrays.psd, hop,
        arrays.omega_rad_s, _reach(arrays.omega_rad_s), band[0], band[1], NEAR_LN,
    ).tolist()  # fmt: skip
    near_moved, moved, pumped, near_pumped, offset_moved = sums[:5]
    index = near_moved / moved if moved > 0 else math.nan
    depth_share = moved / pumped if pumped > 0 else math.nan
    return MovingResonance(
        moving_resonance_index=index,
        moving_resonance_share=index * depth_share if moved > 0 else 0.0,
        work_depth=depth_share,
        resonant_work_share=near_pumped / pumped if pumped > 0 else math.nan,
        ridge_log_offset=math.sqrt(offset_moved / moved) if moved > 0 else math.nan,
        n_half_cycles=int(sums[5]),
        n_stepping_half_cycles=int(sums[6]),
        input_energy_m2_s2=float(sums[7]),
        lowest_omega_f_rad_s=float(sums[8]),
        band_rad_s=band,
    )


@dataclass(frozen=True)
class ResonanceRun:
    """A simulated record with its band spectrum and moving-resonance measures (what the picture
    needs: :meth:`figure`)."""

    result: SimulationResult = field(repr=False)
    spectrum: xr.DataArray | None = field(repr=False)
    measures: MovingResonance
    title: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The measures, JSON-ready."""
        return self.measures.to_dict()

    def figure(self) -> Figure:
        """The record's band spectrum with ω_f(t) over it, and the ground's work below
        (:func:`stepframe.stochastic.plots.time_frequency_figure`)."""
        if self.spectrum is None:
            raise ValueError(f"no picture: {self.measures.message}")
        return resonance_figure(self.result, self.spectrum, self.measures, title=self.title)


def resonance_figure(
    result: SimulationResult,
    spectrum: xr.DataArray,
    measures: MovingResonance,
    *,
    title: str = "",
) -> Figure:
    """The picture of moving resonance for one simulation with history: the record's spectrum
    over the band as a heat map (log frequency, band shaded), ω_f(t) drawn over it, and the
    accumulated work of the ground below, with R_m in the title."""
    from matplotlib.figure import Figure

    figure = Figure(figsize=(9.0, 5.6), layout="constrained")
    draw_resonance(figure, result, spectrum, measures, title=title)
    return figure


def draw_resonance(
    target: Figure | SubFigure,
    result: SimulationResult,
    spectrum: xr.DataArray,
    measures: MovingResonance,
    *,
    title: str = "",
) -> None:
    """:func:`resonance_figure` drawn into ``target`` (a figure or a subfigure)."""
    from stepframe.stochastic.plots import draw_time_frequency

    omega_f, energy = result.frame_frequency, result.input_energy
    if omega_f is None or energy is None:
        raise ValueError("the simulation kept no history, expected record_history=True")
    index = measures.moving_resonance_index
    summary = "R_m = " + ("n/a: ω_f stayed near ω_1" if math.isnan(index) else f"{index:.2f}")
    summary += f", M = {measures.moving_resonance_share:.2f}"
    overturn = result.summary.overturn_time_s if result.summary.overturned else None
    draw_time_frequency(
        target,
        spectrum,
        band_rad_s=measures.band_rad_s,
        path=(omega_f["time"].values, omega_f.values),
        path_label="frame's ω_f(t)",
        cumulative=(energy["time"].values, energy.values),
        cumulative_label="ground's work [m²/s²]",
        marker_s=overturn,
        marker_label="overturned",
        title=f"{title}  ({summary})" if title else summary,
    )


def default_band(frame: PortalFrame) -> tuple[float, float]:
    """The frame's band of the selection, [ω(0.8 x*), ω_1] [rad/s]
    (:func:`stepframe.pipeline.selection.band.frame_band`)."""
    from stepframe.pipeline.selection.band import frame_band

    found = frame_band(frame)
    return (found.omega_low_rad_s, found.omega_1_rad_s)


def measure_run(
    result: SimulationResult,
    ground_acc_m_s2: ArrayLike,
    dt_s: float,
    band_rad_s: Sequence[float],
    *,
    title: str = "",
) -> ResonanceRun:
    """The band spectrum of the record a simulation ran under (any scale) and the run's
    moving-resonance measures; a motion too short for the spectrum gives measures "failed" with
    the reason and no spectrum (the simulation stands without them)."""
    try:
        spectrum = band_spectrum(
            ground_acc_m_s2, dt_s, band_rad_s, n_samples=result.raw.hist_x.size
        )
    except InputError as error:
        band = (float(band_rad_s[0]), float(band_rad_s[1]))
        return ResonanceRun(result, None, _failed(band, f"no band spectrum: {error}"), title)
    return ResonanceRun(result, spectrum, resonance_index(result, spectrum, band_rad_s), title)


def unmeasured(result: SimulationResult, message: str) -> ResonanceRun:
    """A simulation whose moving resonance cannot be measured at all (no band: the frame's
    default band needs 0.8 x* above x_c), the reason in its measures; the simulation stands."""
    return ResonanceRun(result, None, _failed((math.nan, math.nan), message))


def moving_resonance(
    frame: PortalFrame,
    ground_acc_m_s2: ArrayLike,
    dt_s: float,
    *,
    scale: float = 1.0,
    tail_s: float | None = None,
    band_rad_s: Sequence[float] | None = None,
    title: str = "",
) -> ResonanceRun:
    """Simulate ``frame`` under ``scale`` × the record and measure its moving resonance.

    Parameters
    ----------
    frame
        The stepping frame.
    ground_acc_m_s2, dt_s
        The record [m/s²] and its sampling interval [s].
    scale
        Factor on the record [-].
    tail_s
        Free vibration after the record [s] (default the simulator's).
    band_rad_s
        The band (low, high) [rad/s]; default :func:`default_band`.
    title
        The figure's title.
    """
    from stepframe.structure.simulator import DEFAULT_TAIL_S, simulate

    band = default_band(frame) if band_rad_s is None else band_rad_s
    tail = DEFAULT_TAIL_S if tail_s is None else float(tail_s)
    result = simulate(frame, ground_acc_m_s2, dt_s, scale=scale, tail_s=tail)
    return measure_run(result, ground_acc_m_s2, dt_s, band, title=title)


__all__ = [
    "BANDS_PER_OCTAVE",
    "HOP_S",
    "BandPower",
    "MovingResonance",
    "ResonanceRun",
    "band_grid_rad_s",
    "band_power",
    "band_spectrum",
    "closeness",
    "default_band",
    "draw_resonance",
    "measure_run",
    "moving_resonance",
    "resonance_figure",
    "resonance_index",
    "unmeasured",
]
