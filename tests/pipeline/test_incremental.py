"""Incremental runs: keys from content and parameters, so only what is new or changed runs."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from stepframe.pipeline.catalogue.example_files import example_files, write_example_files
from stepframe.pipeline.engine.runner import RunReport, run_workflow
from stepframe.pipeline.engine.store import Store
from stepframe.pipeline.stages import shipped_stages

from .conftest import FEATURES_WORKFLOW, SMALL, tree, write_workflow


def _run(workflow: Path, **options: object) -> RunReport:
    report = run_workflow(workflow, shipped_stages(), jobs=1, **options)  # type: ignore[arg-type]
    assert report.exit_code == 0, report.missing
    return report


def _counts(report: RunReport) -> dict[str, tuple[int, int, int]]:
    return {s.name: (s.computed, s.cached, s.failed) for s in report.stages}


def _features(report: RunReport) -> pd.DataFrame:
    return pd.read_parquet(report.outputs["features"][0])


def test_first_run_matches_the_catalogue_batch_function(scene: Path) -> None:
    from stepframe.stochastic.catalog_features import catalog_features

    report = _run(scene / "wf.toml")
    assert _counts(report) == {"inventory": (SMALL, 0, 0), "features": (SMALL, 0, 0)}
    table = _features(report)
    reference, failures = catalog_features(scene / "records", n_jobs=1)
    assert failures.empty
    reference["file"] = [Path(f).name for f in reference["file"]]
    assert list(table["duplicates"]) == [""] * SMALL  # no two files with the same bytes
    table = table.drop(columns="duplicates")
    pd.testing.assert_frame_equal(table, reference[table.columns], check_dtype=False)
    csv = pd.read_csv(report.outputs["features"][1])
    assert np.allclose(csv["omega_p_rad_s"], table["omega_p_rad_s"], rtol=1e-15)


def test_no_op_rerun_computes_nothing_and_gives_the_same_bytes(scene: Path) -> None:
    first = _run(scene / "wf.toml")
    outputs = tree(scene / "stepframe-work" / "outputs")
    second = _run(scene / "wf.toml")
    assert _counts(second) == {"inventory": (0, SMALL, 0), "features": (0, SMALL, 0)}
    assert tree(scene / "stepframe-work" / "outputs") == outputs
    assert first.outputs == second.outputs


def test_no_op_rerun_leaves_the_output_tables_unwritten_unless_touched(scene: Path) -> None:
    """An unchanged table is not written again (its three files keep their times); an output
    file edited or deleted since is written again, as is a table whose rows changed."""
    outputs = scene / "stepframe-work" / "outputs"
    names = ("features.parquet", "features.csv", "features.columns.csv")

    def stamps() -> dict[str, int]:
        return {name: (outputs / name).stat().st_mtime_ns for name in names}

    _run(scene / "wf.toml")
    before = stamps()
    _run(scene / "wf.toml")
    assert stamps() == before
    csv = outputs / "features.csv"
    original = csv.read_bytes()
    csv.write_bytes(b"edited\n")
    _run(scene / "wf.toml")
    assert csv.read_bytes() == original  # restored from the store's table
    (outputs / "features.columns.csv").unlink()
    _run(scene / "wf.toml")
    assert (outputs / "features.columns.csv").is_file()
    files = sorted((scene / "records").iterdir())
    shutil.copy(files[0], scene / "records" / "copy-of-first.AT2")
    _run(scene / "wf.toml")
    assert "copy-of-first.AT2" in pd.read_csv(csv)["duplicates"].iloc[0]


def test_no_op_rerun_leaves_a_published_set_unwritten_unless_touched(scene: Path) -> None:
    """A whole-set result published by the last run and untouched since is not copied again
    (its files keep their times); an edited or deleted copy, or another result, is published
    again, and an edited copy is the stored bytes again."""
    site = '[site]\nfrom = "records"\nplausible_only = false\n\n[outputs]\nsite = true'
    write_workflow(scene, FEATURES_WORKFLOW.replace("[outputs]", site))
    outputs = scene / "stepframe-work" / "outputs"

    def stamps() -> dict[str, int]:
        return {p.name: p.stat().st_mtime_ns for p in outputs.glob("site_model*")}

    first = _run(scene / "wf.toml")
    before = stamps()
    assert set(before) == {Path(p).name for p in first.outputs["site"]}  # json, parquet, csvs
    second = _run(scene / "wf.toml")
    assert stamps() == before and second.outputs["site"] == first.outputs["site"]
    copy = outputs / "site_model.json"
    original = copy.read_bytes()
    copy.write_bytes(b"{}")
    _run(scene / "wf.toml")
    assert copy.read_bytes() == original
    (outputs / "site_model.csv").unlink()
    _run(scene / "wf.toml")
    assert (outputs / "site_model.csv").is_file()
    # another result (one record fewer): its model published, not the last one's
    sorted((scene / "records").iterdir())[0].unlink()
    _run(scene / "wf.toml")
    assert pd.read_parquet(outputs / "site_model.parquet")["n_components"].iloc[0] == SMALL - 1


def test_two_new_files_compute_exactly_two_items_per_stage(scene: Path) -> None:
    _run(scene / "wf.toml")
    write_example_files(scene / "records", count=SMALL + 2)
    dry = run_workflow(scene / "wf.toml", shipped_stages(), dry_run=True)
    inventory, features = dry.stages
    assert (inventory.name, inventory.computed, inventory.cached) == ("inventory", 2, SMALL)
    assert features.status == "pending"  # its items are known once the new files are read
    report = _run(scene / "wf.toml")
    assert _counts(report) == {"inventory": (2, SMALL, 0), "features": (2, SMALL, 0)}
    assert len(_features(report)) == SMALL + 2


def test_renamed_folder_recomputes_nothing(scene: Path) -> None:
    before = _features(_run(scene / "wf.toml"))
    shutil.move(scene / "records", scene / "renamed")
    text = (scene / "wf.toml").read_text().replace('"records"', '"renamed"')
    write_workflow(scene, text)
    report = _run(scene / "wf.toml")
    assert _counts(report) == {"inventory": (0, SMALL, 0), "features": (0, SMALL, 0)}
    pd.testing.assert_frame_equal(_features(report), before)


def test_renamed_file_keeps_its_results_under_the_new_name(scene: Path) -> None:
    before = _features(_run(scene / "wf.toml"))
    first = sorted((scene / "records").iterdir())[0]
    first.rename(first.with_name("zz-renamed.AT2"))
    after = _features(_run(scene / "wf.toml"))
    assert (after["file"] == "zz-renamed.AT2").sum() == 1
    moved = after[after["file"] == "zz-renamed.AT2"].iloc[0]
    original = before[before["file"] == first.name].iloc[0]
    assert moved["omega_p_rad_s"] == original["omega_p_rad_s"]


def test_changed_parameter_recomputes_only_downstream(scene: Path) -> None:
    _run(scene / "wf.toml")
    text = (scene / "wf.toml").read_text().replace("[features]", "[features]\nwindow_s = 3.0")
    write_workflow(scene, text)
    report = _run(scene / "wf.toml")
    assert _counts(report) == {"inventory": (0, SMALL, 0), "features": (SMALL, 0, 0)}


def test_changed_file_is_recomputed(scene: Path) -> None:
    before = _features(_run(scene / "wf.toml"))
    name, data = next(example_files(scale=0.5))
    (scene / "records" / name).write_bytes(data)
    report = _run(scene / "wf.toml")
    assert _counts(report) == {"inventory": (1, SMALL - 1, 0), "features": (1, SMALL - 1, 0)}
    table = _features(report)
    # the record at half scale: I_g is linear in the record (9-digit rounding of the file aside)
    halved = table[table["file"] == name].iloc[0]["max_intensity_m_s2"]
    original = before[before["file"] == name].iloc[0]["max_intensity_m_s2"]
    assert halved == pytest.approx(0.5 * original, rel=1e-7)


def test_force_recomputes_the_stage(scene: Path) -> None:
    _run(scene / "wf.toml")
    report = _run(scene / "wf.toml", force=["features"])
    assert _counts(report) == {"inventory": (0, SMALL, 0), "features": (SMALL, 0, 0)}


def test_failed_items_are_retried_only_when_asked(scene: Path) -> None:
    (scene / "records" / "garbage.txt").write_text("this is not a record\n")
    report = _run(scene / "wf.toml")
    assert _counts(report)["inventory"] == (SMALL + 1, 0, 1)
    assert report.failures[0].item == "garbage.txt" and report.failures[0].stage == "inventory"
    failures = pd.read_csv(scene / "stepframe-work" / "outputs" / "features.failures.csv")
    # an unreadable file has no features: its failure is in the features' failures table too
    assert list(failures[["item", "stage"]].itertuples(index=False, name=None)) == [
        ("garbage.txt", "inventory")
    ]
    again = _run(scene / "wf.toml")
    assert _counts(again)["inventory"] == (0, SMALL + 1, 1)
    retried = _run(scene / "wf.toml", retry_failed=True)
    assert _counts(retried)["inventory"] == (1, SMALL, 1)


def test_index_is_rebuilt_from_the_segment_files(scene: Path) -> None:
    _run(scene / "wf.toml")
    write_example_files(scene / "records", count=SMALL + 1)
    _run(scene / "wf.toml")
    store = Store(scene / "stepframe-work" / "store")
    index = store.index("features")
    assert len(index) == SMALL + 1
    assert len({entry.segment for entry in index.values()}) == 2
    rows = store.rows("features", list(index))
    assert sorted(rows) == sorted(index)


def test_site_from_records_is_the_median_of_the_fitted_parameters(scene: Path) -> None:
    text = FEATURES_WORKFLOW.replace(
        "[outputs]", '[site]\nfrom = "records"\nplausible_only = false\n\n[outputs]\nsite = true'
    )
    write_workflow(scene, text)
    report = _run(scene / "wf.toml")
    features = _features(report)
    site = pd.read_parquet(scene / "stepframe-work" / "outputs" / "site_model.parquet").iloc[0]
    for name in ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r", "t_max_s"):
        assert site[name] == pytest.approx(float(np.median(features[name])), rel=1e-14)
    assert site["n_components"] == SMALL
    assert site["fp_hz"] == pytest.approx(site["omega_p_rad_s"] / (2 * np.pi), rel=1e-14)


def test_record_options_of_the_records_table_reach_the_reader(tmp_path: Path) -> None:
    """``dt_s``, ``units`` and ``allow_short`` of [records] are the reader's options: a
    one-column text file needs dt and units, and its inventory row says what they gave."""
    records = tmp_path / "records"
    records.mkdir()
    samples = np.sin(np.arange(3000) * 0.05) * 0.1
    np.savetxt(records / "a.txt", samples)
    workflow = tmp_path / "wf.toml"
    workflow.write_text(
        '[records]\nfolder = "records"\ndt_s = 0.01\nunits = "g"\nallow_short = true\n'
        "[outputs]\ninventory = true\n",
        encoding="utf-8",
    )
    report = run_workflow(workflow, shipped_stages(), jobs=1)
    assert report.failures == [] and report.exit_code == 0
    table = pd.read_parquet(tmp_path / "stepframe-work" / "outputs" / "inventory.parquet")
    assert table["dt_s"].tolist() == [0.01] and table["npts"].tolist() == [3000]
    assert table["pga_m_s2"].iloc[0] == pytest.approx(np.abs(samples).max() * 9.80665, rel=1e-9)


def test_the_progress_line_counts_items_and_their_failures(
    scene: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # The chained stages run in groups of items; the line counts the items (it once said
    # "inventory+features: 2 items, 0 failed" for SMALL + 1 files, one of them unreadable).
    (scene / "records" / "garbage.txt").write_text("this is not a record\n")
    capsys.readouterr()
    _run(scene / "wf.toml", progress=True)
    lines = [line for line in capsys.readouterr().err.splitlines() if "items/s" in line]
    assert len(lines) == 1, lines
    assert lines[0].startswith(f"inventory+features: {SMALL + 1} items, 1 failed, "), lines


def test_a_run_lists_the_records_folder_once(scene: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # The check before any work, the inventory's file contents and its tasks all ask for the
    # files; the folder is walked once (it was three times: a second each at 43,000 files).
    import stepframe.core.paths as paths

    walked: list[Path] = []
    original = paths.walk_files

    def counting(folder: Path, *args: object, **kwargs: object) -> object:
        walked.append(Path(folder))
        return original(folder, *args, **kwargs)  # type: ignore[arg-type]

    monkeypatch.setattr(paths, "walk_files", counting)
    _run(scene / "wf.toml")
    assert walked == [scene / "records"]
    _run(scene / "wf.toml")  # a second run lists again: its own workflow, its own listing
    assert len(walked) == 2


def test_a_run_does_not_read_its_own_files_as_records(tmp_path: Path) -> None:
    """Records folder ".", the workflow file and an outputs folder inside it: the second run
    read the workflow and the first run's tables as records (failed inventory items)."""
    write_example_files(tmp_path, count=2)
    text = FEATURES_WORKFLOW.replace('folder = "records"', 'folder = "."')
    text = text.replace("[outputs]\n", '[outputs]\nfolder = "out"\n')
    workflow = write_workflow(tmp_path, text)
    for _ in range(2):
        report = run_workflow(workflow, shipped_stages(), jobs=1)
        assert report.exit_code == 0 and report.failures == []
    features = pd.read_csv(tmp_path / "out" / "features.csv")
    assert len(features) == 2  # the two records, nothing of out/ nor wf.toml
