"""One content, one item: files with the same bytes under several names never multiply a table.

Before issue 27 two copies of a one-component file gave an inventory of 4 rows and a features
table of 8 (each task of a key read back every row stored under it). The property test builds
random folders (copies under new names, in sub-folders, then renamed, moved and copied again
between runs of one workspace) and checks every table against a direct count of the distinct
contents.
"""

from __future__ import annotations

import gzip
import shutil
from pathlib import Path

import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from stepframe.pipeline.catalogue.example_files import example_files
from stepframe.pipeline.engine.runner import RunReport, run_workflow
from stepframe.pipeline.stages import shipped_stages

from .conftest import write_workflow

DATA = Path(__file__).resolve().parents[1] / "data" / "formats"

WORKFLOW = """\
workspace = "{workspace}"

[records]
folder = "records"

[outputs]
inventory = true
features = true
"""


def _pool() -> list[tuple[str, bytes, int]]:
    """Distinct contents: (file suffix, bytes, components), one of them unreadable."""
    examples = [data for _, (_, data) in zip(range(2), example_files(), strict=False)]
    geonet = DATA / "geonet" / "20180212_211557_WPWS_20.V2A.gz"
    knet = DATA / "knet" / "AOM0011801241951.EW.gz"
    return [
        *((".AT2", data, 1) for data in examples),
        (".V2A", gzip.decompress(geonet.read_bytes()), 3),
        (".EW.gz", knet.read_bytes(), 1),
        (".txt", b"not a record\n", 0),
    ]


POOL = _pool()

#: A folder: files as (content, sub-folder, name number); names are unique by construction.
placements = st.lists(
    st.tuples(st.integers(0, len(POOL) - 1), st.sampled_from(["", "a", "a/b"])),
    min_size=1,
    max_size=7,
)


def _lay_out(records: Path, files: list[tuple[int, str]], run: int) -> dict[str, int]:
    """Write ``files`` into a fresh ``records``; relative name → content index."""
    shutil.rmtree(records, ignore_errors=True)
    names = {}
    for number, (content, folder) in enumerate(files):
        suffix, data, _ = POOL[content]
        relative = f"{folder}/r{run}_{number}{suffix}".lstrip("/")
        (records / relative).parent.mkdir(parents=True, exist_ok=True)
        (records / relative).write_bytes(data)
        names[relative] = content
    return names


def _check(report: RunReport, names: dict[str, int]) -> None:
    contents = set(names.values())
    components = sum(POOL[c][2] for c in contents)
    readable = {c for c in contents if POOL[c][2]}
    if not readable:  # nothing to tabulate: no output, exit 1, the failure listed once
        assert report.exit_code == 1 and len(report.failures) == 1
        return
    assert report.exit_code == 0, report.missing
    inventory = pd.read_parquet(report.outputs["inventory"][0])
    features = pd.read_parquet(report.outputs["features"][0])
    failed = [f for f in report.failures if f.stage == "features"]
    assert len(inventory) == components
    assert len(features) + len(failed) == components
    assert inventory["content_sha256"].nunique() == len(readable)
    # every name is recorded once: as the item's file, in its duplicates, or as a failed item
    first_names = {f.item for f in report.failures if f.stage == "inventory"}
    first_names |= set(inventory["file"])
    listed = [*first_names, *(name for _, name, _ in report.duplicates)]
    assert sorted(listed) == sorted(names)
    for row in inventory.drop_duplicates("file").itertuples():
        others = [n for n in str(row.duplicates).split("; ") if n]
        same = sorted(n for n, c in names.items() if POOL[c][1] == POOL[names[row.file]][1])
        assert sorted([row.file, *others]) == same
        assert row.file == same[0]  # named by the first in sorted order


@pytest.fixture(scope="module")
def shared(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """One workspace for every example: results are cached by content, so each component's
    features are computed once for the whole test."""
    folder = tmp_path_factory.mktemp("same-content")
    write_workflow(folder, WORKFLOW.format(workspace="work"))
    return folder


@settings(max_examples=20, deadline=None, derandomize=True)
@given(runs=st.lists(placements, min_size=1, max_size=3))
def test_tables_have_one_row_per_distinct_component(
    shared: Path, runs: list[list[tuple[int, str]]]
) -> None:
    for run, files in enumerate(runs):
        names = _lay_out(shared / "records", files, run)
        report = run_workflow(shared / "wf.toml", shipped_stages(), jobs=1)
        _check(report, names)


def test_two_copies_give_one_row_and_name_both(tmp_path: Path) -> None:
    """The case of the issue: a file saved twice beside another file."""
    records = tmp_path / "records"
    names = _lay_out(records, [(0, ""), (0, "a"), (1, "")], 0)
    workflow = write_workflow(tmp_path, WORKFLOW.format(workspace="work"))
    report = run_workflow(workflow, shipped_stages(), jobs=1)
    _check(report, names)
    inventory = pd.read_parquet(report.outputs["inventory"][0])
    # named by the first name in sorted order (a/ sorts before r), the other beside it
    assert list(inventory["file"]) == ["a/r0_1.AT2", "r0_2.AT2"]
    assert list(inventory["duplicates"]) == ["r0_0.AT2", ""]
    assert report.duplicates == [("inventory", "r0_0.AT2", "a/r0_1.AT2")]
    assert "inventory: r0_0.AT2 = a/r0_1.AT2" in report.describe()
