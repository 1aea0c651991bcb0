"""The result contract: one status vocabulary and one failure-table layout.

Every stage result says how it went with a :data:`Status` from :data:`STATUSES` and a one-line
``message``; a result that is a number, table or array carries it beside the data. A batch never
stops for one bad item: each item that fails becomes a :class:`Failure` (item, stage, error type,
message), and a batch's failures are one table, :func:`failures_table`, written next to the output
it belongs to under the name :func:`failures_path` gives.
"""

from __future__ import annotations

import traceback
from dataclasses import asdict, dataclass
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from stepframe.errors import InputError

if TYPE_CHECKING:
    import pandas as pd

#: Every status a result can have, with its meaning. ``ok`` is success; the others name what went
#: wrong. Add a state here (with its meaning) rather than inventing a local string.
STATUSES: dict[str, str] = {
    "ok": "computed as asked",
    "degraded": "computed, but a flag says part of the result is less reliable (see message)",
    "lower_bound": "the run stopped early; the value is a lower bound of the true one",
    "not_converged": "an iteration or solver did not reach its tolerance",
    "too_many_events": "the event limit of a simulation was reached before the record ended",
    "nonfinite": "a non-finite value appeared; the result is not usable",
    "failed": "no result (see message)",
}

Status = Literal[
    "ok", "degraded", "lower_bound", "not_converged", "too_many_events", "nonfinite", "failed"
]

#: Column dictionary of every failure table: column → meaning.
FAILURE_COLUMNS: dict[str, str] = {
    "item": "the item that failed (file, file [channel], or record name)",
    "stage": "the stage it failed in (read, features, fit, simulate, ...)",
    "error_type": "the kind of error (InputError, FormatError, ValueError, ...)",
    "message": "what went wrong, one line",
}


@dataclass(frozen=True)
class Failure:
    """One item a batch could not process.

    Parameters
    ----------
    item
        The item's name (a file, ``file [channel]``, a record name).
    stage
        The stage it failed in.
    error_type
        The exception class name.
    message
        One line saying what went wrong (an :class:`~stepframe.errors.InputError` gives its
        ``file:line: what, expected what``).
    """

    item: str
    stage: str
    error_type: str
    message: str

    @classmethod
    def from_exception(cls, item: str, stage: str, error: BaseException) -> Failure:
        """The failure record of ``error`` raised while processing ``item`` in ``stage``."""
        if isinstance(error, InputError):
            message = error.one_line()
        else:
            message = str(error).replace("\n", " ").strip()
            if not message:
                # An exception without text: name where it came from so it can be found.
                frames = traceback.extract_tb(error.__traceback__)
                message = f"raised at {frames[-1].filename}:{frames[-1].lineno}" if frames else ""
        return cls(item, stage, type(error).__name__, message)

    def to_dict(self) -> dict[str, str]:
        """The failure as a table row."""
        return asdict(self)


def failures_table(failures: list[Failure] | tuple[Failure, ...]) -> pd.DataFrame:
    """The failures as a DataFrame with columns :data:`FAILURE_COLUMNS` (empty if none)."""
    import pandas as pd

    table = pd.DataFrame([f.to_dict() for f in failures], columns=list(FAILURE_COLUMNS))
    return set_column_dictionary(
        table,
        pd.DataFrame(
            [(name, "", meaning) for name, meaning in FAILURE_COLUMNS.items()],
            columns=["column", "unit", "meaning"],
        ),
    )


def set_column_dictionary(table: pd.DataFrame, dictionary: pd.DataFrame) -> pd.DataFrame:
    """Attach a column dictionary (``column``, ``unit``, ``meaning`` rows) to ``table``.

    It is kept in ``table.attrs["column_dictionary"]`` as plain lists per field, not as a
    DataFrame: pandas compares ``attrs`` when it concatenates or merges tables, and a DataFrame
    there makes ``pd.concat`` and ``merge`` raise ("truth value of a DataFrame is ambiguous").
    Tables with equal dictionaries keep theirs through a concatenation.

    Returns
    -------
    pandas.DataFrame
        ``table`` itself.
    """
    table.attrs["column_dictionary"] = {
        field: [str(value) for value in dictionary[field]]
        for field in ("column", "unit", "meaning")
    }
    return table


