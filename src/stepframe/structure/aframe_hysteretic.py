"""The stepping A-frame with its hysteretic damping (eqs. 4.1-4.2), integrated piecewise exactly.

In the unstepped phase the hysteretic term πξ₁ω₁² sign(ẋ)|x| equals πξ₁ω₁² σ_v σ_x x with
σ_v = sign ẋ and σ_x = sign x, so between the zeros of x and of ẋ eq. 4.1 is the *linear*
undamped oscillator ẍ + k x = -P₁ẍ_g with k = ω₁²(1 + πξ₁σ_vσ_x): stiffer moving away from
x = 0, softer moving back (the loop dissipates 2πξ₁ω₁²A² per cycle). The stepped phase (eq. 4.2)
is linear with k = -ω₂² sec θ. With ground acceleration linear between samples each piece has the
closed form of the sampled-record kernel (:mod:`stepframe.structure._exact`, with β = 0): its
zeros of ẍ are closed form, so ẋ is monotone between them and x monotone between the zeros of ẋ,
and every event (x = 0, ẋ = 0, |x| = x_c, touchdown, cap) is located by bracketed Newton on it.
The peak is read at the extrema of the phase solution, in the stepped phase too.

**Sticking.** At ẋ = 0, sign(ẋ) in eq. 4.1 is any value in [-1, 1]: the hysteretic force can hold
the frame at rest while F = -ω₁²x - P₁ẍ_g stays within ±W, W = πξ₁ω₁²|x| (the Filippov sliding
state; the ground's force within the window ω₁²|x|(1 ∓ πξ₁)). A frame whose velocity reaches 0
with |F| ≤ W sticks; it leaves when F passes ±W, a time in closed form because F is linear
between samples. On the surface |x| = x_c a frame at rest is held while the unstepped phase
pushes it out and the stepped phase pushes it back, and lifts off when the stepped phase's push
turns outward. Under a constant load the motion is a chain of closed-form half cycles ending
stuck, under a slow harmonic it sticks at each reversal of the ground
(tests/structure/test_aframe_sticking.py, against an independent solve_ivp integrator).

The integrator is exact for the model up to rounding; :func:`equivalent_viscous_error`
measures what the simulator's substitute (``AFrame.to_portal_frame(hysteretic=
"equivalent-viscous")``) gets wrong.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.core.jit import njit
from stepframe.core.results import Status
from stepframe.errors import InputError
from stepframe.structure._exact import (
    _acc_at,
    _ecs,
    _inflections,
    _root,
    _segment,
    _v_at,
    _x_at,
)

if TYPE_CHECKING:
    import pandas as pd

    from stepframe.structure.frame import AFrame

#: Phase codes: unstepped and moving (its direction held apart), stepped on side ±1, stuck.
_MOVING = 0
_STUCK = 3
#: Ulps of their terms within which x and the forces at rest are taken as zero.
_ULPS = 64.0
_EPS = 2.2e-16


@njit(cache=True)
def _x_round(seg: Any, sig: float) -> float:
    """Rounding of x from the closed form at σ [m]: a few ulps of its terms."""
    a_p, b_p, y0, y1, _y2, _y3, beta, _k, disc = seg
    ec, es = _ecs(beta, disc, sig)
    return float(_ULPS * _EPS * (abs(a_p) + abs(b_p * sig) + abs(y0 * ec) + abs(y1 * es)))


@njit(cache=True)
def _turn(seg: Any, lo: float, hi: float, d: float) -> float:
    """Zero of ẋ on (lo, hi) where ẋ leaves lo with the sign d and ends with -d.

    Bracketed Newton (ẍ as derivative) like the sampled kernel's root finder, which cannot start
    from a velocity that is exactly 0 at ``lo`` (a frame leaving rest or a stuck state).
    """
    s = 0.5 * (lo + hi)
    for _ in range(200):
        f = _v_at(seg, s)
        if f == 0.0:
            return s
        if (f > 0.0) == (d > 0.0):
            lo = s
        else:
            hi = s
        df = _acc_at(seg, s)
        s_new = 0.5 * (lo + hi)
        if df != 0.0:
            cand = s - f / df
            if lo < cand < hi:
                s_new = cand
        if abs(s_new - s) <= 2.2e-16 * abs(s_new) or hi - lo <= 4.4e-16 * hi:
            return s_new
        s = s_new
    return s


@njit(cache=True)
def _forces(x: float, ag: float, prm: np.ndarray) -> tuple[float, float, float]:
    """At rest at x: (F, W, m). F = -ω₁²x - P₁ẍ_g is the force the hysteretic term must hold,
    W = πξ₁ω₁²|x| the most it can hold (sign(0) ∈ [-1, 1]), and m the outward acceleration of
    the stepped phase on the side of x at x_c, ω₂'²x_c - γ₁' - sP₂'ẍ_g."""
    w1, w2, g1, p1, p2, xi1, xc = prm[0], prm[1], prm[2], prm[3], prm[4], prm[5], prm[6]
    s = 1.0 if x >= 0.0 else -1.0
    return -w1 * w1 * x - p1 * ag, math.pi * xi1 * w1 * w1 * abs(x), w2 * w2 * xc - g1 - s * p2 * ag


