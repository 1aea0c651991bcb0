"""What the chosen set is and does: its scaled spectra, the code's check, the frame's response.

After the choice, one step (:func:`chosen_set`) gathers what an engineer needs to use the set:

- the set's units (records, or components) with their scale factors, the scale rule in words
  and the records whose factor was clipped;
- the scaled spectra of the units (:mod:`.set_spectra`), their mean, the target and the set's
  misfit (RMS over the misfit periods of ln(geometric mean / target), the choice's objective);
- the code's suite check when the target is a code's (:mod:`.code_check`);
- what the set does to the frame at the chosen scale: the exact simulator on every chosen
  component, counted as staying linear (no lift-off), stepping, or overturning, with a warning
  when the whole set leaves the frame linear;
- the motions themselves, scaled, for the export (:mod:`.export`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.pipeline.selection.band import FrameBand
from stepframe.pipeline.selection.code_check import check_periods_s, check_suite, period_range_s
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.set_spectra import SET_PERIODS_S, set_spectra
from stepframe.pipeline.selection.spectral import (
    Target,
    describe_target,
    target_code,
    target_record,
)
from stepframe.records.units import STANDARD_GRAVITY_M_S2

Floats = NDArray[np.float64]
Samples = tuple[Floats, float]


@dataclass(frozen=True)
class Motion:
    """One chosen component as recorded, and the factor it is used at.

    Attributes
    ----------
    file, component, record
        Where it came from and the record it belongs to.
    scale
        Its scale factor.
    acc_m_s2, dt_s
        Ground acceleration as recorded [m/s²] and its sampling interval [s].
    event, station
        As the catalogue names them ('' when it does not).
    """

    file: str
    component: str
    record: str
    scale: float
    acc_m_s2: Floats = field(repr=False)
    dt_s: float
    event: str = ""
    station: str = ""


@dataclass
class ChosenSet:
    """The outcome of :func:`chosen_set`: ``summary`` goes into ``selection.json``, ``spectra``
    is ``spectra.csv``, ``motions`` the export's input, ``warnings`` are printed."""

    summary: dict[str, Any]
    spectra: Any
    motions: list[Motion]
    warnings: list[str]


def _cell(table: Any, column: str, row: int) -> str:
    """A text cell ('' when the column is missing or the value is)."""
    if column not in table.columns:
        return ""
    value = table[column].iat[row]
    return "" if value is None or (isinstance(value, float) and math.isnan(value)) else str(value)


def _units(table: Any, rows: list[int], unit: str) -> list[tuple[str, list[int]]]:
    """The chosen rows as units in the chosen order: records (their rows) or components."""
    if unit != "record":
        return [(f"{table['file'].iat[i]} [{table['component'].iat[i]}]", [i]) for i in rows]
    out: dict[str, list[int]] = {}
    for i in rows:
        out.setdefault(str(table["record"].iat[i]), []).append(i)
    return list(out.items())


def scale_rule(options: SelectionOptions, target: Target | None, period_1_s: float) -> str:
    """The scale rule in words, with the level it scales to (:func:`scale_phrase` reads the
    level back from it)."""
    low, high = options.scale_min, options.scale_max
    if options.unit == "record":
        what = f"each record (both components, by its {options.pair_spectrum})"
    else:
        what = "each component"
    if options.scale == "none":
        return "none: the records as recorded (scale factor 1)"
    if options.scale == "psa-at-t1":
        if target is None:
            level = "the candidates' median PSA(T_1)"
        else:
            at_t1 = target.sa_m_s2(period_1_s) / STANDARD_GRAVITY_M_S2
            level = f"the target's PSA(T_1 = {period_1_s:.3g} s) = {at_t1:.3g} g"
        return f"psa-at-t1: {what} scaled to {level}, factors clipped to [{low:g}, {high:g}]"
    return (
        f"target-mse: {what} scaled by the least squares in ln PSA over the misfit periods, "
        f"factors clipped to [{low:g}, {high:g}]"
    )


