"""A record is complete or refused (issue 27): real files cut short or lengthened by the tests.

Each cut file is refused with one line naming the file, the line of the declaration, the
declared and the found counts; with ``allow_short`` it is read, flagged in
``stats.stepframe.incomplete``, and its samples are exactly the first samples of the whole
file's (checked against the whole file read the same way). More samples than declared are
refused whatever the option says.
"""

from __future__ import annotations

import gzip
import json
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from obspy import Stream

from stepframe.cli import main
from stepframe.errors import InputError
from stepframe.records import read
from stepframe.records.formats._text import FormatWarning

DATA = Path(__file__).parents[1] / "data"
FORMATS = DATA / "formats"
AT2 = DATA / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"
KNET = FORMATS / "knet" / "AOM0011801241951.EW.gz"
KIKNET = FORMATS / "kiknet" / "NGNH311106302345.NS2.gz"
V2A = FORMATS / "geonet" / "20180212_211557_WPWS_20.V2A.gz"
CE58667 = FORMATS / "dmg" / "CE58667.V2.gz"
CICLC = FORMATS / "dmg" / "CICLC.v1.gz"
V2C = FORMATS / "cosmos" / "us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c.gz"
V0C = FORMATS / "cosmos" / "NP1795-n.305.v0c.gz"
ESM = FORMATS / "esm" / "HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz"
MSEED = FORMATS / "miniseed" / "CE.68150.unprocessed_counts.mseed"
STATIONXML = FORMATS / "miniseed" / "CE.68150.stationxml.xml"
SAC = FORMATS / "sac" / "seism.sac"


def _bytes(path: Path) -> bytes:
    raw = path.read_bytes()
    return gzip.decompress(raw) if raw[:2] == b"\x1f\x8b" else raw


def _lines(path: Path) -> list[str]:
    return _bytes(path).decode("latin-1").splitlines(keepends=True)


def _write(tmp_path: Path, source: Path, content: bytes | list[str]) -> Path:
    out = tmp_path / source.name.removesuffix(".gz")
    out.write_bytes(content if isinstance(content, bytes) else "".join(content).encode("latin-1"))
    return out


def _refused(path: Path, pattern: str, **options: Any) -> str:
    with pytest.raises(InputError) as info:
        read(path, **options)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path)), message
    assert re.search(pattern, message), message
    return message


