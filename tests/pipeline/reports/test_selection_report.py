"""The selection report's numbers against its folder, and bad selection folders."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from scipy.stats import spearmanr

from stepframe.cli import main
from stepframe.errors import InputError
from stepframe.pipeline.reports.document import data_folder_of
from stepframe.pipeline.selection.report_folder import read_selection_folder


def test_confirmation_rank_correlation(selection_dir: Path, selection_html: Path) -> None:
    confirmation = pd.read_csv(selection_dir / "confirmation.csv")
    expected = spearmanr(confirmation["end_closeness"], confirmation["peak_drift_m"]).statistic
    numbers = json.loads((data_folder_of(selection_html) / "numbers.json").read_text())
    assert numbers["confirmation"]["spearman_rho"] == pytest.approx(expected, rel=1e-12)
    selected = confirmation[confirmation["group"] == "selected"]["peak_drift_m"]
    assert numbers["confirmation"]["median_response_selected"] == pytest.approx(np.median(selected))
    assert f"ρ = {expected:.2f}" in selection_html.read_text(encoding="utf-8")


def test_filters_count_what_they_dropped(selection_dir: Path, selection_html: Path) -> None:
    candidates = pd.read_csv(selection_dir / "candidates.csv")
    table = pd.read_csv(data_folder_of(selection_html) / "filters.csv").set_index("filter")
    dropped = int((candidates["magnitude"] <= 6.6).sum())
    assert dropped >= 1
    assert table.loc["magnitude", "dropped"] == dropped
    assert table.loc["(passed every filter)", "dropped"] == len(candidates) - dropped


def test_spectra_are_the_records(selection_dir: Path, selection_html: Path) -> None:
    from stepframe.records.examples import fema_p695
    from stepframe.records.spectra import response_spectrum

    spectra = pd.read_csv(data_folder_of(selection_html) / "spectra.csv")
    first = pd.read_csv(selection_dir / "selection.csv").iloc[0]
    stream, _ = fema_p695()
    trace = next(t for t in stream if t.stats.stepframe.source_file == first["file"])
    psa = response_spectrum(trace.data, trace.stats.delta, spectra["period_s"].to_numpy()).psa_g
    np.testing.assert_allclose(spectra.iloc[:, 1], psa * first["scale_factor"], rtol=1e-10)
    stats = pd.read_csv(data_folder_of(selection_html) / "spectra_statistics.csv")
    np.testing.assert_allclose(
        stats["median_psa_g"], np.exp(np.median(np.log(spectra.iloc[:, 1:]), axis=1)), rtol=1e-10
    )
    # the target: two-period spectrum S_DS = 1.0 g, S_D1 = 0.6 g → 0.6/T g beyond T_s = 0.6 s
    long = stats[stats["period_s"] > 1.0]
    np.testing.assert_allclose(long["target_psa_g"], 0.6 / long["period_s"], rtol=1e-9)


def test_column_dictionary_is_carried(selection_html: Path) -> None:
    text = selection_html.read_text(encoding="utf-8")
    assert 'title="exp(-|ln(ω_g(t_dur)/ω_1)|), 1 = ends at ω_1"' in text


@pytest.mark.parametrize("remove", ["selection.csv", "candidates.csv", "selection.json"])
def test_half_complete_folder(
    remove: str,
    selection_dir: Path,
    tmp_path: Path,
    copy_of: Callable[[Path, Path], Path],
    capsys: pytest.CaptureFixture[str],
) -> None:
    folder = copy_of(selection_dir, tmp_path / "out")
    for old in folder.glob("selection_report*"):
        if old.is_dir():
            import shutil

            shutil.rmtree(old)
        else:
            old.unlink()
    (folder / remove).unlink()
    before = sorted(p.name for p in folder.iterdir())
    code = main(["report", "selection", str(folder)])
    captured = capsys.readouterr()
    assert code == 2 and captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and remove in lines[0] and "incomplete selection folder" in lines[0]
    assert sorted(p.name for p in folder.iterdir()) == before  # no partial report


def test_truncated_table(
    selection_dir: Path, tmp_path: Path, copy_of: Callable[[Path, Path], Path]
) -> None:
    folder = copy_of(selection_dir, tmp_path / "out")
    (folder / "candidates.csv").write_text("")
    with pytest.raises(InputError, match="empty file"):
        read_selection_folder(folder)
    (folder / "selection.json").write_text('{"band_rad_s": [1, ')
    with pytest.raises(InputError, match="not valid JSON"):
        read_selection_folder(folder)


def test_missing_folder(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["report", "selection", str(tmp_path / "nothing")]) == 2
    assert "not a folder" in capsys.readouterr().err


def test_cli_writes_beside_the_selection(
    selection_dir: Path, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "sel.html"
    assert main(["report", "selection", str(selection_dir), "-o", str(out), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["report"] == str(out)
    provenance = json.loads((data_folder_of(out) / "provenance.json").read_text())
    names = {Path(entry["name"]).name for entry in provenance["inputs"]}
    assert {"selection.json", "selection.csv", "candidates.csv", "confirmation.csv"} <= names


def test_candidates_mark_the_selected(selection_dir: Path, selection_html: Path) -> None:
    shown = pd.read_csv(data_folder_of(selection_html) / "candidates.csv")
    chosen = pd.read_csv(selection_dir / "selection.csv")
    assert set(shown[shown["selected"]]["file"]) == set(chosen["file"])
    assert shown["selected"].sum() == len(chosen)


def test_moving_resonance_of_the_best_records(selection_dir: Path, selection_html: Path) -> None:
    # Each drawn record is the selection's record at the ranking intensity, simulated with the index
    # over the report's band: the numbers are those of the library on the same record.
    from stepframe.pipeline.dynamics.resonance import moving_resonance
    from stepframe.records.examples import fema_p695
    from stepframe.structure.frame_file import read_frame_file

    numbers = json.loads((data_folder_of(selection_html) / "numbers.json").read_text())
    drawn = numbers["moving_resonance"]
    selection = pd.read_csv(selection_dir / "selection.csv")
    assert len(drawn) == min(3, len(selection))
    first = selection.iloc[0]
    stream, _ = fema_p695()
    trace = next(t for t in stream if t.stats.stepframe.source_file == first["file"])
    summary = json.loads((selection_dir / "selection.json").read_text())
    frame = read_frame_file(selection_dir / summary["frame_file"])
    # the factor at the ranking intensity; a run ranked by a tier has none: its scale factor
    scale = float(first.get("ranking_scale", first["scale_factor"]))
    run = moving_resonance(
        frame, trace.data, trace.stats.delta, scale=scale,
        band_rad_s=numbers["band_rad_s"],
    )  # fmt: skip
    assert drawn[0]["scale"] == pytest.approx(scale)
    for column, key in (("M", "moving_resonance_share"), ("depth", "work_depth"),
                        ("work_m2_s2", "input_energy_m2_s2")):  # fmt: skip
        assert drawn[0][column] == pytest.approx(getattr(run.measures, key), rel=1e-12), key
    assert drawn[0]["stepped_half_cycles"] == run.measures.n_stepping_half_cycles
    table = pd.read_csv(data_folder_of(selection_html) / "moving_resonance.csv")
    assert table["record"].tolist() == [row["record"] for row in drawn]
    html = selection_html.read_text(encoding="utf-8")
    assert "Moving resonance in the best records" in html


def test_a_long_candidates_table_is_drawn_by_its_best_rows_and_written_whole(
    selection_dir: Path, copy_of: Callable[[Path, Path], Path], tmp_path: Path
) -> None:
    """At catalogue size (43,000 candidates) the page showed every row: tens of MB. Past
    PAGE_ROWS the page draws the best-ranked rows, chosen first, and the CSV holds them all."""
    from stepframe.pipeline.reports import collect_provenance
    from stepframe.pipeline.selection.report import PAGE_ROWS, write_selection_report

    folder = copy_of(selection_dir, tmp_path / "long")
    candidates = pd.read_csv(folder / "candidates.csv")
    many = pd.concat(
        [candidates.assign(file=candidates["file"] + f".copy{k}") for k in range(30)]
        + [candidates],
        ignore_index=True,
    )
    many.to_csv(folder / "candidates.csv", index=False)
    provenance = collect_provenance("pytest selection", inputs=[folder / "selection.json"])
    html_path = write_selection_report(folder, provenance=provenance)
    html = html_path.read_text(encoding="utf-8")
    top = html.split('id="tab-candidates_top"')[1].split("</table>")[0]
    assert top.count("<tr>") == PAGE_ROWS + 1  # the heading row and PAGE_ROWS rows
    assert 'id="tab-candidates"' not in html  # the whole table is not drawn
    assert "candidates.csv</code> (not drawn on the page)" in html
    written = pd.read_csv(data_folder_of(html_path) / "candidates.csv")
    assert len(written) == len(many)
    shown = pd.read_csv(data_folder_of(html_path) / "candidates_top.csv")
    chosen = pd.read_csv(folder / "selection.csv")
    assert shown["selected"].head(len(chosen)).all()  # the chosen ones first
    rank_by = json.loads((folder / "selection.json").read_text())["rank_by"]
    rest = shown[rank_by].to_numpy(dtype=float)[len(chosen) :]
    assert np.all(np.diff(rest[np.isfinite(rest)]) <= 0)  # then best ranked first


def test_components_named_like_numbers_stay_text(
    selection_dir: Path, copy_of: Callable[[Path, Path], Path], tmp_path: Path
) -> None:
    """NGA-West2 names components "000" and "090": read back as numbers they became 0 and 90,
    and the report could not find the records' channels."""
    folder = copy_of(selection_dir, tmp_path / "numbers")
    for name in ("selection.csv", "candidates.csv"):
        table = pd.read_csv(folder / name, dtype=str)
        table["component"] = "000"
        table.to_csv(folder / name, index=False)
    outputs = read_selection_folder(folder)
    assert set(outputs.tables["selection"]["component"]) == {"000"}
    assert set(outputs.tables["candidates"]["component"]) == {"000"}


