"""The site amplification report: parameters, ω_g(t) over each record, eqs. 6.18-6.19, response.

What it shows (docs/reports.md), one step each: the site's parameters (per record and combined,
with standard errors and flags: :func:`site_section`), each record's fitted ω_g(t) over its
evolutionary spectrum (:func:`record_paths_section`), the eq. 6.18 spectral ratio with eq. 6.19's
two approximations, the paper's figure (:func:`spectral_ratio_section`), the response
amplification by the covariance method with its Monte Carlo check (:func:`response_curve`,
:func:`monte_carlo_check`, :func:`response_section`) and, with a frame, its band, the
frame-driven amplification and the adjusted design displacement (:func:`frame_part`). The two
kinds of amplification are named for what they are (DESIGN.md): eq. 6.18 is a ratio of spectral
densities, not of responses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import (
    SITE_PARAMETERS,
    AmplificationOptions,
    AmplificationReportOptions,
)
from stepframe.pipeline.amplification.site import SiteFromRecords
from stepframe.pipeline.reports.document import (
    Figure,
    Note,
    Report,
    Section,
    Table,
    figure_from_matplotlib,
    write_report,
)
from stepframe.pipeline.reports.provenance import Provenance, collect_provenance, command_line
from stepframe.stochastic.model import GroundMotionModel

TWO_PI = 2 * math.pi

#: Default amplitude limit of the band without a design displacement: this fraction of the way
#: from the uplift amplitude x_c to the overturning amplitude x* (below x_c the frame does not step
#: and its period does not change, so a limit there would give an empty band).
DEFAULT_A_MAX_FRACTION = 0.5

#: Frequencies checked by Monte Carlo [Hz] (N synthetic motions each): four, with the default N,
#: keep the report under 10 s (docs/benchmarks.md, Reports); more with ``monte_carlo``.
MONTE_CARLO_HZ = np.geomspace(0.2, 8.0, 4)

Items = list[Figure | Table | Note]


def _hz(omega: float) -> float:
    return omega / TWO_PI


def _parameter_table(site: GroundMotionModel | SiteFromRecords) -> pd.DataFrame:
    def row(name: str, values: Any, se: Any, extra: dict[str, Any]) -> dict[str, Any]:
        out: dict[str, Any] = {"record": name}
        for key, label in (
            ("omega_p_rad_s", "f_p_hz"),
            ("omega_s_rad_s", "f_s_hz"),
            ("omega_r_rad_s", "f_r_hz"),
        ):
            out[label] = _hz(values[key])
            out[label + "_se"] = _hz(se.get(key, math.nan))
        for key in ("xi_p", "xi_r"):
            out[key] = values[key]
            out[key + "_se"] = se.get(key, math.nan)
        for key in ("t_max_s", "t_dur_s", "t0_s"):
            out[key] = values[key]
        return out | extra

    if isinstance(site, GroundMotionModel):
        return pd.DataFrame([row("given parameters", site.to_dict(), {}, {"used": True})])
    used = set(site.combined.used.index)
    rows = [
        row(
            f"{Path(str(r['file'])).name} [{r['component']}]",
            r,
            {str(k).removesuffix("_stderr"): r[k] for k in r.index if str(k).endswith("_stderr")},
            {
                "fit_quality": r["fit_quality"],
                "peak_intensity_m_s2": r["max_intensity_m_s2"],
                "used": index in used,
                "flags": str(r["flags"]).replace(";", ", "),
                "implausible_reason": r["implausible_reason"],
            },
        )
        for index, r in site.features.iterrows()
    ]
    combined = {**site.model.to_dict(), "t0_s": math.nan}
    extra = {"fit_quality": math.nan, "peak_intensity_m_s2": site.peak_intensity_m_s2}
    rows.append(row("combined", combined, site.stderr, extra | {"used": True}))
    return pd.DataFrame(rows)


PARAMETER_COLUMNS = {
    "record": "record file [component], or 'combined' (the statistic of the used fits)",
    "f_p_hz": "P-wave dominant frequency ω_p/2π [Hz]",
    "f_s_hz": "S-wave dominant frequency ω_s/2π (ω_g at t_max) [Hz]",
    "f_r_hz": "surface-wave dominant frequency ω_r/2π [Hz]",
    "xi_p": "bandwidth ratio at ω_p [-]",
    "xi_r": "bandwidth ratio at ω_r [-]",
    "t_max_s": "time of peak intensity after t0 [s] (combined: median)",
    "t_dur_s": "strong-motion duration after t0 [s] (combined: median)",
    "t0_s": "time origin in record time [s]",
    "fit_quality": "weighted RMS relative misfit of ω_g(t) [-]",
    "peak_intensity_m_s2": "peak RMS intensity I_g [m/s²] (combined: median)",
    "used": "whether the fit enters the combined parameters (it passes the plausibility checks)",
    "flags": "quality flags of the features and the fit",
    "implausible_reason": "why a fit is not used (empty when it is)",
}
for _key in ("f_p_hz", "f_s_hz", "f_r_hz", "xi_p", "xi_r"):
    PARAMETER_COLUMNS[_key + "_se"] = f"standard error of {_key} (same unit)"


def _frame_band(frame: Any, a_max_m: float) -> tuple[float, float]:
    """[ω(A_max), ω_1] of the frame [rad/s]."""
    from stepframe.structure.period_amplitude import period_amplitude

    period = float(period_amplitude(frame, a_max_m, beyond_x_star="inf"))
    return TWO_PI / period, frame.omega_1_rad_s


@dataclass
class ReportNumbers:
    """What the report states in its summary and ``numbers.json``, filled step by step."""

    summary: list[tuple[str, str]] = field(default_factory=list)
    numbers: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class ResponseCurve:
    """The response amplification of tracking oscillators over the f0 grid (covariance method)."""

    f0_hz: np.ndarray
    table: pd.DataFrame
    vs_fixed: np.ndarray
    vs_stationary: np.ndarray

    @property
    def peak(self) -> int:
        """Index of the largest amplification vs fixed."""
        return int(np.argmax(self.vs_fixed))


@dataclass(frozen=True)
class MonteCarloCheck:
    """The covariance result against N synthetic motions at a few frequencies."""

    figure_arg: tuple[Any, ...]
    table: pd.DataFrame


@dataclass(frozen=True)
class FramePart:
    """With a frame: its band [Hz], its frame-driven point (f_1, value, lower bound), its
    section items."""

    band_hz: tuple[float, float]
    point: tuple[float, float, bool]
    items: Items


def response_curve(model: GroundMotionModel, opts: AmplificationOptions) -> ResponseCurve:
    """Eq. 6.18 and both response amplifications over the options' f0 grid (the same
    composition as the workflow's ``amplification`` stage)."""
    from stepframe.pipeline.amplification.amplify import amplification_curve
    from stepframe.pipeline.amplification.site import SiteModel

    f0_hz = np.geomspace(opts.f_min_hz, opts.f_max_hz, opts.n_frequencies)
    curve = amplification_curve(SiteModel(model), f0_hz, opts.xi0_or_default, n_steps=opts.n_steps)
    vs_fixed = np.asarray(curve["response_amplification_vs_fixed"].values)
    vs_stationary = np.asarray(curve["response_amplification_vs_stationary"].values)
    table = pd.DataFrame(
        {
            "f0_hz": f0_hz,
            "spectral_ratio_eq_6_18": np.asarray(curve["spectral_ratio_eq_6_18"].values),
            "response_vs_fixed": vs_fixed,
            "response_vs_stationary": vs_stationary,
        }
    )
    return ResponseCurve(f0_hz, table, vs_fixed, vs_stationary)


