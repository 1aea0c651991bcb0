"""One name per example component: ``select --example``, the workflow's AT2 files, the report."""

from __future__ import annotations

from pathlib import Path

from stepframe.pipeline.catalogue.example_files import example_metadata, example_name
from stepframe.records.examples import fema_p695, metadata


def test_example_components_have_one_name_everywhere() -> None:
    stream, table = fema_p695()
    in_memory = [str(trace.stats.stepframe.source_file) for trace in stream]
    written = [Path(f).name for f in example_metadata(Path("anywhere"))["file"]]
    rows = table.to_dict(orient="records")
    assert in_memory == written == [example_name(row) for row in rows]
    assert "RSN174_IMPVALL_H-E11230.AT2" in in_memory
    assert len(set(in_memory)) == len(metadata()) == 100
