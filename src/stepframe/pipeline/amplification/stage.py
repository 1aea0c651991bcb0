"""The site amplification job's stages: ``site``, ``amplification`` and ``amplification_report``.

``site`` is the Beck-Papadimitriou model of the site: from the parameters in the workflow (the
paper's P-, S- and surface-wave frequencies) or from the records
(:func:`stepframe.pipeline.amplification.site.site_from_features` over the ``features`` table,
the same function ``stepframe report amplification --records`` uses). ``amplification`` is the
moving-resonance amplification over 0.1-10 Hz: the paper's spectral ratio (eq. 6.18), its two
approximations (eq. 6.19) and the response amplification by the exact covariance method, each
named for what it is. ``amplification_report`` writes the site's report (docs/reports.md) into
the stage's folder; its key is the site's, so it is rebuilt only when what it shows changes.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from stepframe.core.io import publish_copy, write_bytes
from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import (
    SITE_PARAMETERS,
    AmplificationAnalysis,
    AmplificationOptions,
    SiteCombination,
    SiteParameters,
)
from stepframe.pipeline.catalogue.stage import FEATURES_STAGE
from stepframe.pipeline.engine.stage import Context, Param, Stage, params_from_options
from stepframe.pipeline.engine.store import make_key, write_output_table
from stepframe.pipeline.reports.provenance import workflow_provenance

# 2: site_from_features (one combination with the report); 3: the combined standard errors;
# 4: combined in value order (the same bytes whatever the files' order);
# 5: the fits' t_max around the motion, clipped records not plausible (features version 8)
SITE_VERSION = 5
AMPLIFICATION_VERSION = 1

#: The ``[site]`` table: where the site comes from, and the options of ``report amplification``
#: that shape it (declared once, in :mod:`stepframe.pipeline.amplification.analysis`).
SITE_PARAMS: dict[str, Param] = {
    "from": Param(
        "str", "parameters", "where the site model comes from", ("parameters", "records")
    ),
    **params_from_options(SiteParameters, SITE_PARAMETERS),
    **params_from_options(AmplificationAnalysis, ("alpha_reading", "peak_intensity_m_s2")),
    **params_from_options(SiteCombination, ("statistic", "plausible_only")),
}
SITE_JSON = "site_model.json"
CURVE_NETCDF = "amplification.nc"


def _site_upstream(workflow: Any) -> tuple[str, ...]:
    source = workflow.tables.get("site", {}).get("from", "parameters")
    return ("features",) if source == "records" else ()


def _checked(workflow: Any, table: str, options: type, given: dict[str, Any]) -> Any:
    """``options(**given)``, its error pointed at the key's line of ``[table]``."""
    try:
        return options(**given)
    except InputError as error:
        raise workflow.lines.error(f"[{table}] {error.what}", table, error.key) from None


def _site_check(workflow: Any) -> None:
    params = SITE_STAGE.parameters(workflow)
    _checked(workflow, "site", SiteParameters, {k: params[k] for k in SITE_PARAMETERS})
    combination = {k: params[k] for k in ("statistic", "plausible_only")}
    _checked(workflow, "site", SiteCombination, combination)
    if params["from"] == "parameters":
        combination_defaults = SiteCombination()
        for name in ("statistic", "plausible_only"):
            if params[name] != getattr(combination_defaults, name):
                raise workflow.lines.error(
                    f'[site] {name} = {_toml(params[name])} with from = "parameters", expected '
                    'it only with from = "records" (it combines the records\' fits)',
                    "site",
                    name,
                )
        missing = [name for name in SITE_PARAMETERS if params[name] is None]
        if missing:
            raise workflow.lines.error(
                f"[site] {missing[0]} missing, expected all of {', '.join(SITE_PARAMETERS)} "
                'or from = "records"',
                "site",
            )
        try:
            _model_from_parameters(params)
        except InputError as error:
            raise workflow.lines.error(f"[site] {error.what}", "site") from None
        return
    if workflow.records is None:
        raise workflow.lines.error(
            '[site] from = "records" without a [records] table, expected one', "site", "from"
        )
    given = [name for name in SITE_PARAMETERS if params[name] is not None]
    if given:
        raise workflow.lines.error(
            f'[site] {given[0]} with from = "records", expected the parameters or the records',
            "site",
            given[0],
        )
    features = workflow.tables.get("features", {}).get("alpha_reading", "eq-6-11")
    if "alpha_reading" in workflow.tables.get("site", {}) and params["alpha_reading"] != features:
        raise workflow.lines.error(
            f'[site] alpha_reading = "{params["alpha_reading"]}" with records fitted under '
            f'"{features}", expected it in [features] (the fit itself depends on it)',
            "site",
            "alpha_reading",
        )


