"""The default intensity envelope I_g(t) of synthetic motions and of the mean-square analysis.

Shape (a gamma-type envelope, as Saragoni and Hart 1974 used for strong motion)::

    I_g(t) = I_max · (τ/t_max)^a · exp(a·(1 - τ/t_max)),  τ = t - t0 ≥ 0,

which rises from 0, peaks at τ = t_max with value I_max, and decays. The exponent a is chosen so
that I_g has fallen to ``threshold · I_max`` at τ = t_dur, which makes t_dur "the time until
I_g(t) drops below a predefined fraction of max I_g" (the paper's definition, with the end of
strong motion measured from the time origin, as eq. 6.11 uses it). The estimator of t_dur from a
record (:mod:`stepframe.stochastic.features`) uses the same definition and the same default
threshold, so parameters fitted to a record reproduce its envelope.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from stepframe.errors import InputError

#: Default fraction of max I_g that marks the end of strong motion (t_dur).
DEFAULT_DURATION_THRESHOLD = 0.1


def envelope_exponent(
    t_max_s: float, t_dur_s: float, threshold: float = DEFAULT_DURATION_THRESHOLD
) -> float:
    """The exponent a of the envelope that falls to ``threshold`` of its peak at ``t_dur_s``."""
    if not 0 < threshold < 1:
        raise InputError(f"threshold = {threshold}, expected 0 < threshold < 1")
    if not 0 < t_max_s < t_dur_s:
        raise InputError(
            f"t_max_s = {t_max_s}, t_dur_s = {t_dur_s}, expected 0 < t_max < t_dur for the envelope"
        )
    ratio = t_dur_s / t_max_s
    return math.log(threshold) / (math.log(ratio) + 1.0 - ratio)


def default_envelope(
    t_s: ArrayLike,
    t_max_s: float,
    t_dur_s: float,
    peak: float = 1.0,
    *,
    t0_s: float = 0.0,
    threshold: float = DEFAULT_DURATION_THRESHOLD,
) -> NDArray[np.float64]:
    """RMS intensity envelope I_g(t) [units of ``peak``, m/s² for accelerations].

    Parameters
    ----------
    t_s
        Record times [s].
    t_max_s
        Time of the peak after ``t0_s`` [s].
    t_dur_s
        Time after ``t0_s`` at which I_g has fallen to ``threshold · peak`` [s]; > t_max_s.
    peak
        max I_g.
    t0_s
        Time origin [s]; I_g = 0 before it.
    threshold
        Fraction of the peak reached at t_dur (default :data:`DEFAULT_DURATION_THRESHOLD`).
    """
    a = envelope_exponent(t_max_s, t_dur_s, threshold)
    tau = np.maximum(np.asarray(t_s, dtype=np.float64) - t0_s, 0.0) / t_max_s
    with np.errstate(divide="ignore"):
        log_shape = a * (np.log(tau) + 1.0 - tau)  # -inf at tau = 0 gives exactly 0
    return np.asarray(peak * np.exp(log_shape))
