"""Store keys made from a stage's prefix are the keys as first defined, byte for byte, and the
store's table of a stage reads exactly the rows of the keys asked.

A key that changed would make a workspace recompute everything (43,000 items, 17 min), so the
fast form (:class:`~stepframe.pipeline.engine.store.KeyPrefix`, the parameters hashed once per
stage) is checked against the definition written out here independently, and against keys the
former code produced (literal values).
"""

from __future__ import annotations

import hashlib
import json
import math
import pickle
from pathlib import Path
from typing import Any

import pandas as pd
import pytest

from stepframe.core.results import Failure
from stepframe.pipeline.engine.store import KEY_COLUMN, KeyPrefix, Store, make_key


def _former_key(stage: str, version: int, parameters: dict[str, Any], *inputs: str) -> str:
    """The key's first definition: sha256 of the canonical JSON of stage, version and
    parameters, then each input after a zero byte."""
    text = json.dumps(
        {"stage": stage, "version": version, "parameters": parameters},
        sort_keys=True,
        separators=(",", ":"),
        allow_nan=True,
        default=str,
    )
    return hashlib.sha256(
        text.encode() + b"".join(b"\0" + item.encode() for item in inputs)
    ).hexdigest()


CASES: list[tuple[str, int, dict[str, Any], tuple[str, ...]]] = [
    ("inventory", 1, {}, ("a" * 64,)),
    (
        "features",
        3,
        {"frequency": "zero-crossing", "band": [0.1, 25.0], "x": None},
        ("k", "1", "None"),
    ),
    ("responses", 3, {"spec": "é", "nested": {"b": 2, "a": math.nan}}, ("k" * 64,)),
    ("site", 1, {"path": Path("/records/a b"), "n": 10}, ()),
    ("measures", 2, {"zeta": 0.05}, ("k1", "", "k3", "0")),
]


@pytest.mark.parametrize(("stage", "version", "parameters", "inputs"), CASES)
def test_prefix_keys_are_the_former_keys(
    stage: str, version: int, parameters: dict[str, Any], inputs: tuple[str, ...]
) -> None:
    prefix = KeyPrefix(stage, version, parameters)
    expected = _former_key(stage, version, parameters, *inputs)
    assert prefix.key(*inputs) == expected
    assert make_key(stage, version, parameters, *inputs) == expected
    # the prefix's state is copied, never advanced: the same prefix gives the same key again
    assert prefix.key("other") == _former_key(stage, version, parameters, "other")
    assert prefix.key(*inputs) == expected
    # a prefix goes to the workers inside a stage's expand arguments
    assert pickle.loads(pickle.dumps(prefix)).key(*inputs) == expected


def test_keys_the_former_code_made() -> None:
    """Values printed by make_key at main 6345b31 (before the prefix)."""
    params = {"frequency": "zero-crossing", "band": [0.1, 25.0], "x": None}
    assert KeyPrefix("features", 3, params).key("a" * 64, "1", "None") == (
        "25760fc95db3556ded23dc409ed4156c50f25d13525324d58b70477d48e5ea76"
    )
    assert KeyPrefix("responses", 3, {"spec": "é"}).key("k") == (
        "db71b0fd6bf0e18770c7284e805350d43d89ef175cb180cedc16b8eb9e44ebe7"
    )
    assert make_key("site", 1, {}) == (
        "c7cf0110a9fc55751f4b10595762b275061bfd186d891a84acb342038ac7f9e1"
    )


def _rows(pairs: list[tuple[str, float]]) -> pd.DataFrame:
    return pd.DataFrame({KEY_COLUMN: [k for k, _ in pairs], "value": [v for _, v in pairs]})


def _read(store: Store, keys: list[str]) -> list[tuple[str, float]]:
    table = store.table("s", keys)
    if table.empty:  # no row: the table has the key column only
        return []
    return sorted(zip(table[KEY_COLUMN].tolist(), table["value"].tolist(), strict=True))


def test_table_reads_the_rows_of_the_keys_asked(tmp_path: Path) -> None:
    store = Store(tmp_path / "store")
    store.prepare()
    # one segment; a key with two rows, one of them an exact repeat (a store written before
    # one-content-one-item held such copies): read once
    store.add_rows("s", _rows([("a", 1.0), ("a", 2.0), ("a", 2.0), ("b", 3.0), ("c", 4.0)]), [])
    every = [("a", 1.0), ("a", 2.0), ("b", 3.0), ("c", 4.0)]
    assert _read(store, ["a", "b", "c"]) == every
    assert _read(store, ["b"]) == [("b", 3.0)]
    # a later segment writes b again (--force) and fails c: the first segment gives a only
    store.add_rows("s", _rows([("b", 5.0)]), [("c", Failure("c.AT2", "s", "ValueError", "x"))])
    assert _read(store, ["a", "b", "c"]) == [("a", 1.0), ("a", 2.0), ("b", 5.0)]
    # the same from a new process's view of the store (segments read back and checked)
    again = Store(tmp_path / "store")
    assert _read(again, ["a", "b", "c"]) == [("a", 1.0), ("a", 2.0), ("b", 5.0)]
    assert _read(again, ["c", "d"]) == []
    # a segment of distinct keys, all asked: every row, none dropped
    store.add_rows("s", _rows([("d", 6.0), ("e", 6.0)]), [])
    assert _read(store, ["d", "e"]) == [("d", 6.0), ("e", 6.0)]