def test_a_selection_without_its_band_is_drawn_on_the_selection_s_default_band(
    tmp_path: Path,
) -> None:
    # An older selection.json without band_rad_s: the report falls back on the band the
    # selection would have ranked on, frame_band's [ω(0.8 x*), ω_1], computed here from the
    # period-amplitude law at 0.8 x* (not A half-way from x_c to x*, as it once did).
    import math
    import tomllib

    from stepframe.pipeline.selection.report import _band
    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping
    from stepframe.structure.period_amplitude import period_amplitude

    tables = tomllib.loads(FRAME_TEMPLATE)
    del tables["constants"]
    frame = frame_from_mapping(tables)
    low, high = _band({}, frame, tmp_path)
    expected = 2 * math.pi / float(period_amplitude(frame, 0.8 * frame.x_star_m))
    assert low == pytest.approx(expected, rel=1e-9)
    assert high == pytest.approx(frame.omega_1_rad_s, rel=1e-12)
    with pytest.raises(InputError, match="no band_rad_s and no frame"):
        _band({}, None, tmp_path)


def test_the_paths_note_names_the_default_ranking(selection_html: Path) -> None:
    """The note under the ω_g paths says what the default ranking reads: the options' default
    (it named substitute_demand_ratio after the default had become the simulated response)."""
    import html

    from stepframe.pipeline.selection.options import SelectionOptions

    page = html.unescape(selection_html.read_text(encoding="utf-8"))
    assert SelectionOptions().rank_by == "simulated_response"
    assert "it simulates the frame under each candidate (simulated_response;" in page
    assert "default score (substitute_demand_ratio)" not in page


