"""The result of a selection run: tables with column dictionaries, written and read back."""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, replace
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
#: The selection report's default page in a selection's folder (``stepframe report selection
#: DIR``; the workflow's stage and the demo publish it under this name too).
SELECTION_REPORT_HTML = "selection_report.html"

TABLE_FILES = {
    "selection": "selection.csv",
    "candidates": "candidates.csv",
    "confirmation": "confirmation.csv",
    "failures": "failures.csv",
}
COLUMNS_FILE = "columns.csv"
#: The columns of ``spectra.csv`` besides one per unit of the set (:data:`SCALED_COLUMN`).
SPECTRA_COLUMNS = {
    "period_s": ("s", "oscillator period"),
    "target_g": ("g", "target spectrum"),
    "mean_g": ("g", "arithmetic mean of the set's scaled spectra (the codes' average)"),
}
SCALED_COLUMN = ("g", "scaled PSA of this unit (component, or the record's pair spectrum)")
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
        correlations of the confirmation; the grouping of files into records, the target, the
        scale rule, the set's misfit, the code check and the chosen set's response at the
        chosen scale.
    spectra, motions
        The chosen set's scaled spectra and motions (written as ``spectra.csv`` and
        ``motions/``).
    """

    selection: Any
    candidates: Any
    confirmation: Any
    failures: Any
    band_rad_s: tuple[float, float]
    status: str = "ok"
    message: str = ""
    summary: dict[str, Any] = field(default_factory=dict)
    #: The chosen set's scaled spectra (``spectra.csv``: period_s, target_g, mean_g, one column
    #: per unit); None when the run has none.
    spectra: Any = None
    #: The chosen components with their samples and scale factors, written to ``motions/``
    #: (:mod:`.export`); empty for a result read back.
    motions: list[Any] = field(default_factory=list)

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
        """For people: the band and filters, how files were grouped into records, the target
        and scale rule, the chosen set (pick order, score and its rank, scale factor, what it
        does to the frame), the response counts and warnings, the code check, and the
        confirmation's rank correlation and medians when it ran."""
        from stepframe.pipeline.selection.ranking import tie_line

        low, high = self.band_rad_s
        summary = self.summary
        lines = [
            f"band: {low:.3g} to {high:.3g} rad/s (T {math.tau / high:.3g} to "
            f"{math.tau / low:.3g} s); {summary.get('filter_summary', '')}",
            *self._input_lines(),
            f"chosen by {summary.get('rank_by')} ({self.status}: {self.message}):",
            *self._prefilter_lines(),
            *self._chosen_lines(),
            *([tie] if (tie := tie_line(summary)) else []),
            *self._outcome_lines(),
        ]
        return lines + self._confirmation_lines()

    def _prefilter_lines(self) -> list[str]:
        """The prefilter, when one left candidates unsimulated (the summary did not say so: a
        budget of 0.1 CPU s ranked the best 91 by n_p_band and left out five of the exact
        ranking's top ten, each pick still "rank k of 100")."""
        ranking = self.summary.get("ranking") or {}
        if ranking.get("method") != "prefilter":
            return []
        return [
            f"  prefiltered: {ranking.get('text', '')}; the others were not simulated and rank "
            "after them"
        ]

    def _confirmation_lines(self) -> list[str]:
        """The confirmation at its equal intensity (named, with the ranking's when that was
        another), the run's ranking's ρ there, and the selected against the controls there and
        at the chosen scale."""
        summary = self.summary
        medians = summary.get("medians") or {}
        from stepframe.pipeline.selection.confirm import MIN_PAIRS

        rhos = [
            f"  Spearman({entry['score']}, {entry['response']}) = "
            f"{_number(entry.get('spearman'), '.2f')} [{_number(entry.get('low'), '.2f')}, "
            f"{_number(entry.get('high'), '.2f')}], n = {entry['n']}"
            if isinstance(entry.get("spearman"), int | float) and math.isfinite(entry["spearman"])
            else f"  Spearman({entry['score']}, {entry['response']}) undefined ("
            + (
                f"fewer than {MIN_PAIRS} candidates"
                if entry["n"] < MIN_PAIRS
                else "the same value for every candidate, in the score or the response"
            )
            + f"), n = {entry['n']}"
            for entry in summary.get("correlations", [])
            if entry["score"] == summary.get("rank_by")
        ]
        if not medians and not rhos:
            if "options" in summary and not summary["options"].get("confirm"):
                return ["confirmation by simulation: not run (--confirm runs it)"]
            return []
        lines = [f"confirmation, every candidate at {confirmation_level(summary)}:", *rhos]
        if medians:
            lines.append(
                f"  median peak |x|: the {medians['n_selected']} selected "
                f"{_peak_text(medians, 'equal_psa_t1', 'selected')}, "
                + _controls_text(medians, "equal_psa_t1")
            )
        if "chosen_scale_overturned_selected" in medians:
            from stepframe.pipeline.selection.chosen import scale_phrase

            rule = scale_phrase(str(summary.get("scale_rule") or "as recorded"))
            selected = _peak_text(medians, "chosen_scale", "selected")
            controls = _controls_text(medians, "chosen_scale")
            lines.append(
                f"confirmation at the chosen scale ({rule}): median peak |x| of the "
                f"{medians['n_selected']} selected {selected}, "
                + (controls if not medians.get("n_control") else f"of {controls}")
            )
        return lines

    def _input_lines(self) -> list[str]:
        """The grouping of files into records, warnings of the filters, the target, the scale."""
        from stepframe.pipeline.selection.grouping import grouping_line

        summary = self.summary
        lines = []
        if summary.get("grouping"):
            lines.append(grouping_line(summary["grouping"]))
        lines += [f"warning: {r['warning']}" for r in summary.get("filters", []) if "warning" in r]
        target = summary.get("target")
        if isinstance(target, dict):
            lines.append(f"target: {target.get('describe', target.get('kind'))}")
        if summary.get("scale_rule"):
            lines.append(f"scale: {summary['scale_rule']}")
        intensity = summary.get("ranking_intensity")
        if intensity is not None and not isinstance(intensity, dict):
            # a stated intensity (a table with its text) is in the message and "ranked at"
            lines.append(f"ranking intensity: {_intensity_text(intensity)}")
        return lines

    def _chosen_lines(self) -> list[str]:
        """One line per chosen component: pick order, score and its rank among the candidates,
        scale factor (clipped flagged), state at the chosen scale, P(in set) where it means
        something."""
        from stepframe.pipeline.selection.names import ranks_by_fit

        summary = self.summary
        rank_by = str(summary.get("rank_by"))
        options = summary.get("options", {})
        bootstrap = int(options.get("n_bootstrap", 0) or 0)
        meaningful = bootstrap > 0 and ranks_by_fit(rank_by)
        ranks = _score_ranks(self.candidates, rank_by)
        response = {
            (row["file"], row["component"]): row
            for row in (summary.get("chosen_response") or {}).get("rows", [])
        }
        lines = []
        for row in self.selection.itertuples():
            name = str(row.file).rsplit("/", 1)[-1]
            key = (str(row.file), str(row.component))
            place = ranks.get(key)
            rank_text = f" (rank {place[0]} of {place[1]})" if place else ""
            clipped = " clipped" if bool(getattr(row, "scale_clipped", False)) else ""
            text = (
                f"  pick {row.rank:2d}. {name} [{row.component}]  {_score_text(row, rank_by)}"
                f"{rank_text}  scale {row.scale_factor:.3g}{clipped}"
            )
            if key in response:
                state = response[key]
                text += f"  {state['state']} (peak |x| {state['peak_abs_x_m']:.3g} m)"
            if meaningful:
                text += f"  P(in set) {row.selection_probability:.2f}"
            lines.append(text)
        return lines

    def _outcome_lines(self) -> list[str]:
        """The response at the chosen scale, the set's misfit, the code check, warnings."""
        summary = self.summary
        lines = []
        response = summary.get("chosen_response") or {}
        if response.get("n"):
            from stepframe.pipeline.selection.chosen import scale_phrase

            # Which scale, said on the line: the ranking's line above is at another intensity.
            rule = scale_phrase(str(summary.get("scale_rule") or "as recorded"))
            lines.append(
                f"at the chosen scale ({rule}): of {response['n']} components, "
                f"{response['linear']} stay linear, {response['steps']} step, "
                f"{response['overturns']} overturn the frame (x_c = {response['x_c_m']:.3g} m)"
            )
        if summary.get("set_misfit") is not None:
            lines.append(
                f"set misfit: {summary['set_misfit']:.3g} (RMS of ln(geometric mean / target) "
                "over the misfit periods)"
            )
        check = summary.get("code_check")
        if isinstance(check, dict):
            if "line" in check:
                lines.append(f"code check: {check['line']}")
                lines += [f"  note: {note}" for note in check.get("notes", [])]
            elif "not_run" in check:
                lines.append(f"code check: not run ({check['not_run']})")
        lines += [f"warning: {text}" for text in summary.get("warnings", [])]
        return lines

    def _write_chosen(self, folder: Path, paths: dict[str, Path]) -> list[Any]:
        """``spectra.csv`` and ``motions/`` (when the run has them); their column
        dictionaries."""
        import shutil

        from stepframe.core.io import atomic_write
        from stepframe.pipeline.selection.export import (
            MANIFEST_COLUMNS,
            MOTIONS_FOLDER,
            export_motions,
        )

        written = []
        if self.spectra is not None:
            path = folder / SPECTRA_FILE
            with atomic_write(path) as handle:
                self.spectra.to_csv(handle, index=False, float_format="%.8g")
            paths["spectra"] = path
            names = [c for c in self.spectra.columns if c not in SPECTRA_COLUMNS]
            written.append(
                _framed("spectra", {**SPECTRA_COLUMNS, **dict.fromkeys(names, SCALED_COLUMN)})
            )
        elif (folder / SPECTRA_FILE).exists():  # an earlier run's, not this one's
            (folder / SPECTRA_FILE).unlink()
        if self.motions:
            paths.update(export_motions(self.motions, folder))
            written.append(_framed("manifest", MANIFEST_COLUMNS))
        elif (folder / MOTIONS_FOLDER).is_dir():
            shutil.rmtree(folder / MOTIONS_FOLDER)
        return written

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
            spectra=None
            if self.spectra is None
            else self.spectra.rename(columns=lambda name: str(name).replace(prefix, "")),
            motions=[replace(m, file=m.file.removeprefix(prefix)) for m in self.motions],
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
        """Write the tables, their column dictionaries (``columns.csv``) and ``selection.json``;
        what an earlier run wrote into the folder and this one does not (its motions, spectra
        and the selection report made of it) is removed, so the folder is this run's alone.

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
        _remove_stale_report(folder)
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
        dictionaries += self._write_chosen(folder, paths)
        path = folder / COLUMNS_FILE
        with atomic_write(path) as handle:
            pd.concat(dictionaries, ignore_index=True).to_csv(handle, index=False)
        paths["columns"] = path
        summary = self.to_dict()
        summary[FILES_KEY] = written_files(folder, paths.values())
        path = folder / SUMMARY_FILE
        with atomic_write(path) as handle:
            json.dump(summary, handle, indent=2, allow_nan=False)
            handle.write("\n")
        paths["summary"] = path
        return paths


SPECTRA_FILE = "spectra.csv"
#: ``selection.json``'s record of the files the run wrote: path in the folder → sha256, so a
#: report made from the folder later is made of this run's files, not of hand-edited ones
#: (:func:`stepframe.pipeline.selection.report_folder.read_selection_folder` checks them).
FILES_KEY = "files_sha256"


def written_files(folder: Path, paths: Any) -> dict[str, str]:
    """Each written file's path relative to ``folder`` (POSIX) → its sha256 (of the motions,
    their manifest)."""
    from stepframe.core.io import file_sha256

    return {Path(path).relative_to(folder).as_posix(): file_sha256(path) for path in sorted(paths)}


def written_lines(folder: Path, label: str = "outputs") -> list[str]:
    """The lines naming what a selection's output folder holds, read from the folder.

    ``label`` starts the first line (``select`` says ``outputs``, the demo ``tables``); the
    files are those :meth:`SelectionResult.write` writes, in its order, each named only when
    it is there (``spectra.csv`` and ``motions/`` come only with a run that has them), so
    the text names what the run wrote and nothing else.
    """
    from stepframe.pipeline.selection.export import MANIFEST_FILE, MOTIONS_FOLDER

    names = [*TABLE_FILES.values(), COLUMNS_FILE, SPECTRA_FILE, SUMMARY_FILE]
    present = [name for name in names if (folder / name).is_file()]
    lines = [f"{label}: {folder}/ ({', '.join(present)})"]
    if (folder / MOTIONS_FOLDER / MANIFEST_FILE).is_file():
        lines.append(
            f"the chosen motions, scaled: {folder / MOTIONS_FOLDER}/ ({MANIFEST_FILE}, "
            "one AT2 and one one-column text file per component)"
        )
    return lines


def _framed(name: str, columns: dict[str, tuple[str, str]]) -> Any:
    table = column_dictionary(columns)
    table.insert(0, "table", name)
    return table


def confirmation_level(summary: dict[str, Any]) -> str:
    """The confirmation's equal intensity for people, "equal PSA(T_1) = 0.681 g, 1 × the onset
    of stepping", followed by the ranking's intensity when the ranking was at another (the
    summary and the report; a folder of an earlier run, without the level: "equal PSA(T_1)").
    """
    from stepframe.pipeline.selection.intensity import equal_psa_level, intensity_level

    medians = summary.get("medians") or {}
    ratio, psa = medians.get("equal_psa_t1_onset_ratio"), medians.get("equal_psa_t1_g")
    if ratio is None or psa is None:
        return "equal PSA(T_1)"
    level = equal_psa_level(ratio, psa / ratio)
    intensity = summary.get("ranking_intensity")
    if not isinstance(intensity, dict):
        return f"equal {level}"
    if intensity.get("kind") == "equal-psa-t1" and intensity.get("onset_ratio") == ratio:
        return f"equal {level} (the ranking's own intensity)"
    return f"equal {level} (ranked at {intensity_level(str(intensity.get('text', '')))})"


def _peak_text(medians: dict[str, Any], case: str, group: str) -> str:
    """ "0.191 m (2 overturn)": a group's median peak |x| and its overturned count in one case
    of the confirmation's medians (``equal_psa_t1`` or ``chosen_scale``)."""
    peak = _number(medians.get(f"{case}_peak_x_m_{group}"), ".3g")
    overturned = medians.get(f"{case}_overturned_{group}")
    return f"{peak} m" + ("" if overturned is None else f" ({overturned} overturn)")


