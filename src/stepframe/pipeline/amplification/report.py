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
from dataclasses import dataclass
from functools import partial
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import (
    SITE_PARAMETERS,
    AmplificationOptions,
    AmplificationReportOptions,
    band_without_errors,
)
from stepframe.pipeline.amplification.band import ParameterBand
from stepframe.pipeline.amplification.frame_section import FramePart, frame_part
from stepframe.pipeline.amplification.headlines import CurveMaximum, ReportNumbers
from stepframe.pipeline.amplification.site import SiteFromRecords, SiteModel
from stepframe.pipeline.reports.document import (
    Figure,
    FigureJob,
    Note,
    Report,
    Section,
    Table,
    check_report_target,
    draw_figures,
    figure_from_matplotlib,
    write_report,
)
from stepframe.pipeline.reports.provenance import Provenance, collect_provenance, command_line
from stepframe.stochastic.model import GroundMotionModel

if TYPE_CHECKING:
    from concurrent.futures import Executor

    from stepframe.pipeline.catalogue.fit_options import FitOptions

TWO_PI = 2 * math.pi

#: Frequencies checked by Monte Carlo [Hz] (N synthetic motions each): four, with the default N,
#: keep the report under 10 s (docs/benchmarks.md, Reports); more with ``monte_carlo``.
MONTE_CARLO_HZ = np.geomspace(0.2, 8.0, 4)

Items = list[Figure | Table | Note | FigureJob]

#: What a report's site may be: given parameters, a site model (the workflow's ``site`` stage,
#: with the standard errors of a site from records) or the fits of a folder of records.
Site = GroundMotionModel | SiteModel | SiteFromRecords


def model_of(site: Site) -> GroundMotionModel:
    """The site's ground-motion model."""
    return site if isinstance(site, GroundMotionModel) else site.model


def stderr_of(site: Site) -> dict[str, float]:
    """The standard errors of the site's combined parameters (none for given parameters)."""
    return {} if isinstance(site, GroundMotionModel) else dict(site.stderr)


def _hz(omega: float) -> float:
    return omega / TWO_PI


def _parameter_table(site: Site) -> pd.DataFrame:
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
    if isinstance(site, SiteModel):
        name = "combined" if site.stderr else str(site.source.get("site", "site model"))
        extra = {"peak_intensity_m_s2": site.peak_intensity_m_s2, "used": True}
        return pd.DataFrame([row(name, site.model.to_dict(), site.stderr, extra)])
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


@dataclass(frozen=True)
class ResponseCurve:
    """The response amplification of tracking oscillators over f0 (covariance method): the grid
    asked for, the points added past an edge where the curve still rose, its maxima and its band
    from the parameters' standard errors.

    Attributes
    ----------
    f0_hz
        Every frequency computed [Hz], increasing.
    table
        One row per frequency: the table of the page.
    vs_fixed, vs_stationary
        The two response amplifications [-].
    on_grid
        Whether each point is on the grid asked for.
    maxima
        :func:`~stepframe.pipeline.amplification.headlines.curve_maxima` of ``vs_fixed``.
    band
        The band from the parameters' standard errors, or None.
    """

    f0_hz: np.ndarray
    table: pd.DataFrame
    vs_fixed: np.ndarray
    vs_stationary: np.ndarray
    on_grid: np.ndarray
    maxima: list[CurveMaximum]
    band: ParameterBand | None

    @property
    def largest(self) -> CurveMaximum:
        """The largest maximum (or rising edge) of the amplification vs fixed."""
        return self.maxima[0]


@dataclass(frozen=True)
class MonteCarloCheck:
    """The covariance result against N synthetic motions at a few frequencies."""

    figure_arg: tuple[Any, ...]
    table: pd.DataFrame


