"""Bad workflows: one line naming file and line, exit 2, nothing written."""

from __future__ import annotations

import os
import tomllib
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.pipeline.catalogue.example_files import write_example_files

from .conftest import FEATURES_WORKFLOW, tree, write_workflow


def _fails(folder: Path, capsys: pytest.CaptureFixture[str], *extra: str) -> str:
    before = tree(folder)
    assert main(["run", str(folder / "wf.toml"), *extra]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, captured.err
    assert lines[0].startswith("stepframe: error: ")
    assert tree(folder) == before, "a failed run wrote something"
    assert not (folder / "stepframe-work").exists()
    return lines[0]


@pytest.fixture
def folder(tmp_path: Path) -> Path:
    write_example_files(tmp_path / "records", count=1)
    return tmp_path


def test_misspelt_key_names_line_and_suggestion(
    folder: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    write_workflow(folder, FEATURES_WORKFLOW.replace("frequency =", "frequncy ="))
    line = _fails(folder, capsys)
    assert f"{folder / 'wf.toml'}:5:" in line
    assert "frequncy" in line and "did you mean 'frequency'?" in line


def test_unknown_table(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, FEATURES_WORKFLOW + "\n[feature]\nwindow_s = 2.0\n")
    line = _fails(folder, capsys)
    assert "wf.toml:10:" in line and "did you mean 'features'?" in line


def test_wrong_type(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, FEATURES_WORKFLOW.replace("[features]", '[features]\nwindow_s = "two"'))
    line = _fails(folder, capsys)
    assert "wf.toml:5:" in line and "expected a number" in line


def test_bad_choice(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, FEATURES_WORKFLOW.replace('"zero-crossing"', '"zerocrossing"'))
    line = _fails(folder, capsys)
    assert "wf.toml:5:" in line and "expected one of zero-crossing" in line


def test_missing_records_folder(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, FEATURES_WORKFLOW.replace('"records"', '"no-such-folder"'))
    line = _fails(folder, capsys)
    assert "wf.toml:2:" in line and "does not exist" in line


def test_empty_records_folder_is_an_error(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (folder / "empty").mkdir()
    (folder / "empty" / ".hidden").write_text("not a record")
    write_workflow(folder, FEATURES_WORKFLOW.replace('"records"', '"empty"'))
    line = _fails(folder, capsys)
    assert "wf.toml:2:" in line and "expected at least one record file" in line


def test_path_leaving_the_workflow_folder(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, FEATURES_WORKFLOW.replace('"records"', '"../records"'))
    line = _fails(folder, capsys)
    assert "wf.toml:2:" in line and "leaves the workflow's folder" in line


def test_frame_file_with_errors(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (folder / "frame.toml").write_text("[frame]\nname = 'x'\nxi_1 = 'five'\n")
    write_workflow(folder, FEATURES_WORKFLOW + '\n[frame]\nfile = "frame.toml"\n')
    line = _fails(folder, capsys)
    assert f"{folder / 'frame.toml'}:3:" in line


def test_missing_frame_file(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, FEATURES_WORKFLOW + '\n[frame]\nfile = "nope.toml"\n')
    line = _fails(folder, capsys)
    assert "wf.toml:11:" in line and "does not exist" in line


def test_site_parameters_missing(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, "[site]\nfp_hz = 7.43\n[outputs]\nsite = true\n")
    line = _fails(folder, capsys)
    assert "wf.toml:1:" in line and "fs_hz missing" in line


SITE_PARAMETERS = (
    '[site]\nfrom = "parameters"\nfp_hz = 7.43\nfs_hz = 3.12\nfr_hz = 1.11\nxi_p = 0.096\n'
    "xi_r = 0.655\nt_max_s = 5\nt_dur_s = 20\n"
)


@pytest.mark.parametrize(
    ("table", "given", "line"),
    [
        ("", 'statistic = "mean"', '[site] statistic = "mean" with from = "parameters"'),
        ("", "plausible_only = false", '[site] plausible_only = false with from = "parameters"'),
        ("[amplification_report]\n", 'band = "delta"',
         '[amplification_report] band = "delta" with [site] from = "parameters"'),
        ("[amplification_report]\n", "band_samples = 100",
         '[amplification_report] band_samples = 100 with [site] from = "parameters"'),
        ("[amplification_report]\nmonte_carlo = 0\n", "seed = 5",
         "[amplification_report] seed = 5 with monte_carlo = 0"),
    ],
)  # fmt: skip
def test_a_site_option_that_does_nothing_is_refused_at_its_line(
    folder: Path, capsys: pytest.CaptureFixture[str], table: str, given: str, line: str
) -> None:
    """Each ran and wrote the same site and report as without it; at its default value (or
    with a site from records) it is accepted."""
    outputs = "[outputs]\nsite = true\namplification_report = true\n"
    text = SITE_PARAMETERS + table + given + "\n" + outputs
    write_workflow(folder, text)
    at = text.splitlines().index(given) + 1
    assert f"wf.toml:{at}: {line}, expected" in _fails(folder, capsys)
    defaults = {
        'statistic = "mean"': 'statistic = "median"',
        "plausible_only = false": "plausible_only = true",
        'band = "delta"': 'band = "monte-carlo"',
        "seed = 5": "seed = 1",
    }
    if given in defaults:
        write_workflow(folder, text.replace(given, defaults[given]))
        assert main(["run", str(folder / "wf.toml"), "--dry-run"]) == 0, capsys.readouterr().err


def test_not_toml(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, "[outputs]\nfeatures = \n")
    line = _fails(folder, capsys)
    assert "wf.toml:2:" in line and "not valid TOML" in line


def test_no_outputs(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, '[records]\nfolder = "records"\n[outputs]\nfeatures = false\n')
    line = _fails(folder, capsys)
    assert "wf.toml:3:" in line and "asks for nothing" in line


def test_unknown_force_stage(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, FEATURES_WORKFLOW)
    line = _fails(folder, capsys, "--force", "featurs")
    assert "did you mean 'features'?" in line


def test_dry_run_refuses_bad_jobs(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    write_workflow(folder, FEATURES_WORKFLOW)
    line = _fails(folder, capsys, "--dry-run", "--jobs", "0")
    assert line.endswith("--jobs 0, expected in [1, 1024]")


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes anywhere")
def test_unwritable_workspace(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    locked = folder / "locked"
    locked.mkdir()
    text = 'workspace = "locked/work"\n' + FEATURES_WORKFLOW
    write_workflow(folder, text)
    locked.chmod(0o500)
    try:
        line = _fails(folder, capsys)
    finally:
        locked.chmod(0o700)
    assert "locked" in line and "not writable" in line


def test_template_is_a_valid_workflow(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", "--template"]) == 0
    text = capsys.readouterr().out
    tomllib.loads(text)
    # with its records folder and frame file present, the template is a runnable workflow
    write_example_files(tmp_path / "records", count=1)
    from stepframe.structure.frame_file import frame_template

    (tmp_path / "FRAME.toml").write_text(frame_template())
    write_workflow(tmp_path, text)
    assert main(["run", str(tmp_path / "wf.toml"), "--dry-run", "--json"]) == 0
    out = capsys.readouterr().out
    assert '"features"' in out and '"dry_run": true' in out
    assert not (tmp_path / "stepframe-work").exists()
    # --template prints alone: a workflow or an option beside it was ignored (exit 0)
    assert main(["run", "selection", "--template"]) == 2
    assert "--template with WORKFLOW selection, expected --template alone" in (
        capsys.readouterr().err
    )
    assert main(["run", "--template", "--jobs", "2"]) == 2
    assert "--template with --jobs," in capsys.readouterr().err


def test_workspace_under_a_file(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    (folder / "plain-file").write_text("not a folder")
    write_workflow(folder, 'workspace = "plain-file/work"\n' + FEATURES_WORKFLOW)
    line = _fails(folder, capsys)
    assert "plain-file" in line and "not a folder" in line


def test_workspace_that_is_a_file_names_the_key(
    folder: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The workspace key naming an existing file: the error named the file, not the key's line."""
    (folder / "plain-file").write_text("not a folder")
    write_workflow(folder, 'workspace = "plain-file"\n' + FEATURES_WORKFLOW)
    line = _fails(folder, capsys)
    assert "wf.toml:1: workspace 'plain-file' exists and is not a folder" in line


def test_workspace_the_system_refuses(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    # /proc refuses new folders even to root: the error comes from creating the workspace
    write_workflow(folder, 'workspace = "/proc/stepframe-work"\n' + FEATURES_WORKFLOW)
    line = _fails(folder, capsys)
    assert "/proc" in line and "expected a writable folder" in line


SELECTION_WORKFLOW = """\
[records]
folder = "records"

[frame]
file = "frames/example-4.toml"

[selection]
n = 4
{key} = "false"

[outputs]
features = true
selection = true
"""


@pytest.mark.parametrize("key", ["confirm", "require_plausible", "verticals"])
def test_a_string_where_a_selection_switch_belongs(
    folder: Path, capsys: pytest.CaptureFixture[str], key: str
) -> None:
    """``confirm = "false"`` ran the confirmation (a non-empty string is true) and was written
    into selection.json as the string: now the key's line, exit 2, nothing written."""
    frames = Path(__file__).parents[2] / "src" / "stepframe" / "workflows" / "frames"
    (folder / "frames").mkdir()
    (folder / "frames" / "example-4.toml").write_bytes((frames / "example-4.toml").read_bytes())
    write_workflow(folder, SELECTION_WORKFLOW.format(key=key))
    line = _fails(folder, capsys)
    assert line.endswith(f"wf.toml:9: [selection] {key} = 'false', expected true or false")


@pytest.mark.parametrize(
    ("line", "expected"),
    [
        ("dt_s = -1", "[records] dt_s = -1.0, expected in [1e-06, 1]"),
        ("dt_s = 0", "[records] dt_s = 0.0, expected in [1e-06, 1]"),
        ('format = "nonsense"', "[records] unknown format 'nonsense', expected one of "),
    ],
)
@pytest.mark.parametrize("dry", [(), ("--dry-run",)])
def test_a_record_option_out_of_range_is_refused_at_its_line(
    folder: Path, capsys: pytest.CaptureFixture[str], line: str, expected: str, dry: tuple[str]
) -> None:
    """``dt_s = -1`` passed --dry-run, and the run failed every file at read time (exit 1, the
    failures stored): now refused before anything runs, at the key's line, as the command
    line's ``--dt-s`` (one declaration, RecordReadOptions)."""
    write_workflow(
        folder, FEATURES_WORKFLOW.replace('folder = "records"', f'folder = "records"\n{line}')
    )
    message = _fails(folder, capsys, *dry)
    assert f"wf.toml:3: {expected}" in message