def _controls_text(medians: dict[str, Any], case: str) -> str:
    """ "10 controls 0.191 m (3 overturn)", or, when every candidate was selected, that there
    is none (not "0 controls not run m")."""
    if not medians.get("n_control"):
        return "no controls (every candidate was selected)"
    return f"{medians['n_control']} controls {_peak_text(medians, case, 'control')}"


def _number(value: Any, spec: str) -> str:
    """A number for people: "not run" instead of NaN or None."""
    from stepframe.core.text import number_text

    return number_text(value, spec, "not run")


def _score_text(row: Any, rank_by: str) -> str:
    """A chosen row's score as the ranking orders it: for the simulated response, the lowest
    factor on the ranking scale found to overturn the frame (those come first), else the
    response [m]; any other score by its value."""
    from stepframe.pipeline.selection.names import SIMULATED_RESPONSE

    if rank_by != SIMULATED_RESPONSE:
        return f"score {row.score:.4g}"
    factor = float(getattr(row, "overturn_factor", math.nan))
    if math.isfinite(factor):
        return f"overturns from ×{factor:.3g} of the ranking scale"
    return f"response {row.score:.3g} m"


def _intensity_text(value: Any) -> str:
    """The ranking intensity as ``selection.json`` gives it (a number in g, or a table)."""
    if isinstance(value, dict):
        return ", ".join(f"{k} {v}" for k, v in value.items())
    return f"{value} g" if isinstance(value, int | float) else str(value)


