"""The spectral objective and scaling: target spectrum, record spectra, misfit, scale factors.

The paper's Example 4 picked records by closeness to the design spectrum's S_DS/S_D1; here a
target spectrum is optional (ASCE 7-22's two-period or multi-period spectrum, Eurocode 8's
elastic spectrum, :mod:`stepframe.structure.code_spectra`, or a tabulated CSV of
``period_s,sa_g`` rows), the
misfit is the RMS of ln(s·PSA/target) over a period range, and the scale factor s follows a
policy: ``none`` (default: the paper warns that amplitude scaling may bias results),
``psa-at-t1`` (the target's PSA at T_1, or without a target the candidates' median PSA at T_1) or
``target-mse`` (the least-squares s in ln PSA, exp(mean ln(target/PSA))), bounded by
[scale_min, scale_max].
"""

from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.errors import InputError
from stepframe.pipeline.selection.band import FrameBand
from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure.code_spectra import Asce7TwoPeriod, Ec8Elastic
from stepframe.structure.design_spectrum import TabulatedSpectrum, point_problem

Target = Asce7TwoPeriod | Ec8Elastic | TabulatedSpectrum

Floats = NDArray[np.float64]
N_PERIODS = 12
LONGEST_PERIOD_S = 10.0


def read_target_csv(path: str | Path) -> TabulatedSpectrum:
    """A target spectrum from a CSV with a header ``period_s,sa_g`` (PSA in g, 5 % damping).

    Raises
    ------
    InputError
        Unreadable file, missing columns, a value that is not a number (file and line named),
        or a table that is not a spectrum (fewer than 2 rows, periods not increasing).
    """
    source = Path(path)
    try:
        text = source.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(
            f"cannot read the target spectrum ({error}), expected a CSV file", source
        ) from None
    rows = list(csv.reader(text.splitlines()))
    if not rows or [c.strip() for c in rows[0][:2]] != ["period_s", "sa_g"]:
        raise InputError("first line is not 'period_s,sa_g', expected that header", source, 1)
    periods: list[float] = []
    values: list[float] = []
    for number, row in enumerate(rows[1:], start=2):
        if not row or not "".join(row).strip():
            continue
        try:
            period, value = float(row[0]), float(row[1])
        except (ValueError, IndexError):
            raise InputError(
                f"{','.join(row)!r}, expected two numbers: period_s,sa_g", source, number
            ) from None
        # the table's rule, on the row's line and in the file's units
        problem = point_problem(period, value, periods[-1] if periods else None)
        if problem:
            raise InputError(
                f"period_s = {row[0].strip()}, sa_g = {row[1].strip()}, {problem}", source, number
            )
        periods.append(period)
        values.append(value * STANDARD_GRAVITY_M_S2)
    try:
        return TabulatedSpectrum(tuple(periods), tuple(values))
    except InputError as error:
        raise InputError(error.what, source) from None


def target_spectrum(options: SelectionOptions) -> Target | None:
    """The options' target spectrum, or None: a CSV table (ASCE 7-22's multi-period spectrum
    with ``target_code="asce7-22"``), ASCE 7-22's two-period spectrum (S_DS, S_D1, T_L) or
    Eurocode 8's elastic spectrum (:mod:`stepframe.structure.code_spectra`)."""
    if options.target_csv is not None:
        return read_target_csv(options.target_csv)
    if options.target_s_ds_g is not None and options.target_s_d1_g is not None:
        return Asce7TwoPeriod(
            options.target_s_ds_g,
            options.target_s_d1_g,
            options.target_t_l_s,
            STANDARD_GRAVITY_M_S2,
        )
    if (
        options.target_ec8 is not None
        and options.target_ground is not None
        and options.target_ag_g is not None
    ):
        return Ec8Elastic(
            options.target_ec8,
            options.target_ground,
            options.target_ag_g,
            options.target_importance,
            options.target_damping,
            STANDARD_GRAVITY_M_S2,
        )
    return None


def target_code(options: SelectionOptions) -> str | None:
    """The code whose suite rule the target answers to (``asce7-22``, ``ec8``), or None."""
    if options.target_s_ds_g is not None:
        return "asce7-22"
    if options.target_ec8 is not None:
        return "ec8"
    return options.target_code


def describe_target(target: Target, options: SelectionOptions) -> str:
    """The target in words (the output and the report say the same)."""
    if isinstance(target, TabulatedSpectrum):
        code = {"asce7-22": "ASCE 7-22 multi-period spectrum (§11.4.5.1) from "}.get(
            str(options.target_code), ""
        )
        return f"{code}{options.target_csv} ({len(target.periods_s)} points)"
    return str(target.describe())


def target_record(target: Target, options: SelectionOptions, periods_s: Floats) -> dict[str, Any]:
    """The target as ``selection.json`` stores it: what it is, its parameters, its code and
    its values [g] at ``periods_s`` (the report draws these)."""
    data = target.to_dict()
    if isinstance(target, TabulatedSpectrum):
        data = {"kind": "table", "file": options.target_csv, **data, "damping": 0.05}
    return {
        **data,
        "code": target_code(options),
        "describe": describe_target(target, options),
        "periods_s": [float(t) for t in periods_s],
        "sa_g": [target.sa_m_s2(float(t)) / STANDARD_GRAVITY_M_S2 for t in periods_s],
    }


