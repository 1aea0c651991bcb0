"""Tables and datasets on disk, each read back equal to what was written.

A stage's table is a ``pandas.DataFrame`` carrying a column dictionary (``column``, ``unit``,
``meaning``; :func:`stepframe.core.results.get_column_dictionary`). :func:`write_table` writes
the table to ``X.csv`` and the dictionary, with each column's dtype, to ``X.columns.csv``
(both atomically); :func:`read_table` uses the dtypes to give back a table equal to the one
written (text columns stay text, an empty text cell stays ``""``, numbers keep NaN).
:func:`write_dataset` and :func:`read_dataset` do the same for an ``xarray.Dataset`` (NetCDF 4
through h5netcdf).
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

from stepframe.core.io import CSV_FLOAT_FORMAT, atomic_write, columns_path
from stepframe.core.results import get_column_dictionary, set_column_dictionary
from stepframe.errors import InputError

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

#: Columns of a column dictionary as written (``dtype`` is added on writing).
DICTIONARY_COLUMNS = ("column", "unit", "meaning")


def column_dictionary(table: pd.DataFrame) -> pd.DataFrame:
    """The table's column dictionary (``column``, ``unit``, ``meaning``, ``dtype``).

    Columns the attached dictionary does not describe get an empty unit and meaning.
    """
    import pandas as pd

    given = get_column_dictionary(table)
    known: dict[str, tuple[str, str]] = {}
    if given is not None:
        for row in given.itertuples(index=False):
            known[str(row.column)] = (str(row.unit), str(row.meaning))
    return pd.DataFrame(
        [(name, *known.get(str(name), ("", "")), str(table[name].dtype)) for name in table.columns],
        columns=[*DICTIONARY_COLUMNS, "dtype"],
    )


def write_table(table: pd.DataFrame, path: str | PathLike[str]) -> tuple[Path, Path]:
    """Write ``table`` to ``path`` (CSV) and its column dictionary beside it, atomically.

    Returns
    -------
    (Path, Path)
        The table and the column dictionary (``X.columns.csv``).
    """
    target = Path(path)
    dictionary = column_dictionary(table)
    with atomic_write(target) as out:
        table.to_csv(out, index=False, float_format=CSV_FLOAT_FORMAT)
    with atomic_write(columns_path(target)) as out:
        dictionary.to_csv(out, index=False)
    return target, columns_path(target)


def read_table(path: str | PathLike[str]) -> pd.DataFrame:
    """A table written by :func:`write_table`, with its dtypes and column dictionary.

    Raises
    ------
    InputError
        The table or its column dictionary is missing or unreadable.
    """
    import pandas as pd

    target = Path(path)
    dictionary_file = columns_path(target)
    for needed in (target, dictionary_file):
        if not needed.is_file():
            raise InputError("no such file, expected a table and its .columns.csv", needed)
    dictionary = pd.read_csv(dictionary_file, dtype=str, keep_default_na=False)
    dtypes = dict(zip(dictionary["column"], dictionary["dtype"], strict=True))
    text = [name for name, dtype in dtypes.items() if dtype in ("object", "str", "string")]
    numeric = [name for name in dtypes if name not in text]
    table = pd.read_csv(
        target,
        dtype=dict.fromkeys(text, str),
        keep_default_na=False,
        na_values={name: ["", "NaN", "nan"] for name in numeric},
    )
    if list(table.columns) != list(dtypes):
        raise InputError(
            f"columns {list(table.columns)}, expected those of {dictionary_file.name}", target
        )
    for name, dtype in dtypes.items():
        if name not in text and str(table[name].dtype) != dtype:
            table[name] = table[name].astype(dtype)
    set_column_dictionary(table, dictionary[list(DICTIONARY_COLUMNS)].reset_index(drop=True))
    return table


def write_dataset(dataset: xr.Dataset, path: str | PathLike[str]) -> Path:
    """Write ``dataset`` as NetCDF (h5netcdf), atomically; :func:`read_dataset` reads it back."""
    with atomic_write(path, "wb") as out:
        out.write(dataset.to_netcdf(engine="h5netcdf"))
    return Path(path)


def read_dataset(path: str | PathLike[str], what: str = "a NetCDF dataset") -> xr.Dataset:
    """A dataset written by :func:`write_dataset`, loaded into memory (the file is closed).

    Raises
    ------
    InputError
        The file does not exist (``what`` says what was expected).
    """
    import xarray as xr

    target = Path(path)
    if not target.is_file():
        raise InputError(f"no such file, expected {what}", target)
    with xr.open_dataset(target, engine="h5netcdf") as dataset:
        return dataset.load()


__all__ = [
    "column_dictionary",
    "columns_path",
    "read_dataset",
    "read_table",
    "write_dataset",
    "write_table",
]