@njit(cache=True)
def _force_tol(ag: float, prm: np.ndarray) -> float:
    """Rounding of the forces of :func:`_forces` [m/s²]."""
    w1, w2, g1, p1, p2, xc = prm[0], prm[1], prm[2], prm[3], prm[4], prm[6]
    return float(_ULPS * _EPS * (w1 * w1 * xc + w2 * w2 * xc + g1 + (p1 + p2) * abs(ag)))


@njit(cache=True)
def _at_rest(x: float, ag: float, prm: np.ndarray, lift_ok: bool) -> tuple[int, float]:
    """(phase, direction) of the frame at rest at x under ground acceleration ``ag``.

    Inside the unstepped range it moves the way F points once |F| passes W, else it sticks
    (the Filippov sliding state of eq. 4.1 at ẋ = 0). On the surface |x| = x_c it lifts off
    when the stepped phase pushes out (m > 0, unless ``lift_ok`` is False: a contact just made),
    moves in when F points in beyond W, and else is held there (stuck).
    """
    xc = prm[6]
    f, w, m = _forces(x, ag, prm)
    tol = _force_tol(ag, prm)
    s = 1.0 if x >= 0.0 else -1.0
    if abs(x) == xc:
        if lift_ok and m > tol:
            return int(s), s
        if s * f < -w - tol:
            return _MOVING, -s
        return _STUCK, 0.0
    if f > w + tol:
        return _MOVING, 1.0
    if f < -w - tol:
        return _MOVING, -1.0
    return _STUCK, 0.0


@njit(cache=True)
def _stuck_exit(
    x: float, a0: float, slope: float, rem: float, prm: np.ndarray, lift_ok: bool
) -> tuple[float, int, float]:
    """(σ, phase, direction) at which a frame stuck at x leaves, ground a0 + slope·σ (σ ≥ rem:
    it stays). F and m are linear in σ and W constant, so each exit time is closed form; a lift
    off the surface is not an exit while ``lift_ok`` is False."""
    xc, p1, p2 = prm[6], prm[3], prm[4]
    f0, w, m0 = _forces(x, a0, prm)
    tol = _force_tol(abs(a0) + abs(slope) * rem, prm)
    s = 1.0 if x >= 0.0 else -1.0
    df = -p1 * slope
    best = math.inf
    phase = _STUCK
    d = 0.0
    on_surface = abs(x) == xc
    # Moving out (+1) or in (-1) relative to the side of x: F·s crossing +W or -W.
    for sgn in (1.0, -1.0):
        if on_surface and sgn > 0.0:
            continue
        rate = sgn * s * df
        if rate > 0.0:
            t = (w + tol - sgn * s * f0) / rate
            t = max(t, 0.0)
            if t < best:
                best = t
                phase = _MOVING
                d = sgn * s
    if on_surface and lift_ok:
        rate = -s * p2 * slope
        if rate > 0.0:
            t = max((tol - m0) / rate, 0.0)
            if t < best:
                best = t
                phase = int(s)
                d = s
    return best, phase, d