def get_column_dictionary(table: pd.DataFrame) -> pd.DataFrame | None:
    """The column dictionary attached by :func:`set_column_dictionary` as a DataFrame, or None."""
    import pandas as pd

    given = table.attrs.get("column_dictionary")
    return None if given is None else pd.DataFrame(given, columns=["column", "unit", "meaning"])


def failures_path(output: str | PathLike[str]) -> Path:
    """Where the failures of an output go: ``X.failures.csv`` beside ``X.csv``, or
    ``failures.csv`` inside an output folder.

    Parameters
    ----------
    output
        The output file (``catalog.csv``) or output folder (``selection/``).
    """
    target = Path(output)
    if target.suffix == "" or target.is_dir():
        return target / "failures.csv"
    return target.with_name(f"{target.stem}.failures.csv")


def write_failures(failures: pd.DataFrame, output: str | PathLike[str]) -> Path:
    """Write a batch's :func:`failures_table` beside its output (:func:`failures_path`),
    atomically, its text cells spreadsheet-safe; the path written."""
    from stepframe.core.io import CSV_FLOAT_FORMAT, atomic_write
    from stepframe.core.text import spreadsheet_safe

    target = failures_path(output)
    with atomic_write(target) as stream:
        spreadsheet_safe(failures).to_csv(stream, index=False, float_format=CSV_FLOAT_FORMAT)
    return target


def no_usable_record(
    failures: pd.DataFrame, folder: str | PathLike[str] | None, output: str | PathLike[str]
) -> InputError:
    """The error of a batch over a folder that gave no usable record (the project's rule: an
    error, one line, exit 2), after writing its failures, if any, to :func:`failures_path`.

    An empty folder is "no record files"; one whose every file failed names the first failure
    and where all of them were written (nothing else is written: no empty table), and an
    earlier run's table and column dictionary beside them are removed: they would read as this
    run's result next to its failures.

    Parameters
    ----------
    failures
        The batch's :func:`failures_table`.
    folder
        The folder (or example) read, named in the message.
    output
        The batch's output, beside which the failures go.
    """
    where = None if folder is None else Path(folder)
    if len(failures) == 0:
        return InputError("no record files in it, expected at least one record", where)
    target = write_failures(failures, output)
    _remove_earlier_table(output)
    item, message = str(failures.iloc[0]["item"]), str(failures.iloc[0]["message"])
    first = message if message.startswith(item) else f"{item}: {message}"
    return InputError(
        f"0 components read, {len(failures)} failure{'s' * (len(failures) != 1)} (the first: "
        f"{first}; all in {target}), "
        "expected at least one record",
        where,
    )


def _remove_earlier_table(output: str | PathLike[str]) -> None:
    """Remove the table ``output`` and its column dictionary if an earlier run wrote them (an
    output folder is left alone: its results are the stage's to replace)."""
    from stepframe.core.io import columns_path

    table = Path(output)
    if table.suffix == "" or table.is_dir():
        return
    for path in (table, columns_path(table)):
        path.unlink(missing_ok=True)


def check_status(status: str) -> Status:
    """``status`` if it is in :data:`STATUSES`; ValueError otherwise (a programming error)."""
    if status not in STATUSES:
        raise ValueError(f"unknown status {status!r}, expected one of {sorted(STATUSES)}")
    return status  # type: ignore[return-value]  # checked against the vocabulary just above


def result_dict(status: str, message: str = "", **fields: Any) -> dict[str, Any]:
    """A result's dictionary form: ``status``, ``message`` and its fields."""
    return {"status": check_status(status), "message": message, **fields}
