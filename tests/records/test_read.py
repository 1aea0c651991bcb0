"""``read`` and the registry: sniffing, gzip input, components, and bad input in every format.

Bad files are real files with one defect put in on purpose; each must give one line naming the
file, the line and the problem, or read cleanly with a warning where the data are intact.
"""

from __future__ import annotations

import gzip
import re
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from stepframe.errors import FormatError, InputError
from stepframe.records import read
from stepframe.records.formats import FORMATS, SNIFF_BYTES
from stepframe.records.formats._text import FormatWarning

DATA = Path(__file__).parents[1] / "data" / "formats"
# Record files only (StationXML inventories, provenance and licences are not records).
REAL = sorted(
    p for p in DATA.rglob("*") if p.is_file() and p.suffix not in {".md", ".txt", ".xml"}
) + sorted((DATA.parent / "peer_nga_west2").glob("*.AT2"))
EXPECTED_FORMAT = {
    "cosmos": "cosmos",
    "dmg": "dmg",
    "geonet": "geonet",
    "esm": "esm",
    "knet": "knet",
    "kiknet": "knet",
    "miniseed": "mseed",
    "sac": "sac",
    "kinemetrics": "kinemetrics_evt",
    "peer_nga_west2": "at2",
}


def _plain_bytes(path: Path) -> bytes:
    raw = path.read_bytes()
    return gzip.decompress(raw) if raw[:2] == b"\x1f\x8b" else raw


@pytest.mark.parametrize("seed", range(8))
def test_sniffers_never_raise_on_random_bytes(seed: int, tmp_path: Path) -> None:
    rng = np.random.default_rng(seed)
    head = rng.integers(0, 256, size=int(rng.integers(0, SNIFF_BYTES))).astype(np.uint8).tobytes()
    path = tmp_path / "random.bin"
    path.write_bytes(head)
    for fmt in FORMATS.values():
        assert fmt.sniff(head, path) in (True, False)
    assert fmt.sniff(b"", tmp_path / "missing") in (True, False)


@pytest.mark.parametrize("path", REAL, ids=lambda p: p.name)
def test_every_real_file_sniffed_as_its_format(path: Path, tmp_path: Path) -> None:
    plain = tmp_path / path.name.removesuffix(".gz")
    plain.write_bytes(_plain_bytes(path))
    head = plain.read_bytes()[:SNIFF_BYTES]
    matches = [name for name, fmt in FORMATS.items() if fmt.sniff(head, plain)]
    assert matches and matches[0] == EXPECTED_FORMAT[path.parent.name]


def test_gzip_reads_like_plain_and_names_the_gz(tmp_path: Path) -> None:
    gz = DATA / "dmg" / "CICLC.v1.gz"
    plain = tmp_path / "CICLC.v1"
    plain.write_bytes(gzip.decompress(gz.read_bytes()))
    a, b = read(gz), read(plain)
    for x, y in zip(a, b, strict=True):
        np.testing.assert_array_equal(x.data, y.data)
    assert a[0].stats.stepframe.source_file == str(gz)
    broken = tmp_path / "broken.v1.gz"
    broken.write_bytes(gz.read_bytes()[:5000])
    with pytest.raises(InputError, match=r"broken.v1.gz: corrupt gzip file"):
        read(broken)


def test_component_selection() -> None:
    stream = read(DATA / "dmg" / "CICLC.v1.gz", component="360")
    assert [t.stats.channel for t in stream] == ["360"]
    with pytest.raises(InputError, match="no channel 'HNQ'"):
        read(DATA / "dmg" / "CICLC.v1.gz", component="HNQ")