@njit(cache=True)
def integrate_aframe(
    ag: np.ndarray,
    dt: float,
    n_tail: int,
    prm: np.ndarray,
    max_events: int,
    x0: float,
    v0: float,
    hist_x: np.ndarray,
) -> tuple[int, float, float, int, int, int, int, float, float, float, float]:
    """Eqs. 4.1-4.2 through ``ag`` [m/s²] (linear between samples) and n_tail free samples.

    ``prm`` = (ω₁, ω₂√sec θ, γ₁ sec θ, P₁, P₂ sec θ, ξ₁, x_c, C_r, x_cap). ``hist_x`` (length ≥
    samples + 1, or 0) receives x at every sample time.

    Returns
    -------
    (status, peak |x|, t_peak, overturned, n_liftoffs, n_impacts, n_sticks, t_first_stick,
    x_end, v_end, t_end)
    """
    w1, w2, g1, p1, p2, xi1, xc, cr, xcap = (
        prm[0], prm[1], prm[2], prm[3], prm[4], prm[5], prm[6], prm[7], prm[8],
    )  # fmt: skip
    x_star = g1 / (w2 * w2)
    v_eps = 1e-7 * w2 * x_star
    n_rec = ag.shape[0] - 1
    no_cap = xcap == math.inf
    # Largest |ẍ_g| still to come from each sample (the certain-escape bound during the record).
    suffix = np.zeros(n_rec + 2)
    for jj in range(n_rec, -1, -1):
        suffix[jj] = max(abs(ag[jj]), suffix[jj + 1])
    do_hist = hist_x.shape[0] > 0
    x = x0
    v = v0
    n_lift = 0
    lift_ok = True
    if abs(x) > xc or (abs(x) == xc and x * v > 0.0):
        phase = 1 if x > 0.0 else -1
        sv = 0.0
        n_lift = 1 if abs(x) == xc else 0
    elif v != 0.0:
        phase = _MOVING
        sv = 1.0 if v > 0.0 else -1.0
    else:
        phase, sv = _at_rest(x, ag[0], prm, True)
    peak = abs(x)
    t_peak = 0.0
    n_imp = 0
    # Sticks entered during the run (a frame that starts at rest is not counted).
    n_stick = 0
    t_stick = math.nan
    n_ev = 0
    if do_hist:
        hist_x[0] = x
    for i in range(n_rec + n_tail):
        a0 = ag[i] if i < n_rec else 0.0
        a1 = ag[i + 1] if i < n_rec else 0.0
        slope = (a1 - a0) / dt
        t0 = i * dt
        if (phase == 1 or phase == -1) and (no_cap or i >= n_rec):
            # Beyond reach of return whatever the rest of the record does (free: the exact
            # separatrix; ξ₂ = 0, so λ₂ = -ω₂').
            s = float(phase)
            y_e = (g1 + p2 * (suffix[i] if i < n_rec else 0.0)) / (w2 * w2)
            if s * v + w2 * (s * x - y_e) > 0.0:
                return (0, peak, t_peak, 1, n_lift, n_imp, n_stick, t_stick, x, v, t0)
        tau = 0.0
        fresh = False
        while tau < dt:
            n_ev += 1
            if n_ev > max_events:
                return (2, peak, t_peak, 0, n_lift, n_imp, n_stick, t_stick, x, v, t0 + tau)
            rem = dt - tau
            a_now = a0 + slope * tau
            if phase == _STUCK:
                # A contact's latch (no lift straight back out) lasts until the stepped phase's
                # push is no longer outward; m is linear over the interval, so once it is not
                # outward at the start it cannot be again before the next sample.
                m_now = _forces(x, a_now, prm)[2]
                lift_ok = lift_ok or m_now <= _force_tol(a_now, prm)
                sig, new_phase, d = _stuck_exit(x, a_now, slope, rem, prm, lift_ok)
                if sig >= rem:
                    tau = dt
                    break
                tau += sig
                v = 0.0
                phase = new_phase
                sv = d
                fresh = True
                lift_ok = True
                if phase != _MOVING:
                    n_lift += 1
                continue
            if phase == _MOVING:
                sx = 1.0 if x > 0.0 else (-1.0 if x < 0.0 else sv)
                k = w1 * w1 * (1.0 + math.pi * xi1 * sv * sx)
                q0 = -p1 * a_now
                q1 = -p1 * slope
            else:
                k = -w2 * w2
                q0 = -float(phase) * g1 - p2 * a_now
                q1 = -p2 * slope
            seg = _segment(0.0, k, -k, q0, q1, x, v)
            infl = _inflections(seg, rem)
            n_knots = infl.shape[0]
            s_ph = float(phase) if phase != _MOVING else 0.0
            on_surface = abs(x) == xc
            d_a = v
            if d_a == 0.0:
                d_a = sv if phase == _MOVING else s_ph
            a_k = 0.0
            x_a = x
            first = True
            ev = 0  # 1 x = 0, 2 lift-off, 3 turning point, 4 touchdown, 5 cap, 6 contact
            ev_sig = 0.0
            for j in range(n_knots + 1):
                b_k = infl[j] if j < n_knots else rem
                v_b = _v_at(seg, b_k)
                n_sub = 1
                e0 = b_k
                if (d_a > 0.0 and v_b < 0.0) or (d_a < 0.0 and v_b > 0.0):
                    e0 = _turn(seg, a_k, b_k, d_a)
                    n_sub = 2
                for sub in range(n_sub):
                    e_k = e0 if sub == 0 else b_k
                    at_turn = n_sub == 2 and sub == 0
                    x_b = _x_at(seg, e_k)
                    departing = first and on_surface and fresh
                    if phase == _MOVING:
                        if (x_a > 0.0 and x_b <= 0.0) or (x_a < 0.0 and x_b >= 0.0):
                            ev = 1
                            ev_sig = _root(seg, a_k, e_k, 0.0, 0)
                        elif abs(x_b) >= xc and abs(x_a) < xc:
                            ev = 2
                            ev_sig = _root(seg, a_k, e_k, xc if x_b > 0.0 else -xc, 0)
                        elif departing and at_turn and abs(x_b) >= xc - _x_round(seg, e_k):
                            # Back to the surface within rounding: at rest there.
                            ev = 6
                            ev_sig = e_k
                        elif abs(x_b) > xc + _x_round(seg, e_k):
                            return (4, peak, t_peak, 0, n_lift, n_imp, n_stick, t_stick, x_b,
                                    _v_at(seg, e_k), t0 + tau + e_k)  # fmt: skip
                        elif at_turn:
                            ev = 3
                            ev_sig = e_k
                    else:
                        s = s_ph
                        fa = s * x_a - xc
                        fb = s * x_b - xc
                        rnd = _x_round(seg, e_k)
                        if departing and fa == 0.0 and fb <= 0.0:
                            if at_turn and -fb <= rnd:
                                ev = 6
                                ev_sig = e_k
                            elif fb < -rnd:
                                return (4, peak, t_peak, 0, n_lift, n_imp, n_stick, t_stick, x_b,
                                        _v_at(seg, e_k), t0 + tau + e_k)  # fmt: skip
                        elif fb <= 0.0 and (fa > 0.0 or fb < 0.0):
                            if fa > 0.0:
                                ev_sig = _root(seg, a_k, e_k, s * xc, 0)
                            elif -fa <= _x_round(seg, a_k):
                                ev_sig = a_k
                            else:
                                return (4, peak, t_peak, 0, n_lift, n_imp, n_stick, t_stick,
                                        x_a, _v_at(seg, a_k), t0 + tau + a_k)  # fmt: skip
                            ev = 4
                        elif xcap < math.inf and s * x_a < xcap <= s * x_b:
                            ev = 5
                            ev_sig = _root(seg, a_k, e_k, s * xcap, 0)
                    if ev != 0:
                        break
                    if abs(x_b) > peak:
                        peak = abs(x_b)
                        t_peak = t0 + tau + e_k
                    a_k = e_k
                    x_a = x_b
                    first = False
                if ev != 0:
                    break
                d_a = v_b
                if d_a == 0.0:
                    d_a = _acc_at(seg, b_k)
            if ev == 0:
                x = _x_at(seg, rem)
                v = _v_at(seg, rem)
                tau = dt
                if not (math.isfinite(x) and math.isfinite(v)):
                    return (1, peak, t_peak, 0, n_lift, n_imp, n_stick, t_stick, x, v, t0 + dt)
                break
            v_ev = _v_at(seg, ev_sig)
            x_ev = _x_at(seg, ev_sig)
            tau += ev_sig
            t_ev = t0 + tau
            fresh = True
            lift_ok = True
            a_ev = a0 + slope * tau
            if ev == 1 and v_ev == 0.0:
                ev = 3  # turning exactly at x = 0: at rest there
            if ev == 1:
                x = 0.0
                v = v_ev
            elif ev == 2:
                x = xc if x_ev > 0.0 else -xc
                v = v_ev
                phase = 1 if x > 0.0 else -1
                n_lift += 1
            elif ev == 3 or ev == 6:
                x = x_ev
                if ev == 6 or abs(x) > xc:
                    x = math.copysign(xc, x_ev)
                    lift_ok = ev == 3 or phase == _MOVING
                if ev == 6 and phase != _MOVING:
                    n_imp += 1
                v = 0.0
                phase, sv = _at_rest(x, a_ev, prm, lift_ok)
                if phase == 1 or phase == -1:
                    n_lift += 1
            elif ev == 4:
                s = s_ph
                x = s * xc
                v = cr * v_ev
                n_imp += 1
                if abs(v) <= v_eps:
                    v = 0.0
                    phase, sv = _at_rest(x, a_ev, prm, True)
                    if phase == 1 or phase == -1:
                        n_lift += 1
                else:
                    phase = _MOVING
                    sv = -s
            else:
                x = s_ph * xcap
                peak = max(peak, xcap)
                return (0, peak, t_ev, 1, n_lift, n_imp, n_stick, t_stick, x, v_ev, t_ev)
            if abs(x) > peak:
                peak = abs(x)
                t_peak = t_ev
            if phase == _STUCK:
                n_stick += 1
                if math.isnan(t_stick):
                    t_stick = t_ev
        if do_hist and i + 1 < hist_x.shape[0]:
            hist_x[i + 1] = x
    t_end = (n_rec + n_tail) * dt
    return (0, peak, t_peak, 0, n_lift, n_imp, n_stick, t_stick, x, v, t_end)