def test_a_selection_of_every_candidate_is_reported(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """docs/selection.md's run on a folder (the two RSN 8883 horizontals, -n 2, --confirm)
    chooses every candidate: no rest and no controls, whose medians the summary leaves out.
    `stepframe report selection` on its folder was a KeyError traceback (exit 1); the page now
    says there is no other candidate, and the numbers of an empty group are not run."""
    import shutil

    data = Path(__file__).resolve().parents[2] / "data" / "peer_nga_west2"
    records = tmp_path / "records"
    records.mkdir()
    for path in data.glob("*.AT2"):
        shutil.copy(path, records)
    assert main(["structure", "frame-template"]) == 0
    (tmp_path / "FRAME.toml").write_text(capsys.readouterr().out)
    out = tmp_path / "picks"
    words = ["select", "--frame", str(tmp_path / "FRAME.toml"), str(records), "-n", "2"]
    assert main([*words, "--confirm", "-o", str(out)]) == 0
    # its text: why ρ is undefined (2 pairs, below confirm.MIN_PAIRS = 4; the two peaks differ),
    # and no controls rather than "0 controls not run m"
    text = capsys.readouterr().out
    assert (
        "Spearman(simulated_response, peak_drift) undefined (fewer than 4 candidates), n = 2"
        in (text)
    )
    assert (
        "selected 0.0" in text
        and "m (0 overturn), no controls (every candidate was selected)" in (text)
    )
    assert "not run m" not in text
    summary = json.loads((out / "selection.json").read_text())
    versus = summary["ranking"]["chosen_vs_rest"]
    assert (versus["n_chosen"], versus["n_rest"]) == (2, 0) and "peak_x_m_rest" not in versus
    assert main(["report", "selection", str(out)]) == 0
    html = (out / "selection_report.html").read_text()
    assert "no other candidate (every candidate was chosen)" in html
    table = pd.read_csv(out / "selection_report_files" / "chosen_vs_rest.csv")
    rest = table[table["group"] == "the rest"].iloc[0]
    assert rest["candidates"] == 0 and np.isnan(rest["median_peak_x_m"])
    chosen = table[table["group"] == "chosen"].iloc[0]
    assert chosen["median_peak_x_m"] == pytest.approx(versus["peak_x_m_chosen"])
