"""``stepframe records info|spectrum|catalog``: JSON contents, errors with exit 2, outputs."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from stepframe.cli import main

PEER = Path(__file__).parents[1] / "data" / "peer_nga_west2"
H1 = PEER / "RSN8883_14383980_13849360.AT2"
H2 = PEER / "RSN8883_14383980_13849090.AT2"


def _json(capsys: pytest.CaptureFixture[str], *args: str) -> object:
    assert main([*args, "--json"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""  # --json: nothing but JSON, and no progress lines
    return json.loads(captured.out)


def test_info_json(capsys: pytest.CaptureFixture[str]) -> None:
    rows = _json(capsys, "records", "info", str(H1))
    assert isinstance(rows, list) and len(rows) == 1
    row = rows[0]
    for key in (
        "file",
        "station",
        "component",
        "npts",
        "dt_s",
        "duration_s",
        "units_in",
        "pga_g",
        "pgv_m_s",
        "pgd_m",
        "arias_m_s",
        "d5_95_s",
    ):
        assert key in row
    assert row["npts"] == 16396 and row["duration_s"] == pytest.approx(81.975)
    words = [float(w) for line in H1.read_text().splitlines()[4:] for w in line.split()]
    assert row["pga_g"] == pytest.approx(max(abs(w) for w in words), rel=1e-12)


def test_spectrum_two_components_against_peer(capsys: pytest.CaptureFixture[str]) -> None:
    reference = json.loads((PEER / "RSN8883_peer_spectra.json").read_text())
    periods = reference["period"][::10]
    data = _json(
        capsys,
        "records",
        "spectrum",
        str(H1),
        str(H2),
        "--periods-s",
        ",".join(str(p) for p in periods),
    )
    assert isinstance(data, dict)
    assert data["period_s"] == periods
    peer5 = next(s for s in reference["spectra"] if s["damping"] == 0.05)
    np.testing.assert_allclose(data["components"][0]["psa_g"], peer5["h1"][::10], rtol=0.05)
    np.testing.assert_allclose(data["rotd50_g"], peer5["rotd50"][::10], rtol=0.10)
    comp = data["components"][0]
    omega = 2 * np.pi / np.array(periods)
    np.testing.assert_allclose(comp["sd_m"], np.array(comp["psa_g"]) * 9.80665 / omega**2)
    assert len(data["geomean_g"]) == len(data["rotd100_g"]) == len(periods)


def test_spectrum_default_grid_and_plot(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    out = tmp_path / "psa.png"
    data = _json(capsys, "records", "spectrum", str(H1), "--damping", "0.02", "--plot", str(out))
    assert isinstance(data, dict)
    assert len(data["period_s"]) == 91 and data["period_s"][0] == pytest.approx(0.01)
    assert data["period_s"][-1] == pytest.approx(10.0) and "rotd50_g" not in data
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["records", "spectrum", str(H1), "--damping", "5"], "damping 5.0"),
        (["records", "spectrum", str(H1), "--periods-s", "0.1,-2"], "each in [0.001, 10000]"),
        (["records", "spectrum", str(H1), str(H2), str(H1)], "one or two"),
        (["records", "catalog", "/nonexistent/dir", "-o", "x.csv"], "no such file or folder"),
        # Options that apply to files only are refused with the embedded catalogue, never
        # ignored (--max-abs-g 0.01 would have read its 0.42 g records).
        (
            ["records", "info", "--example", "fema-p695", "--allow-short"],
            "--allow-short with --example fema-p695, expected only --component",
        ),
        (
            ["records", "info", "--example", "fema-p695", "--max-abs-g", "0.01", "--units", "g"],
            "--units, --max-abs-g with --example fema-p695",
        ),
    ],
)
def test_errors_are_one_line_exit_2(
    capsys: pytest.CaptureFixture[str], args: list[str], message: str
) -> None:
    assert main(args) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("stepframe: error: ") and message in lines[0]


def test_bad_files_exit_2_without_traceback(tmp_path: Path) -> None:
    truncated = tmp_path / "truncated.AT2"
    truncated.write_text("\n".join(H1.read_text().splitlines()[:50]) + "\n")
    binary = tmp_path / "binary.AT2"
    binary.write_bytes(bytes(range(256)))
    for bad in (truncated, binary):
        result = subprocess.run(
            [sys.executable, "-m", "stepframe.cli", "records", "info", str(bad)],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert result.returncode == 2 and result.stdout == ""
        assert result.stderr.startswith(f"stepframe: error: {bad}")
        assert "Traceback" not in result.stderr and len(result.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize(
    ("command", "label"),
    [(("records", "catalog"), "catalog"), (("stochastic", "features"), "features")],
)
def test_batch_commands_agree_on_a_folder_without_a_usable_record(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: tuple[str, str], label: str
) -> None:
    # One rule for both batch commands: no usable record is an error (exit 2) whose line names
    # the first failure and the failures file, which is written; an empty folder says so.
    junk = tmp_path / "junk"
    junk.mkdir()
    (junk / "a.bin").write_bytes(bytes(range(256)) * 8)
    (junk / "b.txt").write_bytes(b"")
    out = tmp_path / "out.csv"
    # an earlier run's table there: it stood beside this run's failures as if it were its result
    out.write_text("file,component\nearlier.AT2,H1\n")
    (tmp_path / "out.columns.csv").write_text("column,unit,meaning\n")
    assert main([*command, str(junk), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    failures = tmp_path / "out.failures.csv"
    assert f"{label}: 2 items, 2 failed" in err
    assert f"error: {junk}: 0 components read, 2 failures (the first: {junk / 'a.bin'}: " in err
    assert f"all in {failures}), expected at least one record" in err
    assert "see the messages above" not in err and "Traceback" not in err
    rows = failures.read_text().splitlines()
    assert rows[0] == "item,stage,error_type,message" and len(rows) == 3
    assert not out.exists() and not (tmp_path / "out.columns.csv").exists()
    empty = tmp_path / "empty"
    empty.mkdir()
    assert main([*command, str(empty), "-o", str(tmp_path / "e.csv")]) == 2
    err = capsys.readouterr().err
    assert f"error: {empty}: no record files in it, expected at least one record" in err
    assert not (tmp_path / "e.failures.csv").exists()


@pytest.mark.parametrize(
    ("command", "label"),
    [(("records", "catalog"), "catalog"), (("stochastic", "features"), "features")],
)
def test_batch_progress_line_counts_the_failures_file(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], command: tuple[str, str], label: str
) -> None:
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(H1, folder / "a.AT2")
    shutil.copy(H1, folder / "b.AT2")  # the same bytes: read once, listed as a failure
    (folder / "bad.AT2").write_text("not a record\n")
    out = tmp_path / "out.csv"
    assert main([*command, str(folder), "-o", str(out)]) == 0
    err = capsys.readouterr().err
    rows = (tmp_path / "out.failures.csv").read_text().splitlines()[1:]
    assert len(rows) == 2 and any("SameContent" in row for row in rows)
    assert f"{label}: 3 items, 2 failed" in err


def test_catalog_cli(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    folder = tmp_path / "in"
    folder.mkdir()
    shutil.copy(H1, folder)
    (folder / "bad.AT2").write_text("not a record\n")
    out = tmp_path / "cat.csv"
    assert main(["records", "catalog", str(folder), "-o", str(out)]) == 0
    captured = capsys.readouterr()
    assert "catalog: 2 items, 1 failed" in captured.err
    assert "1 components" in captured.out
    summary = _json(capsys, "records", "catalog", str(folder), "-o", str(out))
    assert summary == {
        "table": str(out),
        "columns": str(tmp_path / "cat.columns.csv"),
        "failures": str(tmp_path / "cat.failures.csv"),
        "n_components": 1,
        "n_failures": 1,
    }
    assert (tmp_path / "cat.failures.csv").read_text().splitlines()[
        0
    ] == "item,stage,error_type,message"


def test_spectrum_of_a_three_channel_file_uses_its_horizontals(
    capsys: pytest.CaptureFixture[str], data_dir: Path
) -> None:
    """CSMIP V2 with H1, Up, H2: RotD from H1 and H2 only (the vertical is recognised)."""
    from stepframe.records import read
    from stepframe.records.rotd import rotd_spectrum

    path = data_dir / "formats" / "dmg" / "CE58667.V2.gz"
    data = _json(capsys, "records", "spectrum", str(path), "--periods-s", "0.2,1.0")
    assert isinstance(data, dict)
    assert [c["component"] for c in data["components"]] == ["H1", "Up", "H2"]
    assert (data["h1"], data["h2"]) == ("H1", "H2")
    traces = {t.stats.channel: t for t in read(path)}
    expected = rotd_spectrum(traces["H1"].data, traces["H2"].data, 0.01, [0.2, 1.0], 0.05)
    np.testing.assert_allclose(data["rotd50_g"], expected.in_g("rotd50"), rtol=1e-12)


def _one_error_line(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    assert main(list(args)) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert captured.out == "" and len(lines) == 1 and lines[0].startswith("stepframe: error: ")
    return lines[0]


def test_spectrum_refuses_one_content_twice(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """The same file twice, or its copy under another name, is one component: its RotD100
    was printed as √2 times its PSA."""
    line = _one_error_line(capsys, "records", "spectrum", str(H1), str(H1), "--periods-s", "1")
    assert f"{H1}: given twice, expected two components of one record" in line
    copy = tmp_path / "copy.AT2"
    shutil.copyfile(H1, copy)
    line = _one_error_line(capsys, "records", "spectrum", str(H1), str(copy), "--periods-s", "1")
    assert f"{copy}: the same bytes as {H1}: read once" in line


def test_spectrum_refuses_components_of_two_records(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    """Two PEER files with different record numbers (RSN8883 and a file named RSN174) are not
    one record's components: no geometric mean or RotD of them."""
    other = tmp_path / "RSN174_IMPVALL_H-E11230.AT2"
    shutil.copyfile(H2, other)
    line = _one_error_line(capsys, "records", "spectrum", str(H1), str(other))
    assert "are of two records (RSN8883 and RSN174), expected two components of one record" in line