def _params(frame: AFrame) -> np.ndarray:
    w2, g1, p2 = frame.stepped_constants
    cap = math.inf if frame.x_cap_m is None else float(frame.x_cap_m)
    return np.array(
        [frame.omega_1_rad_s, w2, g1, frame.p_1, p2, frame.xi_1, frame.x_c_m, frame.c_r, cap]
    )


@dataclass(frozen=True)
class AFrameRun:
    """Summary of one hysteretic A-frame run (SI units).

    Attributes
    ----------
    peak_abs_x_m, peak_time_s
        Largest |x| [m] (at the extrema of the phase solution, not at samples) and its time [s].
    overturned
        The cap was reached, or a stepped state was beyond return (the certain-escape test).
    n_liftoffs, n_impacts
        Event counts.
    n_sticks, first_stick_s
        Times the frame stuck (ẋ = 0 held by the hysteretic force) and the first of them [s]
        (NaN: never).
    residual_x_m, residual_v_m_s
        State at the end [m, m/s].
    status, message
        One of :data:`stepframe.core.results.STATUSES` and what went wrong ("" when "ok").
    history_x_m
        x at every sample time [m] when asked for (NaN after a run that stopped), else None.
    """

    peak_abs_x_m: float
    peak_time_s: float
    overturned: bool
    n_liftoffs: int
    n_impacts: int
    n_sticks: int
    first_stick_s: float
    residual_x_m: float
    residual_v_m_s: float
    status: Status
    message: str = ""
    history_x_m: np.ndarray | None = None


