"""core.io: atomic_write leaves the old file or the new one, never a part; read_toml errors."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from stepframe.core.io import (
    atomic_write,
    publish_folder,
    read_toml,
    staged_folder,
    write_bytes,
    write_text,
)
from stepframe.errors import InputError


class Killed(Exception):
    """Stands for anything that stops a write midway."""


def test_an_exception_midway_leaves_no_partial_file_and_no_temporary(tmp_path: Path) -> None:
    target = tmp_path / "table.csv"
    with pytest.raises(Killed), atomic_write(target) as out:
        out.write("half a row,")
        out.flush()
        raise Killed
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []


def test_an_exception_midway_keeps_the_old_file_whole(tmp_path: Path) -> None:
    target = tmp_path / "table.csv"
    target.write_text("old,file\n")
    with pytest.raises(KeyboardInterrupt), atomic_write(target, "wb") as out:
        out.write(b"new but unfinished")
        raise KeyboardInterrupt
    assert target.read_text() == "old,file\n"
    assert [p.name for p in tmp_path.iterdir()] == ["table.csv"]


def test_a_finished_write_replaces_the_file_with_the_umask_mode(tmp_path: Path) -> None:
    target = tmp_path / "out.txt"
    target.write_text("old")
    assert write_text(target, "new\r\nline") == target
    assert target.read_bytes() == b"new\r\nline"  # newline="" keeps line ends as written
    mask = os.umask(0)
    os.umask(mask)
    assert target.stat().st_mode & 0o777 == 0o666 & ~mask
    write_bytes(target, b"\x00\x01")
    assert target.read_bytes() == b"\x00\x01"
    assert [p.name for p in tmp_path.iterdir()] == ["out.txt"]


def test_a_missing_folder_is_a_user_error(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="output folder does not exist"):
        write_text(tmp_path / "missing" / "x.txt", "x")


def test_a_staged_folder_replaces_the_old_one_whole(tmp_path: Path) -> None:
    target = tmp_path / "report_files"
    target.mkdir()
    (target / "old.csv").write_text("old")
    with staged_folder(target) as staging:
        (staging / "new.csv").write_text("new")
        assert sorted(p.name for p in target.iterdir()) == ["old.csv"]  # untouched until the end
    assert sorted(p.name for p in target.iterdir()) == ["new.csv"]
    assert [p.name for p in tmp_path.iterdir()] == ["report_files"]  # no staging, no .old left
    mask = os.umask(0)
    os.umask(mask)
    assert target.stat().st_mode & 0o777 == 0o777 & ~mask


def test_an_exception_in_a_staged_folder_keeps_the_old_folder(tmp_path: Path) -> None:
    target = tmp_path / "set"
    target.mkdir()
    (target / "a.parquet").write_bytes(b"old")
    with pytest.raises(Killed), staged_folder(target) as staging:
        (staging / "a.parquet").write_bytes(b"half")
        raise Killed
    assert (target / "a.parquet").read_bytes() == b"old"
    assert [p.name for p in tmp_path.iterdir()] == ["set"]


def test_a_failed_rename_puts_the_old_folder_back(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "set"
    target.mkdir()
    (target / "kept").write_text("old")
    staging = tmp_path / ".set.tmp"
    staging.mkdir()
    real_replace = os.replace

    def replace(source: os.PathLike[str], destination: os.PathLike[str]) -> None:
        if Path(source) == staging:
            raise Killed
        real_replace(source, destination)

    monkeypatch.setattr(os, "replace", replace)
    with pytest.raises(Killed):
        publish_folder(staging, target)
    assert (target / "kept").read_text() == "old"


def test_read_toml_returns_data_and_text(tmp_path: Path) -> None:
    path = tmp_path / "case.toml"
    path.write_text('[pier]\nheight_m = 27.0\nname = "Ø"\n', encoding="utf-8")
    data, text = read_toml(path, "a design input")
    assert data == {"pier": {"height_m": 27.0, "name": "Ø"}}
    assert text.splitlines()[1] == "height_m = 27.0"


def test_bad_toml_names_the_file_and_line(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text("a = 1\nb = 2\nc = = 3\n", encoding="utf-8")
    with pytest.raises(InputError) as caught:
        read_toml(path, "a frame file")
    assert caught.value.line == 3
    line = caught.value.one_line()
    assert line.startswith(f"{path}:3: not valid TOML")
    assert line.endswith("expected a frame file")


def test_not_utf8_names_the_line_of_the_bad_byte(tmp_path: Path) -> None:
    path = tmp_path / "latin1.toml"
    path.write_bytes(b"a = 1\n# caf\xe9\n")
    with pytest.raises(InputError) as caught:
        read_toml(path, "a frame file")
    assert caught.value.line == 2
    assert "not UTF-8 text (byte 11)" in caught.value.one_line()


def test_missing_file_and_folder(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such file, expected a workflow file"):
        read_toml(tmp_path / "none.toml", "a workflow file")
    with pytest.raises(InputError, match="is a directory"):
        read_toml(tmp_path, "a workflow file")