def response_curve(
    model: GroundMotionModel,
    opts: AmplificationOptions,
    stderr: dict[str, float] | None = None,
    *,
    jobs: int | None = 1,
    executor: Executor | None = None,
) -> ResponseCurve:
    """Eq. 6.18 and both response amplifications over the options' f0 grid (the same
    composition as the workflow's ``amplification`` stage), continued past an edge where the
    amplification still rises (unless ``grid_only``), with the band from ``stderr`` (its Monte
    Carlo curves on ``jobs`` workers or ``executor``:
    :func:`~stepframe.pipeline.amplification.band.parameter_band`)."""
    import xarray as xr

    from stepframe.pipeline.amplification.amplify import amplification_curve
    from stepframe.pipeline.amplification.band import parameter_band
    from stepframe.pipeline.amplification.headlines import (
        ExtendedCurve,
        curve_maxima,
        extend_past_edges,
    )

    site = SiteModel(model)
    xi0 = opts.xi0_or_default
    f0_grid = np.geomspace(opts.f_min_hz, opts.f_max_hz, opts.n_frequencies)
    parts = [amplification_curve(site, f0_grid, xi0, n_steps=opts.n_steps)]

    def evaluate(f0_hz: np.ndarray) -> np.ndarray:
        parts.append(amplification_curve(site, f0_hz, xi0, n_steps=opts.n_steps))
        return np.asarray(parts[-1]["response_amplification_vs_fixed"].values)

    grid_values = np.asarray(parts[0]["response_amplification_vs_fixed"].values)
    if opts.grid_only:
        extended = ExtendedCurve(f0_grid, grid_values, np.ones(f0_grid.size, dtype=bool))
    else:
        extended = extend_past_edges(f0_grid, grid_values, evaluate)
    curve = xr.concat(parts, dim="frequency").sortby("frequency")
    f0_hz = np.asarray(curve["frequency"].values)
    vs_fixed = np.asarray(curve["response_amplification_vs_fixed"].values)
    vs_stationary = np.asarray(curve["response_amplification_vs_stationary"].values)
    band = parameter_band(
        model, stderr or {}, f0_hz, xi0, n_steps=opts.n_steps, method=opts.band,
        n_samples=opts.band_samples_or_default, seed=opts.seed, central=vs_fixed, jobs=jobs,
        executor=executor,
    )  # fmt: skip
    table = pd.DataFrame(
        {
            "f0_hz": f0_hz,
            "on_grid": extended.on_grid,
            "spectral_ratio_eq_6_18": np.asarray(curve["spectral_ratio_eq_6_18"].values),
            "response_vs_fixed": vs_fixed,
            "response_vs_stationary": vs_stationary,
        }
    )
    if band is not None:
        table["band_low"] = band.low
        table["band_high"] = band.high
    maxima = curve_maxima(f0_hz, vs_fixed)
    return ResponseCurve(f0_hz, table, vs_fixed, vs_stationary, extended.on_grid, maxima, band)


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


