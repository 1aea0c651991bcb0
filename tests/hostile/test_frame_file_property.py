"""Property: any value for any key of a FRAME.toml gives a frame or a one-line InputError.

Hypothesis replaces the values of one to four keys of the frame template (the paper's Example 4)
with any TOML value (floats with NaN and infinities, integers far beyond a float, text, booleans,
arrays) or with raw bytes; :func:`read_frame_file` must return a ``PortalFrame`` whose numbers are
finite, or raise ``InputError`` with a one-line message, never another exception.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import asdict
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from stepframe.errors import InputError
from stepframe.structure.frame_file import frame_template, read_frame_file

TEMPLATE = frame_template()
KEYS = sorted(set(re.findall(r"^#?\s*([a-z_0-9]+)\s*=", TEMPLATE, re.M)) - {"name"})


def _toml(value: object) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and math.isnan(value):
        return "nan"
    if isinstance(value, float) and math.isinf(value):
        return "inf" if value > 0 else "-inf"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    if isinstance(value, str):
        return json.dumps(value)
    return str(value)


values = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(10**400), max_value=10**400),
    st.text(max_size=12),
    st.booleans(),
    st.lists(st.floats(allow_nan=False, allow_infinity=False), max_size=3),
)


@settings(max_examples=150, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])  # fmt: skip
@given(changes=st.lists(st.tuples(st.sampled_from(KEYS), values), min_size=1, max_size=4))
def test_any_values(tmp_path: Path, changes: list[tuple[str, object]]) -> None:
    text = TEMPLATE
    for key, value in changes:
        pattern = re.compile(rf"^#?\s*{re.escape(key)}\s*=.*$", re.M)
        line = f"{key} = {_toml(value)}"
        text = pattern.sub(lambda _, line=line: line, text, count=1)
    path = tmp_path / "frame.toml"
    path.write_text(text)
    try:
        frame = read_frame_file(path)
    except InputError as error:
        assert "\n" not in str(error)
        return
    numbers = [v for v in asdict(frame).values() if isinstance(v, float)]
    assert all(math.isfinite(v) for v in numbers)


@settings(max_examples=60, deadline=None, derandomize=True,
          suppress_health_check=[HealthCheck.function_scoped_fixture])  # fmt: skip
@given(content=st.binary(max_size=2000))
def test_any_bytes(tmp_path: Path, content: bytes) -> None:
    path = tmp_path / "frame.toml"
    path.write_bytes(content)
    with pytest.raises(InputError):
        read_frame_file(path)