def monte_carlo_check(
    model: GroundMotionModel, opts: AmplificationOptions
) -> MonteCarloCheck | None:
    """The covariance method against ``opts.report_monte_carlo`` synthetic motions at
    :data:`MONTE_CARLO_HZ` (None when the report asks for none)."""
    from stepframe.stochastic.amplification import response_amplification
    from stepframe.stochastic.mean_square import analysis_grid

    count = opts.report_monte_carlo
    if not count:
        return None
    grid = analysis_grid(model, n_steps=opts.n_steps)
    omega = TWO_PI * MONTE_CARLO_HZ
    mc = response_amplification(
        model, omega, opts.xi0_or_default, time_s=grid, method="monte-carlo",
        n_realisations=count, seed=opts.seed,
    )  # fmt: skip
    assert mc.vs_fixed_band is not None
    covariance_at = response_amplification(model, omega, opts.xi0_or_default, time_s=grid)
    table = pd.DataFrame(
        {
            "f0_hz": MONTE_CARLO_HZ,
            "covariance_vs_fixed": covariance_at.vs_fixed,
            "monte_carlo_vs_fixed": mc.vs_fixed,
            "interval_low": mc.vs_fixed_band[:, 0],
            "interval_high": mc.vs_fixed_band[:, 1],
            "n_realisations": count,
        }
    )
    return MonteCarloCheck((MONTE_CARLO_HZ, mc.vs_fixed, mc.vs_fixed_band, count), table)