def site_section(site: Site, opts: AmplificationOptions) -> Section:
    """The site's parameters: per record and combined, with standard errors and flags; the
    choices that change them; the records that could not be used."""
    model = model_of(site)
    if isinstance(site, SiteFromRecords):
        source = site.combined.site.source
        origin = (
            f"from the records: the {source['statistic']} of the fits passing the plausibility "
            f"checks ({source['n_components']} of {len(site.features)}), time origin "
            f"'{site.options.t0}'"
        )
    elif isinstance(site, SiteModel) and site.stderr:
        origin = (
            f"from the workflow's records: the {site.source.get('statistic', 'median')} of "
            f"{site.source.get('n_components', 0)} fits"
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
    """Each record's measured ω_g(t) and fitted eq. 6.10 path over its evolutionary spectrum, as
    figures still to draw (:class:`FigureJob`: each reads its record, measures ω_g(t) and paints
    in a worker, :func:`amplification_report`; a site of 44 records spent 46 of its report's
    55 s drawing them one after the other)."""
    opts = site.options
    used = set(site.combined.used.index)
    figures: Items = []
    for index, row in site.features.iterrows():
        model = {key: float(row[key]) for key in MODEL_KEYS}
        name = f"{Path(str(row['file'])).name} [{row['component']}]"
        where = (
            str(site.record_path(str(row["file"]))), str(row["component"]),
            dict(site.record_options),
        )  # fmt: skip
        figures.append(
            FigureJob(
                partial(_record_path_figure, where, opts, model, name),
                key=f"omega_g_{len(figures)}",
                title=name + ("" if index in used else " (not used: flagged)"),
                alt=(
                    f"Time-frequency image of {name} with its measured dominant frequency and "
                    f"the fitted eq. 6.10 path from {_hz(model['omega_p_rad_s']):.3g} Hz down "
                    f"to {_hz(model['omega_r_rad_s']):.3g} Hz"
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


#: The fitted eq. 6.10-6.11 parameters of a features row that make its ground-motion model.
MODEL_KEYS = (
    "omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r", "t_max_s", "t_dur_s",
    "t0_s",
)  # fmt: skip


def _record_path_figure(
    where: tuple[str, str, dict[str, Any]],
    opts: FitOptions,
    model: dict[str, float],
    name: str,
) -> Any:
    """One record's ω_g(t) figure (:func:`record_paths_section`): the component read again, its
    features measured as the fit measured them, the fitted path drawn over its spectrum.
    ``where`` is the record file, its component and the options it is read with."""
    from stepframe.records import read
    from stepframe.stochastic import plots
    from stepframe.stochastic.features import record_features
    from stepframe.stochastic.spectra import evolutionary_spectrum

    file, component, record_options = where
    trace = read(file, **record_options).select(channel=component)[0]
    features = record_features(
        trace, frequency=opts.frequency, t0=opts.t0, window_s=opts.window_s, fft=opts.fft,
        omega_max_rad_s=opts.omega_max_rad_s,
    )  # fmt: skip
    fitted = GroundMotionModel(**model, alpha_reading=opts.alpha_reading)
    return plots.omega_path_figure(evolutionary_spectrum(trace), features, fitted, name=name)


def spectral_ratio_section(
    model: GroundMotionModel, name: str, opts: AmplificationOptions
) -> Section:
    """Eq. 6.18 with eq. 6.19's two approximations (the paper's figure), over the f0 grid's
    range widened to hold the site's f_r and f_p."""
    from stepframe.stochastic import plots
    from stepframe.stochastic.amplification import approx_eq_6_19_first, approx_eq_6_19_last

    first, last = approx_eq_6_19_first(model), approx_eq_6_19_last(model)
    low, high = plots.frequency_range_hz(model, opts.f_min_hz, opts.f_max_hz)
    return Section(
        "Spectral ratio, eq. 6.18 (the paper's figure)",
        [
            figure_from_matplotlib(
                plots.spectral_ratio_figure(model, site=name, range_hz=(low, high)),
                key="spectral_ratio",
                title=f"Spectral ratio against oscillator frequency, {low:.3g}-{high:.3g} Hz",
                alt=(
                    f"Log-log plot of the eq. 6.18 spectral ratio from {low:.3g} to {high:.3g} Hz "
                    f"with horizontal lines at eq. 6.19's approximations {first:.3g} and "
                    f"{last:.3g} and the site's f_p, f_s, f_r marked"
                ),
                how_to_read=(
                    "Eq. 6.18 compares the ground-motion spectral density at the moving "
                    "oscillator frequency with that at the fixed one, at t_max. It is a ratio "
                    "of spectral densities, not of responses, and it is not monotone in f_0; "
                    "eq. 6.19's approximations are the horizontal lines. Dotted verticals are "
                    "the site's f_p, f_s, f_r, named on the scale above the plot; the range "
                    "holds all three, beyond the f0 grid if need be."
                ),
            ),
            Note(
                "Eq. 6.18 is not the 'response amplified up to three times' of Beck and "
                "Papadimitriou: that is the response amplification in the next section."
            ),
        ],
    )


def _maxima_text(curve: ResponseCurve) -> str:
    """The maxima of the curve in words, largest first, saying which are edges."""
    interior = [m for m in curve.maxima if m.interior]
    edges = [m for m in curve.maxima if not m.interior]
    parts = [m.describe() for m in interior]
    parts += [m.describe() for m in edges]
    return "; ".join(parts)


def response_section(
    model: GroundMotionModel,
    name: str,
    curve: ResponseCurve,
    check: MonteCarloCheck | None,
    frame: FramePart | None,
    opts: AmplificationOptions,
) -> Section:
    """The response amplification against f0 with its band (figure and table) and the Monte
    Carlo check."""
    from stepframe.stochastic import plots

    mc_arg = check.figure_arg if check is not None else None
    band = curve.band
    band_arg = None
    if band is not None:
        label = f"{100 * band.confidence:g} % band, parameters' standard errors " + (
            "(delta method)" if band.method == "delta" else f"(N = {band.n_curves} sets)"
        )
        band_arg = (band.low, band.high, label)
    grid = curve.f0_hz[curve.on_grid]
    extended = not bool(np.all(curve.on_grid))
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
                parameter_band=band_arg,
                on_grid=curve.on_grid,
            ),
            key="response_amplification",
            title="Response amplification against frequency",
            alt=(
                "Response amplification of a tracking oscillator against its small-amplitude "
                f"frequency from {curve.f0_hz[0]:.3g} to {curve.f0_hz[-1]:.3g} Hz; maxima: "
                + _maxima_text(curve)
                + (", with its band from the parameters' standard errors" if band else "")
                + (", with Monte Carlo intervals" if mc_arg else "")
                + (", the frame's band shaded" if frame else "")
            ),
            how_to_read=(
                "The solid red line is the peak RMS response of an oscillator whose frequency "
                "falls with the ground's, divided by that of a fixed oscillator (exact covariance "
                "method); dashed: divided by the stationary RMS. "
                + (
                    f"The shaded red band is where the solid line lies, with "
                    f"{100 * band.confidence:g} % confidence, given the standard errors of the "
                    "site's parameters (" + band.describe() + "): it is the uncertainty of the "
                    "site, not of the method. "
                    if band is not None
                    else "No band: the site's parameters came without standard errors. "
                )
                + (
                    "Black squares with bars check the method: the Monte Carlo median and 95 % "
                    "interval of the same ratio from synthetic motions; they should sit on the "
                    "solid line. "
                    if mc_arg
                    else "(No Monte Carlo check was asked for.) "
                )
                + (
                    f"The grid asked for ({grid[0]:.3g}-{grid[-1]:.3g} Hz, thin dashed "
                    "verticals) was extended where the curve still rose at an edge, until it "
                    "turned or a decade past the edge. "
                    if extended
                    else ""
                )
                + "With a frame, its band is shaded and its frame-driven point drawn (open, "
                "with an arrow up, when the run overturned and the value is only a lower bound)."
            ),
        ),
        Table(
            "amplification",
            "Amplification by oscillator frequency",
            curve.table,
            "Spectral ratio and response amplification (covariance method)"
            + (f", with the {100 * band.confidence:g} % band" if band else ""),
            {
                "f0_hz": "small-amplitude oscillator frequency [Hz]",
                "on_grid": "on the f0 grid asked for (no: added past an edge where the curve "
                "still rose, to find its maximum)",
                "spectral_ratio_eq_6_18": "eq. 6.18 ratio of spectral densities [-]",
                "response_vs_fixed": "peak RMS, moving / fixed oscillator [-]",
                "response_vs_stationary": "peak RMS, moving / stationary RMS [-]",
                "band_low": "lower edge of the band from the parameters' standard errors [-]",
                "band_high": "upper edge of the band from the parameters' standard errors [-]",
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
                f"(seed {opts.seed}): a check of the covariance method",
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


def _site_frequencies_text(model: GroundMotionModel, curve: ResponseCurve) -> str:
    """f_p, f_s, f_r in Hz, each outside the computed f0 range said so."""
    low, high = float(curve.f0_hz[0]), float(curve.f0_hz[-1])
    words = []
    for omega in (model.omega_p_rad_s, model.omega_s_rad_s, model.omega_r_rad_s):
        f = _hz(omega)
        where = " (above the f0 range)" if f > high else " (below the f0 range)" if f < low else ""
        words.append(f"{f:.3g}{where}")
    return ", ".join(words) + " Hz"


def _site_statement(
    site: Site, name: str, curve: ResponseCurve, opts: AmplificationOptions
) -> ReportNumbers:
    """The summary lines and numbers about the site and the curve: maxima only where they are
    maxima, the band, the site's frequencies (said when outside the computed range)."""
    from stepframe.stochastic.amplification import approx_eq_6_19_first, approx_eq_6_19_last

    model = model_of(site)
    first, last = approx_eq_6_19_first(model), approx_eq_6_19_last(model)
    largest = curve.largest
    grid = curve.f0_hz[curve.on_grid]
    numbers: dict[str, Any] = {
        "site": name,
        "ground_motion_model": model.to_dict(),
        "approx_eq_6_19_first": first,
        "approx_eq_6_19_last": last,
        "max_response_vs_fixed": largest.value,
        "max_response_vs_fixed_at_hz": largest.f0_hz,
        "max_response_vs_fixed_is_maximum": largest.interior,
        "response_maxima": [
            {"f0_hz": m.f0_hz, "value": m.value, "kind": m.kind} for m in curve.maxima
        ],
        "f0_grid_hz": [float(grid[0]), float(grid[-1])],
        "f0_range_hz": [float(curve.f0_hz[0]), float(curve.f0_hz[-1])],
        "xi0": opts.xi0_or_default,
        "alpha_reading": model.alpha_reading,
    }
    if isinstance(site, SiteFromRecords):
        used = site.combined.site.source["n_components"]
        count = len(site.features)
        source = f"{count} record component{'s' * (count != 1)}, {used} used"
        numbers["site_statistic"] = site.combined.site.source["statistic"]
    elif isinstance(site, SiteModel) and site.stderr:
        used = site.source.get("n_components", 0)
        source = f"the workflow's records, {used} component{'s' * (used != 1)} used"
        numbers["site_statistic"] = site.source.get("statistic")
    else:
        source = "given parameters"
    extended = not bool(np.all(curve.on_grid))
    summary = [
        ("Site", name),
        ("Source", source),
        ("f_p, f_s, f_r", _site_frequencies_text(model, curve)),
        ("ξ_p, ξ_r", f"{model.xi_p:.3g}, {model.xi_r:.3g}"),
        ("Eq. 6.19 first / last (ω_p/ω_s)²", f"{first:.3g} / {last:.3g}"),
        (
            "Response amplification vs fixed, maxima",
            _maxima_text(curve)
            + f" (ξ_0 = {opts.xi0_or_default:.3g}"
            + (
                f"; the grid {grid[0]:.3g}-{grid[-1]:.3g} Hz extended to "
                f"{curve.f0_hz[0]:.3g}-{curve.f0_hz[-1]:.3g} Hz where the curve still rose)"
                if extended
                else ")"
            ),
        ),
    ]
    band = curve.band
    if band is not None:
        at = int(np.argmin(np.abs(curve.f0_hz - largest.f0_hz)))
        summary.append(
            (
                "Band from the parameters' standard errors",
                f"{largest.value:.3g} [{band.low[at]:.3g}, {band.high[at]:.3g}] at "
                f"{largest.f0_hz:.3g} Hz ({band.describe()})",
            )
        )
        numbers["band"] = {
            "method": band.method,
            "confidence": band.confidence,
            "varied": list(band.varied),
            "n_curves": band.n_curves,
            "n_rejected": band.n_rejected,
            "grid_steps": list(band.grid_steps),
            "at_largest": [float(band.low[at]), float(band.high[at])],
        }
    else:
        summary.append(
            (
                "Band from the parameters' standard errors",
                "none: "
                + (
                    "not asked for (band = none)"
                    if opts.band == "none"
                    else "the site's parameters came without standard errors"
                ),
            )
        )
    summary.append(("α_g(t_max) reading", _alpha_text(model.alpha_reading)))
    return ReportNumbers(summary, numbers)


def amplification_report(
    site: Site,
    *,
    frame: Any = None,
    options: AmplificationOptions | None = None,
    provenance: Provenance,
    jobs: int | None = 1,
    executor: Executor | None = None,
) -> Report:
    """Compute everything an amplification report shows and assemble it (no file written).

    The steps of docs/reports.md: the site's parameters, each record's ω_g(t), eq. 6.18, the
    response amplification with its band and Monte Carlo check, and the frame.

    Parameters
    ----------
    site
        The site: a ground-motion model (from parameters), a
        :class:`~stepframe.pipeline.amplification.site.SiteModel` (the workflow's, with the
        standard errors of a site from records) or the fits of its records
        (:func:`stepframe.pipeline.amplification.site.site_from_records`).
    frame
        A :class:`stepframe.structure.frame.PortalFrame`, or None.
    options
        The analysis (:class:`~stepframe.pipeline.amplification.analysis.AmplificationOptions`).
    provenance
        How the report was made.
    jobs, executor
        Where the band's Monte Carlo curves are computed (:func:`response_curve`; default this
        process): the same report on any number of workers.
    """
    from stepframe.pipeline.amplification.frame_section import check_design_displacement

    opts = options or AmplificationOptions()
    if frame is not None:
        check_design_displacement(frame, opts.delta_star_m)  # before the curves are computed
    model = model_of(site)
    name = opts.site_name or "site"
    curve = response_curve(model, opts, stderr_of(site), jobs=jobs, executor=executor)
    stated = _site_statement(site, name, curve, opts)
    frame_result = None
    if frame is not None:
        intensity = 1.0 if isinstance(site, GroundMotionModel) else site.peak_intensity_m_s2
        frame_result = frame_part(frame, model, intensity, opts, stated)
    sections = [site_section(site, opts)]
    if isinstance(site, SiteFromRecords):
        sections.append(record_paths_section(site))
    sections.append(spectral_ratio_section(model, name, opts))
    check = monte_carlo_check(model, opts)
    sections.append(response_section(model, name, curve, check, frame_result, opts))
    if frame_result is not None:
        sections.append(Section("Frame", frame_result.items))
    stated.numbers["warnings"] = list(stated.warnings)
    sections, _ = draw_figures(sections, jobs=jobs, executor=executor)
    return Report(
        title=f"Site amplification report: {name}",
        subtitle="Moving resonance under the Beck-Papadimitriou ground-motion model "
        "(Alimoradi and Beck 2025, eqs. 6.10-6.19)",
        summary=stated.summary,
        sections=sections,
        provenance=provenance,
        numbers=stated.numbers,
        warnings=stated.warnings,
    )


def _alpha_text(reading: str) -> str:
    if reading == "paper":
        return "the paper's: the α_g ramp ends at t_max, so α_g(t_max) = ω_r ξ_r"
    return "eq. 6.11 as printed: the α_g ramp ends at t_dur"


def write_amplification_report(
    site: Site,
    out_html: str | PathLike[str],
    *,
    frame: Any = None,
    options: AmplificationOptions | None = None,
    provenance: Provenance,
    jobs: int | None = 1,
    executor: Executor | None = None,
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
    jobs, executor
        As :func:`amplification_report`.

    Returns
    -------
    pathlib.Path
        The HTML file.
    """
    check_report_target(out_html)  # before the curves, not after them
    report = amplification_report(
        site, frame=frame, options=options, provenance=provenance, jobs=jobs, executor=executor
    )
    return write_report(report, out_html)


def _site_of(
    o: AmplificationReportOptions, jobs: int | None
) -> tuple[GroundMotionModel | SiteFromRecords, str]:
    """The site of a report's options (parameters or a records folder, its records fitted on
    ``jobs`` workers) and its name."""
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
            statistic=o.statistic, plausible_only=o.plausible_only, jobs=jobs,
        )  # fmt: skip
        return site, o.site_name or Path(o.records).resolve().name
    # what reads records, set where there are none: an error, not a silent no-op
    band = band_without_errors(o)
    for flag, set_here in (
        (f"--t0 {o.t0}", o.t0 != "auto"),
        (f"--format {o.record_format}", o.record_format is not None),
        (f"--units {o.units}", o.units is not None),
        ("--band delta", band == "band"),
        (f"--band-samples {o.band_samples}", band == "band_samples"),
    ):
        if set_here:
            raise InputError(
                f"{flag} with the site given by its parameters, expected it only with --records "
                "DIR (it applies to the records read and fitted"
                + ("; parameters have no standard errors, so no band)" if "band" in flag else ")")
            )
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


def make_amplification_report(
    out_html: str, options: AmplificationReportOptions, *, jobs: int | None = None
) -> Path:
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
    jobs
        Worker processes for the records' fits and the band's Monte Carlo curves (None: all
        CPUs, as ``--jobs``; the same report on any number).

    Returns
    -------
    pathlib.Path
        The HTML file.
    """
    from dataclasses import fields, replace

    from stepframe.core.options import arguments_of

    o = options
    check_report_target(out_html)  # before the records are fitted and the curves computed
    if o.frame is None and o.delta_star_m is not None:
        raise InputError("--delta-star-m without --frame, expected --frame FRAME.toml with it")
    if o.frame is None and o.peak_intensity_m_s2 is not None:  # as stochastic amplify's
        raise InputError(
            "--peak-intensity-m-s2 without --frame, expected --frame FRAME.toml with it (it "
            "scales the frame-driven run; the response ratios do not depend on it)"
        )
    portal = None
    if o.frame is not None:
        from stepframe.pipeline.amplification.frame_section import check_design_displacement
        from stepframe.structure.frame_file import read_frame_file

        portal = read_frame_file(o.frame)
        check_design_displacement(portal, o.delta_star_m)  # before the records are fitted
    site, name = _site_of(o, jobs)
    inputs = [path for path in (o.records, o.frame) if path is not None]
    analysis = AmplificationOptions(
        **{f.name: getattr(o, f.name) for f in fields(AmplificationOptions)}
    )
    analysis = replace(analysis, site_name=name)
    recorded = arguments_of(o)
    command = command_line(["stepframe", "report", "amplification"], recorded | {"out": out_html})
    provenance = collect_provenance(command, inputs=inputs, parameters=recorded)
    return write_amplification_report(
        site, out_html, frame=portal, options=analysis, provenance=provenance, jobs=jobs
    )
