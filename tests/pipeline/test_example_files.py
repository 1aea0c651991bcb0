"""The embedded example catalogue written as PEER AT2 files (pipeline/catalogue/example_files)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from stepframe.pipeline.catalogue.example_files import at2_bytes, write_example_files
from stepframe.records import read
from stepframe.records.examples import fema_p695


def _value_by_value(values_g: np.ndarray, digits: int) -> list[str]:
    """The data lines as the definition writes them: each value with Python's format, five a
    line, two spaces apart."""
    words = [f"{v: .{digits}E}" for v in values_g]
    return ["  ".join(words[i : i + 5]) for i in range(0, len(words), 5)]


@settings(max_examples=200, deadline=None)
@given(
    values=arrays(
        np.float64,
        st.integers(0, 23),
        elements=st.floats(allow_nan=True, allow_infinity=True, allow_subnormal=True),
    ),
    digits=st.integers(1, 12),
)
def test_data_lines_are_each_value_formatted_by_python(values: np.ndarray, digits: int) -> None:
    text = at2_bytes(values, 0.01, "T", "E", "S", digits=digits).decode("ascii")
    header, body = text.split("\n")[:4], text.split("\n")[4:]
    assert header[3] == f"NPTS= {values.size:7d}, DT= 0.0100 SEC"
    assert body[-1] == ""  # the file ends with a newline
    assert body[:-1] == _value_by_value(values, digits)


def test_a_written_example_reads_back_as_the_embedded_record(tmp_path: Path) -> None:
    """Nine significant digits are the source files' own: the file read back is the embedded
    record bit for bit (first, a record whose length is not a multiple of five, and last)."""
    stream, _ = fema_p695()
    paths = write_example_files(tmp_path)
    assert len(paths) == len(stream) == 100
    uneven = next(k for k, trace in enumerate(stream) if trace.stats.npts % 5)
    for k in (0, uneven, len(stream) - 1):
        trace = read(paths[k])[0]
        assert trace.stats.npts == stream[k].stats.npts
        assert math.isclose(trace.stats.delta, stream[k].stats.delta)
        np.testing.assert_array_equal(trace.data, stream[k].data)


@pytest.mark.parametrize("size", [0, 1, 5, 6])
def test_line_breaks_follow_the_count(size: int) -> None:
    text = at2_bytes(np.arange(size, dtype=float), 0.005, "T", "E", "S").decode("ascii")
    lines = text.splitlines()[4:]
    assert [len(line.split()) for line in lines] == [5] * (size // 5) + (
        [size % 5] if size % 5 else []
    )
