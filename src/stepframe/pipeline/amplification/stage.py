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

from stepframe.core.io import copy_files, write_bytes
from stepframe.errors import InputError
from stepframe.pipeline.engine.stage import Context, Param, Stage
from stepframe.pipeline.engine.store import make_key, write_output_table
from stepframe.pipeline.reports.provenance import workflow_provenance

SITE_VERSION = 1
AMPLIFICATION_VERSION = 1

SITE_PARAMETERS = ("fp_hz", "fs_hz", "fr_hz", "xi_p", "xi_r", "t_max_s", "t_dur_s")
SITE_PARAMS: dict[str, Param] = {
    "from": Param(
        "str", "parameters", "where the site model comes from", ("parameters", "records")
    ),
    "fp_hz": Param("float", None, "P-wave dominant frequency f_p [Hz]"),
    "fs_hz": Param("float", None, "S-wave dominant frequency f_s [Hz]"),
    "fr_hz": Param("float", None, "surface-wave dominant frequency f_r [Hz]"),
    "xi_p": Param("float", None, "bandwidth ratio ξ_p at the start [-]"),
    "xi_r": Param("float", None, "bandwidth ratio ξ_r at the end [-]"),
    "t_max_s": Param("float", None, "time of peak intensity after t0 [s]"),
    "t_dur_s": Param("float", None, "strong-motion duration after t0 [s]"),
    "alpha_reading": Param(
        "str", "eq-6-11", "α_g ramp ends at t_dur (eq. 6.11) or t_max (paper)", ("eq-6-11", "paper")
    ),
    "peak_intensity_m_s2": Param(
        "float", 1.0, "max I_g [m/s²] with parameters (from records: their median)"
    ),
    "statistic": Param(
        "str", "median", "from records: statistic over components", ("median", "mean")
    ),
    "plausible_only": Param("bool", True, "from records: only components passing the checks"),
}
MODEL_FROM_FEATURES = {
    "omega_p_rad_s": "omega_p_rad_s",
    "omega_s_rad_s": "omega_s_rad_s",
    "omega_r_rad_s": "omega_r_rad_s",
    "xi_p": "xi_p",
    "xi_r": "xi_r",
    "t_max_s": "t_max_s",
    "t_dur_s": "t_dur_s",
}
SITE_JSON = "site_model.json"
CURVE_NETCDF = "amplification.nc"


def _site_upstream(workflow: Any) -> tuple[str, ...]:
    source = workflow.tables.get("site", {}).get("from", "parameters")
    return ("features",) if source == "records" else ()


def _site_check(workflow: Any) -> None:
    params = SITE_STAGE.parameters(workflow)
    if params["from"] == "parameters":
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
    elif workflow.records is None:
        raise workflow.lines.error(
            '[site] from = "records" without a [records] table, expected one', "site", "from"
        )


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
    return replace(site, peak_intensity_m_s2=params["peak_intensity_m_s2"])


def _ok_features(context: Context, plausible_only: bool) -> Any:
    table = context.tables["features"]
    if plausible_only:
        table = table[table["plausible"].astype(bool)]
    return table


def _site_key(context: Context) -> str:
    params = SITE_STAGE.parameters(context.workflow)
    if params["from"] == "records":
        used = _ok_features(context, params["plausible_only"])
        return make_key("site", SITE_VERSION, params, *sorted(map(str, used["_key"])))
    return make_key("site", SITE_VERSION, params)