def simulate_aframe(
    frame: AFrame,
    ground_acc_m_s2: Any,
    dt_s: float,
    *,
    scale: float = 1.0,
    tail_s: float = 10.0,
    x0_m: float = 0.0,
    v0_m_s: float = 0.0,
    max_events: int = 10_000_000,
    record_history: bool = False,
) -> AFrameRun:
    """Response of the A-frame (eqs. 4.1-4.2, hysteretic damping) to a record.

    Parameters
    ----------
    frame
        An :class:`~stepframe.structure.frame.AFrame`.
    ground_acc_m_s2
        Ground acceleration [m/s²], linear between samples.
    dt_s
        Sampling interval [s].
    scale
        Record scale factor.
    tail_s
        Free vibration after the record [s]; overturning in it is decided by the exact escape
        test of the stepped phase (no damping there: s·ẋ + ω₂'(s·x - x*) > 0).
    x0_m, v0_m_s
        Initial state [m, m/s].
    max_events
        Bound on pieces and events (status ``too_many_events`` beyond).
    record_history
        Keep x at every sample time (:attr:`AFrameRun.history_x_m`).

    Raises
    ------
    InputError
        A bad record or time step; ξ₁ within 1e-6 of 1/π, where the unloading stiffness
        ω₁²(1 - πξ₁) of the closed form vanishes; work beyond :mod:`stepframe.structure.work`.
    """
    from stepframe.structure import work
    from stepframe.structure.status import (
        STATUS_MESSAGES,
        STATUS_NAMES,
        no_escape_bound_m,
        run_invariant,
    )

    ag = np.asarray(ground_acc_m_s2, dtype=float) * float(scale)
    if ag.ndim != 1 or ag.size < 2 or not np.all(np.isfinite(ag)):
        raise InputError("ground_acc_m_s2 must be a finite 1-D series, expected ≥ 2 samples")
    if not (math.isfinite(dt_s) and dt_s > 0):
        raise InputError(f"dt_s = {dt_s}, expected > 0")
    if abs(1.0 - math.pi * frame.xi_1) < 1e-6:
        raise InputError(
            f"xi_1 = {frame.xi_1} is within 1e-6 of 1/π, where the unloading stiffness "
            "ω₁²(1 - πξ₁) vanishes, expected |1 - πξ₁| ≥ 1e-6"
        )
    n_tail = math.ceil(max(tail_s, 0.0) / dt_s)
    what = f"an A-frame run of {ag.size} samples at {dt_s:g} s with a {tail_s:g} s tail"
    work.check_work(
        work.INTERVAL_UNITS * (ag.size - 1 + n_tail), what, "shorten the tail or the record"
    )
    hist = np.full(ag.size + n_tail if record_history else 0, np.nan)
    if record_history:
        work.check_samples(hist.size, what, "shorten the tail or pass record_history=False")
    prm = _params(frame)
    st, peak, t_peak, over, nl, ni, n_st, t_st, x_end, v_end, _t_end = integrate_aframe(
        ag, float(dt_s), n_tail, prm, int(max_events), float(x0_m), float(v0_m_s), hist
    )
    bound = no_escape_bound_m(prm[2], prm[4], prm[1], float(np.max(np.abs(ag))), x0_m, prm[8])
    code = run_invariant(int(st), bool(over), float(peak), bound, float(x_end), float(v_end))
    return AFrameRun(
        float(peak), float(t_peak), bool(over), int(nl), int(ni), int(n_st), float(t_st),
        float(x_end), float(v_end), STATUS_NAMES[code], STATUS_MESSAGES[code],
        hist if record_history else None,
    )  # fmt: skip


