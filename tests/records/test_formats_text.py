"""Plain text reader: one column with dt, two columns (time, value), header lines, refusals."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from stepframe.errors import FormatError
from stepframe.records import read

AT2 = Path(__file__).parents[1] / "data" / "peer_nga_west2"
H1 = AT2 / "RSN8883_14383980_13849090.AT2"


def _values_g() -> np.ndarray:
    return np.array([float(w) for x in H1.read_text().splitlines()[4:] for w in x.split()])


def test_one_column_real_values(tmp_path: Path) -> None:
    values = _values_g()
    path = tmp_path / "acc.txt"
    path.write_text(
        "RSN 8883 H1, units g\nacceleration\n" + "\n".join(repr(float(v)) for v in values) + "\n"
    )
    trace = read(path, units="g", dt=0.005)[0]
    assert trace.stats.stepframe.format == "text"
    assert trace.stats.stepframe.units_in == "g"
    assert trace.stats.delta == 0.005
    np.testing.assert_array_equal(trace.data, values * 9.80665)


def test_two_columns_give_dt(tmp_path: Path) -> None:
    values = _values_g()[:1000]
    time_s = np.arange(values.size) * 0.005
    path = tmp_path / "acc.csv"
    path.write_text(
        "time_s,acc_gal\n"
        + "\n".join(f"{t:.3f},{float(v)!r}" for t, v in zip(time_s, values, strict=True))
        + "\n"
    )
    trace = read(path, format="text", units="gal")[0]
    assert trace.stats.delta == pytest.approx(0.005, rel=1e-14)
    np.testing.assert_array_equal(trace.data, values * 0.01)
    with pytest.raises(FormatError, match="expected them to agree"):
        read(path, format="text", units="gal", dt=0.01)


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "rec.txt"
    path.write_text(text)
    return path


def test_units_required_with_how(tmp_path: Path) -> None:
    path = _write(tmp_path, "0.1\n0.2\n0.3\n")
    with pytest.raises(FormatError, match=r"expected them given with --units"):
        read(path, format="text", dt=0.01)


def test_dt_required_for_one_column(tmp_path: Path) -> None:
    path = _write(tmp_path, "0.1\n0.2\n0.3\n")
    with pytest.raises(FormatError, match=r"expected it given with --dt-s"):
        read(path, format="text", units="g")


def test_non_uniform_times(tmp_path: Path) -> None:
    path = _write(tmp_path, "t a\n0.00 1\n0.01 2\n0.03 3\n0.04 4\n")
    with pytest.raises(FormatError, match=r"rec.txt:4: time step 0.02 s"):
        read(path, format="text", units="g")


def test_non_numeric_after_data(tmp_path: Path) -> None:
    path = _write(tmp_path, "header\n0.1\n0.2\nbad\n0.3\n")
    with pytest.raises(FormatError, match=r"rec.txt:4: non-numeric line 'bad'"):
        read(path, format="text", units="g", dt=0.01)


def test_column_count_changes(tmp_path: Path) -> None:
    path = _write(tmp_path, "0.0 0.1\n0.01 0.2\n0.3\n")
    with pytest.raises(FormatError, match=r"rec.txt:3: 1 columns, expected 2"):
        read(path, format="text", units="g")
    path = _write(tmp_path, "0.0 0.1 5\n")
    with pytest.raises(FormatError, match=r"rec.txt:1: 3 columns, expected one"):
        read(path, format="text", units="g")


def test_sniffed_as_text(tmp_path: Path) -> None:
    path = _write(tmp_path, "# my record\n0.0 0.1\n0.01 0.2\n0.02 -0.1\n")
    assert read(path, units="m/s2")[0].stats.stepframe.format == "text"


def test_a_short_whole_file_is_sniffed_and_one_sample_refused(tmp_path: Path) -> None:
    """The sniffer dropped the head's last line as possibly cut short even when the head is the
    whole file ending in a line break: a one-line file was "format not recognised"."""
    two = _write(tmp_path, "0.1\n0.2\n")
    assert read(two, units="g", dt=0.01)[0].stats.npts == 2
    one = tmp_path / "one.txt"
    one.write_text("0.1\n")
    with pytest.raises(FormatError, match="1 sample, expected an accelerogram of at least 2"):
        read(one, units="g", dt=0.01)
