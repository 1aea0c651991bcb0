"""The result of a selection run: tables with column dictionaries, written and read back."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

from stepframe.core.jsonable import to_jsonable
from stepframe.core.results import (
    STATUSES,
    check_status,
    get_column_dictionary,
    set_column_dictionary,
)

#: Output files of :meth:`SelectionResult.write` (table name → file name).
TABLE_FILES = {
    "selection": "selection.csv",
    "candidates": "candidates.csv",
    "confirmation": "confirmation.csv",
    "failures": "failures.csv",
}
COLUMNS_FILE = "columns.csv"
SUMMARY_FILE = "selection.json"


def column_dictionary(columns: dict[str, tuple[str, str]]) -> Any:
    """A column dictionary table (column, unit, meaning)."""
    import pandas as pd

    return pd.DataFrame(
        [(name, unit, meaning) for name, (unit, meaning) in columns.items()],
        columns=["column", "unit", "meaning"],
    )


@dataclass
class SelectionResult:
    """What :func:`stepframe.pipeline.selection.select_records` returns.

    Attributes
    ----------
    selection
        The chosen components, best first (rank, file, component, score, scale factor,
        probability of staying in the set, every score).
    candidates
        Every row of the features table with every score and ``dropped_by`` (the filter that
        dropped it, empty when it passed).
    confirmation
        Simulated response (empty without confirmation): one row per (component, case).
    failures
        Components that failed in a stage (``item, stage, error_type, message``).
    band_rad_s
        (ω(A_max), ω_1) [rad/s].
    status, message
        A status of :data:`stepframe.core.results.STATUSES` and one line about it.
    summary
        Everything else, JSON-ready: the band, the filters' reports, the options, the
        correlations of the confirmation.
    """

    selection: Any
    candidates: Any
    confirmation: Any
    failures: Any
    band_rad_s: tuple[float, float]
    status: str = "ok"
    message: str = ""
    summary: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        check_status(self.status)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: the ``--json`` output of ``stepframe select``."""
        selected = self.selection.to_dict(orient="records")
        data: dict[str, Any] = to_jsonable(
            {
                "status": self.status,
                "message": self.message,
                "selected": selected,
                "n_candidates": len(self.candidates),
                "n_filtered": int((self.candidates["dropped_by"] != "").sum())
                if "dropped_by" in self.candidates
                else 0,
                "n_failures": len(self.failures),
                "band_rad_s": list(self.band_rad_s),
                **self.summary,
            }
        )
        return data

    def summary_lines(self) -> list[str]:
        """For people: the band, the chosen components, the confirmation's rank correlation
        (Spearman with its bootstrap interval) and the selected-vs-control medians."""
        low, high = self.band_rad_s
        lines = [
            f"band: {low:.3g} to {high:.3g} rad/s (T {math.tau / high:.3g} to "
            f"{math.tau / low:.3g} s); {self.summary.get('filter_summary', '')}",
            f"chosen by {self.summary.get('rank_by')} ({self.status}: {self.message}):",
        ]
        for row in self.selection.itertuples():
            name = str(row.file).rsplit("/", 1)[-1]
            lines.append(
                f"  {row.rank:2d}. {name} [{row.component}]  score {row.score:.4g}  "
                f"scale {row.scale_factor:.3g}  P(in set) {row.selection_probability:.2f}"
            )
        for entry in self.summary.get("correlations", []):
            if entry["score"] == self.summary.get("rank_by"):
                lines.append(
                    f"confirmation: Spearman({entry['score']}, {entry['response']}) = "
                    f"{entry['spearman']:.2f} [{entry['low']:.2f}, {entry['high']:.2f}], "
                    f"n = {entry['n']}"
                )
        medians = self.summary.get("medians") or {}
        if medians:
            lines.append(
                "median peak |x| at equal PSA(T_1): selected "
                f"{medians['equal_psa_t1_peak_x_m_selected']:.3g} m, controls "
                f"{medians['equal_psa_t1_peak_x_m_control']:.3g} m"
            )
        return lines

    def with_record_identity(
        self, root: str | PathLike[str], hashes: dict[str, str], records: dict[str, Any]
    ) -> SelectionResult:
        """The result naming its records as a later step re-reads them from anywhere.

        Every path under ``root`` (the records folder, absolute) in the tables and the summary
        becomes relative to it, so the result is the same bytes wherever the workspace is;
        ``content_sha256`` (from ``hashes``: file relative to ``root`` → sha256 of its bytes)
        follows each ``file`` column, so that a changed file is found out; and the summary gets
        ``records``: where the folder is (``folder``, relative to the selection's folder or a
        folder above it; or ``example``) and the record options the files were read with.
        """
        prefix = f"{Path(root).as_posix().rstrip('/')}/"
        tables = {
            name: _with_hashes(_relative(table, prefix), hashes)
            for name, table in self.tables().items()
        }
        summary = json.loads(json.dumps(self.summary, default=str).replace(prefix, ""))
        return SelectionResult(
            tables["selection"],
            tables["candidates"],
            tables["confirmation"],
            tables["failures"],
            self.band_rad_s,
            self.status,
            self.message.replace(prefix, ""),
            {**summary, "records": records},
        )

    def tables(self) -> dict[str, Any]:
        """The four tables by name."""
        return {
            "selection": self.selection,
            "candidates": self.candidates,
            "confirmation": self.confirmation,
            "failures": self.failures,
        }

    def write(self, outdir: str | PathLike[str]) -> dict[str, Path]:
        """Write the tables, their column dictionaries (``columns.csv``) and ``selection.json``.

        Every file is written atomically (:func:`stepframe.core.io.atomic_write`); the JSON
        summary is written last, so a folder with a ``selection.json`` is complete.

        Returns
        -------
        dict
            Output name → path.
        """
        import pandas as pd

        from stepframe.core.io import atomic_write

        folder = Path(outdir)
        folder.mkdir(parents=True, exist_ok=True)
        paths: dict[str, Path] = {}
        dictionaries = []
        for name, table in self.tables().items():
            path = folder / TABLE_FILES[name]
            with atomic_write(path) as handle:
                table.to_csv(handle, index=False)
            paths[name] = path
            columns = get_column_dictionary(table)
            if columns is not None:
                framed = columns.copy()
                framed.insert(0, "table", name)
                dictionaries.append(framed)
        path = folder / COLUMNS_FILE
        with atomic_write(path) as handle:
            pd.concat(dictionaries, ignore_index=True).to_csv(handle, index=False)
        paths["columns"] = path
        path = folder / SUMMARY_FILE
        with atomic_write(path) as handle:
            json.dump(self.to_dict(), handle, indent=2, allow_nan=False)
            handle.write("\n")
        paths["summary"] = path
        return paths


