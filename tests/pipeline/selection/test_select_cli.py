"""``stepframe select``: outputs and one-line errors (exit 2)."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.structure.frame_file import FRAME_TEMPLATE


@pytest.fixture
def setup(tmp_path: Path, data_dir: Path) -> tuple[Path, Path]:
    frame = tmp_path / "FRAME.toml"
    frame.write_text(FRAME_TEMPLATE)
    records = tmp_path / "records"
    records.mkdir()
    for source in sorted((data_dir / "peer_nga_west2").glob("*.AT2")):
        shutil.copy(source, records / source.name)
    return frame, records


def _select(frame: Path, records: Path, *options: str, json_first: bool = False) -> int:
    """``stepframe [--json] select --frame FRAME RECORDS OPTIONS...``: the exit status."""
    return main(
        [
            *(["--json"] if json_first else []),
            "select",
            "--frame",
            str(frame),
            str(records),
            *options,
        ]
    )


def _error(capsys: pytest.CaptureFixture[str]) -> str:
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("stepframe: error: ")
    return lines[0]


def test_select_json_and_outputs(
    setup: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, records = setup
    out = tmp_path / "picks"
    code = _select(
        frame,
        records,
        "-n",
        "1",
        "-o",
        str(out),
        "--jobs",
        "1",
        json_first=True,
    )
    assert code == 0
    payload = json.loads(capsys.readouterr().out)
    assert payload["n_candidates"] == 2 and payload["n_failures"] == 0
    assert payload["band_rad_s"][1] == 6.4581
    assert payload["rank_by"] == "simulated_response"  # the default (docs/selection.md)
    assert payload["ranking_intensity"]["kind"] == "as-used"  # the default: as recorded
    assert payload["ranking"]["method"] == "exact" and payload["ranking"]["n_simulated"] == 2
    (chosen,) = payload["selected"]
    assert {"file", "component", "rank", "score", "scale_factor"} <= set(chosen)
    assert chosen["rank"] == 1 and chosen["scale_factor"] == 1.0
    candidates = (out / "candidates.csv").read_text().splitlines()
    assert len(candidates) == 3
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [
            "candidates.csv",
            "columns.csv",
            "confirmation.csv",
            "failures.csv",
            "motions",
            "selection.csv",
            "selection.json",
            "spectra.csv",
        ]
    )


def test_bad_frame_file(
    setup: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, records = setup
    frame.write_text(FRAME_TEMPLATE.replace("xi_1 = 0.05", "xi_1 = 'high'"))
    assert _select(frame, records, "-n", "1", "-o", str(tmp_path / "o")) == 2
    line = _error(capsys)
    assert f"{frame}:15: [frame] xi_1 = 'high', expected a number" in line


def test_too_many_asked(
    setup: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, records = setup
    assert (
        _select(frame, records, "-n", "3", "-o", str(tmp_path / "o"), "--rank-by", "band_coverage")
        == 2
    )
    assert _error(capsys) == (
        "stepframe: error: n = 3 but only 2 candidates left (2 candidates, path → 2, "
        "vertical → 2), expected n ≤ 2"
    )


def test_filter_removing_everything_with_metadata(
    setup: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, records = setup
    metadata = tmp_path / "meta.csv"
    rows = [f"{p},4.4" for p in sorted(records.iterdir())]
    metadata.write_text("file,magnitude\n" + "\n".join(rows) + "\n")
    assert (
        _select(
            frame,
            records,
            "-n",
            "1",
            "-o",
            str(tmp_path / "o"),
            "--metadata",
            str(metadata),
            "--magnitude-min",
            "6",
            "--rank-by",
            "band_coverage",
        )
        == 2
    )
    assert _error(capsys) == (
        "stepframe: error: every candidate was filtered out (2 candidates, path → 2, "
        "vertical → 2, magnitude → 0), expected some left"
    )


def test_unreadable_target(
    setup: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, records = setup
    target = tmp_path / "target.csv"
    target.write_text("period_s,sa_g\n0.2,1.0\n1.0,x\n")
    assert (
        _select(frame, records, "-n", "1", "-o", str(tmp_path / "o"), "--target-csv", str(target))
        == 2
    )
    assert _error(capsys) == (
        f"stepframe: error: {target}:3: '1.0,x', expected two numbers: period_s,sa_g"
    )


def test_unreadable_record_lands_in_failures(
    setup: tuple[Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, records = setup
    (records / "broken.AT2").write_text("not a record\n")
    out = tmp_path / "o"
    assert (
        _select(
            frame,
            records,
            "-n",
            "1",
            "-o",
            str(out),
            "--rank-by",
            "omega_p_over_s_sq",
            "--n-bootstrap",
            "0",
            json_first=True,
        )
        == 0
    )
    payload = json.loads(capsys.readouterr().out)
    assert payload["status"] == "degraded" and payload["n_failures"] == 1
    failures = (out / "failures.csv").read_text().splitlines()
    assert len(failures) == 2 and "broken.AT2" in failures[1]