def scale_phrase(rule: str) -> str:
    """What :func:`scale_rule`'s text says was scaled to what, without the rule's name, the
    clipping and "(scale factor 1)": the response line of the summary names its scale by it
    (a selection folder keeps the rule as text only)."""
    phrase = rule.split(": ", 1)[-1].split(", factors clipped")[0]
    return phrase.removesuffix(" (scale factor 1)")


def _response(frame: Any, motions: list[Motion]) -> dict[str, Any]:
    """The exact simulator on each chosen component at its scale factor, counted."""
    from stepframe.pipeline.selection.confirm import run_batch

    run = run_batch(
        frame,
        [(m.acc_m_s2, m.dt_s) for m in motions],
        np.array([m.scale for m in motions], dtype=np.float64),
    )
    table = run.table
    overturned = table["overturned"].to_numpy(dtype=bool)
    stepped = table["n_stepping_episodes"].to_numpy() > 0
    peaks = table["peak_abs_x_m"].to_numpy(dtype=np.float64)
    states = np.where(overturned, "overturns", np.where(stepped, "steps", "linear"))
    return {
        "n": len(motions),
        "linear": int((states == "linear").sum()),
        "steps": int((states == "steps").sum()),
        "overturns": int((states == "overturns").sum()),
        "x_c_m": float(frame.x_c_m),
        "rows": [
            {
                "file": m.file,
                "component": m.component,
                "record": m.record,
                "scale": m.scale,
                "peak_abs_x_m": float(peak),
                "state": str(state),
            }
            for m, peak, state in zip(motions, peaks, states, strict=True)
        ],
    }


def _set_misfit(psa_g: Floats, grid: Floats, target_g: Floats, periods_s: Floats) -> float:
    """RMS over ``periods_s`` of ln(geometric mean of the units' PSA / target) (the choice's
    misfit), the spectra interpolated in ln-ln from ``grid``."""
    log_mean = np.mean(np.log(psa_g), axis=0)
    at = np.interp(np.log(periods_s), np.log(grid), log_mean)
    goal = np.interp(np.log(periods_s), np.log(grid), np.log(target_g))
    return float(np.sqrt(np.mean((at - goal) ** 2)))


def _code_check(
    code: str | None,
    target: Target | None,
    options: SelectionOptions,
    grid: Floats,
    spectra: Any,
    target_g: Floats | None,
    ranges: list[tuple[float, float]],
) -> dict[str, Any]:
    """The code's suite check of the set's spectra, or why it was not run."""
    if not code or target is None or target_g is None:
        why = (
            "no target spectrum"
            if target is None
            else f"the target {describe_target(target, options)} names no code (give "
            "--target-code asce7-22 or ec8 for a tabulated code spectrum)"
        )
        return {"not_run": why}
    check_at = check_periods_s(grid, ranges[0])
    index = np.searchsorted(grid, check_at)
    return check_suite(
        code,
        check_at,
        spectra.mean_psa_g[index],
        target_g[index],
        ranges[0],
        measure=spectra.measure,
        n_units=len(spectra.names),
        mean_pga_g=float(np.mean(spectra.pga_g)) if spectra.names else None,
        target_pga_g=getattr(target, "pga_g", None),
    ).to_dict()


