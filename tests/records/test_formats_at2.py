"""PEER AT2 reader: the real RSN 8883 files, both header styles, and bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from stepframe.errors import FormatError, InputError
from stepframe.records import read
from stepframe.records.formats._text import FormatWarning
from stepframe.records.formats.at2 import sniff

AT2_DIR = Path(__file__).parents[1] / "data" / "peer_nga_west2"
H1 = AT2_DIR / "RSN8883_14383980_13849090.AT2"
H2 = AT2_DIR / "RSN8883_14383980_13849360.AT2"


def _text_values(path: Path) -> np.ndarray:
    """Independent parse: every word after line 4, as written."""
    return np.array([float(w) for line in path.read_text().splitlines()[4:] for w in line.split()])


@pytest.mark.parametrize(("path", "component"), [(H1, "90"), (H2, "360")])
def test_real_nga_west2_file(path: Path, component: str) -> None:
    stream = read(path)
    assert len(stream) == 1
    trace = stream[0]
    assert trace.stats.npts == 16396
    assert trace.stats.delta == 0.005
    assert trace.stats.channel == component
    assert trace.stats.station == "Anaheim - Lakeview & Riverdale"
    info = trace.stats.stepframe
    assert (info.format, info.units_in, info.event, info.rsn) == ("at2", "g", "14383980", 8883)
    assert info.event_date == "2008-07-29"
    np.testing.assert_array_equal(trace.data, _text_values(path) * 9.80665)


def test_real_peaks_in_g() -> None:
    # PEER's flatfile PGAs of RSN 8883 are 0.0957 g (H1) and 0.160 g (H2).
    pga_g = [np.abs(read(p)[0].data).max() / 9.80665 for p in (H1, H2)]
    assert pga_g == pytest.approx([0.0956788, 0.1598031], abs=1e-7)


def _rewrite(tmp_path: Path, header: list[str], body: list[str] | None = None) -> Path:
    lines = H1.read_text().splitlines()
    out = tmp_path / "edited.AT2"
    out.write_text("\n".join(header + (lines[4:] if body is None else body)) + "\n")
    return out


def test_old_nga_header_style(tmp_path: Path) -> None:
    path = _rewrite(
        tmp_path,
        [
            "PEER NGA STRONG MOTION DATABASE RECORD",
            "CHINO HILLS 07/29/08 1842, ANAHEIM LAKEVIEW, 090",
            "ACCELERATION TIME HISTORY IN UNITS OF G",
            " 16396    0.0050    NPTS, DT",
        ],
    )
    assert sniff(path.read_bytes()[:4096], path)
    trace = read(path)[0]
    assert trace.stats.delta == 0.005 and trace.stats.npts == 16396
    assert trace.stats.channel == "090" and trace.stats.station == "ANAHEIM LAKEVIEW"
    assert trace.stats.stepframe.event == "CHINO HILLS 07/29/08 1842"
    assert trace.stats.stepframe.event_date == "2008-07-29"
    np.testing.assert_array_equal(trace.data, _text_values(H1) * 9.80665)


def test_dt_kept_at_full_precision(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    path = _rewrite(tmp_path, [*lines[:3], "NPTS=  16396, DT=   0.00390625 SEC"])
    assert read(path)[0].stats.delta == 0.00390625


def test_stated_units_cm_s2(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    path = _rewrite(
        tmp_path,
        [
            lines[0],
            lines[1],
            "ACCELERATION TIME SERIES IN UNITS OF CM/S/S".replace("CM/S/S", "CM/SEC/SEC"),
            lines[3],
        ],
    )
    trace = read(path)[0]
    assert trace.stats.stepframe.units_in == "cm/s2"
    np.testing.assert_allclose(trace.data, _text_values(H1) * 0.01, rtol=1e-15)


def _error(path: Path) -> str:
    with pytest.raises(FormatError) as info:
        read(path, format="at2")
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path))
    return message


def test_npts_disagreeing(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    message = _error(_rewrite(tmp_path, [*lines[:3], "NPTS=  16397, DT=   0.005 SEC"]))
    assert ":4:" in message and "16396 values" in message and "NPTS = 16397" in message


def test_truncated(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    message = _error(_rewrite(tmp_path, lines[:4], lines[4:100]))
    assert "480 values" in message and "truncated" in message


def test_missing_dt(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    message = _error(_rewrite(tmp_path, [*lines[:3], "NPTS=  16396,"]))
    assert ":4:" in message and "no DT" in message


def test_missing_dt_is_named_without_format(tmp_path: Path) -> None:
    """A PEER file whose NPTS line lost its DT is sniffed as AT2 and refused by line and cause
    (docs/reading-records.md), not "format not recognised" as it was when the format was sniffed."""
    lines = H1.read_text().splitlines()
    path = _rewrite(tmp_path, [*lines[:3], "NPTS=  16396,"])
    with pytest.raises(FormatError) as info:
        read(path)
    assert str(info.value) == (
        f"{path}:4: NPTS line 'NPTS=  16396,' has no DT, expected 'NPTS= n, DT= dt SEC'"
    )


def test_non_numeric_dt(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    message = _error(_rewrite(tmp_path, [*lines[:3], "NPTS=  16396, DT=   0.0x5 SEC"]))
    assert ":4:" in message and "not numbers" in message


def test_non_numeric_value(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    body = lines[4:]
    body[9] = body[9].replace("E", "Q", 1)
    message = _error(_rewrite(tmp_path, lines[:4], body))
    assert ":14:" in message and "non-numeric" in message


def test_unknown_unit(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    path = _rewrite(
        tmp_path, [lines[0], lines[1], "ACCELERATION TIME SERIES IN UNITS OF FURLONG", lines[3]]
    )
    message = _error(path)
    assert ":3:" in message and "FURLONG" in message


def test_velocity_file_refused(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    path = _rewrite(
        tmp_path, [lines[0], lines[1], "VELOCITY TIME SERIES IN UNITS OF CM/S", lines[3]]
    )
    assert "expected acceleration" in _error(path)


def test_bad_date_warns_and_reads(tmp_path: Path) -> None:
    lines = H1.read_text().splitlines()
    path = _rewrite(tmp_path, [lines[0], "14383980, 13/45/2008, Anaheim, 90", *lines[2:4]])
    with pytest.warns(FormatWarning, match=r":2: bad date '13/45/2008'"):
        trace = read(path)[0]
    assert trace.stats.stepframe.event_date is None and trace.stats.npts == 16396


def test_units_conflicting_with_header() -> None:
    with pytest.raises(InputError, match="expected them to agree"):
        read(H1, units="gal")
    assert read(H1, units="g")[0].stats.stepframe.units_in == "g"
