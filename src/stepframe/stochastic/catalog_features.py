"""Features and B-P parameters of every component of a catalogue, in parallel, failures recorded.

One row per component (:data:`COLUMNS`); a component that fails is skipped and recorded in the
failure table (``file``, ``component``, ``stage``, ``reason``) with stage ``read``, ``features``
or ``fit``; the batch never stops for one bad item. Work is spread over processes
(``concurrent.futures``), a few components per task to amortise the hand-over; rows come back in
input order whatever the worker count, so runs are reproducible.

Plausibility (column ``plausible`` and ``implausible_reason``): ω_p ≥ ω_s ≥ ω_r holds by
construction of the fit, so the checks are that the fitted frequencies lie inside the usable
band (ω_r above both the window's resolution 2π/window_s and, when known, the record's lowest
usable frequency; ω_p below half the Nyquist frequency), that ω_g falls at all (ω_p > 1.05 ω_r),
and that no flag marks a value at a bound, floor or clip
(:func:`stepframe.stochastic.flags.implausible`; every flag's meaning in
:data:`stepframe.stochastic.flags.FLAGS`).
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from stepframe.errors import InputError
from stepframe.stochastic.features import FrequencyMethod, TimeOrigin, record_features
from stepframe.stochastic.fit import PARAMETERS, fit_model
from stepframe.stochastic.flags import implausible, meaning
from stepframe.stochastic.spectra import DEFAULT_WINDOW_S, FftBackend

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
    "p_onset_used": ("", "whether t0 is a picked P onset"),
    "p_onset_s": ("s", "picked P onset in record time (empty if none)"),
    "t0_source": ("", "what t0 is: p-pick (picked P onset) or start (record start)"),
    "p_pick_snr": ("", "P pick confidence: RMS 2 s after it / RMS before (empty if none)"),
    "flags": ("", "degraded results, ';'-separated"),
    "plausible": ("", "passes the plausibility checks"),
    "implausible_reason": ("", "why not (empty when plausible)"),
}
FAILURE_COLUMNS = ("file", "component", "stage", "reason")


@dataclass(frozen=True)
class Options:
    """Options of the per-component computation (picklable, passed to workers)."""

    frequency: FrequencyMethod = "zero-crossing"
    t0: TimeOrigin = "auto"
    window_s: float = DEFAULT_WINDOW_S
    fft: FftBackend = "scipy"
    record_options: tuple[tuple[str, Any], ...] = ()
    omega_max_rad_s: float | None = None


@dataclass(frozen=True)
class Item:
    """One unit of work: a file to read, or one component already in memory."""

    file: str
    data: np.ndarray | None = None
    dt_s: float | None = None
    station: str = ""
    component: str = ""
    lowest_usable_hz: float | None = None


def plausibility(row: dict[str, Any], window_s: float, lowest_usable_hz: float | None) -> str:
    """Empty string if the fitted parameters pass the checks, else the reasons ('; ')."""
    reasons = []
    low = 2 * math.pi / window_s
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


def component_row(
    data: np.ndarray, dt_s: float, options: Options, lowest_usable_hz: float | None = None
) -> tuple[dict[str, Any] | None, tuple[str, str] | None]:
    """Features and fit of one component: (row, None) or (None, (stage, reason))."""
    try:
        features = record_features(
            data, dt_s, frequency=options.frequency, t0=options.t0, window_s=options.window_s,
            fft=options.fft, omega_max_rad_s=options.omega_max_rad_s,
        )  # fmt: skip
    except InputError as error:
        return None, ("features", error.one_line())
    except Exception as error:  # a batch never stops for one item: record the unexpected too
        return None, ("features", f"internal error {type(error).__name__}: {error}")
    try:
        result = fit_model(features)
    except InputError as error:
        return None, ("fit", error.one_line())
    except Exception as error:  # numerical failure inside scipy: recorded, not fatal
        return None, ("fit", f"internal error {type(error).__name__}: {error}")
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
    row["p_onset_used"] = features.p_onset_s is not None
    row["p_onset_s"] = features.p_onset_s if features.p_onset_s is not None else math.nan
    row["t0_source"] = features.t0_source
    row["p_pick_snr"] = math.nan if features.p_pick_snr is None else features.p_pick_snr
    row["flags"] = ";".join(result.flags)
    reason = plausibility(row, options.window_s, lowest_usable_hz)
    row["plausible"] = not reason
    row["implausible_reason"] = reason
    return row, None


def _run_item(item: Item, options: Options) -> list[tuple[dict[str, Any] | None, tuple[str, ...]]]:
    """Rows (or failures) of every component of one item."""
    if item.data is not None and item.dt_s is not None:
        components = [(item.data, item.dt_s, item.station, item.component)]
    else:
        from stepframe.records import read

        try:
            stream = read(item.file, **dict(options.record_options))
        except InputError as error:
            return [(None, (item.file, "", "read", error.one_line()))]
        except Exception as error:  # readers (obspy's too) raise many types: recorded, not fatal
            return [(None, (item.file, "", "read", f"{type(error).__name__}: {error}"))]
        if len(stream) == 0:
            return [(None, (item.file, "", "read", "no traces in the file"))]
        components = [
            (np.asarray(tr.data, dtype=np.float64), float(tr.stats.delta), tr.stats.station,
             tr.stats.channel)
            for tr in stream
        ]  # fmt: skip
    out: list[tuple[dict[str, Any] | None, tuple[str, ...]]] = []
    for data, dt, station, channel in components:
        row, failure = component_row(data, dt, options, item.lowest_usable_hz)
        if row is None:
            assert failure is not None
            out.append((None, (item.file, str(channel), *failure)))
        else:
            out.append(({"file": item.file, "station": station, "component": channel, **row}, ()))
    return out


def _run_chunk(
    items: Sequence[Item], options: Options
) -> list[list[tuple[dict[str, Any] | None, tuple[str, ...]]]]:
    return [_run_item(item, options) for item in items]


def _progress_printer(stream: TextIO, total: int) -> Callable[[int], None]:
    def show(done: int) -> None:
        end = "\n" if done >= total else ""
        print(f"\rfeatures: {done}/{total} items", end=end, file=stream, flush=True)

    return show


def catalog_features(
    source: str | Path | Any,
    *,
    n_jobs: int | None = None,
    progress: bool | Callable[[int], None] = False,
    frequency: FrequencyMethod = "zero-crossing",
    t0: TimeOrigin = "auto",
    window_s: float = DEFAULT_WINDOW_S,
    fft: FftBackend = "scipy",
    record_options: dict[str, Any] | None = None,
    lowest_usable_hz: Iterable[float | None] | None = None,
    chunk_size: int = 4,
    omega_max_rad_s: float | None = None,
) -> tuple[Any, Any]:
    """Features table of a catalogue: a folder of record files or an ``obspy.Stream``.

    Parameters
    ----------
    source
        A directory (every regular, non-hidden file in it is read with
        :func:`stepframe.records.read`), a list of files, or an ``obspy.Stream`` in m/s².
    n_jobs
        Worker processes (default: the number of CPUs; 1 runs in this process).
    progress
        True prints ``features: done/total items`` on stderr; a callable receives ``done``.
    frequency, t0, window_s, fft
        As :func:`stepframe.stochastic.features.record_features`.
    record_options
        Keyword arguments of :func:`stepframe.records.read` (``format``, ``units``, ...).
    lowest_usable_hz
        For a Stream: each trace's lowest usable frequency [Hz] (or None), for the band check.
    chunk_size
        Items per task.
    omega_max_rad_s
        Highest frequency of interest [rad/s]: a component whose Nyquist frequency is below it
        fails at stage ``features`` (dt too coarse for the band).

    Returns
    -------
    table : pandas.DataFrame
        One row per component, columns :data:`COLUMNS` (column dictionary in
        ``table.attrs["column_dictionary"]``).
    failures : pandas.DataFrame
        Columns ``file``, ``component``, ``stage``, ``reason``.
    """
    import os

    import pandas as pd

    items = _items(source, lowest_usable_hz)
    options = Options(
        frequency,
        t0,
        window_s,
        fft,
        tuple(sorted((record_options or {}).items())),
        omega_max_rad_s,
    )
    workers = n_jobs if n_jobs is not None else (os.cpu_count() or 1)
    if workers < 1:
        raise InputError(f"n_jobs = {n_jobs}, expected ≥ 1")
    if chunk_size < 1:
        raise InputError(f"chunk_size = {chunk_size}, expected ≥ 1")
    show: Callable[[int], None] | None = (
        _progress_printer(sys.stderr, len(items)) if progress is True else progress or None
    )
    chunks = [items[i : i + chunk_size] for i in range(0, len(items), chunk_size)]
    results: list[list[tuple[dict[str, Any] | None, tuple[str, ...]]]] = []
    done = 0
    if workers == 1 or len(chunks) <= 1:
        for chunk in chunks:
            results.extend(_run_chunk(chunk, options))
            done += len(chunk)
            if show:
                show(done)
    else:
        with ProcessPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(_run_chunk, chunk, options) for chunk in chunks]
            for chunk, future in zip(chunks, futures, strict=True):
                results.extend(future.result())
                done += len(chunk)
                if show:
                    show(done)
    rows = [row for item in results for row, _ in item if row is not None]
    fails = [fail for item in results for row, fail in item if row is None]
    table = pd.DataFrame(rows, columns=list(COLUMNS))
    table.attrs["column_dictionary"] = pd.DataFrame(
        [(k, u, m) for k, (u, m) in COLUMNS.items()], columns=["column", "unit", "meaning"]
    )
    failures = pd.DataFrame(fails, columns=list(FAILURE_COLUMNS))
    return table, failures


def _items(source: str | Path | Any, lowest: Iterable[float | None] | None) -> list[Item]:
    if isinstance(source, str | Path):
        folder = Path(source)
        if not folder.is_dir():
            raise InputError("not a directory, expected a folder of record files", folder)
        files = sorted(p for p in folder.iterdir() if p.is_file() and not p.name.startswith("."))
        return [Item(str(p)) for p in files]
    if isinstance(source, list | tuple):
        return [Item(str(p)) for p in source]
    traces = list(source)
    usable = list(lowest) if lowest is not None else [None] * len(traces)
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
    return items
