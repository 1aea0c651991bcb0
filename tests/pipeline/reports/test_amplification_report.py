"""The amplification report's numbers against the library and closed forms; bad sites."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest

from stepframe.cli import main
from stepframe.pipeline.amplification.analysis import AmplificationOptions
from stepframe.pipeline.amplification.site import COMBINED, MEDIAN_SE_FACTOR, site_from_records
from stepframe.pipeline.catalogue.fit_options import FitOptions
from stepframe.pipeline.reports.document import data_folder_of
from stepframe.stochastic.amplification import response_amplification, spectral_ratio_eq_6_18
from stepframe.stochastic.mean_square import analysis_grid


def _numbers(html: Path) -> dict[str, Any]:
    return dict(json.loads((data_folder_of(html) / "numbers.json").read_text(encoding="utf-8")))


def test_paper_site_eq_6_19(amplification_html: Path) -> None:
    numbers = _numbers(amplification_html)
    # eq. 6.19's last approximation is (ω_p/ω_s)² = (7.43/3.12)² = 5.671 (the paper prints 5.67)
    assert numbers["approx_eq_6_19_last"] == pytest.approx((7.43 / 3.12) ** 2, rel=1e-12)
    text = amplification_html.read_text(encoding="utf-8")
    assert "5.67" in text
    assert "paper&#39;s site" in text or "paper's site" in text


def test_amplification_table_recomputed(amplification_html: Path, paper_model: Any) -> None:
    table = pd.read_csv(data_folder_of(amplification_html) / "amplification.csv")
    omega = 2 * np.pi * table["f0_hz"].to_numpy()
    np.testing.assert_allclose(
        table["spectral_ratio_eq_6_18"], spectral_ratio_eq_6_18(paper_model, omega), rtol=1e-12
    )
    grid = analysis_grid(paper_model, n_steps=1000)
    picked = [0, 12, 24]
    again = response_amplification(paper_model, omega[picked], 0.05, time_s=grid)
    np.testing.assert_allclose(
        table["response_vs_fixed"].to_numpy()[picked], again.vs_fixed, rtol=1e-9
    )


def test_monte_carlo_interval_brackets_the_covariance(amplification_html: Path) -> None:
    table = pd.read_csv(data_folder_of(amplification_html) / "monte_carlo.csv")
    assert (table["n_realisations"] == 40).all()
    inside = (table["interval_low"] <= table["covariance_vs_fixed"]) & (
        table["covariance_vs_fixed"] <= table["interval_high"]
    )
    # 95 % intervals of 40 motions: at most one of the four frequencies may miss (seeded)
    assert inside.sum() >= len(table) - 1


def test_adjusted_design_displacement(amplification_html: Path) -> None:
    table = pd.read_csv(data_folder_of(amplification_html) / "adjusted_design_displacement.csv")
    row = table.set_index("factor").loc["eq-6-19-last"]
    # δ*_adj = √((ω_p/ω_s)²)·δ* = (7.43/3.12)·0.25 m
    assert row["adjusted_delta_m"] == pytest.approx(7.43 / 3.12 * 0.25, rel=1e-12)
    frame = pd.read_csv(data_folder_of(amplification_html) / "frame.csv").set_index("quantity")
    # the band's upper edge is ω_1/2π of Example 4's frame (6.4581 rad/s)
    assert float(frame.loc["small-amplitude frequency f_1", "value"]) == pytest.approx(
        6.4581 / (2 * math.pi), rel=1e-12
    )
    assert float(frame.loc["band lower edge f(A_max)", "value"]) < 6.4581 / (2 * math.pi)


def _site(folder: Path, **kwargs: object) -> object:
    return site_from_records(
        folder, options=FitOptions(t0="start"), record_options={"units": "m/s2"}, **kwargs
    )


def test_site_from_records_combines_plausible_fits_by_their_median(site_records: Path) -> None:
    site = _site(site_records)
    used = site.features[site.features["plausible"]]
    assert len(site.features) == 3 and len(used) == 2  # Nishi-Akashi: ω_p at its bound
    for key in COMBINED:
        x = used[key].to_numpy(float)
        assert getattr(site.model, key) == pytest.approx(np.median(x), rel=1e-12)
        scatter = np.std(x, ddof=1) / math.sqrt(x.size)
        assert site.stderr[key] == pytest.approx(MEDIAN_SE_FACTOR * scatter, rel=1e-12)
    assert site.model.t_max_s == pytest.approx(np.median(used["t_max_s"]), rel=1e-12)


def test_site_from_records_inverse_variance_weights_each_fit(site_records: Path) -> None:
    site = _site(site_records, statistic="inverse-variance")
    used = site.features[site.features["plausible"]]
    for key in COMBINED:
        x = used[key].to_numpy(float)
        w = 1 / used[f"{key}_stderr"].to_numpy(float) ** 2
        assert getattr(site.model, key) == pytest.approx(np.sum(w * x) / np.sum(w), rel=1e-12)
        assert site.stderr[key] == pytest.approx(1 / math.sqrt(np.sum(w)), rel=1e-12)


def test_records_report_marks_the_unused_fit(records_amplification_html: Path) -> None:
    table = pd.read_csv(data_folder_of(records_amplification_html) / "parameters.csv")
    assert list(table["record"])[-1] == "combined"
    flagged = table[table["record"].str.startswith("12_")].iloc[0]
    assert not flagged["used"] and "omega_p_at_bound" in flagged["flags"]
    numbers = _numbers(records_amplification_html)
    assert numbers["frame_driven_lower_bound"] in (True, False)


def test_record_figures_drawn_on_workers_are_the_ones_drawn_here(
    site_records: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Each record's ω_g(t) figure is a job a worker draws whole (it reads its record again):
    the same PNG bytes, titles and texts as drawn in this process, in the records' order."""
    from stepframe.core import execution
    from stepframe.pipeline.amplification.report import record_paths_section
    from stepframe.pipeline.reports.document import Figure, FigureJob, draw_figures

    site = site_from_records(
        site_records, options=FitOptions(t0="start"), record_options={"units": "m/s2"}
    )
    section = record_paths_section(site)
    assert len(section.items) == 3 and all(isinstance(i, FigureJob) for i in section.items)
    monkeypatch.setattr(execution, "POOL_WORTH_S", 0.0)  # a batch this small would stay here
    (here,), _ = draw_figures([section], jobs=1)
    (there,), _ = draw_figures([section], jobs=2)
    assert all(isinstance(item, Figure) for item in here.items)
    assert here.items == there.items
    assert [item.title for item in here.items] == [  # type: ignore[union-attr]
        f"{path.name} [{path.stem.split('_')[1]}]" + ("" if k != 2 else " (not used: flagged)")
        for k, path in enumerate(sorted(site_records.glob("*.sac")))
    ]


