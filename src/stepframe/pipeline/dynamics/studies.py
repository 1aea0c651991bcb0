"""Stepping dynamics studies: harmonic runs with periodic orbits, bifurcation sweeps, IDA.

Each study composes the functions of :mod:`stepframe.structure` (the closed-form harmonic
integrator, Newton on the stroboscopic map, the brute-force diagram, hunt-trace-fill) into one
call and returns a result with ``to_dict()`` (JSON-ready), ``describe()`` (text for people) and
``figure()`` (a matplotlib Figure from :mod:`stepframe.structure.dynamics_plots`). The commands
``stepframe structure harmonic | bifurcation | ida`` are these functions plus option parsing.

Harmonic amplitudes are in g with g = 9.81 m/s² (:data:`G_M_S2`), as in the paper's worked
examples; an IDA's PGAs are the records' own, in standard gravity (9.80665 m/s²,
:func:`stepframe.structure.ida.ida_records`); the structure functions take m/s².
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from stepframe.core.options import JOBS, Range, check_fields, option
from stepframe.errors import InputError

if TYPE_CHECKING:
    import numpy as np
    import xarray as xr
    from matplotlib.figure import Figure
    from obspy import Stream

    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.harmonic import HarmonicRun
    from stepframe.structure.ida import IdaSettings, ItemIda
    from stepframe.structure.periodic import PeriodicOrbit

#: g [m/s²] of amplitudes given in g (the paper's worked examples use 9.81).
G_M_S2 = 9.81
#: Output samples per forcing period of a harmonic run (the stroboscopic points of its figure).
SAMPLES_PER_PERIOD = 32


def frame_or_block(frame_path: str | None, block_m: Sequence[float] | None) -> PortalFrame:
    """The frame of a frame file, or Housner's rigid block of half-width B, half-height H [m].

    Parameters
    ----------
    frame_path
        A frame file (``stepframe structure frame-template``), or None.
    block_m
        ``(B, H)`` [m] when ``frame_path`` is None.
    """
    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.frame_file import read_frame_file

    if frame_path is not None:
        return read_frame_file(frame_path)
    if block_m is None or len(block_m) != 2:
        raise InputError(f"--block {block_m}, expected two numbers B,H [m]")
    return PortalFrame.housner_block(half_width_m=block_m[0], half_height_m=block_m[1])


@dataclass(frozen=True)
class FrameSource:
    """The frame of a study: a frame file, or Housner's rigid block (one of them)."""

    frame: str | None = option(None, "frame file (see frame-template)", metavar="FRAME.toml")
    block_m: Sequence[float] | None = option(
        None,
        "Housner's rigid block of half-width B and half-height H [m]",
        kind="positive_floats",
        metavar="B,H",
        flag="--block",
        valid=Range(0, 100, low_open=True),  # structure.frame_file.PLAUSIBLE's [block]
    )

    def __post_init__(self) -> None:
        check_fields(self)

    def portal_frame(self) -> PortalFrame:
        """The frame (:func:`frame_or_block`)."""
        return frame_or_block(self.frame, self.block_m)


#: Forcing frequencies accepted [rad/s]: 10⁴ rad/s (1.6 kHz) is far above any ground motion
#: and any frame; the forcing period must stay a number a run can step through.
FORCING_RAD_S = Range(0, 1e4, low_open=True)
#: Forcing amplitudes accepted [g]: 100 g is past any ground motion (the largest recorded peak
#: is about 4 g), and keeps every derived displacement finite.
AMPLITUDES_G = Range(0, 100)


