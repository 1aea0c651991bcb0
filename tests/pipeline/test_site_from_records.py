"""One site from records: ``stepframe report amplification --records DIR`` and a workflow's
``site`` stage over DIR give the same model, by default and with each statistic."""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.pipeline.amplification.site import (
    COMBINED,
    MEDIAN_SE_FACTOR,
    site_from_features,
    site_from_records,
)
from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.stages import shipped_stages

PEER = Path(__file__).resolve().parents[1] / "data" / "peer_nga_west2"


@pytest.fixture(scope="module")
def site_folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """RSN 8883's two horizontal components (PEER AT2) in records/."""
    folder = tmp_path_factory.mktemp("site")
    (folder / "records").mkdir()
    for path in sorted(PEER.glob("*.AT2")):
        shutil.copy(path, folder / "records" / path.name)
    return folder


def _workflow_site(folder: Path, statistic: str) -> dict[str, float]:
    workflow = folder / f"{statistic}.toml"
    workflow.write_text(
        f'workspace = "{statistic}"\n[records]\nfolder = "records"\n'
        f'[site]\nfrom = "records"\nstatistic = "{statistic}"\n[outputs]\nsite = true\n',
        encoding="utf-8",
    )
    report = run_workflow(workflow, shipped_stages(), jobs=1)
    assert report.exit_code == 0
    data = json.loads((folder / statistic / "outputs" / "site_model.json").read_text())
    model: dict[str, float] = data["ground_motion_model"]
    return model


@pytest.mark.parametrize("statistic", ["median", "mean", "inverse-variance"])
def test_the_report_and_the_workflow_give_the_same_site(site_folder: Path, statistic: str) -> None:
    from_workflow = _workflow_site(site_folder, statistic)
    from_report = site_from_records(site_folder / "records", statistic=statistic)  # type: ignore[arg-type]
    assert from_report.combined.site.source["n_components"] == 2
    for key, value in from_report.model.to_dict().items():
        if isinstance(value, float):
            assert from_workflow[key] == pytest.approx(value, rel=1e-12), key


def test_median_is_the_default_with_its_standard_error(site_folder: Path) -> None:
    site = site_from_records(site_folder / "records")
    used = site.features[site.features["plausible"]]
    for key in COMBINED:
        values = used[key].to_numpy(float)
        assert getattr(site.model, key) == pytest.approx(np.median(values), rel=1e-12)
        scatter = np.std(values, ddof=1) / math.sqrt(values.size)
        assert site.stderr[key] == pytest.approx(MEDIAN_SE_FACTOR * scatter, rel=1e-12)


def test_one_component_keeps_its_fits_own_standard_error(site_folder: Path) -> None:
    table = site_from_records(site_folder / "records").features.iloc[:1]
    combined = site_from_features(table)
    for key in COMBINED:
        assert combined.stderr[key] == table[f"{key}_stderr"].iloc[0]


def test_no_plausible_component_is_one_error_naming_why(site_folder: Path) -> None:
    table = site_from_records(site_folder / "records").features.assign(plausible=False)
    with pytest.raises(InputError, match="no component with fitted features passing"):
        site_from_features(table)
    with pytest.raises(InputError, match="statistic 'mode'"):
        site_from_features(table, statistic="mode", plausible_only=False)  # type: ignore[arg-type]


def test_a_record_saved_twice_is_one_record(site_folder: Path) -> None:
    """A copy of a record (another name, a subfolder) is the same record: the site is the one
    of the folder without it, as the workflow's over the same folder, and the copy is listed
    (same bytes as, read once). Counted twice, it moved the median and shrank the standard
    errors by √2 (the band of the report with it)."""
    folder = site_folder / "with_copy"
    shutil.copytree(site_folder / "records", folder / "records")
    first = sorted((folder / "records").glob("*.AT2"))[0]
    (folder / "records" / "again").mkdir()
    copy = folder / "records" / "again" / "copy.at2"
    shutil.copy(first, copy)
    garbage = folder / "records" / "garbage.dat"
    garbage.write_bytes(b"\x00\x01 not a record")
    alone = site_from_records(site_folder / "records")
    twice = site_from_records(folder / "records")
    assert twice.combined.site.source["n_components"] == 2
    assert twice.model.to_dict() == alone.model.to_dict()
    assert twice.stderr == alone.stderr
    assert list(twice.failures["item"]) == [str(copy), str(garbage)]
    assert twice.failures["message"][0] == f"the same bytes as {first}: read once"
    assert list(twice.failures["stage"]) == ["read", "read"]
    from_workflow = _workflow_site(folder, "median")
    for key, value in twice.model.to_dict().items():
        if isinstance(value, float):
            assert from_workflow[key] == pytest.approx(value, rel=1e-12), key


@pytest.mark.parametrize("statistic", ["median", "mean", "inverse-variance"])
def test_the_site_does_not_depend_on_the_rows_order(site_folder: Path, statistic: str) -> None:
    """The rows follow the files' names, which do not change the site: combined in any order,
    the same bytes (the sums of the mean and the scatter rounded by their order: a workspace
    that once held a copy of a file gave a standard error one unit of the last digit off)."""
    import pandas as pd

    two = site_from_records(site_folder / "records").features
    rng = np.random.default_rng(7)
    rows = []
    for k in range(7):  # seven plausible fits near RSN 8883's, each scaled by its own factors
        row = two.iloc[[k % 2]].copy()
        for key in (*COMBINED, "t_max_s", "t_dur_s", "max_intensity_m_s2"):
            row[key] = row[key] * (1 + 0.05 * rng.standard_normal())
        for key in COMBINED:
            row[f"{key}_stderr"] = row[f"{key}_stderr"] * (1 + 0.3 * rng.random())
        rows.append(row)
    table = pd.concat(rows, ignore_index=True)
    reference = site_from_features(table, statistic=statistic)  # type: ignore[arg-type]
    for seed in range(5):
        shuffled = table.sample(frac=1.0, random_state=seed).reset_index(drop=True)
        again = site_from_features(shuffled, statistic=statistic)  # type: ignore[arg-type]
        assert again.model.to_dict() == reference.model.to_dict()
        assert again.stderr == reference.stderr
