"""Features and B-P parameters of every component of a catalogue, in parallel, failures recorded.

One row per component (:data:`COLUMNS`); a component that fails is skipped and recorded in the
failure table (:func:`stepframe.core.results.failures_table`: item, stage, error type, message)
with stage ``read``, ``features`` or ``fit``; the batch never stops for one bad item. Work goes
through :func:`stepframe.core.execution.map_items` (a process pool, or any executor), a few
items per task; rows come back in input order whatever the worker count, so runs are
reproducible.

Plausibility (column ``plausible`` and ``implausible_reason``): ω_p ≥ ω_s ≥ ω_r holds by
construction of the fit, so the checks are that the fitted frequencies lie inside the usable
band (ω_r above both the estimator's resolution floor on the record,
:attr:`stepframe.stochastic.features.RecordFeatures.usable_floor_rad_s` (2π/window_s for a fixed
window, 6π/T for ``frequency="multiwindow"`` on a record of T s), and, when known, the
record's lowest usable frequency; ω_p below half the Nyquist frequency), that ω_g falls at all
(ω_p > 1.05 ω_r), and that no flag marks a value at a bound, floor or clip
(:func:`stepframe.stochastic.flags.implausible`; every flag's meaning in
:data:`stepframe.stochastic.flags.FLAGS`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.core.execution import map_items
from stepframe.core.results import Failure, failures_table, set_column_dictionary
from stepframe.errors import InputError
from stepframe.stochastic.features import FrequencyEstimator, TimeOrigin, record_features
from stepframe.stochastic.fit import PARAMETERS, fit_model
from stepframe.stochastic.flags import implausible, meaning
from stepframe.stochastic.methods import DEFAULT_FREQUENCY_METHOD, FrequencyMethod
from stepframe.stochastic.model import AlphaReading
from stepframe.stochastic.transforms import DEFAULT_WINDOW_S, FftBackend

#: Column dictionary of the features table: name → (unit, meaning).
COLUMNS: dict[str, tuple[str, str]] = {
    "file": ("", "record file (or catalogue entry)"),
    "station": ("", "station name"),
    "component": ("", "channel / component name"),
    "dt_s": ("s", "sampling interval"),
    "duration_s": ("s", "record length"),
    "omega_p_rad_s": ("rad/s", "P-wave dominant frequency (eq. 6.10)"),
    "omega_s_rad_s": ("rad/s", "S-wave dominant frequency, ω_g at t_max"),
    "omega_r_rad_s": ("rad/s", "surface-wave dominant frequency (late asymptote)"),
    "xi_p": ("", "bandwidth ratio at the start (α_g = ω_p ξ_p)"),
    "xi_r": ("", "bandwidth ratio at the end (α_g = ω_r ξ_r)"),
    "t_max_s": ("s", "time of peak intensity after t0"),
    "t_dur_s": ("s", "end of strong motion after t0 (I_g falls to 0.1 of its peak)"),
    "t0_s": ("s", "time origin in record time (P onset used, else 0)"),
    "omega_p_rad_s_stderr": ("rad/s", "standard error of omega_p_rad_s"),
    "omega_s_rad_s_stderr": ("rad/s", "standard error of omega_s_rad_s"),
    "omega_r_rad_s_stderr": ("rad/s", "standard error of omega_r_rad_s"),
    "xi_p_stderr": ("", "standard error of xi_p"),
    "xi_r_stderr": ("", "standard error of xi_r"),
    "t_max_s_stderr": ("s", "standard error of t_max_s (envelope fit; empty if none)"),
    "fit_quality": ("", "weighted RMS relative misfit of ω_g(t) (0 is perfect)"),
    "max_intensity_m_s2": ("m/s2", "max I_g (RMS acceleration over the window)"),
    "omega_range_rad_s": ("rad/s", "ω_max - ω_min of the measured ω_g(t) in strong motion"),
    "omega_floor_rad_s": ("rad/s", "lowest ω_g the estimator resolves on the record"),
    "p_onset_used": ("", "whether t0 is a picked P onset"),
    "p_onset_s": ("s", "picked P onset in record time (empty if none)"),
    "t0_source": ("", "what t0 is: p-pick (picked P onset) or start (record start)"),
    "p_pick_snr": ("", "P pick confidence: RMS 2 s after it / RMS before (empty if none)"),
    "flags": ("", "degraded results, ';'-separated"),
    "plausible": ("", "passes the plausibility checks"),
    "implausible_reason": ("", "why not (empty when plausible)"),
}

if TYPE_CHECKING:
    import pandas as pd
    from obspy import Stream


@dataclass(frozen=True)
class Options:
    """Options of the per-component computation (picklable, passed to workers)."""

    frequency: FrequencyMethod | FrequencyEstimator = DEFAULT_FREQUENCY_METHOD
    t0: TimeOrigin = "auto"
    window_s: float = DEFAULT_WINDOW_S
    fft: FftBackend = "scipy"
    record_options: tuple[tuple[str, Any], ...] = ()
    omega_max_rad_s: float | None = None
    alpha_reading: AlphaReading = "eq-6-11"


@dataclass(frozen=True)
class Item:
    """One unit of work: a file to read, or one component already in memory."""

    file: str
    data: np.ndarray | None = None
    dt_s: float | None = None
    station: str = ""
    component: str = ""
    lowest_usable_hz: float | None = None


def plausibility(row: dict[str, Any], floor_rad_s: float, lowest_usable_hz: float | None) -> str:
    """Empty string if the fitted parameters pass the checks, else the reasons ('; ').

    ``floor_rad_s`` is the estimator's resolution floor on the record [rad/s]
    (:attr:`stepframe.stochastic.features.RecordFeatures.usable_floor_rad_s`).
    """
    reasons = []
    low = floor_rad_s
    if lowest_usable_hz is not None and math.isfinite(lowest_usable_hz):
        low = max(low, 2 * math.pi * lowest_usable_hz)
    high = 0.5 * math.pi / row["dt_s"]
    if row["omega_r_rad_s"] < low:
        reasons.append(f"omega_r {row['omega_r_rad_s']:.3g} rad/s below usable band {low:.3g}")
    if row["omega_p_rad_s"] > high:
        reasons.append(f"omega_p {row['omega_p_rad_s']:.3g} rad/s above usable band {high:.3g}")
    if row["omega_p_rad_s"] <= 1.05 * row["omega_r_rad_s"]:
        reasons.append("omega_g does not fall (omega_p ≈ omega_r)")
    # A value at a bound, floor or clip is where the search stopped, not an estimate.
    for flag in implausible(str(row["flags"]).split(";")):
        reasons.append(f"{flag} ({meaning(flag)})")
    return "; ".join(reasons)


class _StageError(Exception):
    """An error inside one stage of one component: the stage's name and the original error."""

    def __init__(self, stage: str, error: BaseException) -> None:
        super().__init__(stage)
        self.stage = stage
        self.error = error