def _score_ranks(candidates: Any, rank_by: str) -> dict[tuple[str, str], tuple[int, int]]:
    """(file, component) → (rank of the ranking among the candidates that passed the filters,
    1 best; how many): by ``rank_score_percentile`` where the run has it (the simulated
    response orders the overturning candidates by their factor, not by the score), else by
    the score."""
    column = "rank_score_percentile" if "rank_score_percentile" in candidates.columns else rank_by
    if column not in candidates.columns or "dropped_by" not in candidates.columns:
        return {}
    passing = candidates[candidates["dropped_by"].astype(str) == ""]
    score = passing[column].astype(float)
    order = score.rank(ascending=False, method="min")
    return {
        (str(f), str(c)): (int(r), len(passing))
        for f, c, r in zip(passing["file"], passing["component"], order, strict=True)
        if r == r  # not NaN
    }


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
    spectra_path = folder / SPECTRA_FILE
    spectra = pd.read_csv(spectra_path) if spectra_path.is_file() else None
    band = summary.pop("band_rad_s")
    status = summary.pop("status")
    message = summary.pop("message")
    # the folder's record of its files, not the result's (a write records them again)
    for key in ("selected", "n_candidates", "n_filtered", "n_failures", FILES_KEY):
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
        spectra,
    )


def _remove_stale_report(folder: Path) -> None:
    """Remove the selection report an earlier run's folder holds (``stepframe report selection
    DIR``'s default page and its numbers): it described that run ("Selected 2 of 100" beside a
    selection of 3); `stepframe report selection DIR` makes it again for this one."""
    import shutil

    from stepframe.pipeline.reports.document import data_folder_of

    page = folder / SELECTION_REPORT_HTML
    numbers = data_folder_of(page)
    if page.is_file():
        page.unlink()
    if numbers.is_dir():
        shutil.rmtree(numbers)
