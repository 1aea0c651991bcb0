"""The site amplification report: parameters, ω_g(t) over each record, eqs. 6.18-6.19, response.

What it shows (issue 14): the site's parameters (per record and combined, with standard errors and
flags), each record's fitted ω_g(t) over its evolutionary spectrum, the eq. 6.18 spectral ratio
over 0.1-10 Hz with eq. 6.19's two approximations (the paper's figure), the response amplification
(covariance method) with Monte Carlo intervals and, with a frame, its band, the frame-driven
amplification and the adjusted design displacement. The two kinds of amplification are named for
what they are (DESIGN.md): eq. 6.18 is a ratio of spectral densities, not of responses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from stepframe.errors import InputError
from stepframe.pipeline.amplification.report_options import AmplificationReportOptions
from stepframe.pipeline.amplification.site import SITE_PARAMETERS
from stepframe.pipeline.amplification.site_records import SiteFromRecords
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

#: Frequencies of the response-amplification curve [Hz] (covariance method, cheap).
CURVE_HZ = np.geomspace(0.1, 10.0, 25)

#: Frequencies checked by Monte Carlo [Hz] (N synthetic motions each): four, with the default N,
#: keep the report under 10 s (docs/benchmarks.md, Reports); more with ``monte_carlo``.
MONTE_CARLO_HZ = np.geomspace(0.2, 8.0, 4)


@dataclass(frozen=True)
class AmplificationOptions:
    """Choices of an amplification report.

    Attributes
    ----------
    site_name
        Named in titles.
    xi0
        Damping ratio of the oscillator (fraction).
    monte_carlo
        Synthetic motions per Monte Carlo frequency (0: no Monte Carlo).
    seed
        Seed of the Monte Carlo motions.
    n_steps
        Time steps of the mean-square analysis.
    peak_intensity_m_s2
        Peak I_g [m/s²] for the frame-driven run (default: the records' median, else 1).
    delta_star_m
        The frame's quasi-dynamic design displacement δ* [m] (None: no adjusted displacement;
        the band then ends at :data:`DEFAULT_A_MAX_FRACTION` · x*).
    t0
        The time origin used by the fits (``"auto"``, ``"start"`` or ``"p-pick"``), stated
        in the report.
    """

    site_name: str = "site"
    xi0: float = 0.05
    monte_carlo: int = 50
    seed: int | None = 1
    n_steps: int = 2000
    peak_intensity_m_s2: float | None = None
    delta_star_m: float | None = None
    t0: str = "auto"


def _hz(omega: float) -> float:
    return omega / TWO_PI


def _parameter_table(site: GroundMotionModel | SiteFromRecords) -> pd.DataFrame:
    def row(
        name: str, model: GroundMotionModel, se: dict[str, float], extra: dict[str, Any]
    ) -> dict[str, Any]:
        out: dict[str, Any] = {"record": name}
        for key, label in (
            ("omega_p_rad_s", "f_p_hz"),
            ("omega_s_rad_s", "f_s_hz"),
            ("omega_r_rad_s", "f_r_hz"),
        ):
            out[label] = _hz(getattr(model, key))
            out[label + "_se"] = _hz(se.get(key, math.nan))
        for key in ("xi_p", "xi_r"):
            out[key] = getattr(model, key)
            out[key + "_se"] = se.get(key, math.nan)
        out["t_max_s"] = model.t_max_s
        out["t_dur_s"] = model.t_dur_s
        out["t0_s"] = model.t0_s
        return out | extra

    if isinstance(site, GroundMotionModel):
        return pd.DataFrame([row("given parameters", site, {}, {"used": True, "flags": ""})])
    rows = [
        row(
            f.name,
            f.fit.model,
            f.fit.stderr,
            {
                "fit_quality": f.fit.fit_quality,
                "peak_intensity_m_s2": f.features.peak_intensity,
                "used": f.usable,
                "flags": ", ".join(f.fit.flags),
            },
        )
        for f in site.fits
    ]
    combined = {"fit_quality": math.nan, "peak_intensity_m_s2": site.peak_intensity_m_s2}
    rows.append(row("combined", site.model, site.stderr, combined | {"used": True, "flags": ""}))
    return pd.DataFrame(rows)


PARAMETER_COLUMNS = {
    "record": "record file [component], or 'combined' (inverse-variance weighted mean of the "
    "used fits)",
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
    "used": "whether the fit enters the combined parameters",
    "flags": "quality flags of the features and the fit",
}
for _key in ("f_p_hz", "f_s_hz", "f_r_hz", "xi_p", "xi_r"):
    PARAMETER_COLUMNS[_key + "_se"] = f"standard error of {_key} (same unit)"


def _frame_band(frame: Any, a_max_m: float) -> tuple[float, float]:
    """[ω(A_max), ω_1] of the frame [rad/s]."""
    from stepframe.structure.period_amplitude import period_amplitude

    period = float(period_amplitude(frame, a_max_m, beyond_x_star="inf"))
    return TWO_PI / period, frame.omega_1_rad_s


def amplification_report(
    site: GroundMotionModel | SiteFromRecords,
    *,
    frame: Any = None,
    options: AmplificationOptions | None = None,
    provenance: Provenance,
) -> Report:
    """Compute everything an amplification report shows and assemble it (no file written).

    Parameters
    ----------
    site
        The site: a ground-motion model (from parameters) or the fits of its records.
    frame
        A :class:`stepframe.structure.frame.PortalFrame`, or None.
    options
        Choices (damping, Monte Carlo, δ*, ...).
    provenance
        How the report was made.
    """
    from stepframe.pipeline.amplification.amplify import amplification_curve
    from stepframe.pipeline.amplification.site import SiteModel
    from stepframe.stochastic import plots
    from stepframe.stochastic.amplification import (
        adjusted_fixed_point,
        approx_eq_6_19_first,
        approx_eq_6_19_last,
        response_amplification,
    )
    from stepframe.stochastic.mean_square import FrameDriven, analysis_grid

    opts = options or AmplificationOptions()
    if not (math.isfinite(opts.xi0) and 0 < opts.xi0 < 1):
        raise InputError(f"xi0 = {opts.xi0}, expected a damping fraction 0 < ξ0 < 1")
    if opts.monte_carlo < 0 or opts.monte_carlo == 1:
        raise InputError(f"monte_carlo = {opts.monte_carlo}, expected 0 (none) or N ≥ 2")
    from_records = isinstance(site, SiteFromRecords)
    model = site.model if isinstance(site, SiteFromRecords) else site
    name = opts.site_name
    grid = analysis_grid(model, n_steps=opts.n_steps)
    # the pipeline's amplification stage computes the curve (one composition, shared with the CLI)
    curve = amplification_curve(SiteModel(model), CURVE_HZ, opts.xi0, n_steps=opts.n_steps)
    vs_fixed = np.asarray(curve["response_amplification_vs_fixed"].values)
    vs_stationary = np.asarray(curve["response_amplification_vs_stationary"].values)
    first, last = approx_eq_6_19_first(model), approx_eq_6_19_last(model)
    table = pd.DataFrame(
        {
            "f0_hz": CURVE_HZ,
            "spectral_ratio_eq_6_18": np.asarray(curve["spectral_ratio_eq_6_18"].values),
            "response_vs_fixed": vs_fixed,
            "response_vs_stationary": vs_stationary,
        }
    )
    mc_arg = None
    mc_table = None
    if opts.monte_carlo:
        mc = response_amplification(
            model,
            TWO_PI * MONTE_CARLO_HZ,
            opts.xi0,
            time_s=grid,
            method="monte-carlo",
            n_realisations=opts.monte_carlo,
            seed=opts.seed,
        )
        assert mc.vs_fixed_band is not None
        mc_arg = (MONTE_CARLO_HZ, mc.vs_fixed, mc.vs_fixed_band, opts.monte_carlo)
        covariance_at = response_amplification(
            model, TWO_PI * MONTE_CARLO_HZ, opts.xi0, time_s=grid
        )
        mc_table = pd.DataFrame(
            {
                "f0_hz": MONTE_CARLO_HZ,
                "covariance_vs_fixed": covariance_at.vs_fixed,
                "monte_carlo_vs_fixed": mc.vs_fixed,
                "interval_low": mc.vs_fixed_band[:, 0],
                "interval_high": mc.vs_fixed_band[:, 1],
                "n_realisations": opts.monte_carlo,
            }
        )
    peak = int(np.argmax(vs_fixed))
    numbers: dict[str, Any] = {
        "site": name,
        "ground_motion_model": model.to_dict(),
        "approx_eq_6_19_first": first,
        "approx_eq_6_19_last": last,
        "max_response_vs_fixed": float(vs_fixed[peak]),
        "max_response_vs_fixed_at_hz": float(CURVE_HZ[peak]),
        "xi0": opts.xi0,
        "alpha_reading": model.alpha_reading,
    }
    summary = [
        ("Site", name),
        (
            "Source",
            f"{len(site.fits)} record components, {sum(f.usable for f in site.fits)} used"
            if isinstance(site, SiteFromRecords)
            else "given parameters",
        ),
        (
            "f_p, f_s, f_r",
            ", ".join(
                f"{_hz(w):.3g}"
                for w in (model.omega_p_rad_s, model.omega_s_rad_s, model.omega_r_rad_s)
            )
            + " Hz",
        ),
        ("ξ_p, ξ_r", f"{model.xi_p:.3g}, {model.xi_r:.3g}"),
        ("Eq. 6.19 first / last (ω_p/ω_s)²", f"{first:.3g} / {last:.3g}"),
        (
            "Largest response amplification vs fixed",
            f"{vs_fixed[peak]:.3g} at f_0 = {CURVE_HZ[peak]:.3g} Hz (ξ_0 = {opts.xi0:.3g})",
        ),
        ("α_g(t_max) reading", _alpha_text(model.alpha_reading)),
    ]
    choice = Note(
        f"Choices that change these numbers: α_g(t_max) reading '{model.alpha_reading}' "
        f"({_alpha_text(model.alpha_reading)}); t_max = {model.t_max_s:.3g} s and t_dur = "
        f"{model.t_dur_s:.3g} s "
        + (
            "from the records' intensity envelopes (median of the used fits), time origin "
            f"'{opts.t0}'"
            if from_records
            else "as given"
        )
        + f"; oscillator damping ξ_0 = {opts.xi0:.3g}; {opts.n_steps} time steps."
    )
    sections: list[Section] = []
    parameters = _parameter_table(site)
    items: list[Figure | Table | Note] = [
        Table(
            "parameters",
            "Beck-Papadimitriou parameters (eqs. 6.10-6.11)",
            parameters,
            "Per record and combined, with standard errors and flags",
            PARAMETER_COLUMNS,
            sortable=True,
        ),
        choice,
    ]
    if isinstance(site, SiteFromRecords) and site.failures:
        from stepframe.core.results import FAILURE_COLUMNS, failures_table

        items.append(
            Table(
                "failures",
                "Records that could not be used",
                failures_table(list(site.failures)),
                "Read or fit failures (each recorded, none stops the report)",
                FAILURE_COLUMNS,
            )
        )
    sections.append(Section("Site parameters", items))
    if isinstance(site, SiteFromRecords):
        from stepframe.stochastic.spectra import evolutionary_spectrum

        record_figures: list[Figure | Table | Note] = []
        for index, fit in enumerate(site.fits):
            spectrum = evolutionary_spectrum(fit.trace)
            record_figures.append(
                figure_from_matplotlib(
                    plots.omega_path_figure(spectrum, fit.features, fit.fit.model, name=fit.name),
                    key=f"omega_g_{index}",
                    title=f"{fit.name}" + ("" if fit.usable else " (not used: flagged)"),
                    alt=(
                        f"Time-frequency image of {fit.name} with its zero-crossing dominant "
                        "frequency and the fitted eq. 6.10 path from "
                        f"{_hz(fit.fit.model.omega_p_rad_s):.3g} "
                        f"Hz down to {_hz(fit.fit.model.omega_r_rad_s):.3g} Hz"
                    ),
                    how_to_read=(
                        "The background is the record's short-time spectrum (bright = strong). "
                        "Green dots are the dominant frequency estimated from zero crossings "
                        "during strong motion (grey outside it); the blue line is the fitted "
                        "ω_g(t) of eq. 6.10. A good fit follows the green dots and the bright "
                        "ridge; dashed and dotted lines mark t_max and t_dur."
                    ),
                )
            )
        sections.append(
            Section(
                "Dominant frequency ω_g(t) over each record's evolutionary spectrum",
                record_figures,
            )
        )
    sections.append(
        Section(
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
    )
    band_hz = None
    frame_point = None
    frame_items: list[Figure | Table | Note] = []
    if frame is not None:
        x_star = frame.x_star_m
        a_max = (
            opts.delta_star_m
            if opts.delta_star_m is not None
            else frame.x_c_m + DEFAULT_A_MAX_FRACTION * (x_star - frame.x_c_m)
        )
        if a_max >= x_star:
            raise InputError(
                f"delta_star_m = {a_max} m ≥ x* = {x_star:.4g} m, expected a design "
                "displacement below x* (the frame overturns there)"
            )
        lo, hi = _frame_band(frame, a_max)
        band_hz = (_hz(lo), _hz(hi))
        from stepframe.structure.period_amplitude import period_amplitude

        def period_s(amplitude_m: float) -> float:
            return float(period_amplitude(frame, amplitude_m, beyond_x_star="inf"))

        intensity = opts.peak_intensity_m_s2 or (
            site.peak_intensity_m_s2 if isinstance(site, SiteFromRecords) else 1.0
        )
        driven = response_amplification(
            model,
            None,
            frame.xi_1,
            frame=FrameDriven(period_s),
            peak_intensity=intensity * frame.p_1,
            time_s=grid,
        )
        lower = driven.moving.status != "ok"
        frame_point = (_hz(frame.omega_1_rad_s), float(driven.vs_fixed[0]), lower)
        frame_rows: list[dict[str, Any]] = [
            {"quantity": "small-amplitude frequency f_1", "value": _hz(hi), "unit": "Hz"},
            {"quantity": "band lower edge f(A_max)", "value": _hz(lo), "unit": "Hz"},
            {"quantity": "amplitude limit A_max", "value": a_max, "unit": "m"},
            {"quantity": "uplift amplitude x_c", "value": frame.x_c_m, "unit": "m"},
            {"quantity": "overturning amplitude x*", "value": x_star, "unit": "m"},
            {
                "quantity": "peak intensity of the run (× p_1)",
                "value": intensity * frame.p_1,
                "unit": "m/s²",
            },
            {
                "quantity": "frame-driven response amplification vs fixed",
                "value": float(driven.vs_fixed[0]),
                "unit": "-",
            },
            {
                "quantity": "status of the frame-driven run",
                "value": driven.moving.status,
                "unit": "",
            },
        ]
        numbers["frame"] = {row["quantity"]: row["value"] for row in frame_rows}
        numbers["frame_driven_lower_bound"] = lower
        summary.append(("Frame's band", f"{_hz(lo):.3g}-{_hz(hi):.3g} Hz (A_max = {a_max:.3g} m)"))
        summary.append(
            (
                "Frame-driven response amplification",
                ("≥ " if lower else "")
                + f"{driven.vs_fixed[0]:.3g}"
                + (" (lower bound: the frame overturned)" if lower else ""),
            )
        )
        frame_items.append(
            Table(
                "frame",
                "The frame",
                pd.DataFrame(frame_rows),
                "Band from the period-amplitude law, frame-driven amplification",
                {"quantity": "what", "value": "the number", "unit": "its unit"},
            )
        )
        source = (
            "the design displacement δ* given"
            if opts.delta_star_m is not None
            else f"x_c + {DEFAULT_A_MAX_FRACTION}·(x* - x_c) (no design displacement given)"
        )
        frame_items.append(
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
            )
        )
        if opts.delta_star_m is not None:
            adjusted = []
            for factor, meaning in (
                ("eq-6-19-last", "√((ω_p/ω_s)²) · δ*"),
                ("eq-6-19-first", "√(eq. 6.19 first) · δ*"),
                ("eq-6-18", "√(eq. 6.18 at ω_1) · δ*"),
                ("response-vs-fixed", "response amplification at ω_1 (covariance) · δ*"),
            ):
                value = adjusted_fixed_point(
                    opts.delta_star_m,
                    model,
                    factor=factor,  # type: ignore[arg-type]
                    omega_0_rad_s=frame.omega_1_rad_s,
                    xi0=frame.xi_1 if frame.xi_1 > 0 else opts.xi0,
                )
                adjusted.append({"factor": factor, "rule": meaning, "adjusted_delta_m": value})
            adjusted_frame = pd.DataFrame(adjusted)
            adjusted_frame.insert(2, "delta_star_m", opts.delta_star_m)
            numbers["adjusted_design_displacement_m"] = {
                row["factor"]: row["adjusted_delta_m"] for row in adjusted
            }
            by = numbers["adjusted_design_displacement_m"]
            summary.append(
                (
                    "Adjusted design displacement",
                    f"δ* = {opts.delta_star_m:.3g} m → {by['eq-6-19-last']:.3g} m by (ω_p/ω_s)², "
                    f"{by['response-vs-fixed']:.3g} m by the response amplification at f_1",
                )
            )
            frame_items.append(
                Table(
                    "adjusted_design_displacement",
                    "Adjusted design displacement",
                    adjusted_frame,
                    "The quasi-dynamic δ* adjusted for moving resonance, by each factor",
                    {
                        "factor": "which amplification",
                        "rule": "how it adjusts δ* (spectral factors are mean-square ratios)",
                        "delta_star_m": "the unadjusted design displacement δ* [m]",
                        "adjusted_delta_m": "δ* adjusted [m]",
                    },
                )
            )
    response_items: list[Figure | Table | Note] = [
        figure_from_matplotlib(
            plots.response_amplification_figure(
                CURVE_HZ,
                vs_fixed,
                vs_stationary,
                model,
                site=name,
                xi0=opts.xi0,
                monte_carlo=mc_arg,
                band_hz=band_hz,
                frame_point=frame_point,
            ),
            key="response_amplification",
            title="Response amplification against frequency",
            alt=(
                "Response amplification of a tracking oscillator against its small-amplitude "
                f"frequency from 0.1 to 10 Hz; largest {vs_fixed[peak]:.3g} at "
                f"{CURVE_HZ[peak]:.3g} Hz"
                + (", with Monte Carlo intervals" if mc_arg else "")
                + (", the frame's band shaded" if band_hz else "")
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
            table,
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
    if mc_table is not None:
        response_items.append(
            Table(
                "monte_carlo",
                "Monte Carlo check",
                mc_table,
                f"Median and 95 % interval of N = {opts.monte_carlo} synthetic motions "
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
    sections.append(Section("Response amplification", response_items))
    if frame_items:
        sections.append(Section("Frame", frame_items))
    return Report(
        title=f"Site amplification report: {name}",
        subtitle="Moving resonance under the Beck-Papadimitriou ground-motion model "
        "(Alimoradi and Beck 2025, eqs. 6.10-6.19)",
        summary=summary,
        sections=sections,
        provenance=provenance,
        numbers=numbers,
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
        :func:`stepframe.pipeline.amplification.site_records.site_from_records`.
    out_html
        The HTML file.
    frame
        Optional :class:`stepframe.structure.frame.PortalFrame`.
    options
        :class:`AmplificationOptions`.
    provenance
        From :func:`stepframe.pipeline.reports.provenance.collect_provenance`.

    Returns
    -------
    pathlib.Path
        The HTML file.
    """
    report = amplification_report(site, frame=frame, options=options, provenance=provenance)
    return write_report(report, out_html)