def _read_short(path: Path, **options: Any) -> tuple[Stream, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        stream = read(path, allow_short=True, **options)
    return stream, [str(w.message) for w in caught if issubclass(w.category, FormatWarning)]


# --- K-NET and KiK-net (the first cases) ----------------------------------------------


def test_knet_cut_inside_its_data_refused_then_read_short(tmp_path: Path) -> None:
    # 17 header lines and 481 data lines: 3848 samples of the 10200 declared (102 s × 100 Hz).
    path = _write(tmp_path, KNET, _lines(KNET)[: 17 + 481])
    _refused(
        path,
        r"\.EW:12: 3848 values follow \(truncated\), expected Sampling Freq × Duration Time "
        r"\(100 Hz × 102 s\) = 10200 \(a short record is read only with --allow-short\)$",
    )
    stream, caught = _read_short(path)
    (trace,) = stream
    assert trace.stats.stepframe.incomplete == "3848 of 10200 samples"
    assert len(caught) == 1 and "read short (allow_short)" in caught[0]
    # NIED removes the record's mean: the short record differs from the whole one's first
    # samples by a constant (the difference of the two means), and by nothing else.
    whole = read(KNET)[0].data[:3848]
    difference = trace.data - whole
    assert np.ptp(difference) < 1e-15 and abs(difference[0]) > 1e-6


def test_knet_cut_near_the_end_is_still_refused(tmp_path: Path) -> None:
    """10,800 → 10,493 in the issue read with no warning: the peak was before the cut."""
    lines = _lines(KIKNET)
    path = _write(tmp_path, KIKNET, lines[: len(lines) - 40])  # 12000 - 320 samples
    _refused(path, r"\.NS2:12: 11680 values follow \(truncated\), expected .* = 12000")


def test_knet_cut_inside_a_number_drops_that_value(tmp_path: Path) -> None:
    data = b"".join(line.encode("latin-1") for line in _lines(KNET)[: 17 + 10])
    cut = data + b"  -1208"  # the first value of the next line, "-12085", cut after 4 digits
    path = _write(tmp_path, KNET, cut)
    _refused(path, r"81 values follow \(truncated\)")  # read as is, the cut value counts
    stream, _ = _read_short(path)
    assert stream[0].stats.npts == 80


def test_knet_samples_beyond_the_declared_duration_refused(tmp_path: Path) -> None:
    lines = _lines(KNET)
    path = _write(tmp_path, KNET, lines + lines[-20:])
    pattern = r"\.EW:12: 10360 values follow \(longer than stated\), expected .* = 10200$"
    _refused(path, pattern)
    _refused(path, pattern, allow_short=True)


def test_knet_rate_of_a_gigahertz_refused(tmp_path: Path) -> None:
    lines = _lines(KNET)
    assert lines[10] == "Sampling Freq(Hz) 100Hz\n"
    lines[10] = "Sampling Freq(Hz) 1000000000Hz\n"
    _refused(_write(tmp_path, KNET, lines), r"\.EW:11: Sampling Freq\(Hz\) = 1e\+09, expected")


# --- GeoNet: three components a file -----------------------------------------------------------


def _v2a_component_starts(lines: list[str]) -> list[int]:
    return [i for i, line in enumerate(lines) if re.match(r"(Unc|C)orrected accelerogram", line)]


def test_geonet_cut_after_a_component_says_so(tmp_path: Path) -> None:
    lines = _lines(V2A)
    second = _v2a_component_starts(lines)[1]
    path = _write(tmp_path, V2A, lines[:second])  # component 1 whole, 2 and 3 gone
    _refused(
        path,
        r"\.V2A: 1 of 3 components in the file \(cut short\?\), expected 3 \(a GeoNet file "
        r"holds three\) \(a file missing components is read only with --allow-short\)$",
    )
    stream, caught = _read_short(path)
    assert [t.stats.channel for t in stream] == ["S16W"]
    assert stream[0].stats.stepframe.incomplete == "1 of 3 components"
    np.testing.assert_array_equal(stream[0].data, read(V2A)[0].data)
    assert len(caught) == 1


def test_geonet_cut_inside_the_velocity_block(tmp_path: Path) -> None:
    lines = _lines(V2A)
    second = _v2a_component_starts(lines)[1]
    path = _write(tmp_path, V2A, lines[: second - 700])  # inside component 1's velocity block
    # 26 heading lines and 580 of acceleration, then 460 of the velocity's 580 (10 a line).
    where = "in the velocity block of component S16W (4600 of 5800 values)"
    _refused(
        path,
        rf"\.V2A:20: the file ends {re.escape(where)} \(cut short\?\), expected the whole "
        r"component \(a cut file is read only with --allow-short\)$",
    )
    stream, _ = _read_short(path)
    assert stream[0].stats.stepframe.incomplete == f"file ends {where}; 1 of 3 components"


def test_geonet_cut_in_the_second_component(tmp_path: Path) -> None:
    lines = _lines(V2A)
    second = _v2a_component_starts(lines)[1]
    path = _write(tmp_path, V2A, lines[: second + 26 + 100])  # 1000 samples of component 2
    _refused(path, r"\.V2A:1786: 1000 values follow \(truncated\), expected integer 34")
    stream, _ = _read_short(path, max_abs_g=None)
    whole = read(V2A)
    assert [t.stats.npts for t in stream] == [5800, 1000]
    np.testing.assert_array_equal(stream[1].data, whole[1].data[:1000])
    assert [t.stats.stepframe.incomplete for t in stream] == [
        "2 of 3 components",
        "1000 of 5800 samples; 2 of 3 components",
    ]


def test_geonet_values_beyond_a_block_refused(tmp_path: Path) -> None:
    lines = _lines(V2A)
    second = _v2a_component_starts(lines)[1]
    path = _write(tmp_path, V2A, [*lines[:second], lines[second - 1], *lines[second:]])
    _refused(
        path,
        rf"\.V2A:{second + 1}: 5810 values follow \(longer than stated\), expected integer 36 "
        r"\(displacement samples\) = 5800 and then the next component's heading",
    )


# --- CSMIP/DMG -----------------------------------------------------------------------------


def test_dmg_channel_lost_at_a_channel_end_flagged_with_the_option(tmp_path: Path) -> None:
    lines = _lines(CE58667)
    ends = [i for i, line in enumerate(lines) if line.startswith("/&")]
    path = _write(tmp_path, CE58667, lines[: ends[1] + 1])
    _refused(path, r":6: 2 of 3 channels in the file \(cut short\?\), expected 3 \(as the header")
    stream, _ = _read_short(path)
    assert [t.stats.stepframe.incomplete for t in stream] == ["2 of 3 channels"] * 2


def test_dmg_cut_in_the_displacement_block_and_before_the_end_line(tmp_path: Path) -> None:
    lines = _lines(CE58667)
    ends = [i for i, line in enumerate(lines) if line.startswith("/&")]
    path = _write(tmp_path, CE58667, lines[: ends[2] - 10])
    _refused(path, r"the file ends in the displ block of channel H2 \(cut short\?\)")
    path = _write(tmp_path, CE58667, lines[: ends[2]])
    _refused(path, r"the file ends before the '/&' line ending channel H2")
    stream, _ = _read_short(path)
    assert [t.stats.npts for t in stream] == [7500] * 3
    assert (
        stream[2].stats.stepframe.incomplete == "file ends before the '/&' line ending channel H2"
    )


def test_dmg_v1_cut_in_the_second_channel(tmp_path: Path) -> None:
    lines = _lines(CICLC)
    path = _write(tmp_path, CICLC, lines[:6000])
    _refused(path, r"\.v1:4049: \d+ values follow \(truncated\), expected NPTS = 32080")
    stream, _ = _read_short(path)
    whole = read(CICLC)
    n = stream[1].stats.npts
    np.testing.assert_array_equal(stream[1].data, whole[1].data[:n])
    assert stream[0].stats.stepframe.incomplete == "2 of 3 channels"


def test_dmg_values_beyond_the_declared_points_refused(tmp_path: Path) -> None:
    lines = _lines(CICLC)
    end = next(i for i, line in enumerate(lines) if line.startswith("/&"))
    path = _write(tmp_path, CICLC, [*lines[:end], lines[end - 2], *lines[end:]])
    _refused(path, rf"\.v1:{end + 1}: 31940 values follow \(longer than stated\), expected")


# --- COSMOS ------------------------------------------------------------------------------


def test_cosmos_cut_before_its_end_of_data_line(tmp_path: Path) -> None:
    lines = _lines(V2C)
    path = _write(tmp_path, V2C, lines[:-1])
    _refused(path, r"the file ends before the end-of-data line of channel 1 \(cut short\?\)")
    stream, _ = _read_short(path)
    assert stream[0].stats.npts == 42000


def test_cosmos_cut_in_the_header_of_a_later_channel(tmp_path: Path) -> None:
    lines = _lines(V0C)
    second_end = [i for i, line in enumerate(lines) if "End-of-data" in line][1]
    path = _write(tmp_path, V0C, lines[: second_end + 20])
    _refused(path, r"the file ends inside the header of channel 3")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        stream = read(path, allow_short=True)
    assert [t.stats.channel for t in stream] == ["HNE", "HNN"]
    assert stream[0].stats.stepframe.incomplete == "file ends inside the header of channel 3"


def test_cosmos_values_beyond_the_block_refused(tmp_path: Path) -> None:
    lines = _lines(V2C)
    path = _write(tmp_path, V2C, [*lines[:-1], lines[-2], lines[-1]])
    _refused(path, r":42054: 42001 values follow \(longer than stated\), expected NPTS = 42000")


def test_cosmos_cut_in_the_data_read_short_equals_the_prefix(tmp_path: Path) -> None:
    lines = _lines(V2C)
    path = _write(tmp_path, V2C, lines[:20053])
    _refused(path, r":53: 20000 values follow \(truncated\), expected NPTS = 42000")
    stream, _ = _read_short(path)
    np.testing.assert_array_equal(stream[0].data, read(V2C)[0].data[:20000])


# --- AT2, ESM, MiniSEED, SAC ---------------------------------------------------------------


def test_at2_cut_inside_a_number(tmp_path: Path) -> None:
    data = AT2.read_bytes()
    at = data.index(b"\n", 20000) + 6  # a few characters into the next line's first value
    path = _write(tmp_path, AT2, data[:at])
    message = _refused(path, r"\.AT2:4: \d+ values follow \(truncated\), expected NPTS = 16396")
    found = int(re.search(r":4: (\d+) values", message)[1])
    stream, _ = _read_short(path)
    trace = stream[0]
    assert trace.stats.npts == found - 1  # the value cut in two is dropped
    np.testing.assert_array_equal(trace.data, read(AT2)[0].data[: found - 1])
    assert trace.stats.stepframe.incomplete == f"{found - 1} of 16396 samples"


def test_esm_cut_and_lengthened(tmp_path: Path) -> None:
    lines = _lines(ESM)
    path = _write(tmp_path, ESM, lines[:5064])
    _refused(path, r"\.ASC:30: 5000 values follow \(truncated\), expected NDATA = 19128")
    stream, _ = _read_short(path)
    np.testing.assert_array_equal(stream[0].data, read(ESM)[0].data[:5000])
    _refused(_write(tmp_path, ESM, [*lines, "0.1\n"]), r":30: 19129 values follow \(longer")


def test_miniseed_cut_inside_a_record(tmp_path: Path) -> None:
    path = _write(tmp_path, MSEED, MSEED.read_bytes()[:100_000])
    _refused(path, r"file ends inside a MiniSEED record", inventory=STATIONXML)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        stream = read(path, inventory=STATIONXML, allow_short=True)
    assert {t.stats.stepframe.incomplete for t in stream} == {"file ends inside a MiniSEED record"}


def test_sac_cut_refused(tmp_path: Path) -> None:
    path = _write(tmp_path, SAC, SAC.read_bytes()[:1500])
    _refused(path, r"Actual and theoretical file size are inconsistent", units="m/s2")


@pytest.mark.parametrize("rate_hz", [1e7, 0.1])
def test_sampling_interval_out_of_range_refused_in_obspy_formats(
    tmp_path: Path, rate_hz: float
) -> None:
    from obspy import Trace

    path = tmp_path / "rate.mseed"
    Trace(np.sin(np.arange(200.0)), header={"sampling_rate": rate_hz}).write(str(path), "MSEED")
    _refused(
        path,
        rf"rate\.mseed: sampling interval {1 / rate_hz:g} s, expected an accelerogram's "
        r"interval in \[1e-06, 1\] s",
        units="m/s2",
    )


# --- the option, through the command line ----------------------------------------------------


def test_cli_refuses_in_one_line_and_reads_with_allow_short(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _write(tmp_path, KNET, _lines(KNET)[: 17 + 481])
    assert main(["records", "info", str(path)]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err.splitlines() == [
        f"stepframe: error: {path}:12: 3848 values follow (truncated), expected Sampling Freq "
        "× Duration Time (100 Hz × 102 s) = 10200 (a short record is read only with "
        "--allow-short)"
    ]
    assert main(["records", "info", str(path), "--allow-short", "--json"]) == 0
    (row,) = json.loads(capsys.readouterr().out)
    assert row["npts"] == 3848 and row["incomplete"] == "3848 of 10200 samples"
    assert main(["records", "info", str(path), "--allow-short"]) == 0
    assert "INCOMPLETE (3848 of 10200 samples)" in capsys.readouterr().out


def test_catalog_records_a_short_file_as_a_failure_or_flags_it(tmp_path: Path) -> None:
    import pandas as pd

    folder = tmp_path / "records"
    folder.mkdir()
    _write(folder, KNET, _lines(KNET)[: 17 + 481])
    _write(folder, AT2, AT2.read_bytes())
    out = tmp_path / "catalog.csv"
    assert main(["records", "catalog", str(folder), "-o", str(out), "--json"]) == 0
    table, failures = pd.read_csv(out), pd.read_csv(tmp_path / "catalog.failures.csv")
    assert len(table) == 1 and table["incomplete"].isna().all()
    assert "3848 values follow (truncated)" in failures["message"][0]
    assert main(["records", "catalog", str(folder), "-o", str(out), "--allow-short", "--json"]) == 0
    table = pd.read_csv(out).set_index("component")
    assert (
        table.loc["EW", "incomplete"] == "3848 of 10200 samples" and table.loc["EW", "npts"] == 3848
    )
    assert pd.isna(table.loc["90", "incomplete"])


def test_every_output_of_a_short_record_says_so(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """docs/reading-records.md: "every output made from it can say so". The fit's flags, the
    features table's row and the spectrum (text and JSON) lost the mark; only a warning on
    stderr was left. Each output of the cut file carries it, and the whole file's none."""
    lines = AT2.read_text().splitlines(keepends=True)
    cut = tmp_path / "cut.AT2"
    cut.write_text("".join(lines[:2000]))
    folder = tmp_path / "both"
    folder.mkdir()
    (folder / "cut.AT2").write_text(cut.read_text())
    (folder / "whole.AT2").write_text(AT2.read_text())

    def json_of(*argv: str) -> Any:
        assert main(["--json", *argv]) == 0
        return json.loads(capsys.readouterr().out)

    fit = json_of("stochastic", "fit", str(cut), "--allow-short")
    assert "record_incomplete" in fit[0]["flags"]
    whole = json_of("stochastic", "fit", str(AT2))
    assert "record_incomplete" not in whole[0]["flags"]
    spectrum = json_of("records", "spectrum", str(cut), "--allow-short", "--periods-s", "1")
    declared = int(re.search(r"NPTS=\s*(\d+)", AT2.read_text()).group(1))  # type: ignore[union-attr]
    assert spectrum["components"][0]["incomplete"].endswith(f"of {declared} samples")
    table = tmp_path / "features.csv"
    json_of("stochastic", "features", str(folder), "-o", str(table), "--allow-short")
    import pandas as pd

    rows = pd.read_csv(table).set_index("file")["flags"].fillna("")
    assert rows[str(folder / "cut.AT2")] == "record_incomplete"
    assert "record_incomplete" not in rows[str(folder / "whole.AT2")]
