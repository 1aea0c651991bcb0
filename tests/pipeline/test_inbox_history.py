"""An inbox that keeps what it saw (issue 30): the shipped ``inbox`` workflow run as scheduled.

Files arrive, one cannot be read, one is archived (moved out of the inbox), one arrives again
under a second name; the outputs keep every item seen (``present = false`` once gone) and every
failure (first and last seen, ``new`` only in the run that found it), ``--prune`` forgets what
is gone, and each run adds one JSON line to the workspace's run log.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pandas as pd
import pytest

from stepframe.cli import main
from stepframe.pipeline.catalogue.example_files import write_example_files
from stepframe.pipeline.engine.runner import RunReport, run_workflow
from stepframe.pipeline.engine.shipped import copy_workflow
from stepframe.pipeline.stages import shipped_stages


def _run(workflow: Path, **options: object) -> RunReport:
    report = run_workflow(workflow, shipped_stages(), jobs=1, **options)  # type: ignore[arg-type]
    assert report.exit_code == 0, report.missing
    return report


def _log(workflow: Path) -> list[dict[str, object]]:
    text = (workflow.parent / "stepframe-work" / "runs.jsonl").read_text()
    return [json.loads(line) for line in text.splitlines()]


def _outputs(workflow: Path) -> tuple[pd.DataFrame, pd.DataFrame]:
    folder = workflow.parent / "stepframe-work" / "outputs"
    features = pd.read_parquet(folder / "features.parquet")
    failures = pd.read_csv(folder / "features.failures.csv", keep_default_na=False)
    return features, failures


@pytest.fixture
def inbox(tmp_path: Path) -> Path:
    """The shipped inbox copied, with 3 example records and an unreadable file in it."""
    copy_workflow("inbox", tmp_path)
    workflow = tmp_path / "inbox.toml"
    write_example_files(tmp_path / "inbox", count=3)
    (tmp_path / "inbox" / "damaged.AT2").write_text("PEER NGA STRONG MOTION DATABASE\n")
    return workflow


def test_the_inbox_keeps_every_item_and_failure_it_saw(inbox: Path) -> None:
    folder = inbox.parent / "inbox"
    first = _run(inbox)
    features, failures = _outputs(inbox)
    assert list(features["present"]) == [True] * 3
    assert (features["first_seen_utc"] == features["last_seen_utc"]).all()
    assert failures[["item", "stage", "present", "new"]].values.tolist() == [
        ["damaged.AT2", "inventory", True, True]
    ]
    assert first.new_failures == 1

    second = _run(inbox)
    features, failures = _outputs(inbox)
    assert failures[["present", "new"]].values.tolist() == [[True, False]]  # seen before
    assert failures.at[0, "first_seen_utc"] < failures.at[0, "last_seen_utc"]
    assert second.new_failures == 0

    # archiving: a file leaves the inbox; its row stays, marked absent, with its numbers
    archived = sorted(p.name for p in folder.glob("RSN*.AT2"))[0]
    before = features.set_index("file").loc[archived]
    (inbox.parent / "archive").mkdir()
    shutil.move(folder / archived, inbox.parent / "archive" / archived)
    (folder / "damaged.AT2").unlink()
    third = _run(inbox)
    features, failures = _outputs(inbox)
    assert len(features) == 3 and features["present"].tolist() == [True, True, False]
    gone = features.set_index("file").loc[archived]
    assert gone["omega_p_rad_s"] == before["omega_p_rad_s"]
    assert gone["last_seen_utc"] == before["last_seen_utc"] < features.at[0, "last_seen_utc"]
    assert failures[["item", "present", "new"]].values.tolist() == [["damaged.AT2", False, False]]
    assert [s.computed for s in third.stages] == [0, 0]

    # the same bytes under a new name: one item, present again, both names known
    shutil.copy(inbox.parent / "archive" / archived, folder / "again.AT2")
    _run(inbox)
    features, _ = _outputs(inbox)
    assert len(features) == 3 and features["present"].all()
    assert "again.AT2" in set(features["file"])

    # --prune forgets what is gone: the mended failure
    _run(inbox, prune=True)
    features, failures = _outputs(inbox)
    assert len(features) == 3 and failures.empty

    log = _log(inbox)
    assert len(log) == 5
    assert [line["new_failures"] for line in log] == [1, 0, 0, 0, 0]
    assert all(len(json.dumps(line)) < 1000 for line in log)


def test_a_damaged_history_is_quarantined_and_started_again(inbox: Path) -> None:
    _run(inbox)
    history = inbox.parent / "stepframe-work" / "store" / "features" / "history.parquet"
    history.write_bytes(history.read_bytes()[:100])
    report = _run(inbox)
    [event] = report.store_events
    assert event.item == "features/history.parquet" and "started again" in event.action
    features, failures = _outputs(inbox)
    assert len(features) == 3 and features["present"].all()
    assert failures["new"].tolist() == [True]  # first seen again by this run


def test_prune_without_history_is_a_user_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    write_example_files(tmp_path / "records", count=1)
    text = '[records]\nfolder = "records"\n[outputs]\ninventory = true\n'
    (tmp_path / "wf.toml").write_text(text)
    assert main(["run", str(tmp_path / "wf.toml"), "--prune"]) == 2
    assert capsys.readouterr().err.strip() == (
        "stepframe: error: --prune without [outputs] history = true, expected a workflow that "
        "keeps what it saw"
    )
    assert not (tmp_path / "stepframe-work").exists()


def test_a_file_the_run_cannot_read_is_a_failed_item_not_the_end_of_the_run(
    inbox: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    # Before, one file of the inbox without read permission (or gone between the listing and
    # its hashing) ended the whole run: "stepframe: error: .../x.AT2: Permission denied", exit
    # 2, no other file computed. (Patched, not chmod: a test run as root reads any file.)
    from stepframe.pipeline.catalogue import file_hashes, stage

    folder = inbox.parent / "inbox"
    (folder / "damaged.AT2").unlink()
    locked = sorted(folder.glob("RSN*.AT2"))[1]
    real_sha, real_open = file_hashes.file_sha256, open

    def denied(path: object, *args: object, **kwargs: object) -> object:
        if Path(str(path)).name == locked.name:
            raise PermissionError(13, "Permission denied", str(path))
        return real_open(path, *args, **kwargs)  # type: ignore[call-overload]

    monkeypatch.setattr(file_hashes, "file_sha256", lambda p: denied(p) and real_sha(p))
    monkeypatch.setattr(stage, "open", denied, raising=False)
    monkeypatch.setattr(file_hashes, "RACY_S", -3600.0)  # remember files however new
    first = _run(inbox)
    features, failures = _outputs(inbox)
    assert [(s.name, s.computed, s.failed) for s in first.stages] == [
        ("inventory", 3, 1),
        ("features", 2, 0),
    ]
    assert sorted(features["file"]) == sorted(
        p.name for p in folder.glob("RSN*.AT2") if p != locked
    )
    assert failures[["item", "stage", "message", "present", "new"]].values.tolist() == [
        [
            locked.name,
            "inventory",
            f"read: {locked.name}: cannot read (Permission denied), expected a file this run "
            "can read",
            True,
            True,
        ]
    ]
    cache = pd.read_parquet(inbox.parent / "stepframe-work" / "record-hashes.parquet")
    assert sorted(Path(p).name for p in cache["path"]) == sorted(features["file"])

    monkeypatch.undo()  # readable again: read, by its content
    second = _run(inbox)
    features, failures = _outputs(inbox)
    assert [(s.name, s.computed, s.failed) for s in second.stages] == [
        ("inventory", 1, 0),
        ("features", 1, 0),
    ]
    assert sorted(features["file"]) == sorted(p.name for p in folder.glob("RSN*.AT2"))
    assert features["present"].all()
    assert failures[["item", "present", "new"]].values.tolist() == [[locked.name, False, False]]


def test_a_failure_listed_by_several_outputs_is_one_new_failure(inbox: Path) -> None:
    # The damaged file is a failure of the inventory in the failures table of every output
    # computed from it. Before, the run log counted it once per output (3 with measures and
    # rotd50: a monitor alerting on new_failures saw 3 files), and an output turned on later
    # marked it new again although earlier runs had seen it.
    text = inbox.read_text()
    inbox.write_text(text.replace("# measures = true", "measures = true"))
    first = _run(inbox)
    assert first.new_failures == 1
    folder = inbox.parent / "stepframe-work" / "outputs"
    for name in ("features", "measures"):
        table = pd.read_csv(folder / f"{name}.failures.csv", keep_default_na=False)
        assert table[["item", "stage", "new"]].values.tolist() == [
            ["damaged.AT2", "inventory", True]
        ]

    inbox.write_text(inbox.read_text().replace("# rotd50 = true", "rotd50 = true"))
    second = _run(inbox)
    assert second.new_failures == 0
    rotd50 = pd.read_csv(folder / "rotd50.failures.csv", keep_default_na=False)
    features = pd.read_csv(folder / "features.failures.csv", keep_default_na=False)
    assert rotd50[["item", "present", "new"]].values.tolist() == [["damaged.AT2", True, False]]
    assert rotd50.at[0, "first_seen_utc"] == features.at[0, "first_seen_utc"]
    assert rotd50.at[0, "first_seen_utc"] < rotd50.at[0, "last_seen_utc"]
    assert [line["new_failures"] for line in _log(inbox)] == [1, 0]


def test_a_dangling_link_and_a_loop_of_links_are_failed_items(inbox: Path) -> None:
    # Before, a link whose target is gone (a share not mounted) ended the run at hashing
    # ("stepframe: error: inbox/gone.AT2: No such file or directory", exit 2), and a loop of
    # links was skipped without a word.
    folder = inbox.parent / "inbox"
    (folder / "damaged.AT2").unlink()
    (folder / "gone.AT2").symlink_to(inbox.parent / "nowhere" / "gone.AT2")
    (folder / "loop-a.AT2").symlink_to(folder / "loop-b.AT2")
    (folder / "loop-b.AT2").symlink_to(folder / "loop-a.AT2")
    report = _run(inbox)
    features, failures = _outputs(inbox)
    assert len(features) == 3 and report.new_failures == 3
    assert failures[["item", "message"]].values.tolist() == [
        ["gone.AT2", "read: gone.AT2: cannot read (No such file or directory), expected a file "
         "this run can read"],
        ["loop-a.AT2", "read: loop-a.AT2: cannot read (Too many levels of symbolic links), "
         "expected a file this run can read"],
        ["loop-b.AT2", "read: loop-b.AT2: cannot read (Too many levels of symbolic links), "
         "expected a file this run can read"],
    ]  # fmt: skip


def test_a_run_where_every_file_fails_sees_its_failures_first(inbox: Path) -> None:
    # Every record archived, one damaged file left: no features (exit 1). Before, that run
    # wrote no history, so its failure was counted new by the next run that computed
    # something (new_failures 0, then 1), or by none if the file left before it; and the
    # earlier run's tables stayed published, every archived file still present = true.
    folder = inbox.parent / "inbox"
    _run(inbox)
    (inbox.parent / "archive").mkdir()
    for path in folder.glob("RSN*.AT2"):
        shutil.move(path, inbox.parent / "archive" / path.name)
    (folder / "damaged.AT2").unlink()
    (folder / "junk.AT2").write_text("PEER NGA STRONG MOTION DATABASE\njunk\n")
    failed = run_workflow(inbox, shipped_stages(), jobs=1)
    assert failed.exit_code == 1 and failed.new_failures == 1
    outputs = inbox.parent / "stepframe-work" / "outputs"
    assert not (outputs / "features.csv").exists()
    assert _log(inbox)[-1]["new_failures"] == 1

    shutil.move(inbox.parent / "archive" / path.name, folder / path.name)  # one comes back
    again = _run(inbox)
    features, failures = _outputs(inbox)
    assert again.new_failures == 0
    assert len(features) == 3 and features["present"].sum() == 1
    junk = failures.set_index("item").loc["junk.AT2"]
    assert (bool(junk["present"]), bool(junk["new"])) == (True, False)
    assert junk["first_seen_utc"] == _log(inbox)[-2]["started_utc"] < junk["last_seen_utc"]
