"""A re-run with changed options leaves in the outputs folder exactly what the new run made: the
same bytes as the same workflow run into a fresh workspace (docs/workflows.md, "Outputs").

Before, a published folder was copied over file by file: a selection of 3 after one of 4 kept
the fourth record's files in ``selection/``, a report without a frame kept ``frame.csv`` in its
``_files/`` folder (whose page says every number on it is there), and an output no longer asked
for stayed as the last run left it.
"""

from __future__ import annotations

import shutil
from pathlib import Path

import pandas as pd

from stepframe.pipeline.catalogue.example_files import write_example_files
from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.stages import shipped_stages

from .conftest import tree, write_workflow

SHIPPED = Path(__file__).parents[2] / "src" / "stepframe" / "workflows"

#: The paper's site on a coarse curve (seconds, not minutes), with the Example 4 frame.
SITE = """\
[site]
from = "parameters"
fp_hz = 7.43
fs_hz = 3.12
fr_hz = 1.11
xi_p = 0.096
xi_r = 0.655
t_max_s = 5.0
t_dur_s = 20.0
alpha_reading = "paper"

[amplification]
n_frequencies = 6
n_steps = 400

[amplification_report]
monte_carlo = 0
{report}
{frame}
[outputs]
site = true
amplification = true
amplification_report = {report_on}
"""
FRAME = '[frame]\nfile = "frames/example-4.toml"\n'

SELECTION = """\
[records]
folder = "records"

[frame]
file = "frames/example-4.toml"

[selection]
n = {n}
confirm = {confirm}
rank_by = "sa_t1_g"
n_bootstrap = 0

[outputs]
features = true
measures = {measures}
selection = true
"""


def _scene(folder: Path, records: int = 0) -> Path:
    folder.mkdir()
    shutil.copytree(SHIPPED / "frames", folder / "frames")
    if records:
        write_example_files(folder / "records", count=records)
    return folder


def _run(folder: Path, text: str) -> dict[str, bytes]:
    workflow = write_workflow(folder, text)
    report = run_workflow(workflow, shipped_stages(), jobs=1)
    assert report.exit_code == 0, report.describe()
    return tree(folder / "stepframe-work" / "outputs")


def test_a_report_rerun_without_its_frame_keeps_no_number_of_the_frame(tmp_path: Path) -> None:
    """The frame and δ* give the report frame.csv and adjusted_design_displacement.csv; the
    same workflow without them gives neither, as a fresh workspace does."""
    scene = _scene(tmp_path / "scene")
    first = _run(scene, SITE.format(report="delta_star_m = 0.25", frame=FRAME, report_on="true"))
    assert "amplification_report_files/frame.csv" in first
    assert "amplification_report_files/adjusted_design_displacement.csv" in first
    plain = SITE.format(report="", frame="", report_on="true")
    again = _run(scene, plain)
    fresh = _run(_scene(tmp_path / "fresh"), plain)
    assert again == fresh
    assert "amplification_report_files/frame.csv" not in again
    assert "amplification_report_files/adjusted_design_displacement.csv" not in again
    # turned off, the report goes, page and folder, and the rest stays as a fresh run makes it
    off = SITE.format(report="", frame="", report_on="false")
    left = _run(scene, off)
    assert not any(name.startswith("amplification_report") for name in left)
    assert left == _run(_scene(tmp_path / "fresh-off"), off)
    # asked again, it is published again (the store still holds it: nothing recomputed)
    assert _run(scene, plain) == fresh


def test_two_workflows_in_one_workspace_keep_each_others_outputs(tmp_path: Path) -> None:
    """The shipped workflows share ./stepframe-work: running the site workflow, then a features
    workflow beside it, removed the site's model and amplification ("no longer asked for"),
    which the features workflow never asked for. Turned off in its own workflow, an output
    still goes."""
    scene = _scene(tmp_path / "scene", records=2)
    site_text = SITE.format(report="", frame="", report_on="false")
    site = write_workflow(scene, site_text, "site.toml")
    assert run_workflow(site, shipped_stages(), jobs=1).exit_code == 0
    features = write_workflow(
        scene, '[records]\nfolder = "records"\n\n[outputs]\nfeatures = true\n', "features.toml"
    )
    report = run_workflow(features, shipped_stages(), jobs=1)
    assert report.exit_code == 0 and report.removed == {}, report.describe()
    outputs = tree(scene / "stepframe-work" / "outputs")
    assert {"site_model.json", "amplification.nc", "features.csv"} <= set(outputs)
    # the site workflow itself turning amplification off removes it, and leaves the features
    off = site_text.replace("amplification = true", "amplification = false")
    site.write_text(off.replace("[amplification]\nn_frequencies = 6\nn_steps = 400\n", ""))
    report = run_workflow(site, shipped_stages(), jobs=1)
    assert report.exit_code == 0, report.describe()
    assert set(report.removed) == {"amplification"}
    left = set(tree(scene / "stepframe-work" / "outputs"))
    assert "amplification.nc" not in left and {"site_model.json", "features.csv"} <= left


