"""The nightly job's outputs (issue 30 item 4): ``measures``, ``rotd50``, ``waveforms`` and the
``arrivals_report``, on RSN 8883's two PEER AT2 files and two records of the example catalogue.

Checked against what does not share their code: PEER's own published spectra of RSN 8883
(single components and RotD50 at 5 %), independent integrations (scipy's cumulative trapezoid
for PGV, an explicit Husid sum for D5-95), a brute-force RotD50 over 180 angles, and the SAC
files read back by obspy.
"""

from __future__ import annotations

import json
import shutil
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest

from stepframe.cli import main
from stepframe.errors import InputError
from stepframe.pipeline.catalogue.example_files import write_example_files
from stepframe.pipeline.catalogue.measures import (
    STANDARD_PERIODS_S,
    MeasureOptions,
    component_measures,
    psa_column,
)
from stepframe.pipeline.catalogue.measures_stage import record_pairs
from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.engine.shipped import copy_workflow
from stepframe.pipeline.stages import shipped_stages
from stepframe.records import read

PEER = Path(__file__).parents[1] / "data" / "peer_nga_west2"
G = 9.80665

WORKFLOW = """name = "nightly"
[records]
folder = "inbox"
[measures]
{measures}
[outputs]
measures = true
rotd50 = true
waveforms = true
arrivals_report = true
"""


def _run(folder: Path, measures: str = "") -> Path:
    (folder / "wf.toml").write_text(WORKFLOW.format(measures=measures), encoding="utf-8")
    report = run_workflow(folder / "wf.toml", shipped_stages(), jobs=1)
    assert report.exit_code == 0, report.missing
    return folder / "stepframe-work" / "outputs"