def test_missing_empty_binary_directory(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such file"):
        read(tmp_path / "none.AT2")
    with pytest.raises(InputError, match="is a directory"):
        read(tmp_path)
    empty = tmp_path / "empty.AT2"
    empty.write_bytes(b"")
    with pytest.raises(InputError, match=r"empty.AT2: empty file"):
        read(empty)
    binary = tmp_path / "noise.V2"
    binary.write_bytes(np.random.default_rng(1).integers(0, 256, 5000).astype(np.uint8).tobytes())
    with pytest.raises(InputError, match=r"noise.V2: format not recognised"):
        read(binary)
    for name in ("at2", "cosmos", "dmg", "geonet", "esm", "text"):
        with pytest.raises(InputError, match=r"noise.V2: binary content"):
            read(binary, format=name)
        with pytest.raises(InputError, match=r"empty.AT2: empty file"):
            read(empty, format=name)


Edit = Callable[[list[str]], list[str]]


def _replace(line_no: int, old: str, new: str) -> Edit:
    """Replace ``old`` by ``new`` on 1-based line ``line_no`` (checked to be there)."""

    def edit(lines: list[str]) -> list[str]:
        assert old in lines[line_no - 1], lines[line_no - 1]
        lines[line_no - 1] = lines[line_no - 1].replace(old, new, 1)
        return lines

    return edit


def _cut(n_lines: int) -> Edit:
    return lambda lines: lines[:n_lines]


def _drop(line_no: int) -> Edit:
    return lambda lines: lines[: line_no - 1] + lines[line_no:]


V2C = "cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c.gz"
ESM = "esm/HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz"
V2A = "geonet/20180212_211557_WPWS_20.V2A.gz"

BAD = [
    # (file, edit, message pattern with the line)
    (V2C, _cut(1000), r":53: 947 values follow \(truncated\), expected NPTS = 42000"),
    (
        V2C,
        _replace(53, "42000 acc", "42001 acc"),
        r":42054: non-numeric value 'End-of-data for' after 42000 of 42001",
    ),
    (V2C, _replace(60, "e-04", "x-04"), r":60: non-numeric value '3.444521x-04'"),
    (
        V2C,
        _replace(38, "       5.000000", "    -999.000000"),
        r":1: sampling interval Real\(62\) unknown",
    ),
    (V2C, _replace(53, "cm/sec2(04)", "furlong/s2(04)"), r":53: unknown unit 'furlong/s2'"),
    (
        "dmg/CICLC.v1.gz",
        _cut(2000),
        r":28: 15776 values follow \(truncated\), expected NPTS = 31932",
    ),
    (
        "dmg/CICLC.v1.gz",
        _replace(28, "31932 Acc", "31933 Acc"),
        r":4021: non-numeric value '/&  -----' after 31932 of 31933",
    ),
    (
        "dmg/CICLC.v1.gz",
        _replace(28, "at 100 pts", "at x00 pts"),
        r":28: sampling .* not a positive number",
    ),
    (
        "dmg/CICLC.v1.gz",
        _replace(28, "units of g.", "units of furlongs."),
        r":28: unknown unit 'furlongs'",
    ),
    (
        "dmg/CICLC.v1.gz",
        _replace(40, " -.000005", " -.0000x5"),
        r":40: non-numeric value '-.0000x5'",
    ),
    (V2A, _replace(11, "data at 0.020 sec intervals", "data"), r":11: no sampling interval"),
    (V2A, _replace(14, "mm/s/s at", "furlong/s/s at"), r":11: unknown unit 'furlong/s/s'"),
    (
        V2A,
        _replace(20, "    5800    5800    5800", "    5801    5800    5800"),
        r":607: line holds values beyond the 5801 stated",
    ),
    (
        V2A,
        _cut(300),
        r":20: 2740 values follow \(truncated\), expected integer 34 \(acceleration samples\) "
        r"= 5800 \(a short record is read only with --allow-short\)",
    ),
    (ESM, _drop(29), r"no SAMPLING_INTERVAL_S in the header"),
    (
        ESM,
        _replace(30, "19128", "19129"),
        r":30: 19128 values follow \(truncated\), expected NDATA = 19129",
    ),
    (ESM, _replace(33, "cm/s^2", "furlong"), r":33: unknown unit 'furlong'"),
    (ESM, _replace(29, "0.005000", "0.0O5"), r":29: SAMPLING_INTERVAL_S = '0.0O5' is not a number"),
    (ESM, _replace(67, "0.000001", "0.0000x1"), r":67: non-numeric value '-0.0000x1'"),
]


def _edited(name: str, edit: Edit, tmp_path: Path) -> Path:
    lines = _plain_bytes(DATA / name).decode("latin-1").splitlines()
    path = tmp_path / Path(name).name.removesuffix(".gz")
    path.write_text("\n".join(edit(lines)) + "\n", encoding="latin-1")
    return path


@pytest.mark.parametrize(("name", "edit", "pattern"), BAD)
def test_bad_input_one_line_with_file_and_line(
    name: str, edit: Edit, pattern: str, tmp_path: Path
) -> None:
    path = _edited(name, edit, tmp_path)
    with pytest.raises(InputError) as info:
        read(path)
    message = str(info.value)
    assert "\n" not in message and message.startswith(str(path))
    assert __import__("re").search(pattern, message), message


BAD_DATES = [
    (V2C, _replace(19, "      11      30", "      13      30"), r":1: bad start time 2018-13-30"),
    ("dmg/CICLC.v1.gz", _replace(4, " 7/06/19,", "13/06/19,"), r":4: bad start time"),
    (
        V2A,
        _replace(17, "    2018       2      12", "    2018      14      12"),
        r":17: bad start time 2018-14-12",
    ),
    (
        ESM,
        _replace(27, "20190728_160919.870", "20191328_160919.870"),
        r":27: bad date '20191328_160919.870'",
    ),
]


@pytest.mark.parametrize(("name", "edit", "pattern"), BAD_DATES)
def test_bad_date_reads_cleanly_with_warning(
    name: str, edit: Edit, pattern: str, tmp_path: Path
) -> None:
    path = _edited(name, edit, tmp_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        stream = read(path)
    dates = [str(w.message) for w in caught if "bad" in str(w.message)]
    assert len(dates) >= 1 and all(issubclass(w.category, FormatWarning) for w in caught)
    assert __import__("re").search(pattern, dates[0]), dates[0]
    assert all(t.stats.npts > 0 and np.isfinite(t.data).all() for t in stream)


PEAK_EDITS = [
    # One wording in every format, both values in the header's own unit.
    (
        ESM,
        _replace(40, "0.300022", "30.0022"),
        r":40: PGA_CM/S\^2: header peak 30.0022 cm/s2 but the data peak is 0.300022 cm/s2$",
    ),
    (
        "dmg/CE58667.V2.gz",
        _replace(18, "27.114", "2.7114"),
        r":18: channel H1: header peak 2.7114 cm/s2 but the data peak is 27.11\d* cm/s2$",
    ),
    (
        V2A,
        _replace(14, "-41.6", "-4.16"),
        r":14: component \S+: header peak -4.16 mm/s2 but the data peak is 41.6\d* mm/s2$",
    ),
    (
        "knet/AOM0011801241951.EW.gz",
        _replace(15, "4.078", "40.78"),
        r": Max. Acc. \(gal\): header peak 40.78 gal but the data peak is 4.07\d* gal$",
    ),
]


@pytest.mark.parametrize(("name", "edit", "pattern"), PEAK_EDITS)
def test_header_peak_disagreeing_warns_in_the_header_unit(
    tmp_path: Path, name: str, edit: Edit, pattern: str
) -> None:
    path = _edited(name, edit, tmp_path)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        read(path)
    peaks = [str(w.message) for w in caught if "header peak" in str(w.message)]
    assert len(peaks) == 1 and __import__("re").search(pattern, peaks[0]), peaks


def test_fema_text_pga_header_is_checked(tmp_path: Path) -> None:
    values = np.array([0.1, -0.415783, 0.2, 0.05, 0.0])
    header = "# RSN 1, component X/MUL009\n# NPTS= 5 DT= 0.01 SEC  PGA_g= {}\n"
    good = tmp_path / "good.txt"
    good.write_text(header.format("0.415783") + " ".join(f"{v:g}" for v in values) + "\n")
    bad = tmp_path / "bad.txt"
    bad.write_text(header.format("4.15783") + " ".join(f"{v:g}" for v in values) + "\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert read(good)[0].stats.npts == 5
    with pytest.warns(
        FormatWarning,
        match=r"bad.txt:2: PGA_g: header peak 4.15783 g but the data peak is 0.415783 g$",
    ):
        read(bad)


def test_cosmos_channel_not_acceleration_skipped_with_warning(tmp_path: Path) -> None:
    edit = _replace(2103, "raw accel.   pts", "angle pts")
    path = _edited(
        "cosmos/NP1795-n.305.v0c.gz",
        lambda x: _replace(2103, "counts (50)", "deg (10)")(edit(x)),
        tmp_path,
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        stream = read(path)
    assert [t.stats.channel for t in stream] == ["HNE", "HNZ"]
    skipped = [str(w.message) for w in caught if "skipped" in str(w.message)]
    assert len(skipped) == 1 and "channel HNN holds angle (deg), not acceleration" in skipped[0]


def test_cosmos_v0_without_sensitivity_refused(tmp_path: Path) -> None:
    # Real(42), the sensor sensitivity 1.200000 V/g, set to unknown.
    path = _edited(
        "cosmos/NP1795-n.305.v0c.gz", _replace(34, "       1.200000", "    -999.000000"), tmp_path
    )
    with pytest.raises(
        InputError, match=r":51: raw counts with no recorder LSB .* sensor sensitivity"
    ):
        read(path)


def test_options_contradicting_the_file_refused(tmp_path: Path) -> None:
    at2 = DATA.parent / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"
    with pytest.raises(InputError, match=r"file states dt = 0.005 s but --dt-s 0.01"):
        read(at2, dt=0.01)
    assert read(at2, dt=0.005)[0].stats.delta == 0.005
    with pytest.raises(InputError, match=r"defined by the header's scale factor"):
        read(DATA / "knet" / "AOM0011801241951.EW.gz", units="g")
    # The FEMA P695 layout states g in its definition; its reader takes no units option.
    fema = tmp_path / "rec.txt"
    fema.write_text("# RSN 1, component X/Y000\n# NPTS= 3 DT= 0.01 SEC\n0.1 0.2 -0.1\n")
    assert read(fema)[0].stats.stepframe.units_in == "g"
    with pytest.raises(InputError, match=r"rec.txt: file states units 'g' but --units 'gal'"):
        read(fema, units="gal")
    with pytest.raises(InputError, match=r"dt = -1 s, expected a positive"):
        read(at2, dt=-1)


def test_fixed_width_fields_that_touch_and_fortran_d_exponents(tmp_path: Path) -> None:
    from stepframe.records.formats._text import fortran_width, numbers

    # A CSMIP real-header line: 8F10 fields, two of which touch.
    lines = [" 98.200000  .2980232  .4776013      .000 5.0000000-999.00000 4.0000000      .000"]
    values, end = numbers(lines, 0, tmp_path, count=8, width=fortran_width("(8f10.7)"))
    np.testing.assert_array_equal(values, [98.2, 0.2980232, 0.4776013, 0, 5, -999, 4, 0])
    assert end == 1
    values, _ = numbers(["1.5D-03 -2.0d+01"], 0, tmp_path)
    np.testing.assert_array_equal(values, [1.5e-3, -20.0])
    assert fortran_width("Format=(1E15.6)") == 15 and fortran_width("(10I8)") == 8


@given(
    st.lists(
        st.lists(st.floats(-1e6, 1e6, allow_nan=False), min_size=1, max_size=8),
        min_size=1,
        max_size=30,
    ),
    st.sampled_from(["{:.7E}", "{!r}", "{:.3f}"]),
)
@settings(max_examples=60, deadline=None)
def test_blank_separated_numbers_parse_as_python_floats(
    rows: list[list[float]], style: str
) -> None:
    """The vectorised path of `numbers` gives what float() gives word by word, stops at the
    line that completes `count`, and hands anything else to the line-by-line path."""
    from stepframe.records.formats._text import numbers

    lines = ["header", *(" ".join(style.format(v) for v in row) for row in rows), "trailer 1"]
    expected = [float(style.format(v)) for row in rows for v in row]
    values, next_line = numbers(lines, 1, Path("f.txt"), count=len(expected))
    assert values.tolist() == expected
    assert next_line == len(rows) + 1
    lines[-2] += " 1.0D-03"  # a Fortran exponent: line by line, and one value too many
    with pytest.raises(FormatError, match="beyond the"):
        numbers(lines, 1, Path("f.txt"), count=len(expected))


@given(
    st.lists(
        st.lists(
            st.one_of(
                st.floats(-1e6, 1e6, allow_nan=False).map(repr),
                st.sampled_from(["1.0D-03", "nan", "1e999", "-inf", "abc", "1_000", "", "  "]),
            ),
            max_size=8,
        ),
        max_size=40,
    ),
    st.sampled_from([4, 64, 1 << 16]),
)
@settings(max_examples=150, deadline=None)
def test_numbers_to_the_end_equal_word_by_word(rows: list[list[str]], block_values: int) -> None:
    """Without a count, `numbers` reads the words of every line to the end, converted a block
    at a time: the values of float() word by word over the lines (a Fortran D exponent read as
    E), the line count, and for a word that is no finite number below MAX_VALUE the
    line-by-line path's error on that word's line, whatever the block size."""
    from stepframe.records.formats import _text

    lines = ["header", *(" ".join(row) for row in rows)]
    expected: list[float] = []
    error: tuple[str, int] | None = None
    for number, line in enumerate(lines[1:], start=2):
        words = line.split()
        # A line's first word that is no number is named, else its first one out of range.
        bad = [w for w in words if _as_float(w) is None]
        row = [] if bad else [float(w.replace("D", "E")) for w in words]
        bad += [w for w, v in zip(words, row, strict=False) if not abs(v) <= _text.MAX_VALUE]
        if bad:
            error = (repr(bad[0]), number)
            break
        expected += row
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(_text, "_BLOCK_VALUES", block_values)
        if error is None:
            values, next_line = _text.numbers(lines, 1, Path("f.txt"))
            assert values.dtype == np.float64 and values.tobytes() == np.array(expected).tobytes()
            assert next_line == len(lines)
        else:
            with pytest.raises(FormatError, match=f"f.txt:{error[1]}: .*{re.escape(error[0])}"):
                _text.numbers(lines, 1, Path("f.txt"))


_NUMBER_FIELDS = st.one_of(
    st.floats(-1e5, 1e5, allow_nan=False).map(lambda v: f"{v:.4E}"),
    st.floats(-1e3, 1e3, allow_nan=False).map(lambda v: f"{v:.3f}"),
)
_ANY_FIELDS = st.one_of(
    _NUMBER_FIELDS, st.sampled_from(["1.0D-03", "nan", "1e999", "abc", "", "1_000", "é", "-9."])
)


@given(
    st.integers(6, 15),
    st.one_of(  # rows of numbers only (the vectorised path's), or with anything in them
        st.lists(st.tuples(st.lists(_NUMBER_FIELDS, max_size=8), st.integers(0, 3)), max_size=30),
        st.lists(st.tuples(st.lists(_ANY_FIELDS, max_size=8), st.integers(0, 3)), max_size=30),
    ),
    st.one_of(st.none(), st.floats(0.0, 1.2)),  # to the end, or this share of the fields
    st.sampled_from([4, 64, 1 << 16]),
)
@settings(max_examples=300, deadline=None)
def test_fixed_width_numbers_equal_the_line_by_line_path(
    width: int, rows: list[tuple[list[str], int]], share: float | None, block_values: int
) -> None:
    """Fixed-width fields converted a chunk of lines at a time give what the line-by-line path
    gives (it slices, strips and converts field by field): the same values to the bit, the same
    next line, or the same error on the same line; with or without a count, whatever the chunk
    size, for fields that touch, blank fields, Fortran D exponents, words, non-ASCII text and
    lines cut inside a field."""
    from stepframe.records.formats import _text

    lines = ["header"]
    for fields, cut in rows:
        line = "".join(field[-width:].rjust(width) for field in fields)
        lines.append(line[: len(line) - cut] if cut < len(line) else line)
    count = None if share is None else round(share * sum(len(f) for f, _ in rows))
    if count is not None:
        lines.append("trailer")  # a count stops before it

    def outcome() -> tuple[bytes, int] | str:
        try:
            values, next_line = _text.numbers(lines, 1, Path("f.txt"), count=count, width=width)
        except FormatError as error:
            return str(error)
        assert values.dtype == np.float64
        return values.tobytes(), next_line

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(_text, "_BLOCK_VALUES", block_values)
        fast = outcome()
        patch.setattr(_text, "_fixed_width", lambda *args: None)  # the line-by-line path only
        assert fast == outcome()


def test_a_zero_field_width_is_an_error_on_the_formats_line() -> None:
    """A data format such as (10I0) (a damaged COSMOS header) names its line, before any
    field is cut (both paths would otherwise divide by the width)."""
    from stepframe.records.formats._text import fortran_width, numbers

    lines = ["header", "100 Integer-header values follow on 10 lines, Format= (10I0)", "1 2 3"]
    with pytest.raises(FormatError, match=r"f.txt:2: data format with fields 0 characters wide"):
        numbers(lines, 2, Path("f.txt"), count=3, width=fortran_width(lines[1]))


def test_fixed_width_fields_take_the_vectorised_path() -> None:
    """A block of full fixed-width lines and a short last line is converted without the
    line-by-line path (what the property test above compares it with)."""
    from stepframe.records.formats._text import _fixed_width

    lines = ["header", " 1.500E+00-2.250E-01 3.000E+02", " 4.000E+00 5.5", "trailer"]
    values, next_line = _fixed_width(lines, 1, 5, 10) or (None, None)
    assert values is not None and values.tolist() == [1.5, -0.225, 300.0, 4.0, 5.5]
    assert next_line == 3


def _as_float(word: str) -> float | None:
    try:
        return float(word.replace("D", "E"))
    except ValueError:
        return None


def test_numbers_to_the_end_of_no_lines() -> None:
    """No line after the first: no values, and the next line is the first."""
    from stepframe.records.formats._text import numbers

    values, next_line = numbers(["header"], 1, Path("f.txt"))
    assert values.size == 0 and values.dtype == np.float64 and next_line == 1
    values, next_line = numbers(["header", "", "  "], 1, Path("f.txt"))
    assert values.size == 0 and next_line == 3


@pytest.mark.parametrize("kind", ["zip-stored", "zip-deflated", "tar", "tar.gz"])
def test_an_archive_is_named_not_read_as_its_member(tmp_path: Path, kind: str) -> None:
    # A stored zip or a tar of an AT2 file holds the file's text after its member's header:
    # it read as "binary content (NUL bytes), expected PEER AT2 text" (a deflated zip as
    # "format not recognised"); it is named, with what to do.
    import tarfile
    import zipfile

    source = Path(__file__).parents[1] / "data" / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"
    path = tmp_path / f"records.{kind}"
    if kind.startswith("zip"):
        method = zipfile.ZIP_STORED if kind == "zip-stored" else zipfile.ZIP_DEFLATED
        with zipfile.ZipFile(path, "w", compression=method) as archive:
            archive.write(source, source.name)
        named = "a zip archive"
    else:
        with tarfile.open(path, "w:gz" if kind == "tar.gz" else "w") as archive:
            archive.add(source, source.name)
        named = "a tar archive"
    with pytest.raises(InputError) as error:
        read(path)
    assert error.value.what == (
        f"{named}, expected a record file (unpack it: records are read one file each, plain or .gz)"
    )