def misfit_periods_s(options: SelectionOptions, band: FrameBand) -> Floats:
    """Periods of the misfit: ``target_periods_s`` or T_1 to T(A_max) (at most 10 s), log-spaced."""
    if options.target_periods_s is not None:
        low, high = options.target_periods_s
    else:
        low = band.period_1_s
        high = min(2 * math.pi / band.omega_low_rad_s, LONGEST_PERIOD_S)
        high = max(high, 1.5 * low)
    return np.geomspace(low, high, N_PERIODS)


SpectraItem = tuple[Floats, float, tuple[tuple[Floats, float], ...]]


def record_spectra(item: SpectraItem) -> list[Floats]:
    """Peak oscillator displacements SD [m] of one record for each (periods [s], damping) group
    of ``item = (acceleration [m/s²], dt [s], groups)`` (a :func:`map_items` worker)."""
    from stepframe.records.spectra import peak_displacements_m

    acc, dt, groups = item
    return [peak_displacements_m(acc, dt, periods, damping) for periods, damping in groups]


def target_values(target: Any, periods_s: Floats) -> Floats:
    """S_a of the target at each period [m/s²]."""
    return np.array([target.sa_m_s2(float(t)) for t in periods_s])


def scale_factors(
    policy: str,
    psa_t1: Floats,
    psa: Floats | None,
    target_t1: float | None,
    target_psa: Floats | None,
    bounds: tuple[float, float],
) -> tuple[Floats, NDArray[np.bool_]]:
    """Scale factor per candidate and whether it was clipped to ``bounds``.

    Parameters
    ----------
    policy
        ``"none"``, ``"psa-at-t1"`` or ``"target-mse"``.
    psa_t1
        Each candidate's PSA at T_1 [m/s²].
    psa
        Each candidate's PSA at the misfit periods, shape (n, n_periods) (target-mse).
    target_t1, target_psa
        The target at T_1 and at the misfit periods (None without a target).
    bounds
        (scale_min, scale_max).
    """
    n = psa_t1.size
    if policy == "none":
        raw = np.ones(n)
    elif policy == "psa-at-t1":
        level = target_t1 if target_t1 is not None else float(np.nanmedian(psa_t1))
        with np.errstate(divide="ignore", invalid="ignore"):
            raw = level / psa_t1
    else:
        assert psa is not None and target_psa is not None
        with np.errstate(divide="ignore", invalid="ignore"):
            raw = np.exp(np.mean(np.log(target_psa[None, :] / psa), axis=1))
    clipped = np.isfinite(raw) & ((raw < bounds[0]) | (raw > bounds[1]))
    return np.clip(raw, *bounds), np.asarray(clipped)


def spectral_misfit(psa: Floats, scales: Floats, target_psa: Floats) -> Floats:
    """RMS over periods of ln(s·PSA/target), per candidate."""
    with np.errstate(divide="ignore", invalid="ignore"):
        residual = np.log(scales[:, None] * psa / target_psa[None, :])
    return np.asarray(np.sqrt(np.mean(residual**2, axis=1)))


def record_scales(
    members: list[list[int]],
    samples: dict[int, tuple[Floats, float]],
    periods_s: Floats,
    period_1_s: float,
    policy: str,
    target: Target | None,
    bounds: tuple[float, float],
    measure: str,
) -> tuple[Floats, NDArray[np.bool_], Floats, Floats]:
    """One scale factor per record, from the spectrum of its pair (``unit="record"``).

    Both components of a record carry one factor, set by the policy on the pair's spectrum by
    ``measure`` (:mod:`.set_spectra`): the target's PSA(T_1) over the pair's (``psa-at-t1``;
    without a target, the records' median), or the least squares in ln PSA over ``periods_s``
    (``target-mse``).

    Returns
    -------
    scales, clipped, misfit : numpy.ndarray
        Per record: the factor, whether it was clipped to ``bounds``, the RMS of
        ln(s·PSA/target) over ``periods_s`` (NaN without a target).
    log_psa : numpy.ndarray
        Per record, ln of the scaled pair spectrum at ``periods_s``, shape (records, periods).
    """
    from stepframe.pipeline.selection.set_spectra import pair_psa

    with_t1 = np.concatenate([[period_1_s], periods_s])
    pair = np.full((len(members), with_t1.size), np.nan)
    for k, rows in enumerate(members):
        if all(i in samples for i in rows):
            values = pair_psa([samples[i] for i in rows], with_t1, 0.05, measure)
            if values is not None:
                pair[k] = values
    target_t1 = None if target is None else target.sa_m_s2(period_1_s)
    target_psa = None if target is None else target_values(target, periods_s)
    scales, clipped = scale_factors(policy, pair[:, 0], pair[:, 1:], target_t1, target_psa, bounds)
    misfit = (
        spectral_misfit(pair[:, 1:], scales, target_psa)
        if target_psa is not None
        else np.full(len(members), np.nan)
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        log_psa = np.log(scales[:, None] * pair[:, 1:])
    return scales, clipped, misfit, log_psa
