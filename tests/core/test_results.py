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
    assert list(table.attrs["column_dictionary"]["column"]) == list(FAILURE_COLUMNS)


def test_status_vocabulary() -> None:
    assert "ok" in STATUSES and "lower_bound" in STATUSES
    assert result_dict("ok", value=1) == {"status": "ok", "message": "", "value": 1}
    with pytest.raises(ValueError, match="unknown status 'converged'"):
        check_status("converged")