def _toml(value: Any) -> str:
    """A table value as the workflow file writes it (``"mean"``, ``false``, ``5``)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    return f'"{value}"' if isinstance(value, str) else str(value)


def _model_from_parameters(params: dict[str, Any]) -> Any:
    """The :class:`~stepframe.pipeline.amplification.site.SiteModel` of ``[site]``'s parameters."""
    from dataclasses import replace

    from stepframe.pipeline.amplification.site import site_from_parameters

    site = site_from_parameters(
        params["fp_hz"],
        params["fs_hz"],
        params["fr_hz"],
        params["xi_p"],
        params["xi_r"],
        t_max_s=params["t_max_s"],
        t_dur_s=params["t_dur_s"],
        alpha_reading=params["alpha_reading"],
    )
    intensity = params["peak_intensity_m_s2"]
    return site if intensity is None else replace(site, peak_intensity_m_s2=intensity)


def _site_from_records(context: Context, params: dict[str, Any]) -> Any:
    """The site of the workflow's features table (:func:`site_from_features`, as the report)."""
    from dataclasses import replace

    from stepframe.pipeline.amplification.site import site_from_features

    reading = FEATURES_STAGE.parameters(context.workflow)["alpha_reading"]
    site = site_from_features(
        context.tables["features"],
        statistic=params["statistic"],
        plausible_only=params["plausible_only"],
        alpha_reading=reading,
    ).site
    intensity = params["peak_intensity_m_s2"]
    return site if intensity is None else replace(site, peak_intensity_m_s2=intensity)


def _site_key(context: Context) -> str:
    params = SITE_STAGE.parameters(context.workflow)
    if params["from"] == "records":
        table = context.tables["features"]
        used = table[table["plausible"].astype(bool)] if params["plausible_only"] else table
        return make_key("site", SITE_VERSION, params, *sorted(map(str, used["_key"])))
    return make_key("site", SITE_VERSION, params)


def _site_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.amplification.site import write_site_model

    params = SITE_STAGE.parameters(context.workflow)
    if params["from"] == "parameters":
        site = _model_from_parameters(params)
    else:
        site = _site_from_records(context, params)
    write_site_model(site, folder / SITE_JSON)


def site_table(site: Any) -> Any:
    """A site model as a one-row table (the model's fields, f in Hz, intensity, source)."""
    import pandas as pd

    model = site.model
    row = {
        **model.to_dict(),
        "fp_hz": model.omega_p_rad_s / (2 * math.pi),
        "fs_hz": model.omega_s_rad_s / (2 * math.pi),
        "fr_hz": model.omega_r_rad_s / (2 * math.pi),
        "peak_intensity_m_s2": site.peak_intensity_m_s2,
        "source": site.source.get("site", ""),
        "n_components": int(site.source.get("n_components", 0)),
    }
    if row["omega_c_rad_s"] is None:
        row["omega_c_rad_s"] = math.nan
    return pd.DataFrame([row])


def _site_publish(folder: Path, outputs: Path) -> list[Path]:
    from stepframe.pipeline.amplification.site import read_site_model

    site = read_site_model(folder / SITE_JSON)
    json_copy = write_bytes(outputs / SITE_JSON, (folder / SITE_JSON).read_bytes())
    return [json_copy, *write_output_table(site_table(site), outputs / "site_model.parquet")]


SITE_STAGE = Stage(
    name="site",
    version=SITE_VERSION,
    description="site ground-motion model (B-P parameters) from parameters or records",
    kind="set",
    params=SITE_PARAMS,
    upstream=_site_upstream,
    set_key=_site_key,
    run_set=_site_run,
    publish=_site_publish,
    check=_site_check,
)

#: The ``[amplification]`` table: the curve's oscillator and grids (the options of ``report
#: amplification`` and ``stochastic amplify``, declared once in
#: :mod:`stepframe.pipeline.amplification.analysis`).
CURVE_FIELDS = ("xi0", "f_min_hz", "f_max_hz", "n_frequencies", "n_steps")
AMPLIFICATION_PARAMS: dict[str, Param] = params_from_options(AmplificationAnalysis, CURVE_FIELDS)


def _amplification_check(workflow: Any) -> None:
    _checked(
        workflow, "amplification", AmplificationAnalysis, workflow.tables.get("amplification", {})
    )