def test_cli_paper_site(
    tmp_path: Path, frame_file: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    out = tmp_path / "paper.html"
    code = main(
        [
            "report",
            "amplification",
            "--fp-hz",
            "7.43",
            "--fs-hz",
            "3.12",
            "--fr-hz",
            "1.11",
            "--xi-p",
            "0.096",
            "--xi-r",
            "0.655",
            "--t-max-s",
            "5",
            "--t-dur-s",
            "20",
            "--alpha-at-tmax",
            "paper",
            "--monte-carlo",
            "0",
            "--n-steps",
            "500",
            "--frame",
            str(frame_file),
            "-o",
            str(out),
            "--json",
        ]
    )
    assert code == 0
    data = json.loads(capsys.readouterr().out)
    assert data["report"] == str(out) and data["size_bytes"] == out.stat().st_size
    provenance = json.loads((data_folder_of(out) / "provenance.json").read_text())
    assert provenance["command"].startswith("stepframe report amplification")
    assert provenance["inputs"][0]["name"] == str(frame_file)
    assert provenance["parameters"]["fp_hz"] == 7.43


def test_cli_site_with_no_usable_record(
    tmp_path: Path, rsn8883_records: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # From the record start, RSN 8883's two components both fit with ω_p at its bound (pre-event
    # noise): no usable path. (With the default t0 = auto, their P picks make both usable.)
    out = tmp_path / "r.html"
    args = ["--records", str(rsn8883_records), "--t0", "start", "-o", str(out)]
    code = main(["report", "amplification", *args])
    captured = capsys.readouterr()
    assert code == 2
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and "passing the plausibility checks" in lines[0]
    assert "omega_p_at_bound" in lines[0]
    assert list(tmp_path.iterdir()) == []


def test_cli_folder_without_records(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "notes.md").write_text("not a record")
    code = main(
        ["report", "amplification", "--records", str(empty), "-o", str(tmp_path / "r.html")]
    )
    assert code == 2
    assert "no record files" in capsys.readouterr().err
    assert not (tmp_path / "r.html").exists()


def test_cli_unreadable_files_are_failures_not_a_stop(
    tmp_path: Path, site_records: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    import shutil

    folder = tmp_path / "site"
    shutil.copytree(site_records, folder)
    (folder / "garbage.dat").write_bytes(b"\x00\x01 not a record")
    out = tmp_path / "r.html"
    code = main(
        [
            "report",
            "amplification",
            "--records",
            str(folder),
            "--units",
            "m/s2",
            "--monte-carlo",
            "0",
            "--n-steps",
            "300",
            "-o",
            str(out),
        ]
    )
    assert code == 0, capsys.readouterr().err
    failures = pd.read_csv(data_folder_of(out) / "failures.csv")
    assert list(failures["stage"]) == ["read"] and failures["item"][0].endswith("garbage.dat")


def test_cli_missing_parameter(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["report", "amplification", "--fp-hz", "7", "-o", str(tmp_path / "r.html")])
    assert code == 2
    assert capsys.readouterr().err.startswith("stepframe: error: missing --fs-hz")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("extra", "flag"),
    [(["--units", "g"], "--units g"), (["--t0", "start"], "--t0 start"),
     (["--format", "at2"], "--format at2"), (["--band", "delta"], "--band delta"),
     (["--band-samples", "100"], "--band-samples 100")],
)  # fmt: skip
def test_cli_record_options_with_parameters_are_refused(
    extra: list[str], flag: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """What reads records (or their standard errors) given with the site's parameters did
    nothing: now one line, nothing written."""
    site = ["--fp-hz", "7.43", "--fs-hz", "3.12", "--fr-hz", "1.11", "--xi-p", "0.096",
            "--xi-r", "0.655", "--t-max-s", "5", "--t-dur-s", "20"]  # fmt: skip
    code = main(["report", "amplification", *site, *extra, "-o", str(tmp_path / "r.html")])
    assert code == 2
    err = capsys.readouterr().err
    assert (
        err.startswith(
            f"stepframe: error: {flag} with the site given by its parameters, expected it only "
            "with --records DIR"
        )
        and err.count("\n") == 1
    )
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("extra", "line"),
    [(["--monte-carlo", "0", "--seed", "5"],
      "--seed 5 with --monte-carlo 0, expected it only with Monte Carlo motions")],
)  # fmt: skip
def test_cli_options_that_do_nothing_are_refused(
    extra: list[str], line: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The seed of no Monte Carlo motions (it ran and wrote the same page): one line, exit 2,
    nothing written; at the default seed, or with motions, nothing refused."""
    site = ["--fp-hz", "7.43", "--fs-hz", "3.12", "--fr-hz", "1.11", "--xi-p", "0.096",
            "--xi-r", "0.655", "--t-max-s", "5", "--t-dur-s", "20"]  # fmt: skip
    code = main(["report", "amplification", *site, *extra, "-o", str(tmp_path / "r.html")])
    err = capsys.readouterr().err
    assert code == 2 and err.startswith(f"stepframe: error: {line}") and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []
    AmplificationOptions(monte_carlo=0, seed=1)  # the default seed: never refused
    AmplificationOptions(monte_carlo=5, seed=5)


def test_frame_section_draws_the_site_over_the_band(amplification_html: Path) -> None:
    # The time-frequency panel of issue 26 (its values: tests/pipeline/test_moving_resonance.py).
    html = amplification_html.read_text(encoding="utf-8")
    assert "site_band_spectrum" in html
    assert "The site&#39;s evolutionary spectrum over the frame&#39;s band" in html


def test_a_workflows_report_lists_every_fit_as_the_command_lines(
    records_amplification_html: Path, site_records: Path, tmp_path: Path
) -> None:
    """The workflow's report over a folder had the combined row only ("3 components used"),
    where the command line's over the same folder lists each fit with its flags, the unused
    one with its reason, and draws each record's ω_g(t). Same table, same figures now."""
    import shutil

    from stepframe.pipeline.engine.runner import run_workflow
    from stepframe.pipeline.stages import shipped_stages

    shutil.copytree(site_records, tmp_path / "records")
    workflow = tmp_path / "wf.toml"
    workflow.write_text(
        'name = "site"\n[records]\nfolder = "records"\nunits = "m/s2"\n'
        '[features]\nt0 = "start"\n[site]\nfrom = "records"\n[amplification]\nn_steps = 1000\n'
        '[amplification_report]\nmonte_carlo = 0\nband = "delta"\n'
        "[outputs]\namplification_report = true\n",
        encoding="utf-8",
    )
    report = run_workflow(workflow, shipped_stages(), jobs=1)
    assert report.exit_code == 0
    html = tmp_path / "stepframe-work" / "outputs" / "amplification_report.html"
    ours = pd.read_csv(data_folder_of(html) / "parameters.csv")
    cli = pd.read_csv(data_folder_of(records_amplification_html) / "parameters.csv")
    assert list(ours["record"]) == list(cli["record"]) and len(ours) == 4  # three and combined
    pd.testing.assert_frame_equal(ours, cli, check_exact=False, rtol=1e-12)
    page = html.read_text(encoding="utf-8")
    assert page.count('alt="Time-frequency image of ') == 3
    assert str(tmp_path) not in page  # the files named inside the records folder


def test_a_missing_output_folder_is_refused_before_any_work(
    tmp_path: Path, paper_model: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The report found a missing output folder after its curves (7-8 s of work)."""
    from stepframe.errors import InputError
    from stepframe.pipeline.amplification import report as module
    from stepframe.pipeline.reports import collect_provenance

    def no_work(*args: Any, **kwargs: Any) -> None:
        raise AssertionError("the report was computed before its target was checked")

    monkeypatch.setattr(module, "amplification_report", no_work)
    target = tmp_path / "missing" / "r.html"
    with pytest.raises(InputError, match="output folder does not exist"):
        module.write_amplification_report(
            paper_model, target, provenance=collect_provenance("pytest")
        )
