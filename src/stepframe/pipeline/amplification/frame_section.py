"""The amplification report's frame section: band, frame-driven run, design displacement.

With a frame, the report states its band [f(A_max), f_1] from the period-amplitude law, where
that band lies against the ground's own dominant frequency (ω_g(t)/2π runs from f_p down to f_r:
a flexible frame's band usually lies below f_r, and the ground's frequency never reaches it),
the frame-driven response amplification (exact covariance method, ω(t) = 2π/T(A)) with whether
the frame stepped in that run and the intensity at which it would
(:func:`~stepframe.pipeline.amplification.headlines.frame_stepping`), and, with a design
displacement δ*, δ* adjusted by each amplification factor placed against x_c and x*
(:func:`~stepframe.pipeline.amplification.headlines.design_limits`), with a warning for each
adjusted value at or beyond x*, where the frame overturns.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import pandas as pd

from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import AmplificationOptions
from stepframe.pipeline.amplification.headlines import (
    ReportNumbers,
    Stepping,
    design_limits,
    frame_stepping,
)
from stepframe.pipeline.reports.document import Figure, Note, Table
from stepframe.stochastic.model import GroundMotionModel

TWO_PI = 2 * math.pi

#: Default amplitude limit of the band without a design displacement: this fraction of the way
#: from the uplift amplitude x_c to the overturning amplitude x* (below x_c the frame does not step
#: and its period does not change, so a limit there would give an empty band).
DEFAULT_A_MAX_FRACTION = 0.5

Items = list[Figure | Table | Note]


def _hz(omega: float) -> float:
    return omega / TWO_PI


@dataclass(frozen=True)
class FramePart:
    """With a frame: its band [Hz], its frame-driven point (f_1, value, lower bound), whether it
    stepped, its section items."""

    band_hz: tuple[float, float]
    point: tuple[float, float, bool]
    stepping: Stepping
    items: Items


def frame_band(frame: Any, a_max_m: float) -> tuple[float, float]:
    """[ω(A_max), ω_1] of the frame [rad/s]."""
    from stepframe.structure.period_amplitude import period_amplitude

    period = float(period_amplitude(frame, a_max_m, beyond_x_star="inf"))
    return TWO_PI / period, frame.omega_1_rad_s


def _frame_rows(frame: Any, band: tuple[float, float], a_max: float, driven: Any,
                stepping: Stepping) -> list[dict[str, Any]]:  # fmt: skip
    lo, hi = band
    return [
        {"quantity": "small-amplitude frequency f_1", "value": _hz(hi), "unit": "Hz"},
        {"quantity": "band lower edge f(A_max)", "value": _hz(lo), "unit": "Hz"},
        {"quantity": "amplitude limit A_max", "value": a_max, "unit": "m"},
        {"quantity": "uplift amplitude x_c", "value": frame.x_c_m, "unit": "m"},
        {"quantity": "overturning amplitude x*", "value": frame.x_star_m, "unit": "m"},
        {"quantity": "peak intensity I_g of the run", "value": stepping.intensity_m_s2,
         "unit": "m/s²"},
        {"quantity": "peak intensity of the run (× p_1)",
         "value": stepping.intensity_m_s2 * frame.p_1, "unit": "m/s²"},
        {"quantity": "peak amplitude √2·σ_x of the run", "value": stepping.peak_amplitude_m,
         "unit": "m"},
        {"quantity": "stepped in the run (√2·σ_x reached x_c)", "value": stepping.stepped,
         "unit": ""},
        {"quantity": "peak intensity I_g at which the frame steps",
         "value": stepping.onset_intensity_m_s2, "unit": "m/s²"},
        {"quantity": "frame-driven response amplification vs fixed",
         "value": float(driven.vs_fixed[0]), "unit": "-"},
        {"quantity": "status of the frame-driven run", "value": driven.moving.status,
         "unit": ""},
    ]  # fmt: skip


def check_design_displacement(frame: Any, delta_star_m: float | None) -> None:
    """Refuse a design displacement δ* at or beyond the frame's x* (checked before any work).

    Raises
    ------
    InputError
        ``delta_star_m`` ≥ x* (the frame overturns there: no band can end at it).
    """
    if delta_star_m is not None and delta_star_m >= frame.x_star_m:
        raise InputError(
            f"delta_star_m = {delta_star_m} m ≥ x* = {frame.x_star_m:.4g} m, expected a design "
            "displacement below x* (the frame overturns there)",
            key="delta_star_m",
        )


def _amplitude_limit(frame: Any, opts: AmplificationOptions) -> float:
    """A_max [m]: the design displacement δ*, else a fixed fraction of the way to x*."""
    x_star = frame.x_star_m
    if opts.delta_star_m is None:
        return float(frame.x_c_m + DEFAULT_A_MAX_FRACTION * (x_star - frame.x_c_m))
    check_design_displacement(frame, opts.delta_star_m)
    return opts.delta_star_m


def _ground_versus_band(model: GroundMotionModel, band_hz: tuple[float, float]) -> Note:
    """Where the frame's band lies against the ground's dominant frequency f_r ≤ ω_g/2π ≤ f_p."""
    f_p, f_r = _hz(model.omega_p_rad_s), _hz(model.omega_r_rad_s)
    lo, hi = band_hz
    ground = f"The ground's dominant frequency ω_g(t)/2π falls from f_p = {f_p:.3g} Hz to f_r = "
    if hi < f_r:
        return Note(
            ground + f"{f_r:.3g} Hz and never reaches the frame's band ({lo:.3g}-{hi:.3g} Hz, "
            "all below f_r): the curve's values in the band are those of oscillators whose "
            "frequency falls in proportion to the ground's (ω_0·ω_g(t)/ω_p), not of a frame that "
            "the ground's frequency passes through. The frame-driven point is the frame's own "
            "run.",
            "warning",
        )
    if lo > f_p:
        return Note(
            ground + f"{f_r:.3g} Hz, all below the frame's band ({lo:.3g}-{hi:.3g} Hz).",
            "warning",
        )
    return Note(
        ground + f"{f_r:.3g} Hz; the frame's band is {lo:.3g}-{hi:.3g} Hz: they overlap over "
        f"{max(lo, f_r):.3g}-{min(hi, f_p):.3g} Hz."
    )


def frame_part(
    frame: Any,
    model: GroundMotionModel,
    peak_intensity_m_s2: float,
    opts: AmplificationOptions,
    stated: ReportNumbers,
) -> FramePart:
    """The frame's band from its period-amplitude law, its frame-driven amplification (exact
    covariance method) with whether it stepped and the intensity at which it would, and, with
    δ*, the adjusted design displacement against x_c and x*."""
    from stepframe.pipeline.amplification.amplify import frame_oscillator
    from stepframe.stochastic.amplification import response_amplification
    from stepframe.stochastic.mean_square import analysis_grid

    a_max = _amplitude_limit(frame, opts)
    lo, hi = frame_band(frame, a_max)
    intensity = opts.peak_intensity_m_s2 or peak_intensity_m_s2
    oscillator = frame_oscillator(frame)
    law = oscillator.frame_law
    assert law is not None  # a frame's oscillator always has its period law
    driven = response_amplification(
        model, None, oscillator.xi0, frame=law, peak_intensity=intensity * frame.p_1,
        time_s=analysis_grid(model, n_steps=opts.n_steps),
    )  # fmt: skip
    stepping = frame_stepping(frame.x_c_m, driven, intensity, law.amplitude_factor)
    lower = driven.moving.status != "ok"
    rows = _frame_rows(frame, (lo, hi), a_max, driven, stepping)
    stated.numbers["frame"] = {row["quantity"]: row["value"] for row in rows}
    stated.numbers["frame_driven_lower_bound"] = lower
    stated.numbers["frame_stepped"] = stepping.stepped
    stated.numbers["frame_onset_intensity_m_s2"] = stepping.onset_intensity_m_s2
    stated.summary.append(
        ("Frame's band", f"{_hz(lo):.3g}-{_hz(hi):.3g} Hz (A_max = {a_max:.3g} m)")
    )
    value = float(driven.vs_fixed[0])
    if lower:
        driven_text = f"≥ {value:.3g} (lower bound: the frame overturned)"
    elif stepping.stepped:
        driven_text = f"{value:.3g} (the frame stepped)"
    else:
        driven_text = (
            f"{value:.3g}: the frame did not step at I_g = {intensity:.3g} m/s² (it stays linear "
            f"at f_1); it steps from I_g = {stepping.onset_intensity_m_s2:.3g} m/s² "
            f"({stepping.onset_factor:.3g} × the run's)"
        )
    stated.summary.append(("Frame-driven response amplification", driven_text))
    source = (
        "the design displacement δ* given"
        if opts.delta_star_m is not None
        else f"x_c + {DEFAULT_A_MAX_FRACTION}·(x* - x_c) (no design displacement given)"
    )
    items: Items = [
        Table(
            "frame",
            "The frame",
            pd.DataFrame(rows),
            "Band from the period-amplitude law, frame-driven run and its stepping",
            {"quantity": "what", "value": "the number", "unit": "its unit"},
        ),
        Note(f"The band is [f(A_max), f_1] with A_max = {a_max:.3g} m from {source}."),
        _ground_versus_band(model, (_hz(lo), _hz(hi))),
        Note(
            stepping.describe()
            + (
                " Its amplification is only a lower bound and is drawn as an open marker with "
                "an arrow."
                if lower
                else ""
            )
            + " The run's amplitude is √2·σ_x (a harmonic's of that RMS); a random response "
            "peaks higher (a peak factor near 3), so a record steps the frame at a lower "
            "intensity than this onset.",
            "warning" if lower or not stepping.stepped else "note",
        ),
        _band_panel(model, (lo, hi), driven.moving),
    ]
    if opts.delta_star_m is not None:
        items += _adjusted_design(frame, model, opts, stated)
    point = (_hz(frame.omega_1_rad_s), value, lower)
    return FramePart((_hz(lo), _hz(hi)), point, stepping, items)


def _band_panel(model: GroundMotionModel, band: tuple[float, float], moving: Any) -> Figure:
    """The site model's spectrum over the frame's band with the frame-driven ω(t) over it."""
    from stepframe.pipeline.amplification.time_frequency import site_band_figure
    from stepframe.pipeline.reports.document import figure_from_matplotlib

    return figure_from_matplotlib(
        site_band_figure(model, band, moving, title="The site model over the frame's band"),
        key="site_band_spectrum",
        title="The site's evolutionary spectrum over the frame's band, and the frame's ω(t)",
        alt=(
            "heat map of eq. 6.12 times the intensity envelope, frequency in Hz (log) against "
            "time in s, the frame's band shaded, the frame's frequency of the frame-driven "
            "analysis drawn over it; below, the frame's RMS displacement"
        ),
        how_to_read=(
            "Where the green line (the frame's frequency as its RMS amplitude elongates its "
            "period) runs through bright colour, the site's energy is where the frame is: the "
            "moving resonance the frame-driven amplification measures. The same picture as the "
            "selection report's for a simulated record (docs/selection.md)."
        ),
    )


def _adjusted_design(
    frame: Any, model: GroundMotionModel, opts: AmplificationOptions, stated: ReportNumbers
) -> Items:
    """The quasi-dynamic δ* adjusted for moving resonance by each amplification factor, each
    placed against x_c and x*; a warning for each at or beyond x*."""
    from stepframe.stochastic.amplification import adjusted_fixed_point

    assert opts.delta_star_m is not None
    adjusted: list[dict[str, Any]] = []
    xi0 = frame.xi_1 if frame.xi_1 > 0 else opts.xi0_or_default
    # each factor with what it reads: the site alone, ω_1, or ω_1 and the damping
    for factor, meaning, inputs in (
        ("eq-6-19-last", "√((ω_p/ω_s)²) · δ*", {}),
        ("eq-6-19-first", "√(eq. 6.19 first) · δ*", {}),
        ("eq-6-18", "√(eq. 6.18 at ω_1) · δ*", {"omega_0_rad_s": frame.omega_1_rad_s}),
        (
            "response-vs-fixed",
            "response amplification at ω_1 (covariance) · δ*",
            {"omega_0_rad_s": frame.omega_1_rad_s, "xi0": xi0},
        ),
    ):
        value = adjusted_fixed_point(
            opts.delta_star_m, model, factor=factor, **inputs  # type: ignore[arg-type]
        )  # fmt: skip
        adjusted.append({"factor": factor, "rule": meaning, "adjusted_delta_m": value})
    by: dict[str, float] = {str(row["factor"]): float(row["adjusted_delta_m"]) for row in adjusted}
    limits = design_limits({"delta_star": opts.delta_star_m, **by}, frame.x_c_m, frame.x_star_m)
    state = {limit.name: limit.state for limit in limits}
    table = pd.DataFrame(adjusted)
    table.insert(2, "delta_star_m", opts.delta_star_m)
    table["over_x_star"] = table["adjusted_delta_m"] / frame.x_star_m
    table["state"] = [state[row["factor"]] for row in adjusted]
    stated.numbers["adjusted_design_displacement_m"] = by
    stated.numbers["design_limits"] = {
        "x_c_m": frame.x_c_m,
        "x_star_m": frame.x_star_m,
        **{limit.name: limit.state for limit in limits},
    }
    beyond = [limit for limit in limits if limit.overturns]
    stated.summary.append(
        (
            "Adjusted design displacement",
            f"δ* = {opts.delta_star_m:.3g} m → {by['eq-6-19-last']:.3g} m by (ω_p/ω_s)², "
            f"{by['response-vs-fixed']:.3g} m by the response amplification at f_1 "
            f"(x_c = {frame.x_c_m:.3g} m, x* = {frame.x_star_m:.3g} m"
            + (f"; {len(beyond)} of {len(by)} at or beyond x*)" if beyond else ")"),
        )
    )
    items: Items = [
        Table(
            "adjusted_design_displacement",
            "Adjusted design displacement",
            table,
            "The quasi-dynamic δ* adjusted for moving resonance, by each factor, against x_c "
            f"= {frame.x_c_m:.3g} m and x* = {frame.x_star_m:.3g} m",
            {
                "factor": "which amplification",
                "rule": "how it adjusts δ* (spectral factors are mean-square ratios)",
                "delta_star_m": "the unadjusted design displacement δ* [m]",
                "adjusted_delta_m": "δ* adjusted [m]",
                "over_x_star": "adjusted δ* / x* [-] (≥ 1: the frame overturns)",
                "state": "below x_c (no stepping), between x_c and x*, or at or beyond x*",
            },
        )
    ]
    if beyond:
        text = (
            "Adjusted design displacement beyond failure: "
            + "; ".join(f"{b.name} gives {b.displacement_m:.3g} m" for b in beyond)
            + f", at or beyond the overturning displacement x* = {frame.x_star_m:.3g} m. By "
            "these factors the frame overturns: they are not design values, and the design must "
            "change (a stiffer or wider frame, or a smaller δ*)."
        )
        stated.warnings.append(text)
        items.append(Note(text, "warning"))
    if state["delta_star"] == "below x_c":
        text = (
            f"δ* = {opts.delta_star_m:.3g} m is below the uplift amplitude x_c = "
            f"{frame.x_c_m:.3g} m: at its design displacement the frame does not step."
        )
        stated.warnings.append(text)
        items.append(Note(text, "warning"))
    return items


__all__ = ["DEFAULT_A_MAX_FRACTION", "FramePart", "frame_band", "frame_part"]