def _amplification_key(context: Context) -> str:
    params = AMPLIFICATION_STAGE.parameters(context.workflow)
    return make_key("amplification", AMPLIFICATION_VERSION, params, context.set_keys["site"])


def _amplification_run(context: Context, folder: Path) -> None:
    import numpy as np

    from stepframe.pipeline.amplification.amplify import amplification_curve, write_curve
    from stepframe.pipeline.amplification.site import read_site_model
    from stepframe.stochastic.amplification import approx_eq_6_19_first

    params = AMPLIFICATION_STAGE.parameters(context.workflow)
    site = read_site_model(context.set_dirs["site"] / SITE_JSON)
    frequencies = np.geomspace(params["f_min_hz"], params["f_max_hz"], params["n_frequencies"])
    analysis = AmplificationAnalysis(**params)
    curve = amplification_curve(
        site, frequencies, analysis.xi0_or_default, n_steps=analysis.n_steps
    )
    # eq. 6.19 has two approximations; the curve carries the last, the report wants both
    curve.attrs["approx_eq_6_19_first"] = approx_eq_6_19_first(site.model)
    write_curve(curve, folder / CURVE_NETCDF)


def curve_table(curve: Any) -> Any:
    """An amplification curve as a table: a row per frequency, eq. 6.19's values repeated."""
    table = curve.to_dataframe().reset_index()
    for name in ("approx_eq_6_19_first", "approx_eq_6_19_last"):
        table[name] = curve.attrs[name]
    return table


def _amplification_publish(folder: Path, outputs: Path) -> list[Path]:
    from stepframe.pipeline.amplification.amplify import read_curve

    netcdf = write_bytes(outputs / CURVE_NETCDF, (folder / CURVE_NETCDF).read_bytes())
    table = curve_table(read_curve(folder / CURVE_NETCDF))
    return [netcdf, *write_output_table(table, outputs / "amplification.parquet")]


AMPLIFICATION_STAGE = Stage(
    name="amplification",
    version=AMPLIFICATION_VERSION,
    description="amplification curve 0.1-10 Hz: eq. 6.18, eq. 6.19, response amplification",
    kind="set",
    params=AMPLIFICATION_PARAMS,
    upstream=lambda workflow: ("site",),
    set_key=_amplification_key,
    run_set=_amplification_run,
    publish=_amplification_publish,
    check=_amplification_check,
)


# 2: one set of analysis options with the command; 3: maxima past the grid's edges, the band
# from the parameters' standard errors, the frame's stepping and δ* against x_c and x*; 4: the
# frame's simulations by the integrator's chord-bound fast path (the same to rounding); 5: the
# provenance's alpha_reading is the site's (it stated the options' default, eq-6-11); 6: a site
# from records lists every fit and draws each record's ω_g(t), as the command line's report;
# 7: a shipped workflow's provenance names it as it is run (not a file "NAME.toml")
AMPLIFICATION_REPORT_VERSION = 7
AMPLIFICATION_REPORT_HTML = "amplification_report.html"

#: The ``[amplification_report]`` table: the report's own choices (its curve follows
#: ``[amplification]``).
REPORT_FIELDS = ("monte_carlo", "seed", "delta_star_m", "band", "band_samples", "grid_only")
AMPLIFICATION_REPORT_PARAMS: dict[str, Param] = params_from_options(
    AmplificationOptions, REPORT_FIELDS
)


def _report_options(workflow: Any) -> AmplificationOptions:
    """The report's options: ``[amplification]``'s curve, ``[amplification_report]``'s own."""
    tables = workflow.tables
    given = {**tables.get("amplification", {}), **tables.get("amplification_report", {})}
    options: AmplificationOptions = _checked(
        workflow, "amplification_report", AmplificationOptions, given
    )
    return options


def _amplification_report_check(workflow: Any) -> None:
    from stepframe.pipeline.amplification.analysis import band_without_errors

    options = _report_options(workflow)
    if workflow.tables.get("site", {}).get("from", "parameters") == "parameters":
        key = band_without_errors(options)
        if key is not None:
            raise workflow.lines.error(
                f"[amplification_report] {key} = {_toml(getattr(options, key))} with [site] "
                'from = "parameters", expected it only with from = "records" (parameters have '
                "no standard errors, so no band)",
                "amplification_report",
                key,
            )
    if options.delta_star_m is not None and workflow.frame is None:
        raise workflow.lines.error(
            "[amplification_report] delta_star_m without a frame, expected a [frame] table",
            "amplification_report",
            "delta_star_m",
        )
    if hasattr(workflow.frame, "x_star_m"):  # a frame that can overturn
        from stepframe.pipeline.amplification.frame_section import check_design_displacement

        try:
            check_design_displacement(workflow.frame, options.delta_star_m)
        except InputError as error:
            raise workflow.lines.error(
                f"[amplification_report] {error.what}", "amplification_report", "delta_star_m"
            ) from None


