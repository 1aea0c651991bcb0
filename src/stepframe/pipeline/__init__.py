"""Pipeline: the jobs that compose the areas, for the command line and for ``stepframe run``.

The one package allowed to import every area (records, stochastic, structure). It is cut by job;
each job keeps its computation, its report and its workflow stages together:

- :mod:`~stepframe.pipeline.catalogue`: a folder of records → features and fitted parameters
  (``records info | spectrum``, ``stochastic fit | features``; the ``inventory`` and
  ``features`` stages);
- :mod:`~stepframe.pipeline.amplification`: a site's model and its moving-resonance
  amplification (``stochastic amplify``, ``report amplification``; the ``site``,
  ``amplification`` and ``amplification_report`` stages);
- :mod:`~stepframe.pipeline.selection`: record selection by moving resonance (``select``,
  ``report selection``; the ``selection`` and ``selection_report`` stages);
- :mod:`~stepframe.pipeline.dynamics`: design, simulation, harmonic, bifurcation and IDA
  studies (``structure ...``; the ``ida`` stage);

with :mod:`~stepframe.pipeline.reports` (the HTML machinery the reports share),
:mod:`~stepframe.pipeline.engine` (the workflow engine: it imports no job and is handed the
stages), :mod:`~stepframe.pipeline.stages` (the composition root: the shipped stages' table)
and :mod:`~stepframe.pipeline.demo` (``stepframe demo``). The names below are imported when
first used (module ``__getattr__``), so ``stepframe --help`` stays fast.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from stepframe._lazy import lazy_exports

if TYPE_CHECKING:
    from stepframe.core.figures import save_figure
    from stepframe.core.tables import read_table, write_table
    from stepframe.pipeline.amplification.amplify import (
        AmplificationResult,
        Oscillator,
        amplification_curve,
        amplify,
        frame_oscillator,
        read_curve,
        tracking_oscillator,
        write_curve,
    )
    from stepframe.pipeline.amplification.site import (
        SiteModel,
        read_site_model,
        site_from_parameters,
        site_from_record,
        write_site_model,
    )
    from stepframe.pipeline.catalogue.fitted import (
        FitOptions,
        FittedRecord,
        fit_record,
        fit_table,
        fitted_dataset,
        read_fitted,
        write_features,
        write_fitted,
    )
    from stepframe.pipeline.catalogue.record_spectra import SpectrumOptions, record_spectra
    from stepframe.pipeline.dynamics.design import (
        DesignOptions,
        DesignRun,
        design_case,
        design_run,
        merged_design_input,
        read_design_result,
        run_design,
        write_design_result,
    )
    from stepframe.pipeline.dynamics.response import (
        RecordResponse,
        SimulateOptions,
        simulate_file,
        simulate_record,
    )
    from stepframe.pipeline.engine.run_options import RunOptions, run_with_options

_EXPORTS = {
    **dict.fromkeys(
        ("SiteModel", "site_from_parameters", "site_from_record", "write_site_model",
         "read_site_model"),
        "stepframe.pipeline.amplification.site",
    ),
    **dict.fromkeys(
        ("AmplificationResult", "Oscillator", "amplify", "amplification_curve",
         "frame_oscillator", "tracking_oscillator", "write_curve", "read_curve"),
        "stepframe.pipeline.amplification.amplify",
    ),
    **dict.fromkeys(
        ("FitOptions", "FittedRecord", "fit_record", "fit_table", "fitted_dataset",
         "write_fitted", "read_fitted", "write_features"),
        "stepframe.pipeline.catalogue.fitted",
    ),
    **dict.fromkeys(
        ("DesignOptions", "DesignRun", "design_case", "design_run", "merged_design_input",
         "run_design", "write_design_result", "read_design_result"),
        "stepframe.pipeline.dynamics.design",
    ),
    "record_spectra": "stepframe.pipeline.catalogue.record_spectra",
    "SpectrumOptions": "stepframe.pipeline.catalogue.record_spectra",
    **dict.fromkeys(
        ("RecordResponse", "SimulateOptions", "simulate_file", "simulate_record"),
        "stepframe.pipeline.dynamics.response",
    ),
    "RunOptions": "stepframe.pipeline.engine.run_options",
    "run_with_options": "stepframe.pipeline.engine.run_options",
    "read_table": "stepframe.core.tables",
    "write_table": "stepframe.core.tables",
    "save_figure": "stepframe.core.figures",
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
