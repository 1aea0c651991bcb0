"""What every integrator of the stepping simulator shares: status codes, event kinds, the model
constants it is given (:class:`Model`) and the run it hands back (:class:`RawRun`).

The numba kernel (:mod:`stepframe.structure._exact`), the solve_ivp reference
(:mod:`stepframe.structure.reference`) and the result (:mod:`stepframe.structure.simulator`) all
take their integer codes from here, so none imports another for them. The integer codes are what
the kernels can return; :data:`STATUS_NAMES` maps each onto the project's one status vocabulary
(:data:`stepframe.core.results.STATUSES`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal, NamedTuple

import numpy as np

#: The run finished as asked.
STATUS_OK = 0
#: A non-finite displacement or velocity appeared.
STATUS_NONFINITE = 1
#: More events inside one sample interval than the kernel allows.
STATUS_TOO_MANY_EVENTS = 2
#: ``solve_ivp`` reported a failed step (reference only).
STATUS_SOLVER_FAILED = 3
#: After an event, the state lay on the wrong side of its phase (stepped with |x| < x_c, or
#: unstepped with |x| > x_c) by more than rounding: the result is not a solution of the model.
STATUS_INVARIANT = 4
#: The result is physically impossible without an overturning verdict: |x| passed the cap, or
#: the bound (γ₁ + P₂ max|ẍ_g|)/ω₂² that a frame which does not escape can never pass.
STATUS_IMPOSSIBLE = 5

SimulationStatus = Literal["ok", "nonfinite", "too_many_events", "not_converged", "failed"]

#: Integer code → status of :data:`stepframe.core.results.STATUSES`.
STATUS_NAMES: dict[int, SimulationStatus] = {
    STATUS_OK: "ok",
    STATUS_NONFINITE: "nonfinite",
    STATUS_TOO_MANY_EVENTS: "too_many_events",
    STATUS_SOLVER_FAILED: "not_converged",
    STATUS_INVARIANT: "failed",
    STATUS_IMPOSSIBLE: "failed",
}

#: Integer code → the one-line message a result carries with its status.
STATUS_MESSAGES: dict[int, str] = {
    STATUS_OK: "",
    STATUS_NONFINITE: "a non-finite displacement or velocity appeared",
    STATUS_TOO_MANY_EVENTS: "more events in one sample interval than the kernel allows",
    STATUS_SOLVER_FAILED: "solve_ivp failed to take a step",
    STATUS_INVARIANT: "a state lay on the wrong side of its phase after an event",
    STATUS_IMPOSSIBLE: (
        "peak |x| passed the cap or the no-escape bound (γ₁ + P₂ max|ẍ_g|)/ω₂² "
        "without an overturning verdict"
    ),
}

#: Event kinds stored in ``RawRun.ev_kind``.
EVENT_LIFTOFF = 1
EVENT_TOUCHDOWN = 2
EVENT_CAP = 3
EVENT_ESCAPE = 4
#: An accumulation of impacts (chatter) summed in closed form; the frame is seated from then on.
EVENT_SETTLE = 5

EVENT_NAMES: dict[int, str] = {
    EVENT_LIFTOFF: "liftoff",
    EVENT_TOUCHDOWN: "touchdown",
    EVENT_CAP: "cap",
    EVENT_ESCAPE: "escape",
    EVENT_SETTLE: "settle",
}

#: Relative rebound speed below which an impact's excursions are summed in closed form (see
#: docs/paper-notes.md, "Chatter"): a rebound w ≤ CHATTER_EPS·ω·x_ref rises at most about
#: CHATTER_EPS²·x_ref, still 10⁵ times above the rounding of x, and the closed form's neglected
#: terms are O(CHATTER_EPS) of a duration that is itself O(CHATTER_EPS/ω).
CHATTER_EPS = 1e-5

#: Largest relative change of a surface acceleration (from the ground's slope) over a flight or an
#: accumulation summed in closed form, whose leading-order durations assume it constant.
CHATTER_DRIFT = 1e-3

#: Tolerance of the phase invariant, relative to x_ref = max(x_c, x*).
INVARIANT_RTOL = 1e-9


def no_escape_bound_m(
    gamma_1_m_s2: float,
    p_2: float,
    omega_2_rad_s: float,
    max_abs_ground_acc_m_s2: float,
    x0_m: float = 0.0,
    x_cap_m: float = math.inf,
) -> float:
    """Largest |x| [m] a stepping frame that does not overturn can reach.

    A stepped frame beyond y_e = (γ₁ + P₂·max|ẍ_g|)/ω₂² and moving outward is pushed further out
    whatever the ground does (docs/paper-notes.md, "the certain-escape verdict"), so a run without
    an overturning verdict stays within max(|x₀|, y_e) (plus the relative rounding
    :data:`INVARIANT_RTOL`), and within the cap when the frame has one.
    """
    reach = (gamma_1_m_s2 + p_2 * max_abs_ground_acc_m_s2) / omega_2_rad_s**2
    return min(x_cap_m, max(abs(x0_m), reach) * (1.0 + INVARIANT_RTOL))


def run_invariant(
    status: int, overturned: bool, peak_abs_x_m: float, bound_m: float, *values: float
) -> int:
    """The run's status code after the checks every integrator's result must pass.

    A run that ended ``STATUS_OK`` is downgraded to ``STATUS_NONFINITE`` when its peak or any of
    ``values`` (the final state) is not finite, and to ``STATUS_IMPOSSIBLE`` when it did not
    overturn yet its peak passed ``bound_m`` (:func:`no_escape_bound_m`). Never "ok" for an
    impossible answer.
    """
    if status != STATUS_OK:
        return status
    if not all(math.isfinite(value) for value in (peak_abs_x_m, *values)):
        return STATUS_NONFINITE
    if not overturned and not peak_abs_x_m <= bound_m:
        return STATUS_IMPOSSIBLE
    return STATUS_OK


class Model(NamedTuple):
    """Model constants passed to the kernels (SI; x_c may be 0 for the rigid-block limit)."""

    omega_1_rad_s: float
    omega_2_rad_s: float
    p_1: float
    p_2: float
    gamma_1_m_s2: float
    xi_1: float
    xi_2: float
    x_c_m: float
    c_r: float
    x_cap_m: float  # math.inf when there is no cap


@dataclass
class RawRun:
    """What an integrator hands back (:mod:`stepframe.structure.simulator` makes the result)."""

    status: int
    n_liftoffs: int
    n_impacts: int
    peak_abs_x: float
    peak_time_s: float
    overturned: bool
    overturn_time_s: float
    x_end: float
    v_end: float
    phase_end: int
    ev_t: np.ndarray
    ev_kind: np.ndarray
    ev_v_in: np.ndarray
    ev_v_out: np.ndarray
    ev_peak: np.ndarray
    hist_x: np.ndarray
    hist_v: np.ndarray
    hist_p: np.ndarray


#: Error of the small-angle model's cos(αs - θ) ≈ 1 beyond which a linearised block's result
#: carries a note (its sin(u) ≈ u errs by a third as much); docs/structure-dynamics.md measures
#: what it does to peaks and overturning.
SMALL_ANGLE_TOLERANCE = 0.01


def small_angle_note(
    x_c_m: float, x_star_m: float, height_m: float | None, peak_abs_x_m: float
) -> str:
    """One line when a linearised rigid block (x_c = 0, x = hθ) rotated beyond small angles.

    The linearisation replaces sin(αs - θ) by αs - θ and cos(αs - θ) by 1 (α = x*/h). Over a
    motion up to |θ| = θ_max the angle u = αs - θ reaches max(α, θ_max - α), and cos u ≈ 1 errs
    by 1 - cos u. The note gives θ_max, θ_max/α and that error when it passes
    :data:`SMALL_ANGLE_TOLERANCE` ("" otherwise, for a frame that is not a rigid block, or for
    one that never rocked).

    Parameters
    ----------
    x_c_m, x_star_m
        The model's x_c and x* [m].
    height_m
        h, with x = hθ [m] (None: not known, no note).
    peak_abs_x_m
        Largest |x| reached [m].
    """
    if x_c_m != 0.0 or not height_m or not peak_abs_x_m > 0.0:
        return ""
    alpha = x_star_m / height_m
    theta = peak_abs_x_m / height_m
    error = 1.0 - math.cos(max(alpha, theta - alpha))
    if error <= SMALL_ANGLE_TOLERANCE:
        return ""
    return (
        f"linearised rocking block: peak rotation {theta:.3g} rad = {theta / alpha:.3g} α, "
        f"where cos(α - θ) ≈ 1 errs by {100 * error:.2g} % (the full equation: "
        "stepframe.structure.rocking_block)"
    )


# ----------------------------------------------------------------------------- kernel
