"""The command-line conventions: one-line errors with exit 2, --json, --version, --help."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from stepframe import __version__
from stepframe.cli import main


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "stepframe.cli", *args], capture_output=True, text=True, timeout=120
    )


def test_version_in_process(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"stepframe {__version__}"


def test_help_lists_groups_and_examples(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for group in ("records", "stochastic", "structure", "demo", "examples:"):
        assert group in out


def test_unknown_option_is_one_line_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--no-such-option"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("stepframe: error: ")
    assert "--no-such-option" in lines[0]


def test_missing_file_subprocess_has_no_traceback(tmp_path: Path) -> None:
    missing = tmp_path / "nope.AT2"
    result = run_cli("records", "info", str(missing))
    assert result.returncode == 2
    assert result.stdout == ""
    assert (
        result.stderr.strip()
        == f"stepframe: error: {missing}: no such file, expected an existing record file"
    )
    assert "Traceback" not in result.stderr


def test_debug_shows_traceback(tmp_path: Path) -> None:
    result = run_cli("records", "info", str(tmp_path / "nope"), "--debug")
    assert result.returncode == 2
    assert "Traceback" in result.stderr
    assert result.stderr.strip().splitlines()[-1].startswith("stepframe: error: ")


def test_demo_json_subprocess(tmp_path: Path) -> None:
    result = run_cli("--json", "demo", "--out-dir", str(tmp_path / "demo"))
    assert result.returncode == 0, result.stderr
    payload = json.loads(result.stdout)  # stdout is only JSON
    assert payload["n_records"] == 100
    assert len(payload["records"]) == 100
    figure = Path(payload["figure"])
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list(figure.parent.glob("*.part"))


def test_demo_refuses_file_as_out_dir(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    blocker = tmp_path / "file"
    blocker.write_text("x")
    assert main(["demo", "--out-dir", str(blocker)]) == 2
    assert "expected a directory" in capsys.readouterr().err


def test_help_cold_start_avoids_heavy_imports() -> None:
    code = (
        "import sys; from stepframe.cli import build_parser; build_parser();"
        "heavy = ('obspy', 'xarray', 'numba', 'matplotlib', 'pandas', 'scipy');"
        "print(sorted(m for m in heavy if m in sys.modules))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60
    )
    assert result.stdout.strip() == "[]"


def test_reader_warning_is_one_line(data_dir: Path, tmp_path: Path) -> None:
    """A header peak disagreeing with the data: the record is read, the warning is one line."""
    import gzip

    source = data_dir / "formats" / "esm" / "HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz"
    lines = gzip.decompress(source.read_bytes()).decode("latin-1").splitlines()
    assert "0.300022" in lines[39]
    lines[39] = lines[39].replace("0.300022", "0.400022")
    edited = tmp_path / "edited.ASC"
    edited.write_text("\n".join(lines) + "\n", encoding="latin-1")
    completed = run_cli("records", "info", str(edited), "--json")
    assert completed.returncode == 0, completed.stderr
    assert json.loads(completed.stdout)[0]["npts"] > 0
    warning_lines = completed.stderr.strip().splitlines()
    assert len(warning_lines) == 1
    assert warning_lines[0].startswith("stepframe: warning: ")
    assert "edited.ASC:40: PGA_CM/S^2: header peak" in warning_lines[0]


def test_the_command_tree_builds_whatever_module_is_imported_first() -> None:
    """GROUPS names modules instead of importing them: no import-order dependence."""
    for first in (
        "stepframe.commands.records",
        "stepframe.commands.stochastic_fit",
        "stepframe.commands.structure_design",
    ):
        probe = (
            f"import {first}; from stepframe.cli import build_parser; "
            "print(sorted(build_parser()._subparsers._group_actions[0].choices))"
        )
        done = subprocess.run(
            [sys.executable, "-c", probe], capture_output=True, text=True, check=True
        )
        assert done.stdout.strip() == "['demo', 'records', 'run', 'stochastic', 'structure']"