def site_section(site: GroundMotionModel | SiteFromRecords, opts: AmplificationOptions) -> Section:
    """The site's parameters: per record and combined, with standard errors and flags; the
    choices that change them; the records that could not be used."""
    model = site.model if isinstance(site, SiteFromRecords) else site
    if isinstance(site, SiteFromRecords):
        source = site.combined.site.source
        origin = (
            f"from the records: the {source['statistic']} of the fits passing the plausibility "
            f"checks ({source['n_components']} of {len(site.features)}), time origin "
            f"'{site.options.t0}'"
        )
    else:
        origin = "as given"
    items: Items = [
        Table(
            "parameters",
            "Beck-Papadimitriou parameters (eqs. 6.10-6.11)",
            _parameter_table(site),
            "Per record and combined, with standard errors and flags",
            PARAMETER_COLUMNS,
            sortable=True,
        ),
        Note(
            f"Choices that change these numbers: α_g(t_max) reading '{model.alpha_reading}' "
            f"({_alpha_text(model.alpha_reading)}); the parameters {origin}; oscillator damping "
            f"ξ_0 = {opts.xi0_or_default:.3g}; {opts.n_steps} time steps."
        ),
    ]
    if isinstance(site, SiteFromRecords) and not site.failures.empty:
        from stepframe.core.results import FAILURE_COLUMNS

        items.append(
            Table(
                "failures",
                "Records that could not be used",
                site.failures,
                "Read, features or fit failures (each recorded, none stops the report)",
                FAILURE_COLUMNS,
            )
        )
    return Section("Site parameters", items)


def record_paths_section(site: SiteFromRecords) -> Section:
    """Each record's measured ω_g(t) and fitted eq. 6.10 path over its evolutionary spectrum."""
    from stepframe.records import read
    from stepframe.stochastic import plots
    from stepframe.stochastic.features import record_features
    from stepframe.stochastic.spectra import evolutionary_spectrum

    opts = site.options
    used = set(site.combined.used.index)
    figures: Items = []
    for index, row in site.features.iterrows():
        stream = read(str(row["file"]), **site.record_options)
        trace = stream.select(channel=str(row["component"]))[0]
        features = record_features(
            trace, frequency=opts.frequency, t0=opts.t0, window_s=opts.window_s,
            fft=opts.fft, omega_max_rad_s=opts.omega_max_rad_s,
        )  # fmt: skip
        model = GroundMotionModel(
            **{key: float(row[key]) for key in
               ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r",
                "t_max_s", "t_dur_s", "t0_s")},
            alpha_reading=opts.alpha_reading,
        )  # fmt: skip
        name = f"{Path(str(row['file'])).name} [{row['component']}]"
        figures.append(
            figure_from_matplotlib(
                plots.omega_path_figure(evolutionary_spectrum(trace), features, model, name=name),
                key=f"omega_g_{len(figures)}",
                title=name + ("" if index in used else " (not used: flagged)"),
                alt=(
                    f"Time-frequency image of {name} with its measured dominant frequency and "
                    f"the fitted eq. 6.10 path from {_hz(model.omega_p_rad_s):.3g} Hz down to "
                    f"{_hz(model.omega_r_rad_s):.3g} Hz"
                ),
                how_to_read=(
                    "The background is the record's short-time spectrum (bright = strong). "
                    f"Green dots are the dominant frequency measured by {opts.frequency} during "
                    "strong motion (grey outside it); the blue line is the fitted ω_g(t) of eq. "
                    "6.10. A good fit follows the green dots and the bright ridge; dashed and "
                    "dotted lines mark t_max and t_dur."
                ),
            )
        )
    return Section("Dominant frequency ω_g(t) over each record's evolutionary spectrum", figures)


