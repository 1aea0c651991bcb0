"""The record's path: its fitted ω_g(t) (eq. 6.10) during the strong-motion window.

Each row of a features table (:data:`stepframe.stochastic.catalog_features.COLUMNS`) holds the
fitted eq. 6.10-6.11 parameters. The strong-motion window is where the fitted RMS envelope
I_g(t) (:func:`stepframe.stochastic.envelope.default_envelope`, the shape the fit reproduces) is
at least a fraction f of its peak. With u = τ/t_max and the envelope's exponent a,
I_g/I_max = u^a e^{a(1-u)} ≥ f is ln u - u ≥ ln(f)/a - 1 =: c, whose two roots are
u = -W_0(-e^c) < 1 and u = -W_{-1}(-e^c) > 1 (Lambert W): a closed form, vectorised over a whole
catalogue. ω_g(t) is monotone (eq. 6.10), so during the window it sweeps down from ω_g(τ_a) to
ω_g(τ_b). The functions here are array versions of :class:`~stepframe.stochastic.model.
GroundMotionModel` methods (tests check them against the model, row by row).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from stepframe.errors import InputError
from stepframe.stochastic.envelope import DEFAULT_DURATION_THRESHOLD
from stepframe.stochastic.model import MODEL_FIELDS, GroundMotionModel

Floats = NDArray[np.float64]
MODEL_COLUMNS = MODEL_FIELDS


@dataclass(frozen=True)
class Paths:
    """Strong-motion windows and the ω_g range swept in them, one entry per table row.

    Attributes
    ----------
    start_s, end_s
        Window after t0 [s] (NaN where the row has no usable envelope: t_max ≥ t_dur).
    omega_start_rad_s, omega_end_rad_s
        ω_g at the start and end of the window [rad/s] (start ≥ end: ω_g falls).
    """

    start_s: Floats
    end_s: Floats
    omega_start_rad_s: Floats
    omega_end_rad_s: Floats


def model_of_row(row: Any) -> GroundMotionModel:
    """The :class:`GroundMotionModel` of one features row (a mapping or a pandas row)."""
    wp, ws, wr, xi_p, xi_r, t_max, t_dur, t0 = (float(row[name]) for name in MODEL_COLUMNS)
    return GroundMotionModel(wp, ws, wr, xi_p, xi_r, t_max, t_dur, t0)


def omega_g(
    omega_p: Floats, omega_s: Floats, omega_r: Floats, t_max: Floats, tau: Floats
) -> Floats:
    """Eq. 6.10 for arrays: ω_r + (ω_p - ω_r)((ω_s - ω_r)/(ω_p - ω_r))^{τ/t_max} [rad/s]."""
    span = omega_p - omega_r
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.clip((omega_s - omega_r) / span, 0.0, 1.0)
        return np.asarray(omega_r + span * np.power(ratio, np.maximum(tau, 0.0) / t_max))


def envelope_exponents(t_max: Floats, t_dur: Floats) -> Floats:
    """Exponent a of the default envelope (:func:`stepframe.stochastic.envelope.
    envelope_exponent`) for arrays; NaN where t_max ≥ t_dur (no such envelope)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = t_dur / t_max
        a = math.log(DEFAULT_DURATION_THRESHOLD) / (np.log(ratio) + 1.0 - ratio)
    return np.asarray(np.where(ratio > 1.0, a, np.nan))


def strong_motion_paths(table: Any, fraction: float) -> Paths:
    """Strong-motion windows (I_g ≥ ``fraction`` · peak) and ω_g swept in them, per row.

    Parameters
    ----------
    table
        A features table (columns :data:`MODEL_COLUMNS` at least).
    fraction
        Threshold of the window as a fraction of max I_g, in (0.1, 1): the window must lie
        inside [0, t_dur], where I_g ≥ 0.1 · peak by the definition of t_dur.
    """
    from scipy.special import lambertw

    if not DEFAULT_DURATION_THRESHOLD < fraction < 1:
        raise InputError(
            f"strong_motion_fraction = {fraction}, expected {DEFAULT_DURATION_THRESHOLD} < "
            "fraction < 1 (t_dur is where I_g falls to 0.1 of its peak)"
        )
    t_max = np.asarray(table["t_max_s"], dtype=np.float64)
    t_dur = np.asarray(table["t_dur_s"], dtype=np.float64)
    a = envelope_exponents(t_max, t_dur)
    with np.errstate(invalid="ignore", divide="ignore"):
        z = -np.exp(math.log(fraction) / a - 1.0)
        z = np.where(np.isfinite(z), np.maximum(z, -1.0 / math.e), np.nan)
    u_start = -np.real(lambertw(z, 0))
    u_end = -np.real(lambertw(z, -1))
    start = u_start * t_max
    end = u_end * t_max
    wp = np.asarray(table["omega_p_rad_s"], dtype=np.float64)
    ws = np.asarray(table["omega_s_rad_s"], dtype=np.float64)
    wr = np.asarray(table["omega_r_rad_s"], dtype=np.float64)
    return Paths(
        start,
        end,
        omega_g(wp, ws, wr, t_max, start),
        omega_g(wp, ws, wr, t_max, end),
    )
