"""Agency variants of the known formats, each in a small file stepframe wrote itself.

The files are in tests/data/formats/variants/ (README there: the layout each stands for and the
rule of its synthetic samples). Every value is recomputed here from that rule, independently of
the reader; each variant is also read sniffed, as a user who gives no ``--format`` would.
"""

from __future__ import annotations

import math
import re
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from obspy import Stream, UTCDateTime

from stepframe.errors import InputError
from stepframe.records import read
from stepframe.records.formats import SNIFF_BYTES, registered_formats
from stepframe.records.formats._text import FormatWarning

VARIANTS = Path(__file__).parents[1] / "data" / "formats" / "variants"
AGENCY = VARIANTS / "esm" / "TK.0001..HNE.agency.ASC"
DAYFIRST = VARIANTS / "esm" / "TK.3104..HNN.dayfirst.ASC"
CDMG = VARIANTS / "dmg" / "CDMG1983.V2"
STRIPPED = VARIANTS / "dmg" / "stripped.V2"
KNET = VARIANTS / "knet" / "SYN0012301010900.EW"
KIKNET = VARIANTS / "knet" / "SYN0012301010900.NS2"


def _sine(amplitude: float, n: int, decimals: int) -> np.ndarray:
    """The README's rule: round(A sin(pi k / 8), d), k = 0 .. n - 1."""
    return np.array([round(amplitude * math.sin(math.pi * k / 8), decimals) for k in range(n)])


def _read_quietly(path: Path, **options: Any) -> tuple[Stream, list[str]]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        stream = read(path, **options)
    return stream, [str(w.message) for w in caught]


def _edited(path: Path, tmp_path: Path, old: str, new: str) -> Path:
    text = path.read_text(encoding="latin-1")
    assert old in text, old
    out = tmp_path / path.name
    out.write_text(text.replace(old, new, 1), encoding="latin-1")
    return out


@pytest.mark.parametrize(
    "path", sorted(p for p in VARIANTS.rglob("*") if p.is_file() and p.suffix != ".md"), ids=str
)
def test_every_variant_is_sniffed_as_its_format(path: Path) -> None:
    head = path.read_bytes()[:SNIFF_BYTES]
    found = [name for name, fmt in registered_formats().items() if fmt.sniff(head, path)]
    assert found[0] == path.parent.name


def test_esm_agency_file_with_preamble_and_none_fields() -> None:
    stream, caught = _read_quietly(AGENCY)
    assert caught == []  # "None" and empty fields are missing values, not damage
    (trace,) = stream
    info = trace.stats.stepframe
    assert info.format == "esm" and info.units_in == "cm/s2"
    assert trace.stats.npts == 40 and trace.stats.delta == 0.01
    np.testing.assert_array_equal(trace.data, _sine(12.345678, 40, 6) * 0.01)
    assert trace.stats.starttime == UTCDateTime(2023, 2, 6, 1, 17, 32, 512300)
    assert (trace.stats.network, trace.stats.station, trace.stats.location) == ("TK", "0001", "")
    assert trace.stats.channel == "HNE" and info.event == "TK-20230206-0001"
    assert info.preamble == [
        "Processed by the national strong-motion service, 2023-02-07 (stepframe test file)",
        "Baseline: linear, removed; filter: acausal Butterworth, order 4, 0.05-30 Hz",
        "Record of station 0001, component HNE",
    ]
    # The optional numbers the reader uses that the file leaves missing, in reading order.
    assert info.header_missing == ["MAGNITUDE_W", "EPICENTRAL_DISTANCE_KM", "VS30_M/S"]
    assert info.magnitude == 4.7  # MAGNITUDE_W is None: the local magnitude is used
    assert info.repi_km is None and info.vs30_m_s is None and info.incomplete is None


def test_esm_agency_file_was_read_as_text_before(tmp_path: Path) -> None:
    """The issue's case: the preamble hid the header from the sniffer and the parser. Without
    its processing lines the file is plain ESM, and both read to the same samples."""
    plain = tmp_path / "plain.ASC"
    plain.write_text("\n".join(AGENCY.read_text().splitlines()[3:]) + "\n")
    a, b = read(AGENCY)[0], read(plain)[0]
    np.testing.assert_array_equal(a.data, b.data)
    assert b.stats.stepframe.preamble == [] and a.stats.starttime == b.stats.starttime


