"""The stepping response of a frame to one record, summarised.

:func:`simulate_record` checks the record, runs the exact simulator
(:func:`stepframe.structure.simulator.simulate`) and gathers what ``stepframe structure simulate``
reports: the record, the frame with its derived quantities, the summary and the stepping
episodes, as a :class:`RecordResponse` (``to_dict``, ``describe``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from os import PathLike
from typing import TYPE_CHECKING, Any

from stepframe.core.options import Range, check_fields, option
from stepframe.errors import InputError

if TYPE_CHECKING:
    from matplotlib.figure import Figure
    from obspy import Stream, Trace

    from stepframe.pipeline.dynamics.resonance import ResonanceRun
    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.simulator import SimulationResult


#: Peak memory of :func:`simulate_record` per sample of the record and its tail [bytes]: the
#: simulator's history (x, ẋ, phase), its xarray form, ω_f(t), the ground's work and the band
#: spectrum (measured 81.6 bytes on 400,000 and 800,000 samples once the index summed runs of
#: samples instead of keeping c and the ridge at each, 105.1 before, 157 with the Morlet
#: spectrum; tracemalloc, docs/benchmarks.md "The index on the resonator bank").
SIMULATE_BYTES_PER_SAMPLE = 100.0
#: What ``--plot`` adds per sample (the figure's lines and the spectrum's image; measured 411)
#: and once (matplotlib's figure; measured 5-25 MiB) [bytes].
FIGURE_BYTES_PER_SAMPLE = 440.0
FIGURE_FIXED_BYTES = 32.0 * 1024**2


def simulate_memory_bytes(n_samples: int, dt_s: float, tail_s: float, figure: bool) -> float:
    """The estimated peak memory of one simulation summarised (and drawn, with ``figure``)
    [bytes]: the record's samples and the tail's, times :data:`SIMULATE_BYTES_PER_SAMPLE`
    (and the figure's share)."""
    import math

    samples = n_samples + math.ceil(tail_s / dt_s)
    per_sample = SIMULATE_BYTES_PER_SAMPLE + (FIGURE_BYTES_PER_SAMPLE if figure else 0.0)
    return samples * per_sample + (FIGURE_FIXED_BYTES if figure else 0.0)


@dataclass(frozen=True)
class RecordResponse:
    """A frame's response to one record.

    Attributes
    ----------
    summary
        JSON-ready: ``record``, ``component``, ``npts``, ``dt_s``, ``scale``, ``pga_m_s2``
        (scaled), ``tail_s``, ``frame`` (its parameters, x* [m] and uplift acceleration
        [m/s²]), the simulation summary, ``episodes`` and ``moving_resonance``
        (:class:`~stepframe.pipeline.dynamics.resonance.MovingResonance`).
    result
        The simulation, with its history.
    resonance
        The record's band spectrum and the moving-resonance measures (the picture's data).
    """

    summary: dict[str, Any]
    result: SimulationResult = field(repr=False)
    resonance: ResonanceRun = field(repr=False)

    @property
    def status(self) -> str:
        """The simulation's status."""
        return str(self.summary["status"])

    def to_dict(self) -> dict[str, Any]:
        """A copy of :attr:`summary`."""
        return dict(self.summary)

    def describe(self) -> str:
        """Peaks, stepping episodes, impacts, residual and overturning as text."""
        data = self.summary
        drift = data["peak_drift_ratio"]
        ok = data["status"] in ("ok", "success")
        lines = [
            f"{data['record']} [{data['component']}] × {data['scale']:g}: {data['npts']} samples "
            f"at {data['dt_s']:g} s, PGA {data['pga_m_s2']:.4g} m/s², tail {data['tail_s']:g} s",
            f"peak |x| {data['peak_abs_x_m']:.6g} m at {data['peak_time_s']:.4f} s"
            + ("" if drift is None else f" (drift ratio {drift:.4g})"),
            f"x_c {data['frame']['x_c_m']:.6g} m, x* {data['frame']['x_star_m']:.6g} m; "
            f"{data['n_stepping_episodes']} stepping episodes, {data['n_impacts']} impacts",
            (
                f"OVERTURNED at {data['overturn_time_s']:.4f} s (the run stops where |x| passed "
                "its cap: no residual state)"
                if data["overturned"]
                else f"not overturned; residual x {data['residual_x_m']:.6g} m"
            )
            + ("" if ok else f"; numerical status: {data['status']}"),
        ]
        resonance = data["moving_resonance"]
        if resonance["status"] != "ok":
            lines.append(f"moving resonance: not measured ({resonance['message']})")
        else:
            index = resonance["moving_resonance_index"]
            lines.append(
                "moving resonance: "
                + ("R_m n/a (ω_f stayed near ω_1)" if index != index else f"R_m {index:.3g}")
                + f", share M {resonance['moving_resonance_share']:.3g}, work depth "
                f"{resonance['work_depth']:.3g}; ω_f down to "
                f"{resonance['lowest_omega_f_rad_s']:.4g} rad/s"
            )
        return "\n".join(lines)


def simulate_record(
    frame: PortalFrame,
    trace: Trace,
    *,
    scale: float = 1.0,
    tail_s: float | None = None,
    name: str | PathLike[str] = "",
) -> RecordResponse:
    """Simulate ``frame`` under ``trace`` × ``scale`` and summarise.

    Parameters
    ----------
    frame
        The stepping frame.
    trace
        One record component (``obspy.Trace`` in m/s²).
    scale
        Factor on the record [-].
    tail_s
        Free vibration after the record [s] (default the simulator's).
    name
        The record file, reported and named in errors.

    Raises
    ------
    InputError
        A non-finite sample (its index and time).
    """
    import numpy as np

    from stepframe.pipeline.dynamics.resonance import default_band, measure_run, unmeasured
    from stepframe.structure.simulator import DEFAULT_TAIL_S, simulate

    dt_s = float(trace.stats.delta)
    samples = np.asarray(trace.data, dtype=float)
    bad = np.flatnonzero(~np.isfinite(samples))
    if bad.size:
        raise InputError(
            f"sample {bad[0]} (t = {bad[0] * dt_s:g} s) is {samples[bad[0]]} ({bad.size} "
            "non-finite samples), expected finite accelerations",
            name or None,
        )
    tail = DEFAULT_TAIL_S if tail_s is None else float(tail_s)
    result = simulate(frame, samples, dt_s, scale=float(scale), tail_s=tail)
    try:
        band = default_band(frame)
    except InputError as error:  # a frame with little room to step: simulated, not measured
        resonance = unmeasured(result, f"no band: {error}")
    else:
        resonance = measure_run(result, samples, dt_s, band)
    summary: dict[str, Any] = {
        "record": str(name),
        "component": str(trace.stats.channel),
        "npts": int(trace.stats.npts),
        "dt_s": dt_s,
        "scale": float(scale),
        "pga_m_s2": float(np.max(np.abs(trace.data))) * float(scale),
        "tail_s": tail,
        "frame": {
            **frame.to_dict(),
            "x_star_m": frame.x_star_m,
            "uplift_acceleration_m_s2": frame.uplift_acceleration_m_s2,
        },
        **_reported_state(result.summary.to_dict()),
        "episodes": result.episode_records(),
        "moving_resonance": resonance.measures.to_dict(),
    }
    return RecordResponse(summary, result, resonance)


def _reported_state(summary: dict[str, Any]) -> dict[str, Any]:
    """The simulation's summary as reported: an overturned run has no residual state (it stops
    where |x| passed the cap; the state there, x = ±x_cap, was printed as a "residual")."""
    if not summary["overturned"]:
        return summary
    return {k: v for k, v in summary.items() if k not in ("residual_x_m", "residual_v_m_s")}


@dataclass(frozen=True)
class SimulatedComponent:
    """A record file's one component simulated, with what its figure needs."""

    response: RecordResponse
    frame: PortalFrame
    trace: Trace
    scale: float

    def to_dict(self) -> dict[str, Any]:
        """The response's JSON-ready form."""
        return self.response.to_dict()

    def describe(self) -> str:
        """The response as text."""
        return self.response.describe()

    def figure(self) -> Figure:
        """x(t) with the phases under the scaled ground acceleration, and below it the picture
        of moving resonance: the record's spectrum over the frame's band with ω_f(t) over it,
        and the ground's work."""
        import os

        from matplotlib.figure import Figure

        from stepframe.pipeline.dynamics.resonance import draw_resonance
        from stepframe.structure.plots import draw_response

        name = self.response.summary["record"]
        run = self.response.resonance
        if run.spectrum is None:  # a motion too short for the spectrum: the response alone
            from stepframe.structure.plots import response_figure

            return response_figure(
                run.result, self.frame, title=f"{os.path.basename(name)} × {self.scale:g}",
                ground_acc_m_s2=self.trace.data, scale=self.scale,
            )  # fmt: skip
        figure = Figure(figsize=(9.0, 11.0), layout="constrained")
        grid = figure.add_gridspec(2, 1, height_ratios=(6.2, 5.2))
        top, bottom = figure.add_subfigure(grid[0]), figure.add_subfigure(grid[1])
        draw_response(
            top, self.response.result, self.frame,
            title=f"{os.path.basename(name)} × {self.scale:g}", ground_acc_m_s2=self.trace.data,
            scale=self.scale,
        )  # fmt: skip
        draw_resonance(bottom, run.result, run.spectrum, run.measures, title="moving resonance")
        end = float(run.spectrum["time"].values[-1])
        for axes in top.axes:
            axes.set_xlim(0.0, end)  # the spectrum's time axis, so the panels line up
        return figure


def simulate_component(
    frame: PortalFrame,
    stream: Stream,
    *,
    name: str,
    scale: float = 1.0,
    tail_s: float | None = None,
    figure: bool = False,
) -> SimulatedComponent:
    """:func:`simulate_record` on the one component of a record file, its inputs checked and
    its memory (:func:`simulate_memory_bytes`) within the run's budget.

    Parameters
    ----------
    frame
        The stepping frame.
    stream
        The record file's components; exactly one (else an error naming them).
    name
        The record, reported and named in errors.
    scale, tail_s
        As :func:`simulate_record`; ``scale`` in :data:`SCALE_RANGE`, ``tail_s`` [s] in
        :data:`TAIL_RANGE_S` (the command's options, one declaration).
    figure
        Whether the figure will be drawn (its memory is in the estimate).
    """
    from stepframe.core.memory import check_memory
    from stepframe.structure.simulator import DEFAULT_TAIL_S

    if len(stream) != 1:
        channels = ", ".join(str(trace.stats.channel) for trace in stream)
        raise InputError(
            f"{name}: {len(stream)} components ({channels}), expected one: pick it with "
            "--component NAME"
        )
    for flag, value, valid in (("--scale", scale, SCALE_RANGE), ("--tail-s", tail_s, TAIL_RANGE_S)):
        if value is not None and not valid.contains(value):
            raise InputError(f"{flag} {value:g}, expected {valid.describe()}")
    tail = None if tail_s is None else float(tail_s)
    factor = float(scale)
    trace, tail_used = stream[0], DEFAULT_TAIL_S if tail is None else tail
    check_memory(
        simulate_memory_bytes(int(trace.stats.npts), float(trace.stats.delta), tail_used, figure),
        f"simulating {trace.stats.npts} samples with a {tail_used:g} s tail"
        + (" and drawing them" if figure else ""),
        "a shorter record or tail" + (", or no --plot" if figure else ""),
    )
    response = simulate_record(frame, stream[0], scale=factor, tail_s=tail, name=name)
    return SimulatedComponent(response, frame, stream[0], factor)


#: The record scale factors and the free-vibration tails [s] a simulation of a record file
#: accepts (the command's options and :func:`simulate_component`: one rule; they were two,
#: and ``--tail-s 0``, documented, was refused by the second).
SCALE_RANGE = Range(0, 1e4, low_open=True)
TAIL_RANGE_S = Range(0, 3600)


@dataclass(frozen=True)
class SimulateOptions:
    """The frame file and the record's scaling of one simulation (:func:`simulate_file`)."""

    frame: str = option(help="frame file (see frame-template)", metavar="FRAME.toml")
    scale: float = option(
        1.0,
        "record scale factor [-]",
        kind="positive",
        metavar="S",
        valid=SCALE_RANGE,
    )
    tail_s: float | None = option(
        None,
        "free vibration after the record [s] (default: the simulator's, 10 s)",
        kind="non_negative_seconds",
        metavar="T",
        valid=TAIL_RANGE_S,
    )

    def __post_init__(self) -> None:
        check_fields(self)


def simulate_file(
    options: SimulateOptions,
    record: Callable[[], Stream],
    *,
    name: str,
    figure: bool = False,
) -> SimulatedComponent:
    """:func:`simulate_component` of the frame file of ``options`` under the record that
    ``record()`` reads (called after the frame file is read: a bad frame file is reported
    before a long read); ``figure``: whether its figure will be drawn."""
    from stepframe.structure.frame_file import read_frame_file

    frame = read_frame_file(options.frame)
    return simulate_component(
        frame,
        record(),
        name=name,
        scale=options.scale,
        tail_s=options.tail_s,
        figure=figure,
    )


__all__ = [
    "RecordResponse",
    "SimulateOptions",
    "SimulatedComponent",
    "simulate_component",
    "simulate_file",
    "simulate_memory_bytes",
    "simulate_record",
]
