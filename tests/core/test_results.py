"""core.results: one status vocabulary, one failure layout, one failure-file naming rule."""

from __future__ import annotations

from pathlib import Path

import pytest

from stepframe.core.results import (
    FAILURE_COLUMNS,
    STATUSES,
    Failure,
    check_status,
    failures_path,
    failures_table,
    get_column_dictionary,
    result_dict,
)
from stepframe.errors import InputError


def test_failures_path_rule(tmp_path: Path) -> None:
    assert failures_path("out/catalog.csv") == Path("out/catalog.failures.csv")
    assert failures_path("features.csv") == Path("features.failures.csv")
    assert failures_path("selection") == Path("selection/failures.csv")
    folder = tmp_path / "run.d"  # a folder whose name has a suffix is still a folder
    folder.mkdir()
    assert failures_path(folder) == folder / "failures.csv"


def test_failure_from_input_error_and_from_a_bare_exception() -> None:
    error = InputError("3 columns, expected 2", "a.txt", 7)
    failure = Failure.from_exception("a.txt", "read", error)
    assert failure == Failure("a.txt", "read", "InputError", "a.txt:7: 3 columns, expected 2")
    try:
        raise ZeroDivisionError
    except ZeroDivisionError as bare:
        silent = Failure.from_exception("b.txt", "fit", bare)
    assert silent.error_type == "ZeroDivisionError"
    assert silent.message.startswith("raised at ") and "test_results.py" in silent.message


def test_failures_table_layout_even_when_empty() -> None:
    empty = failures_table([])
    assert (
        list(empty.columns) == list(FAILURE_COLUMNS) == ["item", "stage", "error_type", "message"]
    )
    assert empty.empty
    table = failures_table([Failure("x", "read", "OSError", "gone")])
    assert table.to_dict("records") == [
        {"item": "x", "stage": "read", "error_type": "OSError", "message": "gone"}
    ]
    assert list(get_column_dictionary(table)["column"]) == list(FAILURE_COLUMNS)


def test_status_vocabulary() -> None:
    assert "ok" in STATUSES and "lower_bound" in STATUSES
    assert result_dict("ok", value=1) == {"status": "ok", "message": "", "value": 1}
    with pytest.raises(ValueError, match="unknown status 'converged'"):
        check_status("converged")


def test_tables_with_column_dictionaries_concatenate_and_merge() -> None:
    """pandas compares attrs on concat and merge; a DataFrame kept there made both raise."""
    import pandas as pd

    from stepframe.core.results import set_column_dictionary

    dictionary = pd.DataFrame({"column": ["x_m"], "unit": ["m"], "meaning": ["peak"]})
    a = set_column_dictionary(pd.DataFrame({"x_m": [1.0]}), dictionary)
    b = set_column_dictionary(pd.DataFrame({"x_m": [2.0]}), dictionary)
    both = pd.concat([a, b], ignore_index=True)
    assert both["x_m"].tolist() == [1.0, 2.0]
    assert get_column_dictionary(both).equals(dictionary)  # equal dictionaries are kept
    assert a.merge(b, how="outer", on="x_m")["x_m"].tolist() == [1.0, 2.0]
    assert get_column_dictionary(pd.DataFrame({"y": [0]})) is None