def make_amplification_report(out_html: str, options: AmplificationReportOptions) -> Path:
    """The amplification report of a site given by its parameters or by a folder of its records.

    Parameters
    ----------
    out_html
        The HTML file.
    options
        :class:`AmplificationReportOptions`: all of
        :data:`~stepframe.pipeline.amplification.site.SITE_PARAMETERS`, or none with
        ``records`` (fitted with ``t0``, ``record_format`` and ``units``:
        :func:`~stepframe.pipeline.amplification.site_records.site_from_records`); the name in
        titles (default: the records folder's name, else ``site``); an optional frame file and its
        design displacement δ* [m]; the analysis
        (:class:`~stepframe.pipeline.amplification.report.AmplificationOptions`).

    Returns
    -------
    pathlib.Path
        The HTML file.
    """
    o = options
    parameters = {name: getattr(o, name) for name in SITE_PARAMETERS}
    given = [name for name in SITE_PARAMETERS if parameters[name] is not None]
    if o.records is not None and given:
        raise InputError(
            f"--records with --{given[0].replace('_', '-')}, expected either the site "
            "parameters or --records"
        )
    missing = [name for name in SITE_PARAMETERS if parameters[name] is None]
    if o.records is None and missing:
        raise InputError(
            f"missing --{missing[0].replace('_', '-')}, expected all of "
            + ", ".join("--" + n.replace("_", "-") for n in SITE_PARAMETERS)
            + " or --records DIR"
        )
    if not (math.isfinite(o.xi0) and 0 < o.xi0 < 1):
        raise InputError(f"--xi0 {o.xi0}, expected a damping fraction 0 < ξ0 < 1 (e.g. 0.05)")
    if o.monte_carlo < 0 or o.monte_carlo == 1:
        raise InputError(f"--monte-carlo {o.monte_carlo}, expected 0 (none) or N ≥ 2")
    if o.n_steps < 100:
        raise InputError(f"--n-steps {o.n_steps}, expected at least 100")
    if o.frame is None and o.delta_star_m is not None:
        raise InputError("--delta-star-m without --frame, expected --frame FRAME.toml with it")
    site: Any
    inputs: list[str] = []
    if o.records is not None:
        from stepframe.pipeline.amplification.site_records import site_from_records

        site = site_from_records(
            o.records, alpha_reading=o.alpha_reading, t0=o.t0, record_format=o.record_format,
            units=o.units,
        )  # fmt: skip
        inputs.append(o.records)
        name = o.site_name or Path(o.records).resolve().name
    else:
        from stepframe.stochastic.model import GroundMotionModel

        values = {key: float(value) for key, value in parameters.items() if value is not None}
        site = GroundMotionModel.from_hz(
            values["fp_hz"], values["fs_hz"], values["fr_hz"], values["xi_p"], values["xi_r"],
            t_max_s=values["t_max_s"], t_dur_s=values["t_dur_s"], alpha_reading=o.alpha_reading,
        )  # fmt: skip
        name = o.site_name or "site"
    portal = None
    if o.frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        portal = read_frame_file(o.frame)
        inputs.append(o.frame)
    analysis = AmplificationOptions(
        site_name=name, xi0=o.xi0, monte_carlo=o.monte_carlo, seed=o.seed, n_steps=o.n_steps,
        peak_intensity_m_s2=o.peak_intensity_m_s2, delta_star_m=o.delta_star_m, t0=o.t0,
    )  # fmt: skip
    recorded = {
        **parameters,
        "records": o.records,
        "t0": o.t0,
        "frame": o.frame,
        "delta_star_m": o.delta_star_m,
        "alpha_at_tmax": o.alpha_reading,
        "xi0": o.xi0,
        "monte_carlo": o.monte_carlo,
        "seed": o.seed,
        "n_steps": o.n_steps,
        "peak_intensity_m_s2": o.peak_intensity_m_s2,
    }
    recorded = {key: value for key, value in recorded.items() if value is not None}
    command = command_line(["stepframe", "report", "amplification"], recorded | {"out": out_html})
    provenance = collect_provenance(command, inputs=inputs, parameters=recorded)
    return write_amplification_report(
        site, out_html, frame=portal, options=analysis, provenance=provenance
    )