# ------------------------------------------------------------------ harmonic
@dataclass(frozen=True)
class HarmonicOptions:
    """The forcing A cos(ωt), the run's length and initial state, the orbit asked for."""

    amplitude_g: float = option(
        help="amplitude A/g [-] (g = 9.81 m/s²)",
        kind="non_negative",
        metavar="R",
        valid=AMPLITUDES_G,
    )
    omega_rad_s: float = option(
        help="forcing circular frequency [rad/s]",
        kind="positive",
        metavar="W",
        valid=FORCING_RAD_S,
    )
    periods: int = option(
        100,
        "forcing periods simulated (default 100)",
        kind="positive_int",
        metavar="N",
        valid=Range(1, 10_000_000),
    )
    x0_m: float = option(0.0, "initial x [m]", valid=Range(-100, 100))
    v0_m_s: float = option(0.0, "initial ẋ [m/s]", valid=Range(-100, 100))
    orbit: int | None = option(
        None,
        "find the period-N orbit from the final state",
        kind="positive_int",
        metavar="N",
        valid=Range(1, 64),
    )

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class HarmonicStudy:
    """A harmonic run from a given state and, optionally, the period-n orbit it settles on.

    Attributes
    ----------
    frame
        The frame.
    amplitude_g, omega_rad_s, periods
        Forcing A/g [-] (g = :data:`G_M_S2`), circular frequency [rad/s], periods simulated.
    run
        The closed-form run (:class:`stepframe.structure.harmonic.HarmonicRun`).
    orbit
        The orbit found by Newton from the run's final state (None when not asked for, or
        when the run overturned or did not end ``ok``).
    orbit_message
        Why an orbit asked for was not searched ("" otherwise).
    """

    frame: PortalFrame
    amplitude_g: float
    omega_rad_s: float
    periods: int
    run: HarmonicRun
    orbit: PeriodicOrbit | None = None
    orbit_message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """The run's summary, the final state and ``orbit`` when one was found."""
        data: dict[str, Any] = {
            "amplitude_g": self.amplitude_g,
            "omega_rad_s": self.omega_rad_s,
            "periods": self.periods,
            "x_c_m": self.frame.x_c_m,
            "x_star_m": self.frame.x_star_m,
            **self.run.to_dict(),
        }
        if not self.run.overturned:  # an overturned frame has no final state (x left x_cap)
            data["x_end_m"] = float(self.run.x_m[-1])
            data["v_end_m_s"] = float(self.run.v_m_s[-1])
        if self.orbit is not None:
            data["orbit"] = self.orbit.to_dict()
        if self.orbit_message:
            data["orbit_message"] = self.orbit_message
        return data

    def describe(self) -> str:
        """One line for the run, one for the orbit."""
        run = self.run
        lines = [
            f"A = {self.amplitude_g:g} g, ω = {self.omega_rad_s:g} rad/s, {self.periods} periods: "
            f"status {run.status}, {run.n_liftoffs} lift-offs, {run.n_impacts} impacts, peak |x| "
            f"{run.peak_abs_x_m:.6g} m"
            + (f", OVERTURNED at {run.t_end_s:.4f} s" if run.overturned else "")
            + (f"; {run.message}" if run.message else "")
        ]
        orbit = self.orbit
        if orbit is not None:
            mults = ", ".join(f"{m:.6g}" for m in orbit.multipliers)
            lines.append(
                f"period-{orbit.n_periods} orbit: status {orbit.status}, x = {orbit.x_m:.9g} m, "
                f"ẋ = {orbit.v_m_s:.9g} m/s, {orbit.n_impacts} impacts, multipliers {mults}, "
                f"{'stable' if orbit.stable else 'unstable'}"
                + (", symmetric" if orbit.symmetric else "")
            )
        if self.orbit_message:
            lines.append(self.orbit_message)
        return "\n".join(lines)

    def figure(self) -> Figure:
        """Phase portrait with the stroboscopic points."""
        from stepframe.structure.dynamics_plots import phase_portrait_figure

        return phase_portrait_figure(
            self.run,
            x_c_m=self.frame.x_c_m,
            x_star_m=self.frame.x_star_m,
            strobe_every=SAMPLES_PER_PERIOD,
        )


