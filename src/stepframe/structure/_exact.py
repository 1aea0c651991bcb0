"""Numba kernels of the exact piecewise-analytic stepping-frame integrator.

Within one sample interval the ground acceleration is linear, so each phase of eqs. 4.11-4.12 is a
constant-coefficient linear ODE with linear forcing::

    ẍ + 2βẋ + kx = q₀ + q₁σ        (σ: time since the segment start)

with β = ξω and k = ω₁² (unstepped) or k = -ω₂² (stepped, q₀ holding -sγ₁). Its solution is the
affine particular solution x_p = A + Bσ plus a homogeneous part y, and every derivative of y obeys
the same rule::

    f(σ) = f(0)·(E_C + βE_S) + f'(0)·E_S,   E_C = e^{-βσ}C(σ),  E_S = e^{-βσ}S(σ),

where C = cos, cosh or 1 and S = sin(dσ)/d, sinh(dσ)/d or σ for d² = |β² - k| (under-damped,
over-damped/negative stiffness, critical). One formula therefore covers every case, and stays
continuous through critical damping.

Events are found without sampling: the zeros of ẍ (inflections of x) are closed form, so the
segment is cut into pieces where ẋ is monotone; each holds at most one zero of ẋ (a true extremum
of x, found by bracketed Newton), which cuts it into pieces where x is monotone; on each of those a
threshold crossing is bracketed by the end values and found by bracketed Newton. A brief excursion
past x_c between two samples (grazing) is therefore never missed. Most intervals hold nothing to
locate: :func:`_fast_step` proves that from the interval's end values and a bound of ẍ (the chord
bound) or of x⁽³⁾ (x monotone), and takes the closed form's end state in a few products.

Phase codes: 0 unstepped, +1/-1 stepped on that side, +2/-2 held at x = ±x_c with ẋ = 0 (the
contact force balance keeps the frame on the switching surface). An impact whose rebound is too
small to follow by root finding is handled by :func:`_impact_rule`: its excursion, or the whole
accumulating sequence of impacts (chatter), is summed in closed form and the frame is seated
until the ground can lift it again (docs/paper-notes.md, "Chatter").

Without a cap, a stepped state beyond reach of return, s·ẋ - λ₂(s·x - y_e) > 0 with
y_e = (γ₁ + P₂·max|ẍ_g| over the rest of the record)/ω₂², is an overturn from that sample on
(the comparison argument is in docs/paper-notes.md); a run that does not overturn therefore never
passes y_e, and one that does is reported as failed rather than as a success.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from stepframe.core.jit import njit
from stepframe.structure.status import (
    CHATTER_DRIFT,
    CHATTER_EPS,
    EVENT_CAP,
    EVENT_ESCAPE,
    EVENT_LIFTOFF,
    EVENT_SETTLE,
    EVENT_TOUCHDOWN,
    INVARIANT_RTOL,
    STATUS_IMPOSSIBLE,
    STATUS_INVARIANT,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_TOO_MANY_EVENTS,
)

#: Bound on events located inside one sample interval before the kernel gives up (a chattering
#: trajectory the hold state did not catch).
_MAX_EVENTS_PER_INTERVAL = 10_000

#: Bound on free-vibration intervals added after the tail while an escaping frame reaches x_cap.
_MAX_EXTRA_INTERVALS = 10_000_000

_TWO_PI = 2.0 * math.pi


# This and the three evaluators below are compiled functions of their own, which LLVM inlines:
# numba's IR inlining (inline="always") made integrate's first compilation 1.6 times as long.
@njit(cache=True)
def _ecs(beta: float, disc: float, sig: float) -> tuple[float, float]:
    """E_C(σ), E_S(σ) for decay β and discriminant β² - k (sign selects the case)."""
    if disc < 0.0:
        d = math.sqrt(-disc)
        e = math.exp(-beta * sig)
        return e * math.cos(d * sig), e * (math.sin(d * sig) / d)
    if disc > 0.0:
        d = math.sqrt(disc)
        z = d * sig
        if z < 20.0:
            e = math.exp(-beta * sig)
            return e * math.cosh(z), e * (math.sinh(z) / d)
        # Split the exponentials: e^{-βσ}cosh(dσ) overflows in parts but not as a whole.
        ep = math.exp((d - beta) * sig)
        em = math.exp(-(d + beta) * sig)
        return 0.5 * (ep + em), 0.5 * (ep - em) / d
    e = math.exp(-beta * sig)
    return e, e * sig


@njit(cache=True)
def _x_at(seg: Any, sig: float) -> float:
    a_p, b_p, y0, y1, _y2, _y3, beta, _k, disc = seg
    ec, es = _ecs(beta, disc, sig)
    x: float = a_p + b_p * sig + y0 * (ec + beta * es) + y1 * es
    return x


@njit(cache=True)
def _v_at(seg: Any, sig: float) -> float:
    _a, b_p, _y0, y1, y2, _y3, beta, _k, disc = seg
    ec, es = _ecs(beta, disc, sig)
    v: float = b_p + y1 * (ec + beta * es) + y2 * es
    return v


@njit(cache=True)
def _acc_at(seg: Any, sig: float) -> float:
    _a, _b, _y0, _y1, y2, y3, beta, _k, disc = seg
    ec, es = _ecs(beta, disc, sig)
    a: float = y2 * (ec + beta * es) + y3 * es
    return a


@njit(cache=True)
def _segment(beta: float, k: float, disc: float, q0: float, q1: float, x0: float, v0: float) -> Any:
    """Coefficients of one phase segment from its start state and linear forcing q₀ + q₁σ."""
    b_p = q1 / k
    a_p = (q0 - 2.0 * beta * b_p) / k
    y0 = x0 - a_p
    y1 = v0 - b_p
    y2 = -2.0 * beta * y1 - k * y0
    y3 = -2.0 * beta * y2 - k * y1
    return (a_p, b_p, y0, y1, y2, y3, beta, k, disc)


@njit(cache=True)
def _inflections(seg: Any, length: float) -> np.ndarray:
    """Sorted zeros of ẍ in (0, length): closed form from ÿ = e^{-βσ}(u·C + w·S)."""
    _a, _b, _y0, _y1, u, y3, beta, _k, disc = seg
    w = y3 + beta * u
    if disc < 0.0:
        d = math.sqrt(-disc)
        if w == 0.0:
            if u == 0.0:
                return np.empty(0)
            z0 = 0.5 * math.pi
        else:
            # tan(dσ) = -u·d/w; atan keeps σ accurate when d is small (near-critical damping).
            z0 = math.atan(-u * d / w)
            if z0 <= 0.0:
                z0 += math.pi
        n = 0
        if z0 < d * length:
            n = int((d * length - z0) / math.pi) + 1
        out = np.empty(n)
        m = 0
        for i in range(n):
            s = (z0 + i * math.pi) / d
            if 0.0 < s < length:
                out[m] = s
                m += 1
        return out[:m]
    if disc > 0.0:
        d = math.sqrt(disc)
        if w == 0.0:
            return np.empty(0)
        ratio = -u * d / w
        if 0.0 < ratio < 1.0:
            s = math.atanh(ratio) / d
            if s < length:
                out = np.empty(1)
                out[0] = s
                return out
        return np.empty(0)
    if w != 0.0:
        s = -u / w
        if 0.0 < s < length:
            out = np.empty(1)
            out[0] = s
            return out
    return np.empty(0)


@njit(cache=True)
def _root(seg: Any, lo: float, hi: float, target: float, deriv: int) -> float:
    """Root of x(σ) - target (deriv = 0) or ẋ(σ) (deriv = 1) on a bracket where it is monotone.

    Newton on the closed form (its derivative is ẋ or ẍ), kept inside the bracket by bisection.
    """
    f_lo = _x_at(seg, lo) - target if deriv == 0 else _v_at(seg, lo)
    if f_lo == 0.0:
        return lo
    s = 0.5 * (lo + hi)
    for _ in range(200):
        if deriv == 0:
            f = _x_at(seg, s) - target
            df = _v_at(seg, s)
        else:
            f = _v_at(seg, s)
            df = _acc_at(seg, s)
        if f == 0.0:
            return s
        if (f > 0.0) == (f_lo > 0.0):
            lo = s
        else:
            hi = s
        step_ok = False
        if df != 0.0:
            s_new = s - f / df
            if lo < s_new < hi:
                step_ok = True
        if not step_ok:
            s_new = 0.5 * (lo + hi)
        if abs(s_new - s) <= 2.2e-16 * abs(s_new) or hi - lo <= 4.4e-16 * hi:
            return s_new
        s = s_new
    return s


@njit(cache=True)
def _phase_coeffs(
    phase: int,
    w1: float,
    w2: float,
    p1: float,
    p2: float,
    g1: float,
    xi1: float,
    xi2: float,
    ag0: float,
    slope: float,
) -> tuple[float, float, float, float, float]:
    """(β, k, β² - k, q₀, q₁) of a phase with ground acceleration ag0 + slope·σ."""
    if phase == 0:
        beta = xi1 * w1
        k = w1 * w1
        disc = w1 * w1 * (xi1 - 1.0) * (xi1 + 1.0)
        return beta, k, disc, -p1 * ag0, -p1 * slope
    s = 1.0 if phase > 0 else -1.0
    beta = xi2 * w2
    k = -w2 * w2
    disc = w2 * w2 * (xi2 * xi2 + 1.0)
    return beta, k, disc, -s * g1 - p2 * ag0, -p2 * slope


@njit(cache=True)
def _surface_phase(
    s: float, ag: float, w1: float, w2: float, p1: float, p2: float, g1: float, xc: float
) -> int:
    """Phase taken at rest (ẋ = 0) on the surface x = s·x_c, from the outward accelerations."""
    out_stepped = w2 * w2 * xc - g1 - s * p2 * ag
    if out_stepped > 0.0:
        return int(s)
    if xc > 0.0:
        out_unstepped = -w1 * w1 * xc - s * p1 * ag
        if out_unstepped < 0.0:
            return 0
    elif -g1 + s * p2 * ag > 0.0:
        # Rigid-block limit: both sides meet at x = 0, the push may tip it the other way.
        return -int(s)
    return 2 * int(s)


@njit(cache=True)
def _impact_rule(
    s: float,
    w: float,
    ag_now: float,
    slope: float,
    rem: float,
    w1: float,
    w2: float,
    p1: float,
    p2: float,
    g1: float,
    xc: float,
    cr: float,
    w_tiny: float,
) -> tuple[int, float, float]:
    """What follows a touchdown on the surface x = s·x_c with rebound speed w = C_r·|ẋ| ≥ 0.

    Returns (kind, delay, w_back): kind 0, follow the rebound by root finding (it enters the
    inner phase with speed w); kind 1, a rebound too small to follow returns to the surface
    after ``delay`` and lifts off again on side s with speed ``w_back``; kind 2, the impacts
    accumulate (chatter) at ``delay`` after this one and the frame is seated from then on.
    C_r = 0 is the limit C_r → 0+: w = 0 gives delay 0, and the inner phase is preferred.
    """
    # Accelerations at rest on the surface, positive away from it: into the inner phase (the
    # unstepped phase, or for the rigid block the stepped phase on the other side) and back out.
    p_in = w1 * w1 * xc + s * p1 * ag_now if xc > 0.0 else -g1 + s * p2 * ag_now
    p_back = w2 * w2 * xc - g1 - s * p2 * ag_now
    # Accelerations within rounding of zero: the sign at this instant is noise, and the seated
    # state (whose exit follows the sign change of the forcing) decides instead.
    p_eps = INVARIANT_RTOL * max(w1, w2) ** 2 * max(xc, g1 / (w2 * w2))
    if w > w_tiny or p_in > p_eps:
        return 0, 0.0, w
    if p_in >= -p_eps:
        return (2, 0.0, 0.0) if w == 0.0 else (0, 0.0, w)
    t_in = 2.0 * w / -p_in
    # Rates of the two accelerations: the closed form holds them constant over its duration.
    rate_in = abs(s * (p1 if xc > 0.0 else p2) * slope)
    rate_back = abs(p2 * slope)
    # Returning from the other side, a rigid block strikes again (x = 0 is its only surface).
    w_back = w if xc > 0.0 else cr * w
    # Below w_tiny/10 the closed form is used even where the forcing drifts: flights that small
    # would soon sink below the rounding of x if followed one by one.
    forced = w <= 0.1 * w_tiny
    # A back push within rounding below zero seats the frame rather than relaunch it: the
    # rebound would turn straight back, and the seated state's exit follows the forcing.
    if p_back > p_eps or (p_back >= 0.0 and w > 0.0):
        if t_in > rem or (rate_in * t_in > CHATTER_DRIFT * -p_in and not forced):
            return 0, 0.0, w
        return 1, t_in, w_back
    if p_back >= -p_eps:
        return 2, 0.0, 0.0
    # Each cycle (in and back out) takes 2w(1/|p_in| + C_back/|p_back|) and multiplies w by
    # C_r (portal frame: one impact per cycle, C_back = 1) or C_r² (block: two, C_back = C_r).
    c_back = 1.0 if xc > 0.0 else cr
    ratio = cr if xc > 0.0 else cr * cr
    cycle = 2.0 * w * (1.0 / -p_in + c_back / -p_back)
    # C_r = 1 does not accumulate; a rebound below w_tiny is then taken as rest after one cycle.
    delay = cycle / (1.0 - ratio) if ratio < 1.0 else cycle
    drift = max(rate_in * delay / -p_in, rate_back * delay / -p_back)
    if delay > rem or (drift > CHATTER_DRIFT and not forced):
        return 0, 0.0, w
    return 2, delay, 0.0


@njit(cache=True)
def _fast_step(
    x: float,
    v: float,
    q0: float,
    q1: float,
    beta: float,
    k: float,
    bound: Any,
    lo: float,
    hi: float,
    top: float,
) -> tuple[float, float, int]:
    """One interval of a phase in closed form, when nothing inside it needs locating.

    The phase is unstepped or stepped (not held), with forcing q₀ + q₁σ and constants β, k
    (module docstring); ``bound`` holds the phase's constants for dt from
    :func:`_bound_constants`. Returns (x_b, v_b, kind): the state at the interval's
    end and kind 0 (take the slow path: an event or a new peak may lie inside), 1 (x stays in
    (lo, hi), the phase's side of its thresholds, and |x| < ``top``, the running peak,
    throughout) or 2 (x stays in (lo, hi) and is monotone: its largest |x| is at an end).

    Why it is exact. Over the interval the ground acceleration is linear, so x = x_p + y with x_p
    affine (module docstring), hence ẍ = y⁽²⁾ and x⁽³⁾ = y⁽³⁾, and every derivative of y is a
    free vibration of the phase: y⁽ʲ⁾(σ) = e^{-βσ}(y_j·C(σ) + (y_{j+1} + βy_j)·S(σ)), with
    y_{j+2} = -2βy_{j+1} - k·y_j. With β ≥ 0 (e^{-βσ} ≤ 1), on [0, dt]:

    - under-damped (ω_d² = k - β² > 0): C = cos ω_dσ, S = sin(ω_dσ)/ω_d, so
      |y⁽ʲ⁾| ≤ M_j = √(y_j² + (y_{j+1} + βy_j)²/ω_d²);
    - over- or critically damped unstepped phase (0 ≤ d² = β² - k < β²): e^{-βσ}cosh dσ ≤ 1 and
      e^{-βσ}sinh(dσ)/d ≤ σ, so M_j = |y_j| + |y_{j+1} + βy_j|·dt;
    - stepped phase (k = -ω₂² < 0, d > β): cosh dσ and sinh(dσ)/d grow with σ, so
      M_j = |y_j|·cosh(d·dt) + |y_{j+1} + βy_j|·sinh(d·dt)/d.

    Chord bound: a C² function f on [0, h] with |f''| ≤ M differs from its chord (the line
    through f(0) and f(h)) by g with g(0) = g(h) = 0 and |g''| ≤ M; P(σ) = M·σ(h - σ)/2 has
    the same ends and P'' = -M, so P - g and P + g are concave with zero ends, hence ≥ 0:
    |g(σ)| ≤ M·σ(h - σ)/2 ≤ M·h²/8. With f = x and M = M_2, on the whole interval

        min(x_a, x_b) - M_2·dt²/8 ≤ x(σ) ≤ max(x_a, x_b) + M_2·dt²/8.

    If that range lies inside (lo, hi), x crosses no threshold inside: no lift-off (unstepped),
    no touchdown nor cap (stepped), and a graze of a threshold between samples, which the range
    covers, is never skipped; if it also lies inside (-top, top), no new peak lies inside
    (kind 1). Monotone test: the same bound for f = ẋ with M = M_3 keeps ẋ of one sign when v_a
    and v_b share it and min(|v_a|, |v_b|) > M_3·dt²/8; then x is monotone, its extremes are its
    ends, and both ends in (lo, hi) mean no crossing either (kind 2). Otherwise the slow path
    locates what there is. (The a-priori envelope this replaced, |x_p| + M_0 below x_c and the
    peak, is looser by the whole free-vibration amplitude M_0; the slack here is M_2·dt²/8, about
    (ω₁dt)²/8 of M_0 in the unstepped phase.)
    """
    wd_inv, c_c, c_s, chord, inv_k, e_v, e_x, es = bound
    b_p = q1 * inv_k
    a_p = (q0 - 2.0 * beta * b_p) * inv_k
    # ẍ and x⁽³⁾ at the start, from the equation of motion and its derivative: the y₂ and y₃ of
    # _segment (ÿ = ẍ, x_p being affine), without forming y₀ and y₁, so that x_b and v_b are
    # each one short chain of products from the state (as in Nigam-Jennings): the same closed
    # form as _x_at and _v_at at σ = dt, rearranged, so equal to them up to rounding.
    y2 = q0 - 2.0 * beta * v - k * x
    y3 = q1 - 2.0 * beta * y2 - k * v
    x_b = e_v * x + es * v + (1.0 - e_v) * a_p + e_x * b_p
    v_b = e_v * v + es * y2 + (1.0 - e_v) * b_p
    low = min(x, x_b)
    high = max(x, x_b)
    if not (lo < low and high < hi):
        return x_b, v_b, 0
    q = y3 + beta * y2
    # Room left between the ends and the thresholds, and the peak, against the reach M_2·dt²/8
    # (compared squared where M_2 is a root: no square root on the fast path).
    room = min(low - lo, hi - high, top - high, top + low)
    if room > 0.0:
        if wd_inv > 0.0:
            if (y2 * y2 + q * q * wd_inv) * (chord * chord) < room * room:
                return x_b, v_b, 1
        elif (abs(y2) * c_c + abs(q) * c_s) * chord < room:
            return x_b, v_b, 1
    if (v > 0.0 and v_b > 0.0) or (v < 0.0 and v_b < 0.0):
        y4 = -2.0 * beta * y3 - k * y2
        r = y4 + beta * y3
        speed = min(abs(v), abs(v_b))
        if wd_inv > 0.0:
            if (y3 * y3 + r * r * wd_inv) * (chord * chord) < speed * speed:
                return x_b, v_b, 2
        elif (abs(y3) * c_c + abs(r) * c_s) * chord < speed:
            return x_b, v_b, 2
    return x_b, v_b, 0


# Inlined at the IR level: called twice from integrate only, it costs less there than as a
# compiled function of its own (0.35 s of a first run's compilation).
@njit(cache=True, inline="always")
def _bound_constants(beta: float, k: float, disc: float, dt: float) -> Any:
    """Constants of :func:`_fast_step` for one phase and dt: (ω_d⁻², c_C, c_S, dt²/8, 1/k,
    E_C + βE_S, dt - E_S, E_S) at σ = dt. ω_d⁻² > 0 for an under-damped phase, else 0 and
    M_j = |y_j|·c_C + |y_{j+1} + βy_j|·c_S."""
    chord = dt * dt / 8.0
    ec, es = _ecs(beta, disc, dt)
    tail = (ec + beta * es, dt - es, es)
    if disc < 0.0:
        return (-1.0 / disc, 0.0, 0.0, chord, 1.0 / k, *tail)
    if k > 0.0:
        return (0.0, 1.0, dt, chord, 1.0 / k, *tail)
    d = math.sqrt(disc)
    return (0.0, math.cosh(d * dt), math.sinh(d * dt) / d, chord, 1.0 / k, *tail)


# Called, not inlined at the IR level (inline="always" typed a copy per call site into integrate:
# about 0.5 s of its first compilation); the batch runs as fast (bench/bench_batch_threads.py).
@njit(cache=True)
def _push(
    n_ev: int,
    ev_t: np.ndarray,
    ev_kind: np.ndarray,
    ev_v_in: np.ndarray,
    ev_v_out: np.ndarray,
    ev_peak: np.ndarray,
    t: float,
    kind: int,
    v_in: float,
    v_out: float,
    peak: float,
) -> int:
    """Store one event if there is room; returns the new event count."""
    if n_ev < ev_t.shape[0]:
        ev_t[n_ev] = t
        ev_kind[n_ev] = kind
        ev_v_in[n_ev] = v_in
        ev_v_out[n_ev] = v_out
        ev_peak[n_ev] = peak
    return n_ev + 1


@njit(cache=True)
def integrate(
    ag: np.ndarray,
    dt: float,
    n_tail: int,
    w1: float,
    w2: float,
    p1: float,
    p2: float,
    g1: float,
    xi1: float,
    xi2: float,
    xc: float,
    cr: float,
    xcap: float,
    x0: float,
    v0: float,
    hist_x: np.ndarray,
    hist_v: np.ndarray,
    hist_p: np.ndarray,
    ev_t: np.ndarray,
    ev_kind: np.ndarray,
    ev_v_in: np.ndarray,
    ev_v_out: np.ndarray,
    ev_peak: np.ndarray,
) -> tuple[int, int, int, int, float, float, int, float, float, float, int, float]:
    """Integrate eqs. 4.11-4.12 through the record ``ag`` [m/s²] and a free tail of n_tail steps.

    Histories are written at every sample time when ``hist_x`` has room (length ≥ steps + 1).
    Events are written while the event arrays have room and always counted; ``ev_peak`` holds,
    for a lift-off, the peak |x| of the stepping episode it starts.

    Returns
    -------
    (status, n_events, n_liftoffs, n_impacts, peak_abs_x, t_peak, overturned, t_overturn,
    x_end, v_end, phase_end, t_end)
    """
    n_rec = ag.shape[0] - 1
    cap_ev = ev_t.shape[0]
    do_hist = hist_x.shape[0] > 0
    x_star = g1 / (w2 * w2)
    # Negative root of the stepped phase's characteristic equation (escape test, free motion).
    lam2 = -w2 * (xi2 + math.sqrt(1.0 + xi2 * xi2))
    x_ref = max(xc, x_star)
    w_tiny = CHATTER_EPS * max(w1, w2) * x_ref
    tol_x = INVARIANT_RTOL * x_ref
    # Without a cap: the largest |ẍ_g| still to come from each sample (0 in the free tail), for
    # the certain-escape test during the record.
    no_cap = xcap == math.inf
    suffix = np.zeros(n_rec + 2 if no_cap else 0)
    if no_cap:
        for jj in range(n_rec, -1, -1):
            suffix[jj] = max(abs(ag[jj]), suffix[jj + 1])

    # Full-interval constants of the unstepped and stepped phases, for the fast path.
    beta1 = xi1 * w1
    k1 = w1 * w1
    disc1 = w1 * w1 * (xi1 - 1.0) * (xi1 + 1.0)
    bound1 = _bound_constants(beta1, k1, disc1, dt)
    beta2 = xi2 * w2
    k2 = -w2 * w2
    disc2 = w2 * w2 * (xi2 * xi2 + 1.0)
    bound2 = _bound_constants(beta2, k2, disc2, dt)
    # The fast path's bounds take e^{-βσ} ≤ 1 (β ≥ 0, as frames validate), and keep a margin of
    # tol_x inside the thresholds, far above the rounding of the values they compare.
    fast_ok = beta1 >= 0.0 and beta2 >= 0.0
    lim_x = xc - tol_x
    lim_cap = xcap - tol_x
    x = x0
    v = v0
    if abs(x) < xc:
        phase = 0
    elif abs(x) > xc:
        phase = 1 if x > 0.0 else -1
    else:
        s0 = 1.0 if x >= 0.0 else -1.0
        if v * s0 > 0.0:
            phase = int(s0)
        elif v * s0 < 0.0:
            phase = 0 if xc > 0.0 else -int(s0)
        else:
            phase = _surface_phase(s0, ag[0] if n_rec >= 0 else 0.0, w1, w2, p1, p2, g1, xc)
    status = STATUS_OK
    # int(...), not literals (numba types int(c) as int64, a literal as its own type): numba
    # compiles a called kernel once per literal argument (_push six times, _root twice)
    n_ev = int(0)  # noqa: UP018, RUF046
    k_liftoff, k_touchdown = int(EVENT_LIFTOFF), int(EVENT_TOUCHDOWN)
    k_settle, k_escape, k_cap = int(EVENT_SETTLE), int(EVENT_ESCAPE), int(EVENT_CAP)
    on_x, on_v = int(0), int(1)  # noqa: UP018, RUF046
    n_lift = 0
    n_imp = 0
    peak = abs(x)
    t_peak = 0.0
    overturned = 0
    t_over = math.nan
    cur_lift = -1
    cur_side = 1.0
    ep_peak = 0.0
    if do_hist:
        hist_x[0] = x
        hist_v[0] = v
        hist_p[0] = phase
    if phase == 1 or phase == -1:
        ep_peak = abs(x)
        cur_side = 1.0 if phase > 0 else -1.0
        if abs(x) == xc:
            # Starting on the surface and leaving it outward is a lift-off at t = 0; starting
            # beyond x_c is an episode already under way (no lift-off event).
            n_lift += 1
            cur_lift = 0
            n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                         0.0, k_liftoff, v, v, cur_side * xc)  # fmt: skip

    n_total = n_rec + n_tail
    i = 0
    escape_checked = False
    while True:
        if i >= n_total:
            # Free vibration beyond the tail: only while an escaping frame runs to x_cap.
            if not (overturned == 1 and xcap < math.inf and math.isnan(t_over)):
                break
            if i >= n_total + _MAX_EXTRA_INTERVALS:
                break
        t0 = i * dt
        if i < n_rec:
            ag_a = ag[i]
            ag_b = ag[i + 1]
        else:
            ag_a = 0.0
            ag_b = 0.0
        slope = (ag_b - ag_a) / dt
        in_free = i >= n_rec
        if no_cap and overturned == 0 and (phase == 1 or phase == -1):
            # Beyond reach of return whatever the rest of the record does (paper-notes).
            s = 1.0 if phase > 0 else -1.0
            y_e = (g1 + p2 * (suffix[i] if i < n_rec else 0.0)) / (w2 * w2)
            if s * v - lam2 * (s * x - y_e) > 0.0:
                overturned = 1
                t_over = t0
                n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                             t0, k_escape, v, v, x)  # fmt: skip
                break
        if in_free and not escape_checked:
            escape_checked = True
            if phase == 1 or phase == -1:
                s = 1.0 if phase > 0 else -1.0
                if s * v - lam2 * (s * x - x_star) > 0.0 and overturned == 0:
                    overturned = 1
                    n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                                 t0, k_escape, v, v, x)  # fmt: skip
                    if xcap == math.inf:
                        t_over = t0
                        break

        # Fast path: unstepped or stepped over the whole interval, with no event nor new peak
        # possible inside it (the chord bound and the monotone test of _fast_step).
        if fast_ok and (phase == 0 or phase == 1 or phase == -1):
            if phase == 0:
                x_b, v_b, kind = _fast_step(x, v, -p1 * ag_a, -p1 * slope, beta1, k1, bound1,
                                            -lim_x, lim_x, peak)  # fmt: skip
            else:
                s = 1.0 if phase > 0 else -1.0
                lo, hi = (xc + tol_x, lim_cap) if phase > 0 else (-lim_cap, -xc - tol_x)
                x_b, v_b, kind = _fast_step(x, v, -s * g1 - p2 * ag_a, -p2 * slope, beta2, k2,
                                            bound2, lo, hi, ep_peak)  # fmt: skip
            if kind != 0:
                x = x_b
                v = v_b
                i += 1
                if kind == 2:
                    # x monotone over the interval: its largest |x| is at an end.
                    if abs(x) > peak:
                        peak = abs(x)
                        t_peak = t0 + dt
                    if phase != 0 and abs(x) > ep_peak:
                        ep_peak = abs(x)
                if do_hist and i < hist_x.shape[0]:
                    hist_x[i] = x
                    hist_v[i] = v
                    hist_p[i] = phase
                # (x_b passed its range test, so it is finite.)
                if not math.isfinite(v):
                    status = STATUS_NONFINITE
                    break
                continue

        # Slow path: exact event location inside the interval.
        tau = 0.0
        fresh = False  # the segment starts on the surface just handled
        n_here = 0
        stop = False
        while tau < dt:
            n_here += 1
            if n_here > _MAX_EVENTS_PER_INTERVAL:
                status = STATUS_TOO_MANY_EVENTS
                stop = True
                break
            ag_now = ag_a + slope * tau
            length = dt - tau
            if phase == 2 or phase == -2:
                # Held on the surface: leaves when a phase's outward/inward acceleration turns.
                s = 1.0 if phase > 0 else -1.0
                o2a = w2 * w2 * xc - g1 - s * p2 * ag_now
                o2s = -s * p2 * slope
                o1a = -w1 * w1 * xc - s * p1 * ag_now
                o1s = -s * p1 * slope
                t_leave = math.inf
                new_phase = phase
                if o2s > 0.0:
                    tl = -o2a / o2s
                    if tl < length:
                        t_leave = max(tl, 0.0)
                        new_phase = int(s)
                if xc > 0.0 and o1s < 0.0:
                    tl = -o1a / o1s
                    if tl < length and max(tl, 0.0) < t_leave:
                        t_leave = max(tl, 0.0)
                        new_phase = 0
                if xc == 0.0 and s * p2 * slope > 0.0:
                    tl = (g1 - s * p2 * ag_now) / (s * p2 * slope)
                    if tl < length and max(tl, 0.0) < t_leave:
                        t_leave = max(tl, 0.0)
                        new_phase = -int(s)
                if new_phase == phase:
                    x = s * xc
                    v = 0.0
                    tau = dt
                    break
                tau += t_leave
                phase = new_phase
                x = s * xc
                v = 0.0
                fresh = True
                if phase != 0:
                    n_lift += 1
                    cur_lift = n_ev
                    cur_side = 1.0 if phase > 0 else -1.0
                    ep_peak = xc
                    n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                                 t0 + tau, k_liftoff, 0.0, 0.0, cur_side * xc)  # fmt: skip
                continue

            beta, k, disc, q0, q1 = _phase_coeffs(
                phase, w1, w2, p1, p2, g1, xi1, xi2, ag_now, slope
            )
            seg = _segment(beta, k, disc, q0, q1, x, v)
            infl = _inflections(seg, length)
            # Walk the pieces where x is monotone, in time order.
            n_knots = infl.shape[0]
            a_k = 0.0
            x_a = x
            v_a = _v_at(seg, 0.0)
            event_found = False
            first_piece = True
            for j in range(n_knots + 1):
                b_k = infl[j] if j < n_knots else length
                v_b = _v_at(seg, b_k)
                # A zero of ẋ splits the piece (ẋ is monotone here: at most one).
                ends = (b_k, b_k)
                n_sub = 1
                if (v_a > 0.0 and v_b < 0.0) or (v_a < 0.0 and v_b > 0.0):
                    ends = (_root(seg, a_k, b_k, 0.0, on_v), b_k)
                    n_sub = 2
                for sub in range(n_sub):
                    e_k = ends[sub]
                    x_b = _x_at(seg, e_k)
                    ev_sig = -1.0
                    ev_type = 0
                    ev_target = 0.0
                    if phase == 0:
                        for sgn in (1.0, -1.0):
                            fa = sgn * x_a - xc
                            fb = sgn * x_b - xc
                            if fb >= 0.0 and fa <= tol_x and fb > fa:
                                if fresh and first_piece and fa == 0.0:
                                    continue
                                if fa == 0.0 and fb <= tol_x and n_sub == 2 and sub == 0:
                                    # From the surface to an extremum within rounding of it:
                                    # touching x_c, not a lift-off.
                                    continue
                                # Within rounding past x_c (after such a touch) moving on out:
                                # the lift-off is right there.
                                ev_sig = _root(seg, a_k, e_k, sgn * xc, on_x) if fa < 0.0 else a_k
                                ev_type = EVENT_LIFTOFF
                                ev_target = sgn * xc
                    else:
                        s = 1.0 if phase > 0 else -1.0
                        fa = s * x_a - xc
                        fb = s * x_b - xc
                        # Just left the surface: not an impact, unless it went the wrong way by
                        # more than rounding (a departure whose push was rounding: it is back).
                        just_left = fresh and first_piece and fa == 0.0 and fb >= -tol_x
                        if fa == 0.0 and fb >= -tol_x and n_sub == 2 and sub == 0:
                            # Back to an extremum within rounding of the surface: touching
                            # it, not an impact (a seated frame leaving as the ground turns).
                            just_left = True
                        # From within rounding past the surface (an excursion below the
                        # rounding of x, at a threshold) moving back in: a touchdown right there.
                        if fb <= 0.0 and fa >= -tol_x and fb < fa and not just_left:
                            ev_sig = _root(seg, a_k, e_k, s * xc, on_x) if fa > 0.0 else a_k
                            ev_type = EVENT_TOUCHDOWN
                            ev_target = s * xc
                        if xcap < math.inf and ev_type == 0:
                            fa = s * x_a - xcap
                            fb = s * x_b - xcap
                            if fa < 0.0 and fb >= 0.0:
                                ev_sig = _root(seg, a_k, e_k, s * xcap, on_x)
                                ev_type = EVENT_CAP
                                ev_target = s * xcap
                    if ev_type != 0:
                        v_ev = _v_at(seg, ev_sig)
                        t_ev = t0 + tau + ev_sig
                        if abs(ev_target) > peak:
                            peak = abs(ev_target)
                            t_peak = t_ev
                        x = ev_target
                        tau += ev_sig
                        if ev_type == EVENT_LIFTOFF:
                            phase = 1 if ev_target > 0.0 or (xc == 0.0 and v_ev > 0) else -1
                            v = v_ev
                            n_lift += 1
                            cur_lift = n_ev
                            cur_side = 1.0 if phase > 0 else -1.0
                            ep_peak = xc
                            n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak, t_ev,
                                         k_liftoff, v_ev, v_ev, cur_side * xc)  # fmt: skip
                            s = 1.0 if phase > 0 else -1.0
                            p_back = w2 * w2 * xc - g1 - s * p2 * (ag_a + slope * tau)
                            graze = 2.0 * abs(v_ev) / -p_back if p_back < 0.0 else math.inf
                            if abs(v_ev) <= w_tiny and graze <= dt - tau:
                                # A grazing lift-off too slow to follow: the stepped phase pulls
                                # it straight back, a touchdown at speed |ẋ| after 2|ẋ|/|p_back|.
                                tau += graze
                                t_ev += graze
                                v_ev = -v_ev
                                ev_type = EVENT_TOUCHDOWN
                            elif (
                                in_free
                                and s * v - lam2 * (s * x - x_star) > 0.0
                                and overturned == 0
                            ):
                                overturned = 1
                                if xcap == math.inf:
                                    t_over = t_ev
                                    stop = True
                        if ev_type == EVENT_TOUCHDOWN:
                            s = 1.0 if phase > 0 else -1.0
                            w_reb = cr * abs(v_ev)
                            n_imp += 1
                            if cur_lift >= 0 and cur_lift < cap_ev:
                                ev_peak[cur_lift] = cur_side * ep_peak
                            cur_lift = -1
                            kind, delay, w_back = _impact_rule(
                                s, w_reb, ag_a + slope * tau, slope, dt - tau,
                                w1, w2, p1, p2, g1, xc, cr, w_tiny,
                            )  # fmt: skip
                            n_ev = _push(
                                n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                                t_ev, k_touchdown, v_ev, -s * w_reb, ep_peak,
                            )  # fmt: skip
                            if kind == 0:
                                v = -s * w_reb
                                if xc > 0.0:
                                    phase = 0
                                else:
                                    # Rigid-block limit: impact at x = 0 passes to the other side.
                                    phase = -int(s)
                                    n_lift += 1
                                    cur_lift = n_ev
                                    cur_side = -s
                                    ep_peak = 0.0
                                    n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                                                 t_ev, k_liftoff, v, v, 0.0)  # fmt: skip
                            elif kind == 1:
                                tau += delay
                                t_ev += delay
                                if xc == 0.0:
                                    # The block's return strikes again before it lifts off.
                                    n_imp += 1
                                    n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                                                 t_ev, k_touchdown, s * w_reb, s * w_back,
                                                 0.0)  # fmt: skip
                                phase = int(s)
                                v = s * w_back
                                n_lift += 1
                                cur_lift = n_ev
                                cur_side = s
                                ep_peak = xc
                                n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                                             t_ev, k_liftoff, v, v, s * xc)  # fmt: skip
                            else:
                                tau += delay
                                t_ev += delay
                                v = 0.0
                                phase = 2 * int(s)
                                n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                                             t_ev, k_settle, -s * w_reb, 0.0, 0.0)  # fmt: skip
                        elif ev_type == EVENT_CAP:
                            v = v_ev
                            overturned = 1
                            t_over = t_ev
                            n_ev = _push(n_ev, ev_t, ev_kind, ev_v_in, ev_v_out, ev_peak,
                                         t_ev, k_cap, v_ev, v_ev, ev_target)  # fmt: skip
                            stop = True
                        fresh = True
                        event_found = True
                        break
                    # No event on this monotone piece: its end may be a true peak.
                    if abs(x_b) > peak:
                        peak = abs(x_b)
                        t_peak = t0 + tau + e_k
                    if phase != 0 and abs(x_b) > ep_peak:
                        ep_peak = abs(x_b)
                    a_k = e_k
                    x_a = x_b
                    first_piece = False
                if event_found:
                    break
                v_a = v_b
            if stop:
                break
            if not event_found:
                x = _x_at(seg, length)
                v = _v_at(seg, length)
                tau = dt
                if not (math.isfinite(x) and math.isfinite(v)):
                    status = STATUS_NONFINITE
                    stop = True
                elif (phase == 0 and abs(x) > xc + tol_x) or (
                    phase != 0 and (1.0 if phase > 0 else -1.0) * x < xc - tol_x
                ):
                    # The state left its phase's side without an event: not a solution.
                    status = STATUS_INVARIANT
                    stop = True
                break
        if stop:
            if do_hist:
                # Fill the rest of the history with the final state.
                for jj in range(i + 1, hist_x.shape[0]):
                    hist_x[jj] = x
                    hist_v[jj] = v
                    hist_p[jj] = phase
            break
        i += 1
        if do_hist and i < hist_x.shape[0]:
            hist_x[i] = x
            hist_v[i] = v
            hist_p[i] = phase
    if do_hist:
        # A run that stopped early holds its final state to the end of the history.
        for jj in range(i + 1, hist_x.shape[0]):
            hist_x[jj] = x
            hist_v[jj] = v
            hist_p[jj] = phase
    if cur_lift >= 0 and cur_lift < cap_ev:
        ev_peak[cur_lift] = cur_side * ep_peak
    if status == STATUS_OK and overturned == 0:
        # A frame that neither passed the cap nor escaped cannot be beyond either bound.
        bound = xcap
        if no_cap:
            bound = max(abs(x0), (g1 + p2 * suffix[0]) / (w2 * w2)) * (1.0 + INVARIANT_RTOL)
        if not peak <= bound:
            status = STATUS_IMPOSSIBLE
    t_end = i * dt
    if not math.isnan(t_over):
        t_end = t_over
    return (
        status,
        n_ev,
        n_lift,
        n_imp,
        peak,
        t_peak,
        overturned,
        t_over,
        x,
        v,
        phase,
        t_end,
    )


@njit(cache=True, nogil=True)
def integrate_batch(
    flat_ag: np.ndarray,
    offsets: np.ndarray,
    rec_index: np.ndarray,
    scales: np.ndarray,
    dts: np.ndarray,
    tails: np.ndarray,
    params: np.ndarray,
    out: np.ndarray,
) -> None:
    """Run :func:`integrate` for many (record, scale) pairs on this thread, summaries only.

    ``params`` = (ω₁, ω₂, P₁, P₂, γ₁, ξ₁, ξ₂, x_c, C_r, x_cap, x₀, v₀); ``out[j]`` receives
    (status, n_liftoffs, n_impacts, peak, t_peak, overturned, t_overturn, x_end, v_end, phase_end).
    The GIL is released: threads of the caller run disjoint slices of the pairs at once. (A
    ``prange`` loop here cost 3 s more of compilation on a first run, numba's parfor lowering,
    for the same speed: docs/benchmarks.md.)
    """
    n_pairs = rec_index.shape[0]
    empty_f = np.empty(0)
    empty_i = np.empty(0, dtype=np.int8)
    empty_k = np.empty(0, dtype=np.int8)
    for j in range(n_pairs):
        r = rec_index[j]
        ag = flat_ag[offsets[r] : offsets[r + 1]] * scales[j]
        res = integrate(
            ag,
            dts[r],
            tails[r],
            params[0],
            params[1],
            params[2],
            params[3],
            params[4],
            params[5],
            params[6],
            params[7],
            params[8],
            params[9],
            params[10],
            params[11],
            empty_f,
            empty_f,
            empty_i,
            empty_f,
            empty_k,
            empty_f,
            empty_f,
            empty_f,
        )
        out[j, 0] = res[0]
        out[j, 1] = res[2]
        out[j, 2] = res[3]
        out[j, 3] = res[4]
        out[j, 4] = res[5]
        out[j, 5] = res[6]
        out[j, 6] = res[7]
        out[j, 7] = res[8]
        out[j, 8] = res[9]
        out[j, 9] = res[10]
