"""The silent wrong results of issue 16: each is now an error naming the file (and line)."""

from __future__ import annotations

import gzip
from pathlib import Path

import pytest

from stepframe.errors import InputError
from stepframe.records import read

DATA = Path(__file__).parents[1] / "data"


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (
            b"0 0.1\n0.01 0.2\nnan 0.3\n0.03 0.1\n0.04 0.2\n",
            r":3: value nan is not a finite number",
        ),
        (b"0 0.1\n0.01 0.2\n0.02 0.3\n0.5 0.1\n0.51 0.2\n", r"differs from the mean"),
        (b"0 1e308\n0.01 -1e308\n0.02 1e308\n", r":1: value 1e\+308 is not a finite number"),
        (b"0 0.1\n0.01 200\n0.02 0.3\n", r"peak 200 g, expected at most 100 g"),
        (b"0 0\n0.01 0\n0.02 0\n0.03 0\n", r"all samples equal 0\.0"),
        (b"0 0.1\n1e-300 0.2\n2e-300 0.3\n", r":1: time step = 1e-300 s, expected"),
    ],
    ids=["nan-time", "gap", "1e308", "201g", "zeros", "dt-1e-300"],
)
def test_text_records(tmp_path: Path, content: bytes, message: str) -> None:
    path = tmp_path / "acc.txt"
    path.write_bytes(content)
    with pytest.raises(InputError, match=message) as info:
        read(path, units="g")
    assert str(path) in str(info.value)


def test_dmg_cut_at_a_channel_end(tmp_path: Path) -> None:
    text = gzip.decompress((DATA / "formats" / "dmg" / "CE58667.V2.gz").read_bytes()).decode()
    lines = text.splitlines()
    ends = [i for i, line in enumerate(lines) if line.startswith("/&")]
    path = tmp_path / "CE58667.V2"
    path.write_text("\n".join(lines[: ends[1] + 1]) + "\n")  # channels 1 and 2 of 3
    with pytest.raises(
        InputError, match=r":6: 2 of 3 channels in the file \(cut short\?\), expected 3"
    ):
        read(path)


def test_at2_dt_too_small_names_the_line(tmp_path: Path) -> None:
    lines = (DATA / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2").read_text().splitlines()
    lines[3] = "NPTS=  16396, DT=   1e-300 SEC"
    path = tmp_path / "rec.AT2"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match=r"rec\.AT2:4: DT = 1e-300 s, expected"):
        read(path)