def harmonic_study(frame: PortalFrame, options: HarmonicOptions) -> HarmonicStudy:
    """Integrate under A cos(ωt) in closed form; with ``options.orbit = n``, find the period-n
    orbit by Newton on the stroboscopic map from the final state (skipped when the run
    overturned or did not end ``ok``).

    Parameters
    ----------
    frame
        The frame.
    options
        :class:`HarmonicOptions` (A/g with g = :data:`G_M_S2`, ω [rad/s], periods, x0, v0).
    """
    from stepframe.structure.harmonic import simulate_harmonic

    amplitude_m_s2 = options.amplitude_g * G_M_S2
    omega = float(options.omega_rad_s)
    run = simulate_harmonic(
        frame,
        amplitude_m_s2,
        omega,
        options.periods * 2 * math.pi / omega,
        x0_m=options.x0_m,
        v0_m_s=options.v0_m_s,
        samples_per_period=SAMPLES_PER_PERIOD,
    )
    found, why = None, ""
    if options.orbit is not None and (run.overturned or run.status != "ok"):
        ended = "overturned" if run.overturned else f"ended {run.status}"
        why = (
            f"period-{options.orbit} orbit: not searched, the run {ended} (Newton starts from "
            "the final state of a run that settles)"
        )
    elif options.orbit is not None:
        from stepframe.structure.periodic import find_periodic_orbit

        found = find_periodic_orbit(
            frame, amplitude_m_s2, omega, run.x_m[-1], run.v_m_s[-1], n_periods=options.orbit
        )
    return HarmonicStudy(frame, options.amplitude_g, omega, options.periods, run, found, why)


# ------------------------------------------------------------------ bifurcation
@dataclass(frozen=True)
class BifurcationOptions:
    """One sweep (the amplitude at a fixed frequency, or the frequency at a fixed amplitude),
    the initial states and the run length."""

    omega_rad_s: float | None = option(
        None,
        "forcing circular frequency [rad/s] (sweeping --amplitudes-g)",
        kind="positive",
        metavar="W",
        valid=FORCING_RAD_S,
    )
    amplitudes_g: tuple[float, float, int] | None = option(
        None, "N amplitudes from LO to HI [g]", kind="range", metavar="LO,HI,N", valid=AMPLITUDES_G
    )
    amplitude_g: float | None = option(
        None,
        "forcing amplitude [g] (sweeping --omegas-rad-s)",
        kind="non_negative",
        metavar="R",
        valid=AMPLITUDES_G,
    )
    omegas_rad_s: tuple[float, float, int] | None = option(
        None,
        "N circular frequencies from LO to HI [rad/s]",
        kind="range",
        metavar="LO,HI,N",
        valid=FORCING_RAD_S,
    )
    initial: int = option(
        50,
        "initial states (seeded, spread over |x| < x*; default 50)",
        kind="positive_int",
        metavar="N",
        valid=Range(1, 100_000),
    )
    periods: int = option(
        100,
        "forcing periods per run (default 100)",
        kind="positive_int",
        metavar="N",
        valid=Range(1, 10_000_000),
    )
    jobs: int | None = option(
        None,
        "worker processes (default: all CPUs, or STEPFRAME_JOBS)",
        kind="positive_int",
        valid=JOBS,
    )

    def __post_init__(self) -> None:
        check_fields(self)