def _site_from_records(context: Context, params: dict[str, Any]) -> Any:
    """The site of the records: each fitted parameter's statistic over the components used."""
    from stepframe.pipeline.amplification.site import SiteModel
    from stepframe.stochastic.model import GroundMotionModel

    used = _ok_features(context, params["plausible_only"])
    if used.empty:
        raise InputError(
            "no component with fitted features"
            + (" passing the plausibility checks" if params["plausible_only"] else "")
            + ", expected at least one for a site model from records"
        )
    reduce = "median" if params["statistic"] == "median" else "mean"
    values = {
        field: float(getattr(used[column].astype(float), reduce)())
        for field, column in MODEL_FROM_FEATURES.items()
    }
    model = GroundMotionModel(**values, alpha_reading=params["alpha_reading"])
    intensity = float(getattr(used["max_intensity_m_s2"].astype(float), reduce)())
    source = {
        "site": "records",
        "statistic": reduce,
        "plausible_only": params["plausible_only"],
        "n_components": len(used),
    }
    return SiteModel(model, intensity, source)


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

AMPLIFICATION_PARAMS: dict[str, Param] = {
    "xi0": Param("float", 0.05, "damping ratio of the oscillator (a fraction)"),
    "f_min_hz": Param("float", 0.1, "lowest oscillator frequency f0 [Hz]"),
    "f_max_hz": Param("float", 10.0, "highest oscillator frequency f0 [Hz]"),
    "n_frequencies": Param("int", 60, "frequencies, log-spaced"),
    "n_steps": Param("int", 4000, "time steps of the covariance integration"),
}


def _amplification_check(workflow: Any) -> None:
    params = AMPLIFICATION_STAGE.parameters(workflow)
    if not 0 < params["xi0"] < 1:
        raise workflow.lines.error(
            f"[amplification] xi0 = {params['xi0']}, expected a damping fraction in (0, 1)",
            "amplification",
            "xi0",
        )
    if not 0 < params["f_min_hz"] < params["f_max_hz"]:
        raise workflow.lines.error(
            "[amplification] f_min_hz, f_max_hz, expected 0 < f_min_hz < f_max_hz",
            "amplification",
            "f_min_hz",
        )
    for name in ("n_frequencies", "n_steps"):
        if params[name] < 2:
            raise workflow.lines.error(
                f"[amplification] {name} = {params[name]}, expected ≥ 2", "amplification", name
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
    curve = amplification_curve(site, frequencies, params["xi0"], n_steps=params["n_steps"])
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


AMPLIFICATION_REPORT_VERSION = 1
AMPLIFICATION_REPORT_HTML = "amplification_report.html"

AMPLIFICATION_REPORT_PARAMS: dict[str, Param] = {
    "monte_carlo": Param("int", 50, "Monte Carlo motions per checked frequency (0: none)"),
}


def _publish_report(folder: Path, outputs: Path) -> list[Path]:
    return copy_files(folder, outputs)


def _amplification_report_key(context: Context) -> str:
    params = AMPLIFICATION_REPORT_STAGE.parameters(context.workflow)
    params["frame"] = context.workflow.frame_source
    return make_key(
        "amplification_report", AMPLIFICATION_REPORT_VERSION, params, context.set_keys["site"]
    )


def _amplification_report_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.amplification.report import (
        AmplificationOptions,
        write_amplification_report,
    )
    from stepframe.pipeline.amplification.site import read_site_model

    params = AMPLIFICATION_REPORT_STAGE.parameters(context.workflow)
    site = read_site_model(context.set_dirs["site"] / SITE_JSON)
    write_amplification_report(
        site.model,
        folder / AMPLIFICATION_REPORT_HTML,
        frame=context.workflow.frame,
        options=AmplificationOptions(
            site_name=context.workflow.name or "site", monte_carlo=params["monte_carlo"]
        ),
        provenance=workflow_provenance(context.workflow.path, {"site": site.to_dict(), **params}),
    )


AMPLIFICATION_REPORT_STAGE = Stage(
    name="amplification_report",
    version=AMPLIFICATION_REPORT_VERSION,
    description="the site amplification report: self-contained HTML with its numbers",
    kind="set",
    params=AMPLIFICATION_REPORT_PARAMS,
    upstream=lambda workflow: ("site",),
    set_key=_amplification_report_key,
    run_set=_amplification_report_run,
    publish=_publish_report,
)