def spectral_ratio_section(model: GroundMotionModel, name: str) -> Section:
    """Eq. 6.18 over the f0 range with eq. 6.19's two approximations (the paper's figure)."""
    from stepframe.stochastic import plots
    from stepframe.stochastic.amplification import approx_eq_6_19_first, approx_eq_6_19_last

    first, last = approx_eq_6_19_first(model), approx_eq_6_19_last(model)
    return Section(
        "Spectral ratio, eq. 6.18 (the paper's figure)",
        [
            figure_from_matplotlib(
                plots.spectral_ratio_figure(model, site=name),
                key="spectral_ratio",
                title="Spectral ratio against oscillator frequency, 0.1-10 Hz",
                alt=(
                    f"Log-log plot of the eq. 6.18 spectral ratio from 0.1 to 10 Hz with "
                    f"horizontal lines at eq. 6.19's approximations {first:.3g} and {last:.3g} "
                    "and the site's f_p, f_s, f_r marked"
                ),
                how_to_read=(
                    "Eq. 6.18 compares the ground-motion spectral density at the moving "
                    "oscillator frequency with that at the fixed one, at t_max. It is a ratio "
                    "of spectral densities, not of responses, and it is not monotone in f_0; "
                    "eq. 6.19's approximations are the horizontal lines. Dotted verticals are "
                    "the site's f_p, f_s, f_r."
                ),
            ),
            Note(
                "Eq. 6.18 is not the 'response amplified up to three times' of Beck and "
                "Papadimitriou: that is the response amplification in the next section."
            ),
        ],
    )


def _frame_rows(frame: Any, band: tuple[float, float], a_max: float, intensity: float,
                driven: Any) -> list[dict[str, Any]]:  # fmt: skip
    lo, hi = band
    return [
        {"quantity": "small-amplitude frequency f_1", "value": _hz(hi), "unit": "Hz"},
        {"quantity": "band lower edge f(A_max)", "value": _hz(lo), "unit": "Hz"},
        {"quantity": "amplitude limit A_max", "value": a_max, "unit": "m"},
        {"quantity": "uplift amplitude x_c", "value": frame.x_c_m, "unit": "m"},
        {"quantity": "overturning amplitude x*", "value": frame.x_star_m, "unit": "m"},
        {"quantity": "peak intensity of the run (× p_1)", "value": intensity * frame.p_1,
         "unit": "m/s²"},
        {"quantity": "frame-driven response amplification vs fixed",
         "value": float(driven.vs_fixed[0]), "unit": "-"},
        {"quantity": "status of the frame-driven run", "value": driven.moving.status,
         "unit": ""},
    ]  # fmt: skip


def _amplitude_limit(frame: Any, opts: AmplificationOptions) -> float:
    """A_max [m]: the design displacement δ*, else a fixed fraction of the way to x*."""
    x_star = frame.x_star_m
    if opts.delta_star_m is None:
        return float(frame.x_c_m + DEFAULT_A_MAX_FRACTION * (x_star - frame.x_c_m))
    if opts.delta_star_m >= x_star:
        raise InputError(
            f"delta_star_m = {opts.delta_star_m} m ≥ x* = {x_star:.4g} m, expected a design "
            "displacement below x* (the frame overturns there)"
        )
    return opts.delta_star_m