def component_row(
    data: np.ndarray,
    dt_s: float,
    options: Options,
    lowest_usable_hz: float | None = None,
    *,
    incomplete: bool = False,
) -> dict[str, Any]:
    """Features and fit of one component, as a table row; ``incomplete``: the record was read
    cut short (``allow_short``), flagged ``record_incomplete`` in the row as in a fit of it.

    Raises
    ------
    _StageError
        Naming the stage (``features`` or ``fit``) that failed and the error it raised.
    """
    try:
        features = record_features(
            data, dt_s, frequency=options.frequency, t0=options.t0, window_s=options.window_s,
            fft=options.fft, omega_max_rad_s=options.omega_max_rad_s, incomplete=incomplete,
        )  # fmt: skip
    except Exception as error:  # a batch never stops for one item: record the unexpected too
        raise _StageError("features", error) from error
    try:
        result = fit_model(features, alpha_reading=options.alpha_reading)
    except Exception as error:  # numerical failure inside scipy: recorded, not fatal
        raise _StageError("fit", error) from error
    row: dict[str, Any] = {"dt_s": dt_s, "duration_s": dt_s * (data.size - 1)}
    fitted = result.to_dict()
    for key in (*PARAMETERS, "t_max_s", "t_dur_s", "t0_s", "fit_quality"):
        row[key] = fitted[key]
    for key in (*PARAMETERS, "t_max_s"):
        row[f"{key}_stderr"] = result.stderr.get(key, math.nan)
    strong = features.strong_motion() & np.isfinite(features.omega_g_rad_s)
    omega_strong = features.omega_g_rad_s[strong]
    row["max_intensity_m_s2"] = features.peak_intensity
    row["omega_range_rad_s"] = (
        float(omega_strong.max() - omega_strong.min()) if omega_strong.size else math.nan
    )
    row["omega_floor_rad_s"] = features.usable_floor_rad_s
    row["p_onset_used"] = features.p_onset_s is not None
    row["p_onset_s"] = features.p_onset_s if features.p_onset_s is not None else math.nan
    row["t0_source"] = features.t0_source
    row["p_pick_snr"] = math.nan if features.p_pick_snr is None else features.p_pick_snr
    row["flags"] = ";".join(result.flags)
    reason = plausibility(row, features.usable_floor_rad_s, lowest_usable_hz)
    row["plausible"] = not reason
    row["implausible_reason"] = reason
    return row