def test_esm_day_first_time_duration_count_and_unparsable_field() -> None:
    stream, caught = _read_quietly(DAYFIRST)
    (trace,) = stream
    assert trace.stats.starttime == UTCDateTime(2010, 11, 14, 23, 9, 19, 300000)
    # NDATA: None; DURATION_S 0.155 s at 0.005 s is 31 intervals: 32 samples, (n - 1)·dt.
    assert trace.stats.npts == 32 and trace.stats.delta == 0.005
    np.testing.assert_array_equal(trace.data, _sine(-3.5, 32, 6) * 0.01)
    info = trace.stats.stepframe
    assert info.magnitude == 5.1 and info.repi_km == 45.79 and info.vs30_m_s is None
    assert info.header_missing == ["MAGNITUDE_L", "VS30_M/S"]
    assert len(caught) == 1
    assert re.search(
        r"dayfirst\.ASC:9: VS30_M/S = 'n\.a\.' is not a number.*left missing", caught[0]
    )


@pytest.mark.parametrize(
    ("old", "new", "pattern"),
    [
        (
            "SAMPLING_INTERVAL_S: 0.010000",
            "SAMPLING_INTERVAL_S: None",
            r"agency\.ASC:32: SAMPLING_INTERVAL_S is 'None', expected a value \(mandatory\)",
        ),
        (
            "SAMPLING_INTERVAL_S: 0.010000",
            "SAMPLING_INTERVAL_S: 1e-9",
            r":32: SAMPLING_INTERVAL_S = 1e-09 s, expected an accelerogram's interval in "
            r"\[1e-06, 1\] s",
        ),
        (
            "NDATA: 40\nDURATION_S: 0.400",
            "NDATA: None\nDURATION_S:",
            r":33: no NDATA or DURATION_S in the header, expected the sample count or the duration",
        ),
        (
            "NDATA: 40",
            "NDATA: 41",
            r":33: 40 values follow \(truncated\), expected NDATA = 41 \(a short record is read "
            r"only with --allow-short\)",
        ),
        (
            "NDATA: 40",
            "NDATA: 39",
            r":33: 40 values follow \(longer than stated\), expected NDATA = 39",
        ),
        (
            "UNITS: cm/s^2",
            "UNITS: None",
            r"units not stated in the file, expected them given with --units",
        ),
        (
            "DATA_TYPE: Acceleration",
            "DATA_TYPE: Velocity",
            r":53: DATA_TYPE 'Velocity', expected ACCELERATION",
        ),
    ],
    ids=["dt-none", "dt-1ns", "no-count", "short", "long", "units-none", "velocity"],
)
def test_esm_mandatory_fields_still_checked(
    tmp_path: Path, old: str, new: str, pattern: str
) -> None:
    path = _edited(AGENCY, tmp_path, old, new)
    with pytest.raises(InputError) as info:
        read(path)
    assert str(info.value).startswith(str(path)) and "\n" not in str(info.value)
    assert re.search(pattern, str(info.value)), str(info.value)


def test_esm_units_none_read_with_units_given(tmp_path: Path) -> None:
    path = _edited(AGENCY, tmp_path, "UNITS: cm/s^2", "UNITS: None")
    np.testing.assert_array_equal(read(path, units="gal")[0].data, _sine(12.345678, 40, 6) * 0.01)


def test_esm_duration_count_refuses_a_sample_more(tmp_path: Path) -> None:
    path = tmp_path / DAYFIRST.name
    path.write_text(DAYFIRST.read_text() + "0.5\n0.5\n")  # 34 samples: neither 31 nor 32
    pattern = (
        r":16: 34 values follow \(longer than stated\), expected DURATION_S / "
        r"SAMPLING_INTERVAL_S \(0\.155 s / 0\.005 s\) = 31"
    )
    with pytest.raises(InputError, match=pattern):
        read(path)


def test_esm_other_time_spellings(tmp_path: Path) -> None:
    key = "DATE_TIME_FIRST_SAMPLE_YYYYMMDD_HHMMSS: 2023/02/06 01:17:32.512300"
    expected = UTCDateTime(2023, 2, 6, 1, 17, 32, 512300)
    for spelling in (
        "20230206_011732.5123",
        "2023-02-06T01:17:32.512300Z",
        "06/02/2023 01:17:32.5123",
    ):
        path = _edited(AGENCY, tmp_path, key, key.split(": ")[0] + ": " + spelling)
        assert read(path)[0].stats.starttime == expected, spelling
    path = _edited(AGENCY, tmp_path, key, key.split(": ")[0] + ": Feb 6 2023")
    with pytest.warns(FormatWarning, match=r":30: bad date 'Feb 6 2023', expected YYYYMMDD_HHMMSS"):
        assert read(path)[0].stats.starttime == UTCDateTime(0)