def frame_part(
    frame: Any,
    model: GroundMotionModel,
    peak_intensity_m_s2: float,
    opts: AmplificationOptions,
    stated: ReportNumbers,
) -> FramePart:
    """The frame's band from its period-amplitude law, its frame-driven amplification (exact
    covariance method) and, with δ*, the adjusted design displacement."""
    from stepframe.stochastic.amplification import response_amplification
    from stepframe.stochastic.mean_square import FrameDriven, analysis_grid
    from stepframe.structure.period_amplitude import period_amplitude

    a_max = _amplitude_limit(frame, opts)
    lo, hi = _frame_band(frame, a_max)

    def period_s(amplitude_m: float) -> float:
        return float(period_amplitude(frame, amplitude_m, beyond_x_star="inf"))

    intensity = opts.peak_intensity_m_s2 or peak_intensity_m_s2
    driven = response_amplification(
        model, None, frame.xi_1, frame=FrameDriven(period_s),
        peak_intensity=intensity * frame.p_1, time_s=analysis_grid(model, n_steps=opts.n_steps),
    )  # fmt: skip
    lower = driven.moving.status != "ok"
    rows = _frame_rows(frame, (lo, hi), a_max, intensity, driven)
    stated.numbers["frame"] = {row["quantity"]: row["value"] for row in rows}
    stated.numbers["frame_driven_lower_bound"] = lower
    stated.summary.append(
        ("Frame's band", f"{_hz(lo):.3g}-{_hz(hi):.3g} Hz (A_max = {a_max:.3g} m)")
    )
    stated.summary.append(
        (
            "Frame-driven response amplification",
            ("≥ " if lower else "")
            + f"{driven.vs_fixed[0]:.3g}"
            + (" (lower bound: the frame overturned)" if lower else ""),
        )
    )
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
            "Band from the period-amplitude law, frame-driven amplification",
            {"quantity": "what", "value": "the number", "unit": "its unit"},
        ),
        Note(
            f"The band is [f(A_max), f_1] with A_max = {a_max:.3g} m from {source}. "
            + (
                "The frame-driven run overturned (reached x*) before the motion ended: its "
                "amplification is only a lower bound and is drawn as an open marker with an "
                "arrow."
                if lower
                else "The frame-driven run stayed below x*."
            ),
            "warning" if lower else "note",
        ),
    ]
    if opts.delta_star_m is not None:
        items.append(_adjusted_design(frame, model, opts, stated))
    point = (_hz(frame.omega_1_rad_s), float(driven.vs_fixed[0]), lower)
    return FramePart((_hz(lo), _hz(hi)), point, items)


def _adjusted_design(
    frame: Any, model: GroundMotionModel, opts: AmplificationOptions, stated: ReportNumbers
) -> Table:
    """The quasi-dynamic δ* adjusted for moving resonance by each amplification factor."""
    from stepframe.stochastic.amplification import adjusted_fixed_point

    assert opts.delta_star_m is not None
    adjusted = []
    for factor, meaning in (
        ("eq-6-19-last", "√((ω_p/ω_s)²) · δ*"),
        ("eq-6-19-first", "√(eq. 6.19 first) · δ*"),
        ("eq-6-18", "√(eq. 6.18 at ω_1) · δ*"),
        ("response-vs-fixed", "response amplification at ω_1 (covariance) · δ*"),
    ):
        value = adjusted_fixed_point(
            opts.delta_star_m, model, factor=factor,  # type: ignore[arg-type]
            omega_0_rad_s=frame.omega_1_rad_s,
            xi0=frame.xi_1 if frame.xi_1 > 0 else opts.xi0_or_default,
        )  # fmt: skip
        adjusted.append({"factor": factor, "rule": meaning, "adjusted_delta_m": value})
    table = pd.DataFrame(adjusted)
    table.insert(2, "delta_star_m", opts.delta_star_m)
    by = {row["factor"]: row["adjusted_delta_m"] for row in adjusted}
    stated.numbers["adjusted_design_displacement_m"] = by
    stated.summary.append(
        (
            "Adjusted design displacement",
            f"δ* = {opts.delta_star_m:.3g} m → {by['eq-6-19-last']:.3g} m by (ω_p/ω_s)², "
            f"{by['response-vs-fixed']:.3g} m by the response amplification at f_1",
        )
    )
    return Table(
        "adjusted_design_displacement",
        "Adjusted design displacement",
        table,
        "The quasi-dynamic δ* adjusted for moving resonance, by each factor",
        {
            "factor": "which amplification",
            "rule": "how it adjusts δ* (spectral factors are mean-square ratios)",
            "delta_star_m": "the unadjusted design displacement δ* [m]",
            "adjusted_delta_m": "δ* adjusted [m]",
        },
    )


