"""Numba kernel: the stepping frame under sinusoidal ground acceleration, in closed form.

Within one phase, eqs. 4.11-4.12 with ground acceleration ẍ_g = A cos(ωt + φ) are a
constant-coefficient linear ODE with sinusoidal forcing::

    ẍ + 2βẋ + kx = q₀ + c cos(ωt + φ),   c = -P·A

(k = ω₁², q₀ = 0 unstepped; k = -ω₂², q₀ = -sγ₁ stepped on side s). Its solution is the
particular part x_p = q₀/k + M cos θ + N sin θ (θ = ωt + φ, M = c(k - ω²)/D, N = 2cβω/D,
D = (k - ω²)² + 4β²ω²; at exact undamped resonance x_p = q₀/k + cσ sin θ/(2ω)) plus the
homogeneous part y, written with E_C = e^{-βσ}C(σ), E_S = e^{-βσ}S(σ) as in
:mod:`stepframe.structure._exact` (C, S = cos/sin, cosh/sinh or 1/σ by the sign of β² - k).

Events are found on the closed form without sampling error: a phase is cut into pieces short
against the forcing period and the homogeneous time scale (a sixteenth of each); a piece is cut at
the zero of ẍ it holds when |ẋ| falls and rises again over it without changing sign (ẋ may then
have two zeros, one on each side) and at the zero of ẋ on each part (bracketed Newton on ẍ with
the jerk, on ẋ with ẍ); a crossing of the switching surface on a piece where x is monotone is
bracketed by the end values and located by bracketed Newton on x. A tangential visit of x_c
(grazing) is therefore found at the extremum, and a short flight after an impact (chatter) turns
back inside its piece.

Thresholds (issue 31): a frame at rest on the surface leaves it when a margin (the acceleration
the phase would have there) turns positive beyond its rounding; the time is closed form. A phase
leaving the surface starts in its own direction even from rest, so the extremum of a small
excursion is found; an excursion that turns back within the rounding of x is a contact at rest;
and a state on the wrong side of the surface by more than rounding ends the run with the status
``failed`` (:data:`K_INVARIANT`) instead of being integrated on (where the other phase's
equation grows without bound).

The kernel also carries the 2×2 Jacobian of the flow: inside a phase the state transition matrix
Φ(σ) = [[E_C + βE_S, E_S], [-kE_S, E_C - βE_S]]; at an event on x = x_s the saltation matrix
S = [[ρ, 0], [(a⁺ - ρa⁻)/v⁻, ρ]] (ρ = C_r at an impact, 1 at a lift-off; a∓ the accelerations of
the phases before and after at the event, v⁻ the velocity before), which is
S = G + (f⁺ - G f⁻)∇hᵀ/(∇h·f⁻) for the surface h = x - x_s and the jump G = diag(1, ρ)
(Aizerman and Gantmakher 1958; Leine and Nijmeijer 2004, ch. 7). A hold on the surface
(ẋ = 0, entered when the rebound velocity is negligible) forgets the state: Φ = 0.

Phase codes: 0 unstepped, ±1 stepped on that side, ±2 held at x = ±x_c (for x_c = 0, the block
at rest on its base).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from stepframe.core.jit import njit

# E_C(σ), E_S(σ) of a linear phase: the same closed form as the sampled-record kernel's.
from stepframe.structure._exact import _ecs
from stepframe.structure.status import (
    STATUS_INVARIANT,
    STATUS_NONFINITE,
    STATUS_OK,
    STATUS_TOO_MANY_EVENTS,
)

#: Kernel status codes: the simulator's (:mod:`stepframe.structure.status`, whose names and
#: messages the callers report).
K_OK = STATUS_OK
K_NONFINITE = STATUS_NONFINITE
K_TOO_MANY_EVENTS = STATUS_TOO_MANY_EVENTS
#: The state left its phase's side of the switching surface without an event (not a solution).
K_INVARIANT = STATUS_INVARIANT

#: Parameter vector layout: (ω₁, ω₂, P₁, P₂, γ₁, ξ₁, ξ₂, x_c, C_r, x_cap (inf: none)).
N_PARAMS = 10

_PIECES_PER_CYCLE = 16.0
#: Ulps of its largest term within which x from the closed form is taken as exact (surface
#: contacts and the phase invariant at the end of a call).
_ROUNDING_ULPS = 16.0
#: Ulps of their terms within which the margins on the surface are taken as zero.
_MARGIN_ULPS = 64.0
_TWO_PI = 2.0 * math.pi


@njit(cache=True)
def _coeffs(phase: int, prm: np.ndarray, amp: float) -> tuple[float, float, float, float, float]:
    """(β, k, β² - k, q₀, c) of a moving phase under ground acceleration amplitude ``amp``."""
    w1 = prm[0]
    w2 = prm[1]
    if phase == 0:
        xi1 = prm[5]
        return xi1 * w1, w1 * w1, w1 * w1 * (xi1 - 1.0) * (xi1 + 1.0), 0.0, -prm[2] * amp
    s = 1.0 if phase > 0 else -1.0
    xi2 = prm[6]
    return xi2 * w2, -w2 * w2, w2 * w2 * (xi2 * xi2 + 1.0), -s * prm[4], -prm[3] * amp


@njit(cache=True)
def _segment(
    beta: float,
    k: float,
    disc: float,
    q0: float,
    c: float,
    om: float,
    th0: float,
    x0: float,
    v0: float,
) -> np.ndarray:
    """Closed-form coefficients of one phase from its start state (σ = 0 at angle θ₀)."""
    seg = np.empty(14)
    a0 = q0 / k
    res = 0.0
    mm = 0.0
    nn = 0.0
    if beta == 0.0 and om > 0.0 and abs(k - om * om) <= 1e-13 * abs(k):
        res = c / (2.0 * om)
    else:
        den = (k - om * om) ** 2 + (2.0 * beta * om) ** 2
        mm = c * (k - om * om) / den
        nn = c * 2.0 * beta * om / den
    xp0 = a0 + mm * math.cos(th0) + nn * math.sin(th0)
    vp0 = om * (-mm * math.sin(th0) + nn * math.cos(th0)) + res * math.sin(th0)
    y0 = x0 - xp0
    y1 = v0 - vp0
    y2 = -2.0 * beta * y1 - k * y0
    y3 = -2.0 * beta * y2 - k * y1
    seg[0] = a0
    seg[1] = mm
    seg[2] = nn
    seg[3] = res
    seg[4] = th0
    seg[5] = om
    seg[6] = y0
    seg[7] = y1
    seg[8] = y2
    seg[9] = y3
    seg[10] = beta
    seg[11] = k
    seg[12] = disc
    seg[13] = -2.0 * beta * y3 - k * y2
    return seg


@njit(cache=True)
def _eval(seg: np.ndarray, sig: float) -> tuple[float, float, float]:
    """x, ẋ, ẍ at σ."""
    a0, mm, nn, res, th0, om = seg[0], seg[1], seg[2], seg[3], seg[4], seg[5]
    y0, y1, y2, y3, beta, disc = seg[6], seg[7], seg[8], seg[9], seg[10], seg[12]
    th = th0 + om * sig
    cs = math.cos(th)
    sn = math.sin(th)
    xp = a0 + mm * cs + nn * sn + res * sig * sn
    vp = om * (-mm * sn + nn * cs) + res * (sn + sig * om * cs)
    ap = -om * om * (mm * cs + nn * sn) + res * (2.0 * om * cs - sig * om * om * sn)
    ec, es = _ecs(beta, disc, sig)
    f = ec + beta * es
    return xp + y0 * f + y1 * es, vp + y1 * f + y2 * es, ap + y2 * f + y3 * es


@njit(cache=True)
def _jerk(seg: np.ndarray, sig: float) -> float:
    """The third derivative of x at σ (Newton's derivative for the zeros of ẍ)."""
    mm, nn, res, th0, om = seg[1], seg[2], seg[3], seg[4], seg[5]
    y3, y4, beta, disc = seg[9], seg[13], seg[10], seg[12]
    th = th0 + om * sig
    cs = math.cos(th)
    sn = math.sin(th)
    jp = om**3 * (mm * sn - nn * cs) - res * om * om * (3.0 * sn + sig * om * cs)
    ec, es = _ecs(beta, disc, sig)
    return float(jp + y3 * (ec + beta * es) + y4 * es)


@njit(cache=True)
def _root(
    seg: np.ndarray, lo: float, hi: float, target: float, deriv: int, lo_sign: float = 0.0
) -> float:
    """Root of x - target (deriv 0), ẋ (1) or ẍ (2) on a bracket: Newton kept inside by bisection.

    A function that is zero at ``lo`` is taken to leave it with the sign of ``lo_sign`` (a
    velocity that starts at 0 and turns back inside the bracket); with ``lo_sign`` 0, ``lo``
    itself is the root.
    """
    xa, va, aa = _eval(seg, lo)
    f_lo = xa - target if deriv == 0 else (va if deriv == 1 else aa)
    if f_lo == 0.0:
        if lo_sign == 0.0:
            return lo
        f_lo = lo_sign
    s = 0.5 * (lo + hi)
    for _ in range(200):
        xs, vs, acs = _eval(seg, s)
        if deriv == 0:
            f = xs - target
            df = vs
        elif deriv == 1:
            f = vs
            df = acs
        else:
            f = acs
            df = _jerk(seg, s)
        if f == 0.0:
            return s
        if (f > 0.0) == (f_lo > 0.0):
            lo = s
        else:
            hi = s
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
def _piece(om: float, disc: float, remaining: float) -> float:
    h = remaining
    if om > 0.0:
        h = min(h, _TWO_PI / om / _PIECES_PER_CYCLE)
    if disc < 0.0:
        h = min(h, _TWO_PI / math.sqrt(-disc) / _PIECES_PER_CYCLE)
    elif disc > 0.0:
        h = min(h, 1.0 / math.sqrt(disc))
    return h


@njit(cache=True)
def _margin_tols(prm: np.ndarray, amp: float, th: float) -> tuple[float, float]:
    """Rounding of the (outward, inward) margins [m/s²] under amplitude ``amp`` at angle θ.

    A few ulps of each margin's terms, plus what the rounding of θ = ωt + φ itself (an ulp of
    |θ|) moves the ground term by. A margin is taken as positive only beyond it: at a crossing
    the frame then leaves with an acceleration the closed form resolves, never with one whose
    sign is rounding (which would turn it straight back, at the same instant, without end).
    """
    w1, w2, p1, p2, g1, xc = prm[0], prm[1], prm[2], prm[3], prm[4], prm[7]
    e = _MARGIN_ULPS * 2.2e-16
    drift = 2.2e-16 * abs(amp) * abs(th)
    tol_out = e * (w2 * w2 * xc + g1 + p2 * abs(amp)) + p2 * drift
    if xc > 0.0:
        tol_in = e * (w1 * w1 * xc + p1 * abs(amp)) + p1 * drift
    else:
        tol_in = e * (g1 + p2 * abs(amp)) + p2 * drift
    return tol_out, tol_in


@njit(cache=True)
def _hold_margins(
    s: float, ag: float, prm: np.ndarray, tol_out: float, tol_in: float
) -> tuple[float, float]:
    """(outward push of the stepped side s, inward push) on the surface at rest, each less its
    rounding (:func:`_margin_tols`); > 0 leaves."""
    w1, w2, p1, p2, g1, xc = prm[0], prm[1], prm[2], prm[3], prm[4], prm[7]
    out = w2 * w2 * xc - g1 - s * p2 * ag - tol_out
    inward = w1 * w1 * xc + s * p1 * ag if xc > 0.0 else -g1 + s * p2 * ag
    return out, inward - tol_in


@njit(cache=True)
def _leave_phase(s: float, out: float, inward: float, xc: float) -> int:
    if out > 0.0:
        return int(s)
    if inward > 0.0:
        return 0 if xc > 0.0 else -int(s)
    return 2 * int(s)


@njit(cache=True)
def start_phase(x: float, v: float, ag: float, prm: np.ndarray) -> int:
    """Phase of a state at rest or moving, by its position, velocity and the ground push."""
    xc = prm[7]
    if abs(x) < xc:
        return 0
    if abs(x) > xc:
        return 1 if x > 0.0 else -1
    s = 1.0 if (x > 0.0 or (x == 0.0 and v >= 0.0)) else -1.0
    if v * s > 0.0:
        return int(s)
    if v * s < 0.0:
        return 0 if xc > 0.0 else -int(s)
    tol_out, tol_in = _margin_tols(prm, ag, 0.0)
    out, inward = _hold_margins(s, ag, prm, tol_out, tol_in)
    ph = _leave_phase(s, out, inward, xc)
    if ph == 2 * int(s) and xc == 0.0:
        # At rest on the base: test the other side too (either corner may lift).
        out2, _ = _hold_margins(-s, ag, prm, tol_out, tol_in)
        if out2 > 0.0:
            return -int(s)
    return ph


@njit(cache=True)
def _x_rounding(seg: np.ndarray, sig: float) -> float:
    """Rounding error of x evaluated from the closed form at σ [m]: a few ulps of its terms."""
    a0, mm, nn, res = seg[0], seg[1], seg[2], seg[3]
    y0, y1, beta, disc = seg[6], seg[7], seg[10], seg[12]
    ec, es = _ecs(beta, disc, sig)
    terms = abs(a0) + abs(mm) + abs(nn) + abs(res * sig) + abs(y0 * (ec + beta * es))
    return float(_ROUNDING_ULPS * 2.2e-16 * (terms + abs(y1 * es)))


@njit(cache=True)
def _entry(c0: float, c1: float, th0: float, om: float, armed: bool) -> float:
    """σ at which the margin c₀ + c₁cos(θ₀ + ωσ) next turns positive (inf: never).

    Closed form: the margin is positive on an arc of cos θ > r (c₁ > 0) or cos θ < r (c₁ < 0),
    r = -c₀/c₁, entered at θ = ∓acos r (mod 2π). A margin touching 0 tangentially (|r| = 1)
    never turns positive. ``armed`` False (the margin is positive now, a contact just made
    against it) skips the arc the frame is on: the next entry strictly after θ₀.
    """
    if c1 == 0.0 or om == 0.0:
        m0 = c0 + c1 * math.cos(th0)
        return 0.0 if (armed and m0 > 0.0) else math.inf
    r = -c0 / c1
    if (r >= 1.0 and c1 > 0.0) or (r <= -1.0 and c1 < 0.0):
        return math.inf
    if (r < -1.0 and c1 > 0.0) or (r > 1.0 and c1 < 0.0):
        return 0.0 if armed else math.inf
    acr = math.acos(r)
    enter = -acr if c1 > 0.0 else acr
    base = th0 - _TWO_PI * math.floor(th0 / _TWO_PI)
    d = enter - base
    d -= _TWO_PI * math.floor(d / _TWO_PI)
    if armed and c0 + c1 * math.cos(th0) > 0.0:
        # Already inside the arc although armed: the rounding of the entry angle.
        return 0.0
    if not armed and d == 0.0:
        d = _TWO_PI
    return d / om


@njit(cache=True)
def _hold(
    s: float, prm: np.ndarray, amp: float, om: float, th0: float, remaining: float
) -> tuple[int, float]:
    """(phase left to, σ) of a frame held on the surface x = s·x_c from angle θ₀ of the forcing.

    The frame leaves when its outward or inward margin (:func:`_hold_margins`, sinusoidal in the
    forcing angle) turns positive; the time is found in closed form (:func:`_entry`), so a short
    window above the threshold is never stepped over. A margin already positive at σ = 0 is one
    the frame has just touched against (a contact within the rounding of x, :func:`advance`): it
    must drop to ≤ 0 before it can move the frame. Returns the hold phase itself and
    ``remaining`` when the frame stays held.
    """
    w1, w2, p1, p2, g1, xc = prm[0], prm[1], prm[2], prm[3], prm[4], prm[7]
    # The tolerances at the end of the call: the larger |θ| there bounds the rounding on the way.
    tol_out, tol_in = _margin_tols(prm, amp, abs(th0) + om * remaining)
    o0, i0 = _hold_margins(s, amp * math.cos(th0), prm, tol_out, tol_in)
    t_out = _entry(w2 * w2 * xc - g1 - tol_out, -s * p2 * amp, th0, om, o0 <= 0.0)
    if xc > 0.0:
        t_in = _entry(w1 * w1 * xc - tol_in, s * p1 * amp, th0, om, i0 <= 0.0)
        in_phase = 0
    else:
        t_in = _entry(-g1 - tol_in, s * p2 * amp, th0, om, i0 <= 0.0)
        in_phase = -int(s)
    if t_out <= t_in and t_out < remaining:
        return int(s), t_out
    if t_in < remaining:
        return in_phase, t_in
    return 2 * int(s), remaining


@njit(cache=True)
def advance(
    prm: np.ndarray,
    amp: float,
    om: float,
    phi: float,
    t0: float,
    t1: float,
    x: float,
    v: float,
    phase: int,
    jac: np.ndarray,
    want_jac: bool,
    max_events: int,
    amp_bound: float,
) -> tuple[int, float, float, int, int, int, float, int, float]:
    """Integrate from t0 to t1 under ẍ_g = amp·cos(om·t + phi), starting in ``phase``.

    ``jac`` (2×2) is left-multiplied by the flow's Jacobian when ``want_jac``. ``amp_bound`` is
    the largest |ẍ_g| the future can bring (for the certain-escape test).

    A phase that starts on the switching surface (after an event, or from rest) leaves it in the
    direction of its phase (a velocity of 0 takes the sign its phase gives it, so the extremum a
    small excursion turns back at is found). An excursion whose extremum lies within the
    rounding of x of the surface (:func:`_x_rounding`: the threshold case, where the frame barely
    lifts) is a contact at rest: the frame is held and the margins decide. A phase that crosses
    to the wrong side of the surface without an event ends the call with ``K_INVARIANT``.

    Returns
    -------
    (status, x, v, phase, n_liftoffs, n_impacts, peak |x|, overturned, t_end)
    """
    w2 = prm[1]
    p2 = prm[3]
    g1 = prm[4]
    xi2 = prm[6]
    xc = prm[7]
    cr = prm[8]
    xcap = prm[9]
    x_star = g1 / (w2 * w2)
    lam1 = w2 * (math.sqrt(1.0 + xi2 * xi2) - xi2)
    lam2 = -w2 * (xi2 + math.sqrt(1.0 + xi2 * xi2))
    # Rounding margin: a state on the separatrix (z = 0 unforced) is not declared escaping.
    esc = p2 * amp_bound / lam1 + 1e-11 * lam1 * x_star
    # Rebound speeds below v_eps end an impact sequence in the hold state: the excursion they
    # allow, v²/γ₁, would be below the rounding of x (~1e-16·x*) once v < 1e-8·ω₂x*, where root
    # finding on the closed form stops being meaningful; the energy left is ~1e-14 of the
    # separatrix energy.
    v_eps = 1e-7 * w2 * x_star
    n_lift = 0
    n_imp = 0
    n_ev = 0
    peak = abs(x)
    t = t0
    fresh = False
    # Cut points of a piece: ẍ's zero and ẋ's zeros (ẋ is monotone between zeros of ẍ, so each
    # part holds at most one), then the piece end; ``ext`` marks the zeros of ẋ.
    ends = np.empty(4)
    ext = np.zeros(4, dtype=np.bool_)
    while t < t1:
        if n_ev > max_events:
            return K_TOO_MANY_EVENTS, x, v, phase, n_lift, n_imp, peak, 0, t
        remaining = t1 - t
        if phase == 2 or phase == -2:
            s = 1.0 if phase > 0 else -1.0
            new_phase, t_leave = _hold(s, prm, amp, om, om * t + phi, remaining)
            x = s * xc
            v = 0.0
            if new_phase == phase:
                t = t1
                break
            t += t_leave
            phase = new_phase
            fresh = True
            n_ev += 1
            if phase != 0:
                n_lift += 1
            continue
        beta, k, disc, q0, c = _coeffs(phase, prm, amp)
        th0 = om * t + phi
        seg = _segment(beta, k, disc, q0, c, om, th0, x, v)
        h = _piece(om, disc, remaining)
        a_k = 0.0
        # The start values themselves (the closed form returns them only up to rounding), so a
        # state set on the surface by an event is exactly on it.
        x_a = x
        on_surface = abs(x) == xc
        s_ph = 1.0 if phase > 0 else -1.0
        # Direction the velocity leaves 0 with: into the phase from the surface, else with ẍ.
        _x0, _v0, acc_a = _eval(seg, 0.0)
        dir_a = v
        if dir_a == 0.0:
            dir_a = (s_ph if phase != 0 else -x) if on_surface else acc_a
        first = True
        ev_sig = -1.0
        ev_type = 0
        ev_target = 0.0
        overturned = 0
        while a_k < remaining and ev_type == 0:
            b_k = min(a_k + h, remaining)
            x_b, v_b, acc_b = _eval(seg, b_k)
            n_parts = 1
            s_infl = b_k
            # ẋ changing sign over the piece has one zero (monotone on each side of ẍ's zero).
            # Keeping its sign, it may have two only if |ẋ| falls and then rises (ẍ against ẋ,
            # then with it): cut at ẍ's zero then. A zero of ẍ where |ẋ| peaks needs no cut.
            v_turns = (dir_a > 0.0 and v_b < 0.0) or (dir_a < 0.0 and v_b > 0.0)
            if not v_turns and dir_a * acc_a < 0.0 < dir_a * acc_b:
                s_infl = _root(seg, a_k, b_k, 0.0, 2)
                n_parts = 2
            n_sub = 0
            lo_k = a_k
            d_k = dir_a
            for part in range(n_parts):
                pe = s_infl if part == 0 else b_k
                v_pe = v_b
                a_pe = acc_b
                if pe != b_k:
                    _xq, v_pe, a_pe = _eval(seg, pe)
                if (d_k > 0.0 and v_pe < 0.0) or (d_k < 0.0 and v_pe > 0.0):
                    ends[n_sub] = _root(seg, lo_k, pe, 0.0, 1, d_k)
                    ext[n_sub] = True
                    n_sub += 1
                ends[n_sub] = pe
                ext[n_sub] = False
                n_sub += 1
                lo_k = pe
                d_k = v_pe
                if d_k == 0.0:
                    d_k = a_pe if a_pe != 0.0 else _jerk(seg, pe)
            p_k = a_k
            x_p = x_a
            for sub in range(n_sub):
                e_k = ends[sub]
                x_e, v_e, _ae = _eval(seg, e_k)
                # Leaving the surface into the phase (after an event, at rest, or moving in).
                if phase == 0:
                    departing = first and on_surface and (fresh or v * x <= 0.0)
                else:
                    departing = first and on_surface and (fresh or v * s_ph >= 0.0)
                at_extremum = ext[sub]
                if phase == 0:
                    for sgn in (1.0, -1.0):
                        fa = sgn * x_p - xc
                        fb = sgn * x_e - xc
                        if departing and fa == 0.0:
                            if fb > 0.0 and not (at_extremum and fb <= _x_rounding(seg, e_k)):
                                # Left the surface outward in the unstepped phase.
                                return K_INVARIANT, x_e, v_e, phase, n_lift, n_imp, peak, 0, t + e_k
                        elif fa <= 0.0 < fb:
                            ev_sig = _root(seg, p_k, e_k, sgn * xc, 0)
                            ev_type = 1
                            ev_target = sgn * xc
                else:
                    s = s_ph
                    fa = s * x_p - xc
                    fb = s * x_e - xc
                    if departing and fa == 0.0 and fb <= 0.0:
                        if at_extremum and -fb <= _x_rounding(seg, e_k):
                            # The excursion turned back within the rounding of x: a contact.
                            ev_sig = e_k
                            ev_type = 5
                            ev_target = s * xc
                        elif fb < -_x_rounding(seg, e_k):
                            return K_INVARIANT, x_e, v_e, phase, n_lift, n_imp, peak, 0, t + e_k
                    elif fb <= 0.0 and (fa > 0.0 or (fa <= 0.0 and fb < 0.0)):
                        if fa > 0.0:
                            ev_sig = _root(seg, p_k, e_k, s * xc, 0)
                        elif -fa <= _x_rounding(seg, p_k):
                            # Starting on the surface (or within rounding past it) moving in.
                            ev_sig = p_k
                        else:
                            return K_INVARIANT, x_p, v_e, phase, n_lift, n_imp, peak, 0, t + p_k
                        ev_type = 2
                        ev_target = s * xc
                    elif xcap < math.inf and s * x_p < xcap <= s * x_e:
                        ev_sig = _root(seg, p_k, e_k, s * xcap, 0)
                        ev_type = 3
                        ev_target = s * xcap
                if ev_type != 0:
                    break
                if abs(x_e) > peak:
                    peak = abs(x_e)
                if phase != 0 and s_ph * v_e - lam2 * (s_ph * x_e - x_star) > esc:
                    ev_sig = e_k
                    ev_type = 4
                    break
                p_k = e_k
                x_p = x_e
                first = False
            a_k = b_k
            x_a = x_b
            dir_a = v_b
            if dir_a == 0.0:
                dir_a = acc_b
            acc_a = acc_b
            if not (math.isfinite(x_b) and math.isfinite(v_b)):
                return K_NONFINITE, x_b, v_b, phase, n_lift, n_imp, peak, 0, t + b_k
        if ev_type == 0:
            if want_jac:
                _left_phi(jac, seg, remaining)
            x, v, _a = _eval(seg, remaining)
            t = t1
            # The phase invariant at the end of the call: a state on the wrong side of the surface
            # by more than rounding is not a solution; within rounding it is on the surface.
            over = abs(x) - xc if phase == 0 else xc - s_ph * x
            if over > 0.0:
                if over > _x_rounding(seg, remaining):
                    return K_INVARIANT, x, v, phase, n_lift, n_imp, peak, 0, t
                x = s_ph * xc if phase != 0 else math.copysign(xc, x)
            break
        x_ev, v_ev, a_minus = _eval(seg, ev_sig)
        if want_jac:
            _left_phi(jac, seg, ev_sig)
        t += ev_sig
        n_ev += 1
        fresh = True
        if ev_type == 4:
            x = x_ev
            v = v_ev
            overturned = 1
            return K_OK, x, v, phase, n_lift, n_imp, peak, overturned, t
        x = ev_target
        if abs(x) > peak:
            peak = abs(x)
        if ev_type == 3:
            v = v_ev
            return K_OK, x, v, phase, n_lift, n_imp, peak, 1, t
        ag_now = amp * math.cos(om * t + phi)
        if ev_type == 5:
            # Contact at rest: the frame is held, or leaves by the margins, but never straight
            # back out on the side it touched (:func:`_hold` waits for that margin to drop).
            s = s_ph
            n_imp += 1
            v = 0.0
            tol_out, tol_in = _margin_tols(prm, amp, om * t + phi)
            _out, inward = _hold_margins(s, ag_now, prm, tol_out, tol_in)
            phase = _leave_phase(s, -1.0, inward, xc)
            if want_jac:
                jac[:, :] = 0.0
            if xc == 0.0 and phase == -int(s):
                n_lift += 1
            continue
        if ev_type == 1:
            new_phase = 1 if ev_target > 0.0 else -1
            rho = 1.0
            n_lift += 1
            v = v_ev
        else:
            s = s_ph
            rho = cr
            n_imp += 1
            v = cr * v_ev
            new_phase = 0 if xc > 0.0 else -int(s)
            if abs(v) <= v_eps:
                v = 0.0
                tol_out, tol_in = _margin_tols(prm, amp, om * t + phi)
                out, inward = _hold_margins(s, ag_now, prm, tol_out, tol_in)
                new_phase = _leave_phase(s, out, inward, xc)
                if want_jac:
                    jac[:, :] = 0.0
                if new_phase == int(s):
                    n_lift += 1
                phase = new_phase
                continue
            if xc == 0.0:
                n_lift += 1
        if want_jac:
            b2, k2, _d2, q02, c2 = _coeffs(new_phase, prm, amp)
            a_plus = q02 + c2 * math.cos(om * t + phi) - 2.0 * b2 * v - k2 * x
            s21 = (a_plus - rho * a_minus) / v_ev
            j00 = jac[0, 0]
            j01 = jac[0, 1]
            j10 = jac[1, 0]
            j11 = jac[1, 1]
            jac[0, 0] = rho * j00
            jac[0, 1] = rho * j01
            jac[1, 0] = s21 * j00 + rho * j10
            jac[1, 1] = s21 * j01 + rho * j11
        phase = new_phase
    return K_OK, x, v, phase, n_lift, n_imp, peak, 0, t


@njit(cache=True)
def _left_phi(jac: np.ndarray, seg: np.ndarray, sig: float) -> None:
    beta, k, disc = seg[10], seg[11], seg[12]
    ec, es = _ecs(beta, disc, sig)
    f00 = ec + beta * es
    f01 = es
    f10 = -k * es
    f11 = ec - beta * es
    j00 = jac[0, 0]
    j01 = jac[0, 1]
    j10 = jac[1, 0]
    j11 = jac[1, 1]
    jac[0, 0] = f00 * j00 + f01 * j10
    jac[0, 1] = f00 * j01 + f01 * j11
    jac[1, 0] = f10 * j00 + f11 * j10
    jac[1, 1] = f10 * j01 + f11 * j11


@njit(cache=True)
def strobe(
    prm: np.ndarray,
    amp: float,
    om: float,
    phi: float,
    x0: float,
    v0: float,
    n_periods: int,
    n_keep: int,
    max_events: int,
    out: np.ndarray,
) -> tuple[int, int, int, int]:
    """Iterate the stroboscopic map n_periods times from (x0, v0) at t = 0.

    ``out[j]`` (n_keep × 4) receives (x, v, impacts, lift-offs) after each of the last n_keep
    periods. Returns (status, overturned, periods done, total impacts).
    """
    period = _TWO_PI / om
    jac = np.eye(2)
    x = x0
    v = v0
    phase = start_phase(x0, v0, amp * math.cos(phi), prm)
    n_imp_total = 0
    for i in range(n_periods):
        st, x, v, phase, nl, ni, _pk, ov, _te = advance(
            prm,
            amp,
            om,
            phi,
            i * period,
            (i + 1) * period,
            x,
            v,
            phase,
            jac,
            False,
            max_events,
            abs(amp),
        )
        n_imp_total += ni
        if st != K_OK:
            return st, 0, i, n_imp_total
        if ov == 1:
            return K_OK, 1, i, n_imp_total
        j = i - (n_periods - n_keep)
        if j >= 0:
            out[j, 0] = x
            out[j, 1] = v
            out[j, 2] = ni
            out[j, 3] = nl
    return K_OK, 0, n_periods, n_imp_total


@njit(cache=True)
def strobe_grid(
    prm: np.ndarray,
    amps: np.ndarray,
    om: float,
    phi: float,
    x0s: np.ndarray,
    v0s: np.ndarray,
    n_periods: int,
    n_keep: int,
    max_events: int,
) -> tuple[Any, Any]:
    """:func:`strobe` for every (amplitude, initial state): (samples, status/overturn flags)."""
    na = amps.shape[0]
    ni = x0s.shape[0]
    out = np.full((na, ni, n_keep, 4), np.nan)
    flags = np.zeros((na, ni, 2), dtype=np.int64)
    buf = np.empty((n_keep, 4))
    for a in range(na):
        for j in range(ni):
            buf[:, :] = np.nan
            st, ov, _n, _imp = strobe(
                prm, amps[a], om, phi, x0s[j], v0s[j], n_periods, n_keep, max_events, buf
            )
            out[a, j] = buf
            flags[a, j, 0] = st
            flags[a, j, 1] = ov
    return out, flags