def _relative(table: Any, prefix: str) -> Any:
    """``table`` with ``prefix`` (a folder's absolute path and ``/``) taken off its text cells."""
    from pandas.api.types import is_object_dtype, is_string_dtype

    out = table.copy()
    for column in out.columns:
        if is_object_dtype(out[column]) or is_string_dtype(out[column]):
            out[column] = [
                value.replace(prefix, "") if isinstance(value, str) else value
                for value in out[column]
            ]
    dictionary = get_column_dictionary(table)
    if dictionary is not None:
        set_column_dictionary(out, dictionary)
    return out


def _with_hashes(table: Any, hashes: dict[str, str]) -> Any:
    """``table`` with ``content_sha256`` after its ``file`` column (if it has one)."""
    import pandas as pd

    if "file" not in table.columns or "content_sha256" in table.columns:
        return table
    out = table.copy()
    out.insert(
        list(out.columns).index("file") + 1,
        "content_sha256",
        [hashes.get(str(file), "") for file in out["file"]],
    )
    dictionary = get_column_dictionary(table)
    if dictionary is not None:
        row = pd.DataFrame(
            [("content_sha256", "", "sha256 of the record file's bytes (its identity)")],
            columns=["column", "unit", "meaning"],
        )
        names = list(dictionary["column"])
        at = names.index("file") + 1 if "file" in names else len(names)
        dictionary = pd.concat([dictionary.iloc[:at], row, dictionary.iloc[at:]])
        set_column_dictionary(out, dictionary.reset_index(drop=True))
    return out


def read_selection(outdir: str | PathLike[str]) -> SelectionResult:
    """Read back what :meth:`SelectionResult.write` wrote (column dictionaries in attrs)."""
    import pandas as pd

    from stepframe.errors import InputError

    folder = Path(outdir)
    summary_path = folder / SUMMARY_FILE
    if not summary_path.is_file():
        raise InputError(
            f"no {SUMMARY_FILE}, expected a folder written by stepframe select", folder
        )
    summary = json.loads(summary_path.read_text(encoding="utf-8"))
    dictionaries = pd.read_csv(folder / COLUMNS_FILE, keep_default_na=False)
    tables: dict[str, Any] = {}
    for name, file in TABLE_FILES.items():
        text_columns = {
            "file": str,
            "content_sha256": str,
            "component": str,
            "station": str,
            "dropped_by": str,
        }
        try:
            table = pd.read_csv(folder / file, dtype=text_columns, keep_default_na=True)
        except pd.errors.EmptyDataError:
            table = pd.DataFrame()
        for column in ("dropped_by", "flags", "implausible_reason", "message"):
            if column in table.columns:
                table[column] = table[column].astype(object).fillna("").astype(str)
        mine = dictionaries[dictionaries["table"] == name].drop(columns="table")
        set_column_dictionary(table, mine.reset_index(drop=True))
        tables[name] = table
    band = summary.pop("band_rad_s")
    status = summary.pop("status")
    message = summary.pop("message")
    for key in ("selected", "n_candidates", "n_filtered", "n_failures"):
        summary.pop(key, None)
    if status not in STATUSES:
        raise InputError(f"status {status!r}, expected one of {sorted(STATUSES)}", summary_path)
    return SelectionResult(
        tables["selection"],
        tables["candidates"],
        tables["confirmation"],
        tables["failures"],
        (float(band[0]), float(band[1])),
        status,
        message,
        summary,
    )