def response_section(
    model: GroundMotionModel,
    name: str,
    curve: ResponseCurve,
    check: MonteCarloCheck | None,
    frame: FramePart | None,
    opts: AmplificationOptions,
) -> Section:
    """The response amplification against f0 (figure and table) and the Monte Carlo check."""
    from stepframe.stochastic import plots

    peak = curve.peak
    mc_arg = check.figure_arg if check is not None else None
    items: Items = [
        figure_from_matplotlib(
            plots.response_amplification_figure(
                curve.f0_hz,
                curve.vs_fixed,
                curve.vs_stationary,
                model,
                site=name,
                xi0=opts.xi0_or_default,
                monte_carlo=mc_arg,
                band_hz=frame.band_hz if frame else None,
                frame_point=frame.point if frame else None,
            ),
            key="response_amplification",
            title="Response amplification against frequency",
            alt=(
                "Response amplification of a tracking oscillator against its small-amplitude "
                f"frequency from {opts.f_min_hz:g} to {opts.f_max_hz:g} Hz; largest "
                f"{curve.vs_fixed[peak]:.3g} at {curve.f0_hz[peak]:.3g} Hz"
                + (", with Monte Carlo intervals" if mc_arg else "")
                + (", the frame's band shaded" if frame else "")
            ),
            how_to_read=(
                "The solid red line is the peak RMS response of an oscillator whose frequency "
                "falls with the ground's, divided by that of a fixed oscillator (exact covariance "
                "method); dashed: divided by the stationary RMS. "
                + (
                    "Black squares with bars are the Monte Carlo median and 95 % interval from "
                    "synthetic motions; they should sit on the solid line. "
                    if mc_arg
                    else "(No Monte Carlo check was asked for.) "
                )
                + "With a frame, its band is shaded and its frame-driven point drawn (open, "
                "with an arrow up, when the run overturned and the value is only a lower bound)."
            ),
        ),
        Table(
            "amplification",
            "Amplification by oscillator frequency",
            curve.table,
            "Spectral ratio and response amplification (covariance method)",
            {
                "f0_hz": "small-amplitude oscillator frequency [Hz]",
                "spectral_ratio_eq_6_18": "eq. 6.18 ratio of spectral densities [-]",
                "response_vs_fixed": "peak RMS, moving / fixed oscillator [-]",
                "response_vs_stationary": "peak RMS, moving / stationary RMS [-]",
            },
            sortable=True,
        ),
    ]
    if check is not None:
        items.append(
            Table(
                "monte_carlo",
                "Monte Carlo check",
                check.table,
                f"Median and 95 % interval of N = {opts.report_monte_carlo} synthetic motions "
                f"(seed {opts.seed})",
                {
                    "f0_hz": "oscillator frequency [Hz]",
                    "covariance_vs_fixed": "exact covariance method [-]",
                    "monte_carlo_vs_fixed": "Monte Carlo estimate [-]",
                    "interval_low": "2.5 % point [-]",
                    "interval_high": "97.5 % point [-]",
                    "n_realisations": "synthetic motions",
                },
            )
        )
    return Section("Response amplification", items)