def equivalent_viscous_error(
    frame: AFrame, records: list[tuple[Any, float]], scales: Any, *, tail_s: float = 10.0
) -> pd.DataFrame:
    """Peak |x| and overturning by the hysteretic model against its equivalent-viscous substitute.

    One row per (record, scale): ``peak_hysteretic_m``, ``peak_viscous_m``, ``rel_error`` (viscous
    over hysteretic minus 1), both overturning verdicts and the hysteretic run's status.
    :func:`equivalent_viscous_summary` reduces it.
    """
    import warnings

    import pandas as pd

    from stepframe.structure.frame import EquivalentViscousWarning
    from stepframe.structure.simulator import simulate

    with warnings.catch_warnings():
        # Measuring the substitute is the point here.
        warnings.simplefilter("ignore", EquivalentViscousWarning)
        viscous = frame.to_portal_frame(hysteretic="equivalent-viscous")
    rows = []
    for r, (acc, dt) in enumerate(records):
        for s in np.atleast_1d(np.asarray(scales, dtype=float)):
            hyst = simulate_aframe(frame, acc, dt, scale=float(s), tail_s=tail_s)
            vis = simulate(viscous, acc, dt, scale=float(s), tail_s=tail_s, record_history=False)
            rows.append(
                {
                    "record": r,
                    "scale": float(s),
                    "peak_hysteretic_m": hyst.peak_abs_x_m,
                    "peak_viscous_m": vis.summary.peak_abs_x_m,
                    "rel_error": vis.summary.peak_abs_x_m / hyst.peak_abs_x_m - 1.0
                    if hyst.peak_abs_x_m > 0
                    else math.nan,
                    "overturned_hysteretic": hyst.overturned,
                    "overturned_viscous": vis.summary.overturned,
                    "status": hyst.status if vis.summary.status == "ok" else vis.summary.status,
                }
            )
    return pd.DataFrame(rows)