def _run_item(item: Item, options: Options) -> list[dict[str, Any] | Failure]:
    """Rows (or failures) of every component of one item."""
    if item.data is not None and item.dt_s is not None:
        components = [(item.data, item.dt_s, item.station, item.component, False)]
    else:
        from stepframe.records import read
        from stepframe.records.processing import measured_stream

        try:
            # Raw counts: fitted after the standard processing, as every command measures them.
            stream = measured_stream(read(item.file, **dict(options.record_options)))
        except Exception as error:  # readers (obspy's too) raise many types: recorded, not fatal
            return [Failure.from_exception(item.file, "read", error)]
        if len(stream) == 0:
            return [Failure(item.file, "read", "InputError", "no traces in the file")]
        components = [
            (np.asarray(tr.data, dtype=np.float64), float(tr.stats.delta), tr.stats.station,
             tr.stats.channel, bool(tr.stats.stepframe.get("incomplete")))
            for tr in stream
        ]  # fmt: skip
    out: list[dict[str, Any] | Failure] = []
    for data, dt, station, channel, incomplete in components:
        try:
            row = component_row(data, dt, options, item.lowest_usable_hz, incomplete=incomplete)
        except _StageError as failed:
            name = f"{item.file} [{channel}]" if channel else item.file
            out.append(Failure.from_exception(name, failed.stage, failed.error))
        else:
            out.append({"file": item.file, "station": station, "component": channel, **row})
    return out


