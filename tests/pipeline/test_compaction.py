"""Small segments merged: a store fed one file per run stays as small as a batch run's store.

Ten runs each find one new file (one segment per stage per run); once a stage holds
:data:`~stepframe.pipeline.engine.store.COMPACT_AT` small segments the run merges them. The
outputs are byte-identical to one batch run over the same files, and the store verifies clean.
"""

from __future__ import annotations

from pathlib import Path

from stepframe.pipeline.catalogue.example_files import write_example_files
from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.engine.store import COMPACT_AT, Store
from stepframe.pipeline.stages import shipped_stages

from .conftest import FEATURES_WORKFLOW, tree, write_workflow

RUNS = 10


def _segments(workspace: Path, stage: str) -> int:
    return len(list((workspace / "store" / stage).glob("seg-*.parquet")))


def test_trickled_files_are_merged_and_give_the_batch_outputs(tmp_path: Path) -> None:
    trickle = write_workflow(tmp_path, 'workspace = "trickle"\n' + FEATURES_WORKFLOW, "t.toml")
    batch = write_workflow(tmp_path, 'workspace = "batch"\n' + FEATURES_WORKFLOW, "b.toml")
    counts = []
    for run in range(1, RUNS + 1):
        write_example_files(tmp_path / "records", count=run)
        report = run_workflow(trickle, shipped_stages(), jobs=1)
        assert [s.computed for s in report.stages] == [1, 1]
        counts.append(_segments(tmp_path / "trickle", "features"))
    # merged when the 8th small segment arrived: 8 → 1, then one more per run
    assert counts == [1, 2, 3, 4, 5, 6, 7, 1, 2, 3]
    assert max(counts) < COMPACT_AT
    run_workflow(batch, shipped_stages(), jobs=1)
    assert tree(tmp_path / "trickle" / "outputs") == tree(tmp_path / "batch" / "outputs")
    store = Store(tmp_path / "trickle" / "store")
    assert store.verify()["features"]["items"] == RUNS and store.events == []


def test_compaction_keeps_only_the_rows_in_use(tmp_path: Path) -> None:
    """A forced stage writes its keys again: the merge keeps the latest rows of each key."""
    workflow = write_workflow(tmp_path, FEATURES_WORKFLOW)
    write_example_files(tmp_path / "records", count=2)
    for _ in range(3):
        run_workflow(workflow, shipped_stages(), jobs=1, force=["inventory"])
    store = Store(tmp_path / "stepframe-work" / "store")
    assert _segments(tmp_path / "stepframe-work", "inventory") == 3
    assert store.compact("inventory", at=2) == 3
    assert _segments(tmp_path / "stepframe-work", "inventory") == 1
    assert len(store.table("inventory", list(store.index("inventory")))) == 2