@dataclass(frozen=True)
class BifurcationSweep:
    """A brute-force bifurcation diagram and its summary per swept value.

    Attributes
    ----------
    sweep
        ``"amplitude_g"`` or ``"omega_rad_s"``: what was swept.
    omega_rad_s, amplitude_g
        The fixed forcing value (the other one is None).
    values
        The swept values [g or rad/s].
    initial, periods
        Initial states per value and forcing periods per run.
    dataset
        :func:`stepframe.structure.bifurcation.bifurcation_diagram`'s dataset.
    points
        Per value: the value, the fraction of initial states that overturned, the number that
        stopped, and the orbit periods found.
    """

    sweep: str
    omega_rad_s: float | None
    amplitude_g: float | None
    values: np.ndarray
    initial: int
    periods: int
    dataset: xr.Dataset
    points: list[dict[str, Any]] = field(default_factory=list)

    def to_dict(self) -> dict[str, Any]:
        """Sweep, fixed value, points and the runs that failed."""
        return {
            "sweep": self.sweep,
            "omega_rad_s": self.omega_rad_s,
            "amplitude_g": self.amplitude_g,
            "points": self.points,
            "failures": self.dataset.attrs["failures"],
        }

    def describe(self) -> str:
        """A header line and at most about 20 values: every k-th and the last, the header
        saying which when not all are shown."""
        n = len(self.points)
        if self.sweep == "amplitude_g":
            unit, fixed = "g", f"ω = {self.omega_rad_s:g} rad/s"
        else:
            unit, fixed = "rad/s", f"A = {self.amplitude_g:g} g"
        step = max(1, n // 20)
        shown = list(range(0, n, step))
        if shown and shown[-1] != n - 1:
            shown.append(n - 1)
        header = f"{n} values × {self.initial} initial states × {self.periods} periods at {fixed}"
        if step > 1:
            header += f" (one value in {step} shown, and the last; --json or --plot: all)"
        lines = [header]
        lines += [
            f"  {r[self.sweep]:.4g} {unit}: overturn {r['overturned_fraction']:.2f}, "
            f"periods {r['periods_found'] or '-'}"
            for r in (self.points[i] for i in shown)
        ]
        return "\n".join(lines)

    def figure(self) -> Figure:
        """The diagram."""
        from stepframe.structure.dynamics_plots import bifurcation_figure

        return bifurcation_figure(self.dataset, g_m_s2=G_M_S2)


def bifurcation_sweep(
    frame: PortalFrame, options: BifurcationOptions, *, figure: bool = False
) -> BifurcationSweep:
    """Sweep the amplitude at a fixed frequency, or the frequency at a fixed amplitude.

    Parameters
    ----------
    frame
        The frame.
    options
        :class:`BifurcationOptions`: ``omega_rad_s`` [rad/s] with ``amplitudes_g`` (low, high,
        n) [g], or ``amplitude_g`` [g] with ``omegas_rad_s`` (low, high, n) [rad/s]; the
        initial states per value (seeded, spread over |x| < x*), the forcing periods per run
        (the last ``min(20, periods)`` stroboscopic points are kept) and the worker processes.
    figure
        Whether the diagram will be drawn (its memory is in the estimate).

    Raises
    ------
    InputError
        A diagram whose memory
        (:func:`~stepframe.structure.bifurcation.diagram_memory_bytes`) passes the run's budget.
    """
    import numpy as np

    from stepframe.core.memory import check_memory
    from stepframe.structure.bifurcation import (
        bifurcation_diagram,
        diagram_memory_bytes,
        frequency_diagram,
        orbit_period,
    )

    omega_rad_s, amplitudes_g = options.omega_rad_s, options.amplitudes_g
    amplitude_g, omegas_rad_s = options.amplitude_g, options.omegas_rad_s
    initial, periods = options.initial, options.periods
    by_amp = amplitudes_g is not None and omega_rad_s is not None
    by_omega = omegas_rad_s is not None and amplitude_g is not None
    # an option of the other sweep beside a complete one would be ignored: refused instead
    stray = (
        [("--amplitude-g", amplitude_g), ("--omegas-rad-s", omegas_rad_s)]
        if by_amp and not by_omega
        else [("--omega-rad-s", omega_rad_s), ("--amplitudes-g", amplitudes_g)]
        if by_omega and not by_amp
        else []
    )
    ignored = [flag for flag, value in stray if value is not None]
    if ignored:
        sweep = "amplitude" if by_amp else "frequency"
        raise InputError(
            f"{' and '.join(ignored)} with the {sweep} sweep, expected the options of one sweep "
            "(--omega-rad-s W with --amplitudes-g LO,HI,N, or --amplitude-g R with "
            "--omegas-rad-s LO,HI,N)"
        )
    if by_amp == by_omega:
        raise InputError(
            "give --omega-rad-s W with --amplitudes-g LO,HI,N, or --amplitude-g R with "
            "--omegas-rad-s LO,HI,N, expected exactly one sweep"
        )
    common: dict[str, Any] = {
        "n_initial": initial,
        "n_periods": periods,
        "n_keep": min(20, periods),
        "jobs": options.jobs,
    }
    sizes = amplitudes_g or omegas_rad_s
    n_points = int(sizes[2]) * initial * min(20, periods) if sizes else 0
    check_memory(
        diagram_memory_bytes(n_points, figure),
        f"a bifurcation diagram of {n_points} points (values × initial states × the last "
        f"{min(20, periods)} periods)" + (" drawn" if figure else ""),
        "fewer values or initial states" + (", or no --plot" if figure else ""),
    )
    if amplitudes_g is not None and omega_rad_s is not None:
        lo, hi, n = amplitudes_g
        values = np.linspace(lo, hi, n)
        ds = bifurcation_diagram(frame, values * G_M_S2, omega_rad_s, **common)
        key = "amplitude_g"
    else:
        assert omegas_rad_s is not None and amplitude_g is not None
        lo, hi, n = omegas_rad_s
        if lo <= 0:
            raise InputError(f"--omegas-rad-s starts at {lo:g}, expected > 0")
        values = np.linspace(lo, hi, n)
        ds = frequency_diagram(frame, amplitude_g * G_M_S2, values, **common)
        key = "omega_rad_s"
    points = []
    for a in range(n):
        found = {orbit_period(ds["x_m"].values[a, j]) for j in range(initial)}
        outcome = ds["outcome"].values[a]
        points.append(
            {
                key: float(values[a]),
                "overturned_fraction": float((outcome == 1).mean()),
                "stopped": int((outcome == 2).sum()),
                "periods_found": sorted(p for p in found if p > 0),
            }
        )
    return BifurcationSweep(key, omega_rad_s, amplitude_g, values, initial, periods, ds, points)


# ------------------------------------------------------------------ ida
#: (probe factor, probes) of an IDA over records, and over one-cycle pulses: a pulse's survival
#: band above the first overturning s_c reaches 3.7 (ω = 2p) to 6.7 (ω = 4p) times s_c for
#: Housner's block and is at least 0.75 s_c wide (docs/structure-dynamics.md), so probes 0.56 s_c
#: apart up to 10 s_c see it.
RECORD_PROBES = (2.0, 8)
PULSE_PROBES = (10.0, 16)


@dataclass(frozen=True)
class IdaOptions:
    """What an IDA runs over (records or pulses) and how finely it traces."""

    fema_p695: int | None = option(
        None,
        "use the first N of the embedded FEMA P695 components",
        kind="positive_int",
        metavar="N",
        valid=Range(1, 100),  # the catalogue's 100 components
    )
    pulse: str | None = option(None, "one-cycle pulse instead", choices=("cosine", "sine"))
    omegas_rad_s: tuple[float, ...] | None = option(
        None,
        "pulse circular frequencies [rad/s] (with --pulse)",
        kind="positive_floats",
        metavar="W1,W2",
        flag="--omega-rad-s",
        valid=FORCING_RAD_S,
    )
    resolution_g: float = option(
        0.01,
        "width of each traced outcome change [g of PGA] (default 0.01; with --pulse, in units "
        "of the static uplift acceleration γ₁/P₂)",
        kind="positive",
        metavar="D",
        valid=Range(0, 10, low_open=True),
    )
    max_intensity_g: float = option(
        5.0,
        "largest intensity hunted [g of PGA] (default 5; with --pulse, 10·S in units of "
        "the static uplift acceleration γ₁/P₂)",
        kind="positive",
        metavar="S",
        flag="--max-g",
        valid=Range(0, 100, low_open=True),
    )
    tail_s: float = option(
        10.0,
        "free vibration after each record [s] (default 10)",
        kind="non_negative",
        metavar="T",
        valid=Range(0, 3600),
    )
    probe_factor: float | None = option(
        None,
        "probe up to F times the first overturning intensity for survival above it "
        f"(default {RECORD_PROBES[0]:g} for records, {PULSE_PROBES[0]:g} for pulses)",
        kind="positive",
        metavar="F",
        valid=Range(1, 1000),
    )
    probes: int | None = option(
        None,
        "probes evenly spaced in that range "
        f"(default {RECORD_PROBES[1]} for records, {PULSE_PROBES[1]} for pulses)",
        kind="positive_int",
        metavar="N",
        valid=Range(1, 1000),
    )

    def __post_init__(self) -> None:
        check_fields(self)
        if self.resolution_g >= self.max_intensity_g:
            raise InputError(
                f"--resolution-g {self.resolution_g:g} is not below --max-g "
                f"{self.max_intensity_g:g}, expected a resolution finer than the largest "
                "intensity hunted (nothing would be run)"
            )

    def settings(self) -> IdaSettings:
        """The hunt-trace-fill settings of an IDA over records, in g of PGA (the command's and
        the workflow's ``ida`` stage's)."""
        from stepframe.structure.ida import IdaSettings

        factor, probes = RECORD_PROBES
        return IdaSettings(
            start=max(self.resolution_g, 0.05),
            step=0.1,
            step_increment=0.05,
            resolution=self.resolution_g,
            max_intensity=self.max_intensity_g,
            probe_factor=factor if self.probe_factor is None else self.probe_factor,
            n_probe=probes if self.probes is None else self.probes,
        )


@dataclass(frozen=True)
class IdaStudy:
    """Hunt-trace-fill IDA of a frame under records or one-cycle pulses.

    Attributes
    ----------
    items
        One :class:`stepframe.structure.ida.ItemIda` per record or pulse.
    names
        Their names (``file [channel]``, ``RSN n channel`` or ``cosine ω = w rad/s``).
    settings
        The hunt-trace-fill settings used.
    intensity
        The intensity's name and unit (``PGA [g]`` or ``amplitude / (γ₁/P₂)``).
    """

    items: list[ItemIda]
    names: list[str]
    settings: IdaSettings
    intensity: str

    def to_dict(self) -> dict[str, Any]:
        """Table rows, fractiles of the first overturning, simulation counts."""
        from stepframe.core.jsonable import without_none
        from stepframe.structure.ida import capacity_fractiles, fixed_step_runs, ida_table

        return {
            "intensity": self.intensity,
            # a capacity not found is absent (a pandas column of None and numbers is NaN, of
            # None alone None: both left out, as a number documented "absent")
            "items": [
                without_none((str(key), value) for key, value in row.items())
                for row in ida_table(self.items, self.names).to_dict(orient="records")
            ],
            "fractiles": capacity_fractiles(self.items),
            "simulations": int(sum(item.n_runs for item in self.items)),
            "fixed_step_simulations": fixed_step_runs(self.items, self.settings),
            "resurrected": int(sum(bool(item.resurrections) for item in self.items)),
        }

    def describe(self) -> str:
        """Counts, the first 50 items, the fractiles."""
        data = self.to_dict()
        lines = [
            f"{len(self.items)} items, intensity {self.intensity}, {data['simulations']} "
            f"simulations (a fixed step of {self.settings.resolution:g} would need "
            f"{data['fixed_step_simulations']}); resurrection in {data['resurrected']}"
        ]
        for row in data["items"][:50]:
            first = row.get("first_overturning")
            shown = "none found" if first is None or first != first else f"{first:.6g}"
            extra = ""
            if row["resurrected"]:
                item = self.items[self.names.index(row["item"])]
                bands = ", ".join(f"[{a:.6g}, {b:.6g}]" for a, b in item.overturning_bands)
                extra = f", resurrections {row['resurrections']}; overturns on {bands}"
            lines.append(f"  {row['item']}: first overturning {shown} ({row['status']}){extra}")
        # an undefined fractile says why (items that never overturned: lower bounds only)
        fractiles = ", ".join(
            f"{k} {v:.4g}" if v == v else f"{k} undefined" for k, v in data["fractiles"].items()
        )
        unfound = sum(item.first_overturning is None for item in self.items)
        lines.append(
            "fractiles of the first overturning: "
            + fractiles
            + (
                f" ({unfound} of {len(self.items)} never overturned: lower bounds)"
                if unfound
                else ""
            )
        )
        return "\n".join(lines)

    def figure(self) -> Figure:
        """The IDA curves."""
        from stepframe.structure.dynamics_plots import ida_figure

        return ida_figure(self.items, names=self.names, intensity_label=self.intensity)


#: Peak memory of an IDA over records [bytes per sample]: each record held and once more in the
#: batch's concatenated block (16; the tail is not stored), the largest one's read and its
#: block built beside it (48 more) (measured 12 MiB for one record of 200,000 samples, 39 MiB
#: for two of 800,000, 22 MiB for six of 200,000: tracemalloc, docs/benchmarks.md).
IDA_BYTES_PER_SAMPLE, IDA_LARGEST_BYTES_PER_SAMPLE = 16.0, 48.0


def ida_memory_bytes(samples: Sequence[int]) -> float:
    """The estimated peak memory of an IDA over records of ``samples`` samples each [bytes];
    independent of the number of scales since a record's runs share one copy of it."""
    if not samples:
        return 0.0
    return IDA_BYTES_PER_SAMPLE * float(sum(samples)) + IDA_LARGEST_BYTES_PER_SAMPLE * max(samples)


def ida_study(
    frame: PortalFrame, options: IdaOptions, records: Sequence[tuple[str, Stream]] = ()
) -> IdaStudy:
    """IDA by hunt-trace-fill over records (PGA in g) or over one-cycle pulses.

    Parameters
    ----------
    frame
        The frame.
    options
        :class:`IdaOptions`: also the first ``fema_p695`` components of the embedded FEMA P695
        catalogue; or, with ``pulse`` (``"cosine"`` or ``"sine"``), one-cycle pulses at
        ``omegas_rad_s`` [rad/s] instead of records (intensities then in units of the static
        uplift acceleration γ₁/P₂, the hunt starting at 1 with ten times ``max_intensity_g`` as
        its cap);
        the width of every traced outcome change, the largest intensity hunted and the free
        vibration after each record [s].
    records
        ``(file name, stream)`` pairs; every component of each stream is an item.
    """
    import numpy as np

    from stepframe.core.memory import check_memory
    from stepframe.structure.ida import IdaSettings, ida_pulse, ida_records

    fema_p695, pulse, omegas_rad_s = options.fema_p695, options.pulse, options.omegas_rad_s
    resolution_g, tail_s = options.resolution_g, options.tail_s
    if pulse is not None:
        # what an IDA over records reads is an error here, not ignored
        unread = [
            name
            for name, given in (
                ("--fema-p695", bool(fema_p695)),
                ("RECORD files", bool(records)),
                ("--tail-s", tail_s != IdaOptions.tail_s),
            )
            if given
        ]
        if unread:
            raise InputError(
                f"--pulse with {', '.join(unread)}, expected pulses or records, not both (a "
                "pulse IDA reads no record and has no tail)"
            )
        factor, probes = PULSE_PROBES
        factor = factor if options.probe_factor is None else options.probe_factor
        probes = probes if options.probes is None else options.probes
        if not omegas_rad_s:
            raise InputError("--pulse needs --omega-rad-s W1,W2,..., expected pulse frequencies")
        settings = IdaSettings(
            start=1.0,
            step=0.5,
            step_increment=0.25,
            resolution=resolution_g,
            max_intensity=options.max_intensity_g * 10,
            probe_factor=factor,
            n_probe=probes,
        )
        names = [f"{pulse} ω = {w:g} rad/s" for w in omegas_rad_s]
        items = ida_pulse(frame, omegas_rad_s, kind=pulse, settings=settings)
        return IdaStudy(items, names, settings, "amplitude / (γ₁/P₂)")
    if omegas_rad_s:  # what a pulse IDA reads
        raise InputError("--omega-rad-s without --pulse, expected it only with --pulse cosine|sine")
    settings = options.settings()
    motions: list[tuple[np.ndarray, float]] = []
    names = []
    if fema_p695:
        from stepframe.records.examples import fema_p695 as example

        for trace in example()[0][:fema_p695]:
            motions.append((np.asarray(trace.data, dtype=float), float(trace.stats.delta)))
            names.append(f"RSN {trace.stats.stepframe.rsn} {trace.stats.channel}")
    for path, stream in records:
        for trace in stream:
            motions.append((np.asarray(trace.data, dtype=float), float(trace.stats.delta)))
            names.append(f"{path} [{trace.stats.channel}]")
    if not motions:
        raise InputError("no records: give RECORD files or --fema-p695 N, expected at least one")
    check_memory(
        ida_memory_bytes([acc.size for acc, _ in motions]),
        f"an IDA of {len(motions)} record(s) of {sum(acc.size for acc, _ in motions)} samples",
        "fewer or shorter records",
    )
    items = ida_records(frame, motions, settings=settings, tail_s=tail_s)
    return IdaStudy(items, names, settings, "PGA [g]")


__all__ = [
    "G_M_S2",
    "BifurcationOptions",
    "BifurcationSweep",
    "FrameSource",
    "HarmonicOptions",
    "HarmonicStudy",
    "IdaOptions",
    "IdaStudy",
    "bifurcation_sweep",
    "frame_or_block",
    "harmonic_study",
    "ida_memory_bytes",
    "ida_study",
]
