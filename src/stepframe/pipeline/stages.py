"""The composition root: the shipped stages, in one explicit table, handed to the engine.

The workflow engine (:mod:`stepframe.pipeline.engine`) imports no job and no science: the
commands and :mod:`stepframe.pipeline.demo` give it :func:`shipped_stages`, and a user's own
program can give it more (``shipped_stages().with_stages(my_stage)``; docs/architecture.md, "A
stage"). The order below is the order of ``stepframe run --template`` and of a run's summary
where the dependencies allow; the engine orders a run by each stage's declared upstreams.
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

from stepframe.pipeline.engine.stage import Scene, StageTable


def _frame_from_mapping(mapping: dict[str, Any], path: Path) -> Any:
    from stepframe.structure.frame_file import frame_from_mapping

    return frame_from_mapping(mapping, path=path, text=None)


def _read_frame_file(path: Path) -> Any:
    from stepframe.structure.frame_file import read_frame_file

    return read_frame_file(path)


def _check_units(units: str) -> object:
    from stepframe.records.units import normalize_units

    return normalize_units(units)


def _check_record_options(options: dict[str, Any]) -> object:
    from stepframe.records.read_options import RecordReadOptions

    if "format" in options:
        from stepframe.records.io import format_by_name

        format_by_name(options["format"])
    return RecordReadOptions(**options)


@functools.cache
def shipped_stages() -> StageTable:
    """The stages shipped with stepframe: catalogue (with the nightly job's measures, RotD50,
    waveforms and arrivals summary), site amplification, selection, dynamics."""
    from stepframe.pipeline.amplification.stage import (
        AMPLIFICATION_REPORT_STAGE,
        AMPLIFICATION_STAGE,
        SITE_STAGE,
    )
    from stepframe.pipeline.catalogue.arrivals import ARRIVALS_REPORT_STAGE
    from stepframe.pipeline.catalogue.measures_stage import (
        MEASURES_STAGE,
        ROTD50_STAGE,
        WAVEFORMS_STAGE,
    )
    from stepframe.pipeline.catalogue.stage import FEATURES_STAGE, INVENTORY_STAGE
    from stepframe.pipeline.dynamics.stage import IDA_STAGE
    from stepframe.pipeline.selection.stage import (
        RESPONSES_STAGE,
        SELECTION_REPORT_STAGE,
        SELECTION_STAGE,
    )

    return StageTable(
        stages=(
            INVENTORY_STAGE,
            FEATURES_STAGE,
            MEASURES_STAGE,
            ROTD50_STAGE,
            WAVEFORMS_STAGE,
            ARRIVALS_REPORT_STAGE,
            SITE_STAGE,
            AMPLIFICATION_STAGE,
            RESPONSES_STAGE,
            SELECTION_STAGE,
            SELECTION_REPORT_STAGE,
            AMPLIFICATION_REPORT_STAGE,
            IDA_STAGE,
        ),
        scene=Scene(
            read_frame_file=_read_frame_file,
            frame_from_mapping=_frame_from_mapping,
            check_units=_check_units,
            check_record_options=_check_record_options,
        ),
    )
