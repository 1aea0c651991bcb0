"""Pipeline: the stages that compose the areas, for the command line and for ``stepframe run``.

The one package allowed to import every area (records, stochastic, structure). Stage modules:
:mod:`~stepframe.pipeline.site` (the site model from records or parameters),
:mod:`~stepframe.pipeline.amplification` (frame-driven and fixed-oscillator amplification),
:mod:`~stepframe.pipeline.fitted` (fitted records: tables and NetCDF),
:mod:`~stepframe.pipeline.design` (the design case from TOML plus overrides),
:mod:`~stepframe.pipeline.record_spectra` and :mod:`~stepframe.pipeline.response` (what
``records spectrum`` and ``structure simulate`` report), with :mod:`~stepframe.pipeline.tables`
(tables with their column dictionary, read back equal) and :mod:`~stepframe.pipeline.figures`
(saving figures atomically). The names below are imported when first used (module
``__getattr__``), so ``stepframe --help`` stays fast.

``stepframe run`` (docs/workflows.md): :mod:`~stepframe.pipeline.workflow` (workflow files,
checked with file:line errors), :mod:`~stepframe.pipeline.stages` (the stage registry, with the
stages in :mod:`~stepframe.pipeline.stage_items` and :mod:`~stepframe.pipeline.stage_sets`),
:mod:`~stepframe.pipeline.plan`, :mod:`~stepframe.pipeline.store` (results keyed by content,
parameters and version), :mod:`~stepframe.pipeline.lock`, :mod:`~stepframe.pipeline.scheduler`
(process pool or Dask) and :mod:`~stepframe.pipeline.runner` (its options:
:mod:`~stepframe.pipeline.run_options`); :mod:`~stepframe.pipeline.shipped`
(the workflows shipped in the package, run by name) and :mod:`~stepframe.pipeline.demo`
(``stepframe demo``: the shipped selection workflow run into one folder).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from stepframe._lazy import lazy_exports

if TYPE_CHECKING:
    from stepframe.pipeline.amplification import (
        AmplificationResult,
        Oscillator,
        amplification_curve,
        amplify,
        frame_oscillator,
        read_curve,
        tracking_oscillator,
        write_curve,
    )
    from stepframe.pipeline.design import (
        DesignOptions,
        DesignRun,
        design_case,
        design_run,
        merged_design_input,
        read_design_result,
        run_design,
        write_design_result,
    )
    from stepframe.pipeline.figures import save_figure
    from stepframe.pipeline.fitted import (
        FitOptions,
        FittedRecord,
        features_table,
        fit_record,
        fit_table,
        fitted_dataset,
        read_fitted,
        write_features,
        write_fitted,
    )
    from stepframe.pipeline.record_spectra import SpectrumOptions, record_spectra
    from stepframe.pipeline.response import (
        RecordResponse,
        SimulateOptions,
        simulate_file,
        simulate_record,
    )
    from stepframe.pipeline.run_options import RunOptions, run_with_options
    from stepframe.pipeline.site import (
        SiteModel,
        read_site_model,
        site_from_parameters,
        site_from_record,
        write_site_model,
    )
    from stepframe.pipeline.tables import read_table, write_table

_EXPORTS = {
    **dict.fromkeys(
        ("SiteModel", "site_from_parameters", "site_from_record", "write_site_model",
         "read_site_model"),
        "stepframe.pipeline.site",
    ),
    **dict.fromkeys(
        ("AmplificationResult", "Oscillator", "amplify", "amplification_curve",
         "frame_oscillator", "tracking_oscillator", "write_curve", "read_curve"),
        "stepframe.pipeline.amplification",
    ),
    **dict.fromkeys(
        ("FitOptions", "FittedRecord", "fit_record", "fit_table", "fitted_dataset",
         "write_fitted", "read_fitted", "features_table", "write_features"),
        "stepframe.pipeline.fitted",
    ),
    **dict.fromkeys(
        ("DesignOptions", "DesignRun", "design_case", "design_run", "merged_design_input",
         "run_design", "write_design_result", "read_design_result"),
        "stepframe.pipeline.design",
    ),
    "record_spectra": "stepframe.pipeline.record_spectra",
    "SpectrumOptions": "stepframe.pipeline.record_spectra",
    **dict.fromkeys(
        ("RecordResponse", "SimulateOptions", "simulate_file", "simulate_record"),
        "stepframe.pipeline.response",
    ),
    "RunOptions": "stepframe.pipeline.run_options",
    "run_with_options": "stepframe.pipeline.run_options",
    "read_table": "stepframe.pipeline.tables",
    "write_table": "stepframe.pipeline.tables",
    "save_figure": "stepframe.pipeline.figures",
}  # fmt: skip


__getattr__ = lazy_exports(__name__, _EXPORTS)


__all__ = [
    "AmplificationResult",
    "DesignOptions",
    "DesignRun",
    "FitOptions",
    "FittedRecord",
    "Oscillator",
    "RecordResponse",
    "RunOptions",
    "SimulateOptions",
    "SiteModel",
    "SpectrumOptions",
    "amplification_curve",
    "amplify",
    "design_case",
    "design_run",
    "features_table",
    "fit_record",
    "fit_table",
    "fitted_dataset",
    "frame_oscillator",
    "merged_design_input",
    "read_curve",
    "read_design_result",
    "read_fitted",
    "read_site_model",
    "read_table",
    "record_spectra",
    "run_design",
    "run_with_options",
    "save_figure",
    "simulate_file",
    "simulate_record",
    "site_from_parameters",
    "site_from_record",
    "tracking_oscillator",
    "write_curve",
    "write_design_result",
    "write_features",
    "write_fitted",
    "write_site_model",
    "write_table",
]