def test_one_record_needs_overlapping_times() -> None:
    """Two days of one station (start times stated, windows apart) are two records; two
    components without a stated start (epoch 0) are taken as given."""
    from stepframe.errors import InputError
    from stepframe.pipeline.catalogue.record_spectra import check_one_record
    from stepframe.records.trace import make_trace

    data = np.sin(np.arange(200) * 0.1)
    day1 = make_trace(data, 0.01, station="S", channel="HNE", starttime="2020-01-01T00:00:00")
    day2 = make_trace(data, 0.01, station="S", channel="HNN", starttime="2020-01-02T00:00:00")
    with pytest.raises(InputError, match="expected overlapping times"):
        check_one_record(day1, day2)
    same = make_trace(data, 0.01, station="S", channel="HNN", starttime="2020-01-01T00:00:01")
    check_one_record(day1, same)  # overlapping: one record
    check_one_record(make_trace(data, 0.01, channel="E"), make_trace(data, 0.01, channel="N"))


DATA = Path(__file__).parents[1] / "data" / "formats"
XML = DATA / "miniseed" / "CE.68150.stationxml.xml"


@pytest.mark.parametrize(
    "args",
    [
        ["records", "info", str(H1), "--inventory", str(XML)],
        ["records", "info", str(H1), "--inventory", str(H1)],  # not even XML
        ["records", "spectrum", str(H1), "--inventory", str(XML)],
        ["records", "info", str(DATA / "geonet" / "20180212_211557_WPWS_20.V2A.gz"),
         "--inventory", str(XML)],
        ["records", "info", "--format", "text", "--units", "gal", "--dt-s", "0.01",
         str(DATA / "text" / "acc.txt"), "--inventory", str(XML)],
        ["stochastic", "fit", str(H1), "--inventory", str(XML)],
    ],
)  # fmt: skip
def test_an_inventory_no_reader_uses_is_refused(
    capsys: pytest.CaptureFixture[str], args: list[str]
) -> None:
    """--inventory with a format that states its units was silently ignored (exit 0)."""
    line = _one_error_line(capsys, *args)
    assert "reader does not use one" in line and "expected no --inventory" in line


