"""select_records end to end on the example: records in, a report that agrees, motions out."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest

from stepframe.pipeline.reports.document import data_folder_of
from stepframe.pipeline.selection import SelectionOptions, select_records
from stepframe.pipeline.selection.report import make_selection_report
from stepframe.records.rotd import rotd_spectrum
from stepframe.structure.code_spectra import Asce7TwoPeriod
from stepframe.structure.frame import PortalFrame


@pytest.fixture(scope="module")
def records_run(
    example_inputs: tuple[Any, Any, Any], example4: PortalFrame, tmp_path_factory: Any
) -> tuple[Any, Path]:
    table, records, _ = example_inputs
    options = SelectionOptions(
        n=4, unit="record", target_s_ds_g=1.0, target_s_d1_g=0.6, scale="psa-at-t1",
        pair_spectrum="rotd50", n_bootstrap=0,
    )  # fmt: skip
    result = select_records(table.copy(), example4, options, records=records, jobs=1)
    folder = tmp_path_factory.mktemp("records_run")
    result.write(folder)
    return result, folder


def test_records_are_pairs_scaled_by_their_rotd50(
    records_run: tuple[Any, Path], example_inputs: tuple[Any, Any, Any], example4: PortalFrame
) -> None:
    result, _ = records_run
    selection, records = result.selection, example_inputs[1]
    assert len(selection) == 8 and selection["record"].nunique() == 4
    target = Asce7TwoPeriod(1.0, 0.6, g_m_s2=9.80665)  # the selection works in standard g
    target_t1 = target.sa_m_s2(2 * np.pi / example4.omega_1_rad_s)
    for _, pair in selection.groupby("record"):
        assert pair["scale_factor"].nunique() == 1  # one factor per record
        keys = zip(pair["file"], pair["component"], strict=True)
        (a, dt), (b, _) = (records[key] for key in keys)
        rotd50 = rotd_spectrum(a, b, dt, [2 * np.pi / example4.omega_1_rad_s]).rotd50_m_s2[0]
        if not pair["scale_clipped"].iat[0]:
            assert pair["scale_factor"].iat[0] * rotd50 == pytest.approx(target_t1, rel=1e-9)
    assert not selection["component"].str.contains("UP|DWN").any()
    grouping = result.summary["grouping"]
    assert grouping["records"] == 50 and grouping["by_rule"] == {"rsn": 50}


def test_selection_json_stores_target_scale_rule_misfit_and_check(
    records_run: tuple[Any, Path],
) -> None:
    result, folder = records_run
    summary = json.loads((folder / "selection.json").read_text())
    assert summary["target"]["kind"] == "asce7-22-two-period"
    assert summary["target"]["standard"] == "ASCE/SEI 7-22 §11.4.5.2"
    assert summary["scale_rule"].startswith(
        "psa-at-t1: each record (both components, by its rotd50)"
    )
    assert summary["set_misfit"] == pytest.approx(result.summary["set_misfit"])
    check = summary["code_check"]
    assert check["clause"] == "ASCE/SEI 7-22 §16.2" and check["measure"] == "rotd50"
    assert check["n_units"] == 4
    spectra = pd.read_csv(folder / "spectra.csv")
    units = [c for c in spectra.columns if c not in ("period_s", "target_g", "mean_g")]
    assert len(units) == 4
    np.testing.assert_allclose(spectra["mean_g"], spectra[units].mean(axis=1), rtol=1e-6)
    # the check's ratios are the mean over the target at the checked periods of spectra.csv
    # (spectra.csv holds 8 significant digits: the periods are matched to that)
    periods = spectra["period_s"].to_numpy()
    rows = [int(np.argmin(np.abs(periods / t - 1))) for t in check["periods_s"]]
    np.testing.assert_allclose(periods[rows], check["periods_s"], rtol=1e-7)
    at = spectra.iloc[rows]
    np.testing.assert_allclose(check["ratio"], at["mean_g"] / at["target_g"], rtol=1e-6)
    assert check["passes"] == bool(min(check["ratio"]) >= 0.9)
    response = summary["chosen_response"]
    assert response["n"] == 8
    assert response["linear"] + response["steps"] + response["overturns"] == 8
    manifest = pd.read_csv(folder / "motions" / "manifest.csv")
    assert manifest["record"].tolist() == result.selection["record"].tolist()


def test_report_agrees_with_the_run_and_says_not_run(records_run: tuple[Any, Path]) -> None:
    _, folder = records_run
    html = make_selection_report(str(folder))
    numbers = json.loads((data_folder_of(html) / "numbers.json").read_text())
    summary = json.loads((folder / "selection.json").read_text())
    assert numbers["confirmation"] == "not run"
    assert numbers["code_check"]["passes"] == summary["code_check"]["passes"]
    assert numbers["code_check"]["lowest_ratio"] == pytest.approx(
        summary["code_check"]["lowest_ratio"]
    )
    assert numbers["chosen_response"] == {
        k: summary["chosen_response"][k] for k in ("n", "linear", "steps", "overturns")
    }
    text = html.read_text(encoding="utf-8")
    assert "The run had no target spectrum" not in text
    assert summary["code_check"]["line"] in text
    visible = re.sub(r"<[^>]+>|data:[^\"']+", " ", text)
    assert not re.search(r"\bnan\b", visible, flags=re.IGNORECASE)
    drawn = pd.read_csv(data_folder_of(html) / "spectra.csv")
    np.testing.assert_allclose(drawn["target_g"], pd.read_csv(folder / "spectra.csv")["target_g"])


def test_a_cap_per_event_counts_each_earthquake_once(
    example_inputs: tuple[Any, Any, Any], example4: PortalFrame
) -> None:
    # The catalogue's 100 components record 19 earthquakes; the source table named Northridge
    # 1994, Imperial Valley 1979 and Superstition Hills 1987 two ways each, and a cap of one per
    # event chose 22 components, two of each of those three.
    table, records, _ = example_inputs
    options = SelectionOptions(n=22, max_per_event=1, rank_by="omega_p_over_s_sq", n_bootstrap=0)
    result = select_records(table, example4, options, records=records, jobs=1)
    assert len(result.selection) == 19 and result.status == "degraded"
    assert "only 19 of 22" in result.message
    years = result.selection["event"].str.rsplit(" ", n=1).str[-1]
    assert not (years.isin(["1994", "1979", "1987"]) & years.duplicated()).any()


def test_partial_metadata_caps_count_unknown_events_apart(
    example_inputs: tuple[Any, Any, Any], example4: PortalFrame
) -> None:
    # Only Northridge's and Kobe's records keep their event: before, every record without one
    # counted as one event "nan", and a cap of 1 per event chose 3 of 7.
    table, records, _ = example_inputs
    table = table.copy()
    known = table["event"].isin(["Northridge-01 1994", "Kobe, Japan 1995"])
    table.loc[~known, "event"] = None
    options = SelectionOptions(n=7, max_per_event=1, rank_by="omega_p_over_s_sq", n_bootstrap=0)
    result = select_records(table, example4, options, records=records, jobs=1)
    assert len(result.selection) == 7 and result.status == "ok"
    chosen_events = result.selection["event"].dropna().tolist()
    assert len(chosen_events) == len(set(chosen_events)) <= 2


def test_confirmation_section_marks_the_chosen_and_prints_the_run_medians(
    example_inputs: tuple[Any, Any, Any], example4: PortalFrame, tmp_path: Path
) -> None:
    table, records, _ = example_inputs
    plausible = table[table["plausible"].astype(bool)]
    small = plausible.head(10).reset_index(drop=True)  # a short confirmation
    options = SelectionOptions(n=3, confirm=True, n_bootstrap=0)
    result = select_records(small, example4, options, records=records, jobs=1)
    result.write(tmp_path)
    html = make_selection_report(str(tmp_path))
    numbers = json.loads((data_folder_of(html) / "numbers.json").read_text())
    medians = json.loads((tmp_path / "selection.json").read_text())["medians"]
    confirmation = numbers["confirmation"]
    # the report's selected/controls medians are the run's (what the command printed)
    assert confirmation["median_response_selected"] == pytest.approx(
        medians["equal_psa_t1_peak_x_m_selected"]
    )
    assert confirmation["median_response_controls"] == pytest.approx(
        medians["equal_psa_t1_peak_x_m_control"]
    )
    # and they are the medians of the chosen rows at equal intensity (marked by file, component)
    rows = pd.read_csv(tmp_path / "confirmation.csv")
    equal = rows[rows["case"] == "equal-psa-t1"]
    chosen = set(zip(result.selection["file"], result.selection["component"], strict=True))
    mine = [(f, c) in chosen for f, c in zip(equal["file"], equal["component"], strict=True)]
    assert sum(mine) == 3
    assert np.median(equal["peak_abs_x_m"][mine]) == pytest.approx(
        medians["equal_psa_t1_peak_x_m_selected"]
    )
    table_csv = pd.read_csv(data_folder_of(html) / "confirmation_summary.csv")
    assert table_csv["group"].tolist() == ["selected", "controls"] * 2
    assert table_csv["at"].tolist() == ["equal PSA(T_1)"] * 2 + ["chosen scale"] * 2
    # the chosen-scale rows: the selected and their controls as the run simulated them
    at_scale = rows[rows["case"] == "chosen-scale"]
    for place, group in ((2, "selected"), (3, "control")):
        runs = at_scale[at_scale["group"] == group]
        assert len(runs) == 3
        assert table_csv["median_peak_abs_x_m"][place] == pytest.approx(
            np.median(runs["peak_abs_x_m"])
        )
        assert table_csv["overturned"][place] == runs["overturned"].sum()


def test_a_report_refuses_a_folder_edited_after_its_run(
    example_inputs: tuple[Any, Any, Any], example4: PortalFrame, tmp_path: Path
) -> None:
    # A hand-shortened selection.csv made a report saying "Selected 2" above the summary's "of
    # 3 components": selection.json now records each file's sha256 and the folder is checked.
    from stepframe.core.io import file_sha256
    from stepframe.errors import InputError
    from stepframe.pipeline.selection.report_folder import read_selection_folder
    from stepframe.pipeline.selection.result import read_selection

    table, records, _ = example_inputs
    options = SelectionOptions(n=3, rank_by="omega_p_over_s_sq", n_bootstrap=0)
    folder = tmp_path / "out"
    select_records(table, example4, options, records=records, jobs=1).write(folder)
    recorded = json.loads((folder / "selection.json").read_text())["files_sha256"]
    assert set(recorded) >= {"selection.csv", "candidates.csv", "columns.csv", "failures.csv"}
    assert all(file_sha256(folder / name) == digest for name, digest in recorded.items())
    assert len(read_selection_folder(folder).tables["selection"]) == 3
    # read back and written again (without the motions, which read_selection does not read),
    # the result records the files it wrote, not the first folder's
    again = tmp_path / "again"
    read_selection(folder).write(again)
    rewritten = json.loads((again / "selection.json").read_text())["files_sha256"]
    assert set(rewritten) == set(recorded) - {"motions/manifest.csv"}
    assert all(file_sha256(again / name) == digest for name, digest in rewritten.items())
    shortened = pd.read_csv(folder / "selection.csv").iloc[:2]
    shortened.to_csv(folder / "selection.csv", index=False)
    with pytest.raises(InputError) as changed:
        read_selection_folder(folder)
    assert changed.value.what.startswith("selection.csv was changed after the selection run")
    (again / "candidates.csv").unlink()
    with pytest.raises(InputError, match=r"candidates\.csv missing"):
        read_selection_folder(again)
