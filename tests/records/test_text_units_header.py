"""Plain text records whose header names the units (PEER-style and exported files): read in those
units without --units; a --units that contradicts the header is an error naming its line."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import numpy as np
import pytest

from stepframe.cli import main
from stepframe.errors import FormatError
from stepframe.records import read
from stepframe.records.formats._text import header_units

DATA = Path(__file__).parents[1] / "data"
AT2 = DATA / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"
G = 9.80665


def _values_g(n: int = 2000) -> np.ndarray:
    lines = AT2.read_text().splitlines()[4:]
    return np.array([float(w) for x in lines for w in x.split()])[:n]


def _two_columns(tmp_path: Path, header: str, values: np.ndarray, name: str = "rec.txt") -> Path:
    """A (time, value) file at dt = 0.005 s under ``header`` (lines joined as written)."""
    time_s = np.arange(values.size) * 0.005
    body = "\n".join(f"{t:.3f} {v!r}" for t, v in zip(time_s, values.tolist(), strict=True))
    path = tmp_path / name
    path.write_text(header + body + "\n")
    return path


@pytest.mark.parametrize(
    ("header", "factor", "units_in"),
    [
        ("RSN8883 360\nTime[s]  Accel[g]\n", 1.0, "g"),
        ("Time (s), Acceleration (g)\n", 1.0, "g"),
        ("ACCELERATION TIME SERIES IN UNITS OF G\n", 1.0, "g"),
        ("# station LRC\n# units: cm/s/s\n# t a\n", 100 * G, "cm/s2"),
        ("Time (sec)   Acceleration (cm/sec^2)\n", 100 * G, "cm/s2"),
        ("time_s,acc_gal\n", 100 * G, "gal"),
        ("t [s]   a [gal]\n", 100 * G, "gal"),
        ("Time (s)  Acc (m/s²)\n", G, "m/s2"),
        ("Time (s)  Acc (mm/s**2)\n", 1000 * G, "mm/s2"),
    ],
)
def test_header_units_are_used_without_units(
    tmp_path: Path, header: str, factor: float, units_in: str
) -> None:
    values_g = _values_g()
    path = _two_columns(tmp_path, header, values_g * factor)
    trace = read(path)[0]  # sniffed, no --units
    assert trace.stats.stepframe.format == "text"
    assert trace.stats.stepframe.units_in == units_in
    np.testing.assert_allclose(trace.data, values_g * G, rtol=1e-12)
    # the same --units as the header (or an alias of it) is accepted
    alias = {"g": "g", "cm/s2": "gal", "gal": "cm/s2", "m/s2": "m/s2", "mm/s2": "mm/s2"}
    np.testing.assert_array_equal(read(path, units=alias[units_in])[0].data, trace.data)


def test_one_column_file_from_the_shipped_text_record(tmp_path: Path) -> None:
    values = np.loadtxt(DATA / "formats" / "text" / "acc.txt")
    path = tmp_path / "acc.txt"
    path.write_text("Acceleration (cm/s/s)\n" + (DATA / "formats" / "text" / "acc.txt").read_text())
    trace = read(path, dt=0.005)[0]  # the shipped file is in gal (PROVENANCE.md)
    assert trace.stats.stepframe.units_in == "cm/s2"
    np.testing.assert_allclose(trace.data, values * 0.01, rtol=1e-12)
    with pytest.raises(FormatError, match=r"acc.txt:1: header line 1 'Acceleration \(cm/s/s\)'"):
        read(path, dt=0.005, units="g")


def test_contradicting_units_name_the_header_line(tmp_path: Path) -> None:
    path = _two_columns(tmp_path, "RSN8883 360\n\nTime[s]  Accel[g]\n", _values_g())
    with pytest.raises(FormatError) as caught:
        read(path, units="gal")
    message = str(caught.value)
    assert message.startswith(f"{path}:3: header line 3 'Time[s] Accel[g]' states units 'g'")
    assert "--units 'gal'" in message and "omit --units" in message


def test_contradicting_units_through_the_cli(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _two_columns(tmp_path, "Time (s), Acceleration (g)\n", _values_g())
    assert main(["records", "info", str(path), "--units", "cm/s2", "--json"]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1
    assert f"{path}:1: header line 1" in err and "Acceleration (g)" in err
    with contextlib.redirect_stdout(io.StringIO()) as buffer:
        assert main(["records", "info", str(path), "--json"]) == 0
    (row,) = json.loads(buffer.getvalue())
    assert row["units_in"] == "g"
    assert row["pga_g"] == pytest.approx(float(np.max(np.abs(_values_g()))), rel=1e-12)


def test_two_different_units_need_units(tmp_path: Path) -> None:
    path = _two_columns(tmp_path, "PGA (cm/s/s) below\nTime (s)  Accel (g)\n", _values_g())
    with pytest.raises(FormatError, match=r"rec.txt:2: header names units 'cm/s/s' \(line 1\)"):
        read(path)
    assert read(path, units="g")[0].stats.stepframe.units_in == "g"


@pytest.mark.parametrize(
    "header",
    [
        "Time (s)  Velocity (cm/s)\n",  # not an acceleration unit
        "t a\n",
        "# my record, component (H1), station G12\n",
        "NPTS= 2000, DT= 0.005 SEC\n",
    ],
)
def test_headers_without_acceleration_units_still_need_units(tmp_path: Path, header: str) -> None:
    path = _two_columns(tmp_path, header, _values_g())
    assert header_units(header.splitlines()) == []
    with pytest.raises(FormatError, match="expected them given with --units"):
        read(path, format="text")
