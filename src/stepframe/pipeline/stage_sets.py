"""Whole-set stages: ``site`` (ground-motion model), ``amplification`` (curve), ``selection``.

``site`` is the Beck-Papadimitriou model of the site: from the parameters in the workflow (the
paper's P-, S- and surface-wave frequencies) or from the records (the median, or mean, of each
fitted parameter over the plausible components; the order ω_p ≥ ω_s ≥ ω_r and t_max ≤ t_dur of
every component carries over to these statistics, which are monotone). ``amplification`` is the
moving-resonance amplification over 0.1-10 Hz: the paper's spectral ratio (eq. 6.18), its two
approximations (eq. 6.19) and the response amplification by the exact covariance method, each
named for what it is. ``selection`` calls :func:`stepframe.pipeline.selection.select_records`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from stepframe.core.io import write_bytes
from stepframe.errors import InputError

# The per-item stages register first, whichever stage module is imported first: registry order
# is pipeline order (features before site and selection).
from stepframe.pipeline import stage_items  # noqa: F401
from stepframe.pipeline.stages import Context, Param, Stage, register_stage
from stepframe.pipeline.store import make_key, write_output_table

SITE_VERSION = 1
AMPLIFICATION_VERSION = 1
SELECTION_VERSION = 2  # 2: default rank_by substitute_demand_ratio

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
    """The :class:`~stepframe.pipeline.site.SiteModel` of the ``[site]`` parameters."""
    from dataclasses import replace

    from stepframe.pipeline.site import site_from_parameters

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
    from stepframe.pipeline.site import SiteModel
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
    from stepframe.pipeline.site import write_site_model

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


def copy_files(source: Path, target: Path) -> list[Path]:
    """Copy every file under ``source`` to ``target`` (atomically each); the written paths."""
    target.mkdir(parents=True, exist_ok=True)
    written = []
    for file in sorted(source.rglob("*")):
        if file.is_file():
            destination = target / file.relative_to(source)
            destination.parent.mkdir(parents=True, exist_ok=True)
            written.append(write_bytes(destination, file.read_bytes()))
    return written


def _site_publish(folder: Path, outputs: Path) -> list[Path]:
    from stepframe.pipeline.site import read_site_model

    site = read_site_model(folder / SITE_JSON)
    json_copy = write_bytes(outputs / SITE_JSON, (folder / SITE_JSON).read_bytes())
    return [json_copy, *write_output_table(site_table(site), outputs / "site_model.parquet")]


SITE_STAGE = register_stage(
    Stage(
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

    from stepframe.pipeline.amplification import amplification_curve, write_curve
    from stepframe.pipeline.site import read_site_model
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
    from stepframe.pipeline.amplification import read_curve

    netcdf = write_bytes(outputs / CURVE_NETCDF, (folder / CURVE_NETCDF).read_bytes())
    table = curve_table(read_curve(folder / CURVE_NETCDF))
    return [netcdf, *write_output_table(table, outputs / "amplification.parquet")]


AMPLIFICATION_STAGE = register_stage(
    Stage(
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
)


def _selection_options(workflow: Any) -> Any:
    from stepframe.pipeline.selection import SelectionOptions

    given = workflow.tables.get("selection", {})
    try:
        return SelectionOptions.from_dict(given)
    except InputError as error:
        raise workflow.lines.error(f"[selection] {error.what}", "selection") from None


def _selection_check(workflow: Any) -> None:
    if workflow.records is None:
        raise workflow.lines.error("selection without a [records] table, expected one", "outputs")
    _selection_options(workflow)


def _selection_key(context: Context) -> str:
    table = context.tables["features"]
    return make_key(
        "selection",
        SELECTION_VERSION,
        {
            "options": context.workflow.tables.get("selection", {}),
            "frame": context.workflow.frame_source,
        },
        *map(str, table["_key"]),
    )


def _selection_run(context: Context, folder: Path) -> None:
    from stepframe.pipeline.selection import select_records
    from stepframe.pipeline.stage_items import record_folder

    features = context.tables["features"].drop(columns=["_key"])
    # select_records re-reads records by path (spectra, confirmation): give it absolute paths
    folder_of_records = record_folder(context).absolute()
    features["file"] = [str(folder_of_records / name) for name in features["file"]]
    inventory = context.tables["inventory"]
    extra = inventory[["file", "component", "event", "magnitude"]].copy()
    extra["file"] = [str(folder_of_records / name) for name in extra["file"]]
    features = features.merge(extra, on=["file", "component"], how="left")
    records = context.workflow.records
    if records is not None and records.example is not None:
        from stepframe.pipeline.example_files import example_metadata

        features = _join_new_columns(features, example_metadata(folder_of_records))
    kwargs: dict[str, Any] = {"jobs": context.jobs, "executor": context.executor}
    if records is not None and records.options:
        kwargs["record_options"] = dict(records.options)
    result = select_records(
        features, context.workflow.frame, _selection_options(context.workflow), **kwargs
    )
    result.write(folder)


def _join_new_columns(table: Any, extra: Any) -> Any:
    """``table`` with the columns of ``extra`` it lacks, matched on ``file``."""
    new = [c for c in extra.columns if c not in table.columns]
    return table.merge(extra[["file", *new]], on="file", how="left")


def _selection_publish(folder: Path, outputs: Path) -> list[Path]:
    return copy_files(folder, outputs / "selection")


register_stage(
    Stage(
        name="selection",
        version=SELECTION_VERSION,
        description="records ranked by their moving-resonance match to the frame",
        kind="set",
        params={},
        upstream=lambda workflow: ("features",),
        set_key=_selection_key,
        run_set=_selection_run,
        publish=_selection_publish,
        needs_records=True,
        needs_frame=True,
        check=_selection_check,
        free_params=True,
    )
)