def test_a_selection_rerun_with_fewer_records_keeps_only_its_own_files(tmp_path: Path) -> None:
    """n = 4 with confirmation and measures, then n = 3 without either: ``selection/`` holds
    the second run's files only (no confirmation rows, no file of a fourth record) and the
    measures tables are gone, byte for byte as a fresh workspace."""
    scene = _scene(tmp_path / "scene", records=8)
    first = _run(scene, SELECTION.format(n=4, confirm="true", measures="true"))
    fourth = {name for name in first if name.startswith("selection/motions/04_")}
    assert len(fourth) == 2 and "measures.parquet" in first  # its .AT2 and .txt
    second_text = SELECTION.format(n=3, confirm="false", measures="false")
    again = _run(scene, second_text)
    fresh = _run(_scene(tmp_path / "fresh", records=8), second_text)
    assert sorted(again) == sorted(fresh)
    assert again == fresh
    assert not fourth & set(again)
    assert len(again["selection/confirmation.csv"].splitlines()) == 1  # its header: not run
    assert len(first["selection/confirmation.csv"].splitlines()) > 1
    assert not any(name.startswith("measures.") for name in again)


def _values(data: object, key: str) -> list[object]:
    """Every value of ``key`` anywhere in a JSON document."""
    if isinstance(data, dict):
        return [v for k, v in data.items() if k == key] + [
            found for v in data.values() for found in _values(v, key)
        ]
    if isinstance(data, list):
        return [found for v in data for found in _values(v, key)]
    return []


def test_the_report_states_the_alpha_reading_its_site_used(tmp_path: Path) -> None:
    """A site with the paper's α reading: the report's provenance stated the options' unused
    default ("eq-6-11", top level, and on the page under Parameters) beside the site's "paper".
    Now one value, the site's, everywhere (this is a report of the run, not of its defaults)."""
    import json

    scene = _scene(tmp_path / "scene")
    outputs = _run(scene, SITE.format(report="", frame="", report_on="true"))
    provenance = json.loads(outputs["amplification_report_files/provenance.json"])
    assert _values(provenance, "alpha_reading") == ["paper", "paper"]  # options', site's
    assert json.loads(outputs["site_model.json"])["ground_motion_model"]["alpha_reading"] == "paper"
    page = outputs["amplification_report.html"].decode()
    assert "eq-6-11" not in page and "alpha_reading&#34;: &#34;paper&#34;" in page


SITE_FROM_RECORDS = """\
[records]
folder = "records"

[site]
from = "records"

[amplification]
n_frequencies = 6
n_steps = 400

[outputs]
features = true
site = true
amplification = true
"""


def test_an_output_a_rerun_cannot_produce_leaves_no_copy_of_an_earlier_run(
    tmp_path: Path,
) -> None:
    """Records archived until none left fits plausibly: the site (and its curve) cannot be
    made. Before, the earlier run's site_model.json and amplification.* stayed in the outputs
    folder beside this run's features, as if this run had made them from the records now
    there; now they are removed and named, and the folder is what a fresh workspace gives."""
    scene = _scene(tmp_path / "scene", records=4)
    first = _run(scene, SITE_FROM_RECORDS)
    assert {"site_model.json", "amplification.nc"} <= set(first)

    esm = Path(__file__).parents[1] / "data" / "formats" / "esm"
    records = scene / "records"
    for path in records.iterdir():
        path.unlink()
    shutil.copy(esm / "HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz", records)
    report = run_workflow(scene / "wf.toml", shipped_stages(), jobs=1)
    assert report.exit_code == 1 and sorted(report.missing) == ["amplification", "site"]
    # why, as report amplification --records says it (the stage said only "(1 in the table)")
    assert report.missing["site"] == (
        "no component with fitted features passing the plausibility checks (1 in the table), "
        "expected at least one for a site from records (HI.ARS1..HNE.D.20190728.160908.C.ACC."
        "ASC.gz [HNE]: "
        + pd.read_csv(scene / "stepframe-work" / "outputs" / "features.csv").at[
            0, "implausible_reason"
        ]
        + ")"
    )
    assert "omega_not_decreasing" in report.missing["site"]
    assert report.removed == {
        "amplification": [
            "amplification.columns.csv", "amplification.csv", "amplification.nc",
            "amplification.parquet",
        ],
        "site": ["site_model.columns.csv", "site_model.csv", "site_model.json",
                 "site_model.parquet"],
    }  # fmt: skip
    assert "output site removed (an earlier run's, not produced by this one)" in report.describe()
    left = tree(scene / "stepframe-work" / "outputs")
    assert sorted(left) == [
        "features.columns.csv", "features.csv", "features.failures.csv", "features.parquet",
    ]  # fmt: skip
    fresh = _scene(tmp_path / "fresh")
    shutil.copytree(records, fresh / "records")
    write_workflow(fresh, SITE_FROM_RECORDS)
    assert run_workflow(fresh / "wf.toml", shipped_stages(), jobs=1).exit_code == 1
    assert left == tree(fresh / "stepframe-work" / "outputs")