@pytest.fixture(scope="module")
def outputs(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("measures")
    (folder / "inbox").mkdir()
    for path in sorted(PEER.glob("*.AT2")):
        shutil.copy(path, folder / "inbox" / path.name)
    write_example_files(folder / "inbox", count=2)
    return _run(folder)


def _peer() -> dict[str, Any]:
    reference = json.loads((PEER / "RSN8883_peer_spectra.json").read_text())
    [spectra] = [s for s in reference["spectra"] if s["damping"] == 0.05]
    at = [reference["period"].index(t) for t in STANDARD_PERIODS_S]
    return {key: np.array(spectra[key])[at] for key in ("h1", "h2", "rotd50")} | {
        "fnames": reference["fnames"]
    }


def test_every_component_is_measured(outputs: Path) -> None:
    table = pd.read_parquet(outputs / "measures.parquet")
    assert len(table) == 4 and (table["processing"] == "").all()  # PEER files: processed
    assert set(table["station"]) == {"Anaheim - Lakeview & Riverdale", "Beverly Hills - Mulhol"}
    assert table["processed_utc"].nunique() == 1
    dictionary = pd.read_csv(outputs / "measures.columns.csv")
    units = dict(zip(dictionary["column"], dictionary["unit"], strict=True))
    assert units["pgv_m_s"] == "m/s" and units[psa_column(1.0)] == "g"


def test_psa_of_each_component_matches_peers_published_spectra(outputs: Path) -> None:
    table = pd.read_parquet(outputs / "measures.parquet").set_index("file")
    peer = _peer()
    for name, key in zip(peer["fnames"], ("h1", "h2"), strict=True):
        ours = table.loc[name, [psa_column(t) for t in STANDARD_PERIODS_S]].to_numpy(float)
        error = np.abs(ours / peer[key] - 1)
        assert error.max() < 0.025, (name, STANDARD_PERIODS_S[int(np.argmax(error))])


def test_rotd50_matches_peers_published_rotd50(outputs: Path) -> None:
    table = pd.read_parquet(outputs / "rotd50.parquet")
    assert len(table) == 2  # RSN 8883 across its two files, and the example record's pair
    row = table[table["event"] == "14383980"].iloc[0]
    assert row["files"].count(";") == 1 and row["components"] == "90;360"
    ours = np.array([row[psa_column(t).replace("psa_", "psa_rotd50_")] for t in STANDARD_PERIODS_S])
    error = np.abs(ours / _peer()["rotd50"] - 1)
    assert error.max() < 0.03, STANDARD_PERIODS_S[int(np.argmax(error))]


def test_peaks_and_durations_against_independent_computations(outputs: Path) -> None:
    from scipy.integrate import cumulative_trapezoid

    table = pd.read_parquet(outputs / "measures.parquet").set_index("file")
    for path in sorted(PEER.glob("*.AT2")):
        trace = read(path)[0]
        a, dt = trace.data.astype(float), float(trace.stats.delta)
        row = table.loc[path.name]
        assert row["pga_g"] == pytest.approx(np.max(np.abs(a)) / G, rel=1e-12)
        velocity = cumulative_trapezoid(a, dx=dt, initial=0.0)
        assert row["pgv_m_s"] == pytest.approx(np.max(np.abs(velocity)), rel=5e-3)
        # the record read as piecewise linear, integrated by trapezoids on 8 points a step
        fine_t = np.arange(8 * (a.size - 1) + 1) * dt / 8
        fine = np.interp(fine_t, np.arange(a.size) * dt, a)
        husid = cumulative_trapezoid(fine * fine, fine_t, initial=0.0)
        arias = np.pi / (2 * G) * husid[-1]
        t5, t95 = np.interp([0.05, 0.95], husid / husid[-1], fine_t)
        assert row["d5_95_s"] == pytest.approx(t95 - t5, abs=dt / 8)
        assert row["arias_m_s"] == pytest.approx(arias, rel=1e-3)


def test_rotd50_of_pga_against_brute_force(outputs: Path) -> None:
    table = pd.read_parquet(outputs / "rotd50.parquet")
    row = table[table["event"] == "14383980"].iloc[0]
    first, second = (read(PEER / name)[0].data.astype(float) for name in row["files"].split(";"))
    angles = np.deg2rad(np.arange(180.0))
    peaks = [np.max(np.abs(first * np.cos(t) + second * np.sin(t))) for t in angles]
    assert row["pga_rotd50_g"] == pytest.approx(np.median(peaks) / G, rel=1e-12)


def test_waveforms_read_back(outputs: Path) -> None:
    index = pd.read_csv(outputs / "waveforms" / "index.csv", keep_default_na=False)
    assert len(index) == 4 and (index["reason"] == "").all()
    for row in index.itertuples():
        written = read(outputs / "waveforms" / row.waveform)[0]
        original = read(outputs.parents[1] / "inbox" / row.file)[0]
        # SAC stores float32: the samples to its precision
        np.testing.assert_allclose(written.data, original.data, rtol=1e-6, atol=1e-6)
        assert written.stats.delta == pytest.approx(original.stats.delta)


def test_record_pairs_group_components_as_the_selection_does() -> None:
    kik = "NGNH311106302345"
    inventory = pd.DataFrame(
        {
            "file": ["RSN8883_14383980_13849090.AT2", "RSN8883_14383980_13849360.AT2",
                     "c.mseed", "c.mseed", "c.mseed", "d.AT2", "e.AT2",
                     *(f"{kik}.{c}" for c in ("EW1", "NS1", "UD1", "EW2", "NS2", "UD2"))],
            "station": ["", "", "", "", "", "S3", "S3", *["NGNH31"] * 6],
            "event": ["", "", "", "", "", "E1", "E2", *[""] * 6],
            "component": ["90", "360", "HNE", "HNN", "HNZ", "000", "090",
                          "EW1", "NS1", "UD1", "EW2", "NS2", "UD2"],
            "channel_index": [0, 0, 0, 1, 2, 0, 0, *[0] * 6],
        }
    )  # fmt: skip
    pairs = [(r, a["file"], a["component"], b["component"]) for r, a, b in record_pairs(inventory)]
    # PEER's two files by their RSN; c.mseed (no station or event) alone, its vertical left out;
    # S3's two files are two events: no pair; KiK-net's borehole and surface sensors two records
    assert pairs == [
        ("RSN8883", "RSN8883_14383980_13849090.AT2", "90", "360"),
        ("c.mseed", "c.mseed", "HNE", "HNN"),
        (f"NGNH31 {kik[6:]} sensor 1", f"{kik}.EW1", "EW1", "NS1"),
        (f"NGNH31 {kik[6:]} sensor 2", f"{kik}.EW2", "EW2", "NS2"),
    ]


def test_standard_processing_is_recorded() -> None:
    trace = read(PEER / "RSN8883_14383980_13849090.AT2")[0]
    row = component_measures(trace, MeasureOptions(processing="standard", highpass_hz=0.2))
    assert row["processing"] == "demean;detrend;taper;bandpass" and row["highpass_hz"] == 0.2
    as_read = component_measures(trace, MeasureOptions())
    assert as_read["processing"] == "" and np.isnan(as_read["highpass_hz"])
    # an offset of 0.01 m/s² (a sensor's) integrates to ½·0.01·82² = 34 m as read; the standard
    # processing takes it out and the PGD is back near the record's own (6 mm)
    trace.data = trace.data + 0.01
    drifting = component_measures(trace, MeasureOptions())["pgd_m"]
    mended = component_measures(trace, MeasureOptions(processing="standard"))["pgd_m"]
    assert drifting > 30 and mended < 2 * as_read["pgd_m"]


def test_a_corner_without_processing_is_an_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    with pytest.raises(InputError, match=r"highpass_hz = 0\.2 with processing = 'none'"):
        MeasureOptions(processing="none", highpass_hz=0.2)
    write_example_files(tmp_path / "inbox", count=1)
    (tmp_path / "wf.toml").write_text(
        WORKFLOW.format(measures='processing = "none"\nhighpass_hz = 0.2'), encoding="utf-8"
    )
    assert main(["run", str(tmp_path / "wf.toml")]) == 2
    err = capsys.readouterr().err
    assert "wf.toml:6: [measures] highpass_hz = 0.2 with processing = 'none'" in err
    assert not (tmp_path / "stepframe-work").exists()


def test_the_arrivals_report_shows_the_latest_run(tmp_path: Path) -> None:
    (tmp_path / "inbox").mkdir()
    for path in sorted(PEER.glob("*.AT2")):
        shutil.copy(path, tmp_path / "inbox" / path.name)
    first = _run(tmp_path)
    numbers = json.loads((first / "arrivals_report_files" / "numbers.json").read_text())
    assert (numbers["components"], numbers["pairs"], numbers["runs"]) == (2, 1, 1)
    write_example_files(tmp_path / "inbox", count=2)  # two more arrive, one record
    second = _run(tmp_path)
    numbers = json.loads((second / "arrivals_report_files" / "numbers.json").read_text())
    assert (numbers["components"], numbers["records"], numbers["pairs"]) == (2, 1, 1)
    assert (numbers["components_in_folder"], numbers["runs"]) == (4, 2)
    arrived = pd.read_csv(second / "arrivals_report_files" / "arrived_all.csv")
    assert set(arrived["station"]) == {"Beverly Hills - Mulhol"}
    html = (second / "arrivals_report.html").read_text(encoding="utf-8")
    assert f"Records measured in the run of {numbers['run_utc']}" in html


def test_a_run_that_only_removes_files_says_what_its_page_shows(tmp_path: Path) -> None:
    """A junk file's failure was named beside the run that brought it; a run that only removes
    it makes the page again for the folder as it is: the same run named, its failure gone, the
    line saying it is the folder's (it read "Without a result none" beside the earlier run)."""
    (tmp_path / "inbox").mkdir()
    for path in sorted(PEER.glob("*.AT2")):
        shutil.copy(path, tmp_path / "inbox" / path.name)
    (tmp_path / "inbox" / "bad.txt").write_text("garbage\n")
    outputs = _run(tmp_path)
    numbers = json.loads((outputs / "arrivals_report_files" / "numbers.json").read_text())
    assert numbers["without_result"] == [{"stage": "inventory", "item": "bad.txt"}]
    named = numbers["run_utc"]
    (tmp_path / "inbox" / "bad.txt").unlink()
    outputs = _run(tmp_path)
    numbers = json.loads((outputs / "arrivals_report_files" / "numbers.json").read_text())
    assert (numbers["run_utc"], numbers["without_result"], numbers["runs"]) == (named, [], 1)
    html = (outputs / "arrivals_report.html").read_text(encoding="utf-8")
    assert "Without a result in the records folder" in html and "bad.txt" not in html


NIGHTLY = ("measures", "rotd50", "arrivals_report", "waveforms")


def test_the_inbox_keeps_what_it_saw_in_the_nightly_outputs(tmp_path: Path) -> None:
    """The shipped inbox with its nightly lines uncommented: history and measures together."""
    copy_workflow("inbox", tmp_path)
    workflow = tmp_path / "inbox.toml"
    text = workflow.read_text(encoding="utf-8")
    for name in NIGHTLY:
        assert f"# {name} = true" in text
        text = text.replace(f"# {name} = true", f"{name} = true")
    workflow.write_text(text, encoding="utf-8")
    inbox = tmp_path / "inbox"
    for path in sorted(PEER.glob("*.AT2")):
        shutil.copy(path, inbox / path.name)
    (inbox / "damaged.AT2").write_text("PEER NGA STRONG MOTION DATABASE\n")
    outputs = tmp_path / "stepframe-work" / "outputs"

    def sets() -> list[str]:
        """The whole-set results stored of the waveforms and the summary."""
        store = tmp_path / "stepframe-work" / "store"
        return [folder.name for stage in ("waveforms", "arrivals_report")
                for folder in sorted((store / stage / "sets").iterdir())]  # fmt: skip

    def run() -> tuple[pd.DataFrame, pd.DataFrame, pd.DataFrame, dict[str, Any]]:
        report = run_workflow(workflow, shipped_stages(), jobs=1)
        assert report.exit_code == 0, report.missing
        numbers = json.loads((outputs / "arrivals_report_files" / "numbers.json").read_text())
        failures = pd.read_csv(outputs / "measures.failures.csv", keep_default_na=False)
        return (pd.read_parquet(outputs / "measures.parquet"),
                pd.read_parquet(outputs / "rotd50.parquet"), failures, numbers)  # fmt: skip

    measures, rotd50, failures, numbers = run()
    assert failures[["item", "stage", "new"]].values.tolist() == [
        ["damaged.AT2", "inventory", True]
    ]
    assert numbers["without_result"] == [{"stage": "inventory", "item": "damaged.AT2"}]
    # a row computed by the run that first found it is stamped with that run's start
    assert (measures["processed_utc"] == measures["first_seen_utc"]).all()
    assert rotd50["record"].tolist() == ["RSN8883"]
    before = measures.set_index("file")
    first_sets = sets()
    assert len(first_sets) == 2

    # one of RSN 8883's files is archived, two example files arrive (one record)
    archived = sorted(p.name for p in PEER.glob("*.AT2"))[0]
    (inbox / archived).rename(tmp_path / archived)
    write_example_files(inbox, count=2)
    measures, rotd50, failures, numbers = run()
    assert failures[["item", "present", "new"]].values.tolist() == [["damaged.AT2", True, False]]
    assert (numbers["components"], numbers["pairs"], numbers["components_in_folder"]) == (2, 1, 3)
    kept = measures.set_index("file")
    assert len(kept) == 4 and not kept.at[archived, "present"]
    assert kept.at[archived, "pga_g"] == before.at[archived, "pga_g"]  # its numbers kept
    new = kept[kept["first_seen_utc"] > before["first_seen_utc"].max()]
    assert len(new) == 2 and (new["processed_utc"] == new["first_seen_utc"]).all()
    # the waveforms and the summary were made again; the store keeps only the latest of each
    assert len(sets()) == 2 and not set(sets()) & set(first_sets)
    # RSN 8883 lost a component: its pair stays in the table, absent
    assert rotd50.set_index("record")["present"].to_dict() == {"RSN8883": False, "RSN953": True}


def test_a_dry_run_after_a_run_with_a_failure_finds_the_report_cached(tmp_path: Path) -> None:
    """The arrivals report's key names the items without a result; the dry run did not know
    the tasks, so after any run with a failed file it said "arrivals_report 1 to compute"
    where the run itself took the page from the store."""
    (tmp_path / "inbox").mkdir()
    for path in sorted(PEER.glob("*.AT2")):
        shutil.copy(path, tmp_path / "inbox" / path.name)
    (tmp_path / "inbox" / "bad.txt").write_text("garbage\n")
    _run(tmp_path)
    plan = run_workflow(tmp_path / "wf.toml", shipped_stages(), jobs=1, dry_run=True)
    again = run_workflow(tmp_path / "wf.toml", shipped_stages(), jobs=1)
    assert [(s.name, s.computed, s.cached) for s in plan.stages] == [
        (s.name, s.computed, s.cached) for s in again.stages
    ]
    assert {s.name: s.computed for s in plan.stages} == dict.fromkeys(
        ("inventory", "measures", "rotd50", "waveforms", "arrivals_report"), 0
    )


def test_the_arrivals_report_agrees_with_the_measures_of_a_forced_run(tmp_path: Path) -> None:
    """--force measures measures every component again: their processed_utc is that run's.
    Before, the page was taken from the store (its key names the measures' keys, unchanged)
    and still showed the earlier run's two arrivals and two runs beside a measures table
    whose every row had the forced run's time."""
    (tmp_path / "inbox").mkdir()
    for path in sorted(PEER.glob("*.AT2")):
        shutil.copy(path, tmp_path / "inbox" / path.name)
    _run(tmp_path)
    write_example_files(tmp_path / "inbox", count=2)
    _run(tmp_path)
    report = run_workflow(tmp_path / "wf.toml", shipped_stages(), jobs=1, force=["measures"])
    assert report.exit_code == 0
    outputs = tmp_path / "stepframe-work" / "outputs"
    measures = pd.read_parquet(outputs / "measures.parquet")
    numbers = json.loads((outputs / "arrivals_report_files" / "numbers.json").read_text())
    assert measures["processed_utc"].nunique() == 1
    assert numbers["run_utc"] == measures["processed_utc"].iat[0]
    assert (numbers["components"], numbers["runs"]) == (4, 1)


def test_the_catalogue_and_the_measures_name_a_psa_column_alike() -> None:
    """One name per PSA column (records.spectra.psa_column), the one docs/workflows.md gives
    (``psa_0.01s_g`` to ``psa_10s_g``): ``records catalog`` wrote PSA(0.2 s) as ``psa_0p2s_g``
    where the measures stage writes ``psa_0.2s_g``."""
    from stepframe.records.catalog import COLUMNS

    assert psa_column(0.01) == "psa_0.01s_g" and psa_column(10.0) == "psa_10s_g"
    assert [c for c in COLUMNS if c.startswith("psa_")] == ["psa_0.2s_g", "psa_1s_g"]