def equivalent_viscous_summary(table: pd.DataFrame) -> dict[str, Any]:
    """Median and worst error of the equivalent-viscous route in a table of
    :func:`equivalent_viscous_error`.

    Returns
    -------
    dict
        ``all_runs``; ``runs``, those that neither model overturned (both "ok", a finite error);
        over them ``median_abs_rel_error`` (median of |viscous/hysteretic - 1|) and
        ``worst_rel_error`` (the signed error of largest size) with its ``worst_record``; and
        ``verdicts_differing``, the runs that one model overturned and the other did not.
    """
    both = table[
        ~table["overturned_hysteretic"]
        & ~table["overturned_viscous"]
        & (table["status"] == "ok")
        & np.isfinite(table["rel_error"])
    ]
    errors = both["rel_error"].to_numpy(dtype=float)
    worst = int(np.argmax(np.abs(errors))) if errors.size else -1
    return {
        "all_runs": len(table),
        "runs": len(both),
        "median_abs_rel_error": float(np.median(np.abs(errors))) if errors.size else math.nan,
        "worst_rel_error": float(errors[worst]) if errors.size else math.nan,
        "worst_record": int(both["record"].iloc[worst]) if errors.size else None,
        "verdicts_differing": int(
            (table["overturned_hysteretic"] != table["overturned_viscous"]).sum()
        ),
    }