def _publish_report(folder: Path, outputs: Path) -> list[Path]:
    return publish_copy(folder, outputs)


def _amplification_report_key(context: Context) -> str:
    params = {
        **AMPLIFICATION_STAGE.parameters(context.workflow),
        **AMPLIFICATION_REPORT_STAGE.parameters(context.workflow),
        "frame": context.workflow.frame_source,
    }
    # A site from records: the page lists every component's fit (the implausible ones too)
    features = (
        sorted(map(str, context.tables["features"]["_key"]))
        if "features" in _site_upstream(context.workflow)
        else []
    )
    return make_key(
        "amplification_report",
        AMPLIFICATION_REPORT_VERSION,
        params,
        context.set_keys["site"],
        *features,
    )


def _site_of_records(context: Context, site: Any) -> Any:
    """The workflow's site from records as the command line's report has it
    (:class:`~stepframe.pipeline.amplification.site.SiteFromRecords`): every component's fit,
    the implausible ones with their reason, and what each record's ω_g(t) figure reads again.
    Before, the page had the combined row only ("4 components used"), where the command line's
    over the same folder listed all six with their flags."""
    import pandas as pd

    from stepframe.core.results import FAILURE_COLUMNS
    from stepframe.pipeline.amplification.site import SiteFromRecords, site_from_features
    from stepframe.pipeline.catalogue.fit_options import ESTIMATION_FIELDS, FitOptions
    from stepframe.pipeline.catalogue.stage import record_folder

    workflow = context.workflow
    records = workflow.records
    assert records is not None  # a site from records (the features stage needs [records])
    folder = record_folder(context)  # the folder, or the embedded example written out
    table = context.tables["features"]
    features = table.drop(columns=[c for c in table.columns if str(c).startswith("_")])
    params = SITE_STAGE.parameters(workflow)
    fitted = FEATURES_STAGE.parameters(workflow)
    options = FitOptions(**{k: fitted[k] for k in ESTIMATION_FIELDS if k in fitted})
    combined = site_from_features(
        features,
        statistic=params["statistic"],
        plausible_only=params["plausible_only"],
        alpha_reading=options.alpha_reading,
        name=folder.name,
    )
    # the stated peak intensity ([site] peak_intensity_m_s2) is the site model's
    from dataclasses import replace

    combined = replace(combined, site=site)
    # read and fit failures are the run's (its summary, features.failures.csv), not listed here
    failures = pd.DataFrame(columns=list(FAILURE_COLUMNS))
    # files named inside the records folder (the page shows them so: it is relocatable)
    return SiteFromRecords(
        combined, features, failures, folder, options, dict(records.options), True
    )


def _amplification_report_run(context: Context, folder: Path) -> None:
    from dataclasses import asdict, replace

    from stepframe.pipeline.amplification.report import write_amplification_report
    from stepframe.pipeline.amplification.site import read_site_model

    site = read_site_model(context.set_dirs["site"] / SITE_JSON)
    reported = (
        _site_of_records(context, site) if "features" in _site_upstream(context.workflow) else site
    )
    options = replace(
        _report_options(context.workflow),
        site_name=context.workflow.name or "site",
        peak_intensity_m_s2=site.peak_intensity_m_s2,
        # the reading the site was made with ([site] or [features]), not the options' unused
        # default: the provenance states one reading, the page's
        alpha_reading=site.model.alpha_reading,
    )
    parameters = {"site": site.to_dict(), **asdict(options)}
    write_amplification_report(
        reported,
        folder / AMPLIFICATION_REPORT_HTML,
        frame=context.workflow.frame,
        options=options,
        provenance=workflow_provenance(context.workflow.path, parameters),
        jobs=context.jobs,
        executor=context.executor,
    )


AMPLIFICATION_REPORT_STAGE = Stage(
    name="amplification_report",
    version=AMPLIFICATION_REPORT_VERSION,
    description="the site amplification report: self-contained HTML with its numbers",
    kind="set",
    params=AMPLIFICATION_REPORT_PARAMS,
    upstream=lambda workflow: ("site", *_site_upstream(workflow)),
    set_key=_amplification_report_key,
    run_set=_amplification_report_run,
    publish=_publish_report,
    check=_amplification_report_check,
)