def catalog_features(
    source: str | Path | Sequence[str | Path] | Stream,
    *,
    n_jobs: int | None = None,
    executor: Executor | None = None,
    progress: bool | str = False,
    frequency: FrequencyMethod | FrequencyEstimator = DEFAULT_FREQUENCY_METHOD,
    t0: TimeOrigin = "auto",
    window_s: float = DEFAULT_WINDOW_S,
    fft: FftBackend = "scipy",
    record_options: dict[str, Any] | None = None,
    lowest_usable_hz: Iterable[float | None] | None = None,
    chunk_size: int = 4,
    omega_max_rad_s: float | None = None,
    alpha_reading: AlphaReading = "eq-6-11",
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Features table of a catalogue: a folder of record files or an ``obspy.Stream``.

    Parameters
    ----------
    source
        A directory (every regular, non-hidden file in it is read with
        :func:`stepframe.records.read`), a list of files, or an ``obspy.Stream`` in m/s².
    n_jobs, executor
        Where the work runs (:func:`stepframe.core.execution.map_items`): worker processes
        (default: the CPUs available; 1 runs in this process), or any
        ``concurrent.futures.Executor``.
    progress
        Count, rate and ETA on stderr (True, or a label).
    frequency, t0, window_s, fft
        As :func:`stepframe.stochastic.features.record_features`.
    record_options
        Keyword arguments of :func:`stepframe.records.read` (``format``, ``units``, ...).
    lowest_usable_hz
        For a Stream: each trace's lowest usable frequency [Hz] (or None), for the band check
        (default: each trace's ``stats.stepframe.lowest_usable_hz`` when it has one, as the
        embedded example's traces do).
    chunk_size
        Items per task.
    omega_max_rad_s
        Highest frequency of interest [rad/s]: a component whose Nyquist frequency is below it
        fails at stage ``features`` (dt too coarse for the band).
    alpha_reading
        Where the fitted α_g ramp ends (:func:`stepframe.stochastic.fit.fit_model`).

    Returns
    -------
    table : pandas.DataFrame
        One row per component, columns :data:`COLUMNS` (column dictionary in
        ``stepframe.core.results.get_column_dictionary(table)``).
    failures : pandas.DataFrame
        :func:`stepframe.core.results.failures_table`: ``item`` (``file [component]``),
        ``stage`` (``read``, ``features`` or ``fit``), ``error_type``, ``message``. A file with
        the same bytes as an earlier one is one record (read once): it is listed here, stage
        ``read``, error type ``SameContent``
        (:func:`stepframe.records.catalog.distinct_contents`).
    """
    import pandas as pd

    from stepframe.records.catalog import copy_failures

    items, copies = _items(source, lowest_usable_hz)
    options = Options(
        frequency,
        t0,
        window_s,
        fft,
        tuple(sorted((record_options or {}).items())),
        omega_max_rad_s,
        alpha_reading,
    )
    if n_jobs is not None and n_jobs < 1:
        raise InputError(f"n_jobs = {n_jobs}, expected ≥ 1")
    outcome = map_items(
        partial(_run_item, options=options),
        items,
        jobs=n_jobs,
        executor=executor,
        chunk_size=chunk_size,
        stage="features",
        name_of=_item_name,
        progress="features" if progress is True else progress,
        # the line counts what the failures table holds: the items' own failures and copies
        failures_in=lambda entries: sum(isinstance(entry, Failure) for entry in entries),
        settled_failures=len(copies),
    )
    produced = [entry for entries in outcome.results for entry in entries]
    rows = [entry for entry in produced if not isinstance(entry, Failure)]
    fails = [entry for entry in produced if isinstance(entry, Failure)]
    table = pd.DataFrame(rows, columns=list(COLUMNS))
    set_column_dictionary(
        table,
        pd.DataFrame(
            [(k, u, m) for k, (u, m) in COLUMNS.items()], columns=["column", "unit", "meaning"]
        ),
    )
    # A file with the same bytes as another is read once and listed here; _run_item records
    # its own failures; one the executor caught is an internal error.
    return table, failures_table([*copy_failures(copies), *fails, *outcome.failures])


def _item_name(item: Item) -> str:
    return item.file


def _items(
    source: str | Path | Any, lowest: Iterable[float | None] | None
) -> tuple[list[Item], list[tuple[Path, Path]]]:
    """The items to read, and the files left out as copies of a kept one (copy, kept)."""
    from stepframe.records.catalog import distinct_contents, record_files

    if isinstance(source, str | Path | list | tuple):
        if isinstance(source, str | Path):
            folder = Path(source)
            if not folder.is_dir():
                raise InputError("not a directory, expected a folder of record files", folder)
            files = record_files(folder)  # the catalogue's rule: recursive
        else:
            files = [Path(p) for p in source]
        kept, copies = distinct_contents(files)
        return [Item(str(p)) for p in kept], copies
    traces = list(source)
    usable = (
        list(lowest)
        if lowest is not None
        else [trace.stats.get("stepframe", {}).get("lowest_usable_hz") for trace in traces]
    )
    if len(usable) != len(traces):
        raise InputError(
            f"{len(usable)} lowest usable frequencies for {len(traces)} traces, expected one each"
        )
    items = []
    for trace, low in zip(traces, usable, strict=True):
        info = trace.stats.get("stepframe", {})
        name = info.get("source_file") or trace.id
        items.append(
            Item(
                str(name),
                np.asarray(trace.data, dtype=np.float64),
                float(trace.stats.delta),
                str(trace.stats.station),
                str(trace.stats.channel),
                None if low is None else float(low),
            )
        )
    return items, []
