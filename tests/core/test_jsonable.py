"""core.jsonable.to_jsonable: every value a result holds becomes a JSON value."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np

from stepframe.core.jsonable import to_jsonable


def test_numpy_tuples_paths_and_non_finite_numbers() -> None:
    """A non-finite number is left out of its object (a key documented as a number is a number
    or absent) and is null in an array (where its position means something); None stays."""
    value = {
        "a": np.float64(0.25),
        "b": np.array([1.0, np.nan, np.inf]),
        "c": (np.int64(3), -math.inf),
        1: Path("out/x.csv"),
        "d": [True, None, "s"],
        "rho": math.nan,
        "peak": np.float64(np.inf),
        "nested": [{"low": np.float64(np.nan), "n": 3}],
        "unset": None,
    }
    converted = to_jsonable(value)
    assert converted == {
        "a": 0.25,
        "b": [1.0, None, None],
        "c": [3, None],
        "1": "out/x.csv",
        "d": [True, None, "s"],
        "nested": [{"n": 3}],
        "unset": None,
    }
    assert type(converted["c"][0]) is int
    assert json.loads(json.dumps(converted, allow_nan=False)) == converted