def _site_statement(
    site: GroundMotionModel | SiteFromRecords,
    name: str,
    curve: ResponseCurve,
    opts: AmplificationOptions,
) -> ReportNumbers:
    """The summary lines and numbers about the site and the curve."""
    from stepframe.stochastic.amplification import approx_eq_6_19_first, approx_eq_6_19_last

    model = site.model if isinstance(site, SiteFromRecords) else site
    first, last = approx_eq_6_19_first(model), approx_eq_6_19_last(model)
    peak = curve.peak
    numbers = {
        "site": name,
        "ground_motion_model": model.to_dict(),
        "approx_eq_6_19_first": first,
        "approx_eq_6_19_last": last,
        "max_response_vs_fixed": float(curve.vs_fixed[peak]),
        "max_response_vs_fixed_at_hz": float(curve.f0_hz[peak]),
        "xi0": opts.xi0_or_default,
        "alpha_reading": model.alpha_reading,
    }
    if isinstance(site, SiteFromRecords):
        used = site.combined.site.source["n_components"]
        source = f"{len(site.features)} record components, {used} used"
        numbers["site_statistic"] = site.combined.site.source["statistic"]
    else:
        source = "given parameters"
    frequencies = (model.omega_p_rad_s, model.omega_s_rad_s, model.omega_r_rad_s)
    summary = [
        ("Site", name),
        ("Source", source),
        ("f_p, f_s, f_r", ", ".join(f"{_hz(w):.3g}" for w in frequencies) + " Hz"),
        ("ξ_p, ξ_r", f"{model.xi_p:.3g}, {model.xi_r:.3g}"),
        ("Eq. 6.19 first / last (ω_p/ω_s)²", f"{first:.3g} / {last:.3g}"),
        (
            "Largest response amplification vs fixed",
            f"{curve.vs_fixed[peak]:.3g} at f_0 = {curve.f0_hz[peak]:.3g} Hz "
            f"(ξ_0 = {opts.xi0_or_default:.3g})",
        ),
        ("α_g(t_max) reading", _alpha_text(model.alpha_reading)),
    ]
    return ReportNumbers(summary, numbers)


def amplification_report(
    site: GroundMotionModel | SiteFromRecords,
    *,
    frame: Any = None,
    options: AmplificationOptions | None = None,
    provenance: Provenance,
) -> Report:
    """Compute everything an amplification report shows and assemble it (no file written).

    The steps of docs/reports.md: the site's parameters, each record's ω_g(t), eq. 6.18, the
    response amplification with its Monte Carlo check, and the frame.

    Parameters
    ----------
    site
        The site: a ground-motion model (from parameters) or the fits of its records
        (:func:`stepframe.pipeline.amplification.site.site_from_records`).
    frame
        A :class:`stepframe.structure.frame.PortalFrame`, or None.
    options
        The analysis (:class:`~stepframe.pipeline.amplification.analysis.AmplificationOptions`).
    provenance
        How the report was made.
    """
    opts = options or AmplificationOptions()
    from_records = isinstance(site, SiteFromRecords)
    model = site.model if isinstance(site, SiteFromRecords) else site
    name = opts.site_name or "site"
    curve = response_curve(model, opts)
    stated = _site_statement(site, name, curve, opts)
    frame_result = None
    if frame is not None:
        intensity = site.peak_intensity_m_s2 if isinstance(site, SiteFromRecords) else 1.0
        frame_result = frame_part(frame, model, intensity, opts, stated)
    sections = [site_section(site, opts)]
    if from_records:
        assert isinstance(site, SiteFromRecords)
        sections.append(record_paths_section(site))
    sections.append(spectral_ratio_section(model, name))
    check = monte_carlo_check(model, opts)
    sections.append(response_section(model, name, curve, check, frame_result, opts))
    if frame_result is not None:
        sections.append(Section("Frame", frame_result.items))
    return Report(
        title=f"Site amplification report: {name}",
        subtitle="Moving resonance under the Beck-Papadimitriou ground-motion model "
        "(Alimoradi and Beck 2025, eqs. 6.10-6.19)",
        summary=stated.summary,
        sections=sections,
        provenance=provenance,
        numbers=stated.numbers,
    )


def _alpha_text(reading: str) -> str:
    if reading == "paper":
        return "the paper's: the α_g ramp ends at t_max, so α_g(t_max) = ω_r ξ_r"
    return "eq. 6.11 as printed: the α_g ramp ends at t_dur"