def test_read_refuses_an_unused_inventory() -> None:
    from stepframe.errors import InputError
    from stepframe.records import read

    with pytest.raises(InputError, match="at2 reader does not use one"):
        read(H1, inventory=XML)
    # The reader that uses it records the step naming the inventory, and is not refused.
    stream = read(DATA / "miniseed" / "CE.68150.unprocessed_counts.mseed", inventory=XML)
    assert all(t.stats.stepframe.processing[0]["inventory"] == str(XML) for t in stream)


def test_spectrum_plot_to_a_folder_is_refused_before_the_work(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    folder = tmp_path / "isdir.png"
    folder.mkdir()
    line = _one_error_line(capsys, "records", "spectrum", str(H1), "--plot", str(folder))
    assert f"{folder}: --plot target is a directory, expected a file name" in line


@pytest.mark.parametrize(
    ("periods", "item"), [("0.2,,1", "item 2 of 3"), ("0.2,1,", "item 3 of 3")]
)
def test_an_empty_item_of_a_number_list_is_refused(
    capsys: pytest.CaptureFixture[str], periods: str, item: str
) -> None:
    assert main(["records", "spectrum", str(H1), "--periods-s", periods]) == 2
    err = capsys.readouterr().err
    assert f"argument --periods-s: {periods!r}: {item} is empty" in err
    assert len(err.strip().splitlines()) == 1


def test_units_help_lists_every_accepted_unit(capsys: pytest.CaptureFixture[str]) -> None:
    from stepframe.records.units import ACCELERATION_UNITS_TO_M_S2

    assert main(["records", "info", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "does not say: g, m/s2, cm/s2 (= gal), mm/s2, nm/s2" in text
    assert all(unit in text for unit in ACCELERATION_UNITS_TO_M_S2)


def test_info_text_of_a_record_without_a_channel_name(capsys: pytest.CaptureFixture[str]) -> None:
    """A plain-text record has a station (its file's stem) but no channel: the line reads
    'acc.txt acc: 16396 samples ...', not 'acc.txt acc : ...' with a blank name before the colon."""
    acc = Path(__file__).parents[1] / "data" / "formats" / "text" / "acc.txt"
    words = ["--format", "text", "--units", "gal", "--dt-s", "0.005", str(acc)]
    assert main(["records", "info", *words]) == 0
    assert capsys.readouterr().out.startswith(f"{acc} acc: 16396 samples at 0.005 s, units gal,")
    assert main(["stochastic", "fit", *words]) == 0
    assert capsys.readouterr().out.splitlines()[0] == f"{acc}:"
