"""The flags of features and fits: one dictionary with each flag's meaning and consequence.

A flag marks a degraded result. Flags whose value is a bound, a floor or a clip rather than an
estimate make a fit *not plausible* (:func:`implausible`): the number printed is where the
search stopped, not what the record says; so does ``record_clipped``, whose record no longer
says what the ground did. The others are caveats a reader should see.
"""

from __future__ import annotations

from collections.abc import Iterable

#: flag → (makes the fit implausible, meaning).
FLAGS: dict[str, tuple[bool, str]] = {
    "record_incomplete": (
        False,
        "the record was read cut short (--allow-short): what is missing may hold the end of the "
        "strong motion (t_dur) and the late omega_g(t)",
    ),
    "record_clipped": (
        True,
        "the record holds its largest or smallest value over several samples on two or more "
        "cycles (clipped at the instrument's full scale): I_g(t) and omega_g(t) are those of the "
        "clipped signal",
    ),
    "envelope_fit_failed": (
        False,
        "the gamma envelope did not fit I_g(t): t_max is the raw argmax of I_g, no standard error",
    ),
    "window_long": (
        False,
        "the smoothing window is over twice t_max: I_g(t) is smeared, t_max and t_dur come out "
        "late, and t_max has no standard error (it would not cover the bias)",
    ),
    "p_pick_failed": (
        False,
        "no reliable P onset (t0='p-pick' asked): the record start is the time origin",
    ),
    "peak_at_origin": (
        True,
        "max I_g at or before the time origin: t_max is set to one frame (a floor)",
    ),
    "duration_truncated": (
        True,
        "I_g is still above the duration threshold at the record end: t_dur is clipped there",
    ),
    "duration_at_floor": (
        True,
        "strong motion ends before t_max: t_dur is set to t_max plus one frame (a floor)",
    ),
    "few_frequency_estimates": (
        True,
        "fewer than 5 strong-motion frames have an omega_g estimate",
    ),
    "band_limited": (
        False,
        "omega_g in strong motion exceeds half the Nyquist frequency (the estimate is biased low)",
    ),
    "omega_below_floor": (
        False,
        "omega_g in over 10 % of the strong-motion frames is below the estimator's resolution "
        "floor there (2 pi/window for a fixed window; frequency=multiwindow resolves lower)",
    ),
    "omega_not_decreasing": (
        True,
        "omega_r = omega_p within 0.1 %: omega_g(t) does not fall (eq. 6.10 degenerates)",
    ),
    "omega_p_at_bound": (
        True,
        "omega_p at its bound (0.5 or 1.5 x the measured omega_g range): a bound, not an estimate",
    ),
    "omega_s_at_bound": (
        True,
        "omega_s equals omega_r or omega_p (eq. 6.10 base at 0 or 1): the decay is not resolved",
    ),
    "omega_r_at_bound": (
        True,
        "omega_r at its floor, 0.01 x omega_p: a floor, not an estimate",
    ),
    "xi_clipped": (
        True,
        "a bandwidth ratio xi_p or xi_r fell outside 0.005-3 and was clipped to that range",
    ),
    "omega_c_not_fitted": (
        False,
        "fewer than 3 spectrum bins below omega_s: the corner frequency omega_c is not resolved",
    ),
}


def meaning(flag: str) -> str:
    """What ``flag`` means (one line); unknown flags are returned as they are."""
    return FLAGS[flag][1] if flag in FLAGS else flag


def implausible(flags: Iterable[str]) -> list[str]:
    """The flags among ``flags`` that make a fit implausible, in order."""
    return [flag for flag in flags if flag in FLAGS and FLAGS[flag][0]]


def describe(flags: Iterable[str]) -> list[str]:
    """``"flag: meaning"`` lines for text output."""
    return [f"{flag}: {meaning(flag)}" for flag in flags]