def write_amplification_report(
    site: GroundMotionModel | SiteFromRecords,
    out_html: str | PathLike[str],
    *,
    frame: Any = None,
    options: AmplificationOptions | None = None,
    provenance: Provenance,
) -> Path:
    """Write the amplification report (HTML + ``<stem>_files/`` of its numbers), all or nothing.

    Parameters
    ----------
    site
        A ground-motion model, or
        :func:`stepframe.pipeline.amplification.site.site_from_records`.
    out_html
        The HTML file.
    frame
        Optional :class:`stepframe.structure.frame.PortalFrame`.
    options
        :class:`~stepframe.pipeline.amplification.analysis.AmplificationOptions`.
    provenance
        From :func:`stepframe.pipeline.reports.provenance.collect_provenance`.

    Returns
    -------
    pathlib.Path
        The HTML file.
    """
    report = amplification_report(site, frame=frame, options=options, provenance=provenance)
    return write_report(report, out_html)


def _site_of(o: AmplificationReportOptions) -> tuple[GroundMotionModel | SiteFromRecords, str]:
    """The site of a report's options (parameters or a records folder) and its name."""
    parameters = o.parameters
    given = [name for name in SITE_PARAMETERS if parameters[name] is not None]
    if o.records is not None:
        if given:
            raise InputError(
                f"--records with --{given[0].replace('_', '-')}, expected either the site "
                "parameters or --records"
            )
        from stepframe.pipeline.amplification.site import site_from_records
        from stepframe.pipeline.catalogue.fit_options import FitOptions

        site = site_from_records(
            o.records, options=FitOptions(t0=o.t0, alpha_reading=o.alpha_reading),
            record_options={"format": o.record_format, "units": o.units},
            statistic=o.statistic, plausible_only=o.plausible_only,
        )  # fmt: skip
        return site, o.site_name or Path(o.records).resolve().name
    missing = [name for name in SITE_PARAMETERS if parameters[name] is None]
    if missing:
        raise InputError(
            f"missing --{missing[0].replace('_', '-')}, expected all of "
            + ", ".join("--" + n.replace("_", "-") for n in SITE_PARAMETERS)
            + " or --records DIR"
        )
    values = {key: float(value) for key, value in parameters.items() if value is not None}
    model = GroundMotionModel.from_hz(
        values["fp_hz"], values["fs_hz"], values["fr_hz"], values["xi_p"], values["xi_r"],
        t_max_s=values["t_max_s"], t_dur_s=values["t_dur_s"], alpha_reading=o.alpha_reading,
    )  # fmt: skip
    return model, o.site_name or "site"


def make_amplification_report(out_html: str, options: AmplificationReportOptions) -> Path:
    """The amplification report of a site given by its parameters or by a folder of its records.

    Parameters
    ----------
    out_html
        The HTML file.
    options
        :class:`~stepframe.pipeline.amplification.analysis.AmplificationReportOptions`: all of
        :data:`~stepframe.pipeline.amplification.analysis.SITE_PARAMETERS`, or none with
        ``records`` (fitted with ``t0`` and ``alpha_reading``, read with ``record_format`` and
        ``units``, combined by ``statistic``:
        :func:`~stepframe.pipeline.amplification.site.site_from_records`); the name in titles
        (default: the records folder's name, else ``site``); an optional frame file and its
        design displacement δ* [m]; the analysis.

    Returns
    -------
    pathlib.Path
        The HTML file.
    """
    from dataclasses import fields, replace

    from stepframe.core.options import arguments_of

    o = options
    if o.frame is None and o.delta_star_m is not None:
        raise InputError("--delta-star-m without --frame, expected --frame FRAME.toml with it")
    site, name = _site_of(o)
    inputs = [path for path in (o.records, o.frame) if path is not None]
    portal = None
    if o.frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        portal = read_frame_file(o.frame)
    analysis = AmplificationOptions(
        **{f.name: getattr(o, f.name) for f in fields(AmplificationOptions)}
    )
    analysis = replace(analysis, site_name=name)
    recorded = arguments_of(o)
    command = command_line(["stepframe", "report", "amplification"], recorded | {"out": out_html})
    provenance = collect_provenance(command, inputs=inputs, parameters=recorded)
    return write_amplification_report(
        site, out_html, frame=portal, options=analysis, provenance=provenance
    )