def test_cdmg_1983_v2_upper_case_pdt_crlf_and_dos_eof() -> None:
    stream, caught = _read_quietly(CDMG)
    assert caught == []  # the stated peak -267.957 cm/s² agrees with the data
    (trace,) = stream
    assert (trace.stats.station, trace.stats.channel) == ("36456", "90")
    assert trace.stats.delta == 0.02 and trace.stats.stepframe.units_in == "cm/s2"
    np.testing.assert_array_equal(trace.data, _sine(-267.957, 24, 3) * 0.01)
    # TRIGGER TIME 16:42:48.2 PDT is 23:42:48.2 UTC (PDT = UTC - 7 h).
    assert trace.stats.starttime == UTCDateTime(1983, 5, 2, 23, 42, 48, 200000)


def test_v2_without_fortran_formats_splits_touching_fields() -> None:
    stream, caught = _read_quietly(STRIPPED)
    assert caught == []
    (trace,) = stream
    np.testing.assert_array_equal(trace.data, _sine(-15.7, 16, 6) * 0.01)
    assert trace.stats.delta == 0.005 and trace.stats.channel == "360"
    assert trace.stats.starttime == UTCDateTime(2012, 2, 13, 21, 6, 45)


@pytest.mark.parametrize(
    ("name", "pattern"),
    [
        (
            "spectra.V3",
            r"spectra\.V3:1: CSMIP V3 response and Fourier spectra, expected a V1 or V2",
        ),
        ("film.RAW", r"film\.RAW:6: digitised film record \(\(time, acceleration\) pairs"),
    ],
)
def test_other_csmip_products_refused_by_name(name: str, pattern: str) -> None:
    with pytest.raises(InputError, match=pattern):
        read(VARIANTS / "dmg" / name)


def _nied_gal(offset: int, amplitude: int, n: int) -> np.ndarray:
    counts = np.array([offset + round(amplitude * math.sin(math.pi * k / 8)) for k in range(n)])
    gal = counts * 3920 / 6182761
    return gal - gal.mean()


def test_knet_and_kiknet_written_by_hand() -> None:
    stream, caught = _read_quietly(KNET)
    assert caught == []  # Max. Acc. 1.940 gal agrees with the data
    (trace,) = stream
    assert (trace.stats.channel, trace.stats.delta, trace.stats.npts) == ("EW", 0.01, 100)
    np.testing.assert_allclose(trace.data, _nied_gal(-12000, 3000, 100) * 0.01, rtol=0, atol=1e-15)
    (borehole,) = read(KIKNET)
    assert borehole.stats.channel == "NS2" and borehole.stats.stepframe.format == "kiknet"
    assert borehole.stats.delta == 0.005 and borehole.stats.npts == 200
    np.testing.assert_allclose(borehole.data, _nied_gal(4800, 150, 200) * 0.01, rtol=0, atol=1e-15)


@pytest.mark.parametrize(
    ("old", "new", "pattern"),
    [
        (
            "100Hz",
            "1000000000Hz",
            r"\.EW:11: Sampling Freq\(Hz\) = 1e\+09, expected a value in \[1, 1e\+06\]",
        ),
        (
            "100Hz",
            "0.5Hz",
            r"\.EW:11: Sampling Freq\(Hz\) = 0\.5, expected a value in \[1, 1e\+06\]",
        ),
        (
            "Duration Time(s)  1",
            "Duration Time(s)  2",
            r"\.EW:12: 100 values follow \(truncated\), expected Sampling Freq × Duration Time "
            r"\(100 Hz × 2 s\) = 200",
        ),
        (
            "100Hz",
            "50Hz",
            r"\.EW:12: 100 values follow \(longer than stated\), expected Sampling Freq × "
            r"Duration Time \(50 Hz × 1 s\) = 50",
        ),
    ],
    ids=["1e9Hz", "0.5Hz", "duration", "rate"],
)
def test_knet_rate_and_count_checked(tmp_path: Path, old: str, new: str, pattern: str) -> None:
    path = _edited(KNET, tmp_path, old, new)
    with pytest.raises(InputError, match=pattern):
        read(path)