def chosen_set(
    table: Any,
    rows: list[int],
    samples: dict[int, Samples],
    frame: Any,
    band: FrameBand,
    options: SelectionOptions,
    target: Target | None,
    misfit_periods_s: Floats,
) -> ChosenSet:
    """The chosen set's spectra, code check, response at the chosen scale and motions.

    Parameters
    ----------
    table
        The candidate table (``file``, ``component``, ``record``, ``scale_factor``,
        ``scale_clipped``).
    rows
        The chosen rows, in the chosen order.
    samples
        Row → (acceleration [m/s²], dt [s]) for at least the chosen rows.
    frame, band, options, target
        The run's frame, band, options and target spectrum (None without).
    misfit_periods_s
        The periods of the set's misfit [s].
    """
    import pandas as pd

    units = _units(table, rows, options.unit)
    scales = table["scale_factor"].to_numpy(dtype=np.float64)
    motions = [
        Motion(
            str(table["file"].iat[i]),
            str(table["component"].iat[i]),
            str(table["record"].iat[i]),
            float(scales[i]),
            samples[i][0],
            samples[i][1],
            _cell(table, "event", i),
            _cell(table, "station", i),
        )
        for i in rows
        if i in samples
    ]
    warnings: list[str] = []
    summary: dict[str, Any] = {
        "scale_rule": scale_rule(options, target, band.period_1_s),
        "scale_factors": {name: float(scales[members[0]]) for name, members in units},
    }
    clipped = [name for name, members in units if bool(table["scale_clipped"].iat[members[0]])]
    summary["clipped"] = clipped
    if clipped:
        warnings.append(
            f"{len(clipped)} scale factor(s) clipped to [{options.scale_min:g}, "
            f"{options.scale_max:g}]: {', '.join(clipped)} (the record does not reach the "
            "level; widen --scale-min/--scale-max or leave it out)"
        )
    code = target_code(options) if target is not None else None
    t_amax = 2 * math.pi / band.omega_low_rad_s
    ranges = [period_range_s(code, band.period_1_s, t_amax)] if code else []
    grid = np.unique(
        np.concatenate([SET_PERIODS_S, misfit_periods_s, *(np.array(r) for r in ranges)])
    )
    damping = options.target_damping
    with_samples = [(n, m) for n, m in units if all(i in samples for i in m)]
    if not with_samples:
        warnings.append(
            "the chosen records' samples could not be read (give records=, or files at their "
            "paths): the set's spectra, the code check, the response and the motions: not run"
        )
        summary.update(
            target=None if target is None else target_record(target, options, grid),
            set_misfit=None,
            set_spectra={"not_run": "no samples"},
            code_check={"not_run": "no samples of the chosen records"},
            chosen_response={"n": 0},
            warnings=warnings,
        )
        return ChosenSet(summary, None, [], warnings)
    spectra = set_spectra(
        [(n, [samples[i] for i in m], float(scales[m[0]])) for n, m in with_samples],
        grid,
        damping,
        options.pair_spectrum,
    )
    warnings += list(spectra.notes)
    columns: dict[str, Any] = {"period_s": grid}
    if target is not None:
        target_g = np.array([target.sa_m_s2(float(t)) for t in grid]) / STANDARD_GRAVITY_M_S2
        columns["target_g"] = target_g
        summary["target"] = target_record(target, options, grid)
        summary["set_misfit"] = _set_misfit(spectra.psa_g, grid, target_g, misfit_periods_s)
    else:
        summary["target"] = None
        summary["set_misfit"] = None
    columns["mean_g"] = spectra.mean_psa_g
    for name, values in zip(spectra.names, spectra.psa_g, strict=True):
        columns[name] = values
    summary["set_spectra"] = {
        "measure": spectra.measure,
        "damping": damping,
        "units": spectra.names,
    }
    summary["code_check"] = _code_check(
        code, target, options, grid, spectra, columns.get("target_g"), ranges
    )
    response = _response(frame, motions) if motions else {"n": 0}
    summary["chosen_response"] = response
    if response["n"] and response["linear"] == response["n"]:
        warnings.append(
            f"at the chosen scale the set leaves the frame linear: none of the {response['n']} "
            f"components makes it step (peak |x| < x_c = {frame.x_c_m:.3g} m); "
            + (
                "a target with --scale psa-at-t1 scales the set to a stated intensity"
                if options.scale == "none"
                else "a stronger target, or records that reach it unclipped, make it step"
            )
        )
    summary["warnings"] = warnings
    return ChosenSet(summary, pd.DataFrame(columns), motions, warnings)
