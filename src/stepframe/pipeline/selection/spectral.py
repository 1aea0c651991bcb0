"""The spectral objective and scaling: target spectrum, record spectra, misfit, scale factors.

The paper's Example 4 picked records by closeness to the design spectrum's S_DS/S_D1; here a
target spectrum is optional (the two-period design spectrum of
:mod:`stepframe.structure.design_spectrum`, or a tabulated CSV of ``period_s,sa_g`` rows), the
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
from stepframe.structure.design_spectrum import TabulatedSpectrum, TwoPeriodSpectrum

Floats = NDArray[np.float64]
#: Standard gravity for target spectra and PGA given in g [m/s²].
G_M_S2 = 9.80665
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
        periods.append(period)
        values.append(value * G_M_S2)
    try:
        return TabulatedSpectrum(tuple(periods), tuple(values))
    except InputError as error:
        raise InputError(error.what, source) from None


def target_spectrum(options: SelectionOptions) -> TwoPeriodSpectrum | TabulatedSpectrum | None:
    """The options' target spectrum, or None."""
    if options.target_csv is not None:
        return read_target_csv(options.target_csv)
    if options.target_s_ds_g is not None and options.target_s_d1_g is not None:
        return TwoPeriodSpectrum.from_g(options.target_s_ds_g, options.target_s_d1_g, g_m_s2=G_M_S2)
    return None


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
