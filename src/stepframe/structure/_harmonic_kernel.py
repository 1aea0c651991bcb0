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
against the forcing period and the homogeneous time scale (a sixteenth of each), each piece is
cut at the zero of ẋ it holds (bracketed Newton on ẋ with ẍ as derivative), and a crossing of the
switching surface on a piece where x is monotone is bracketed by the end values and located by
bracketed Newton on x. A tangential visit of x_c (grazing) is therefore found at the extremum.

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

#: Kernel status codes (mapped to :data:`stepframe.core.results.STATUSES` by the caller).
K_OK = 0
K_NONFINITE = 1
K_TOO_MANY_EVENTS = 2

#: Parameter vector layout: (ω₁, ω₂, P₁, P₂, γ₁, ξ₁, ξ₂, x_c, C_r, x_cap (inf: none)).
N_PARAMS = 10

_PIECES_PER_CYCLE = 16.0
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
    seg[13] = 0.0
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
def _root(seg: np.ndarray, lo: float, hi: float, target: float, deriv: int) -> float:
    """Root of x - target (deriv 0) or ẋ (deriv 1) on a bracket: Newton kept inside by bisection."""
    xa, va, _aa = _eval(seg, lo)
    f_lo = xa - target if deriv == 0 else va
    if f_lo == 0.0:
        return lo
    s = 0.5 * (lo + hi)
    for _ in range(200):
        xs, vs, acs = _eval(seg, s)
        if deriv == 0:
            f = xs - target
            df = vs
        else:
            f = vs
            df = acs
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
def _hold_margins(s: float, ag: float, prm: np.ndarray) -> tuple[float, float]:
    """(outward push of the stepped side s, inward push) on the surface at rest; > 0 leaves."""
    w1, w2, p1, p2, g1, xc = prm[0], prm[1], prm[2], prm[3], prm[4], prm[7]
    out = w2 * w2 * xc - g1 - s * p2 * ag
    inward = w1 * w1 * xc + s * p1 * ag if xc > 0.0 else -g1 + s * p2 * ag
    return out, inward


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
    out, inward = _hold_margins(s, ag, prm)
    ph = _leave_phase(s, out, inward, xc)
    if ph == 2 * int(s) and xc == 0.0:
        # At rest on the base: test the other side too (either corner may lift).
        out2, _ = _hold_margins(-s, ag, prm)
        if out2 > 0.0:
            return -int(s)
    return ph


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
    while t < t1:
        if n_ev > max_events:
            return K_TOO_MANY_EVENTS, x, v, phase, n_lift, n_imp, peak, 0, t
        remaining = t1 - t
        if phase == 2 or phase == -2:
            s = 1.0 if phase > 0 else -1.0
            # Leave time: first σ where a margin turns positive (sinusoidal in σ).
            th0 = om * t + phi
            h = remaining if om == 0.0 else min(remaining, _TWO_PI / om / _PIECES_PER_CYCLE)
            sig = 0.0
            new_phase = phase
            t_leave = remaining
            while sig < remaining:
                b = min(sig + h, remaining)
                o_b, i_b = _hold_margins(s, amp * math.cos(th0 + om * b), prm)
                if o_b > 0.0 or i_b > 0.0:
                    lo = sig
                    hi = b
                    for _ in range(100):
                        mid = 0.5 * (lo + hi)
                        o_m, i_m = _hold_margins(s, amp * math.cos(th0 + om * mid), prm)
                        if o_m > 0.0 or i_m > 0.0:
                            hi = mid
                        else:
                            lo = mid
                        if hi - lo <= 4.4e-16 * max(hi, 1e-300):
                            break
                    o_h, i_h = _hold_margins(s, amp * math.cos(th0 + om * hi), prm)
                    new_phase = _leave_phase(s, o_h, i_h, xc)
                    t_leave = hi
                    break
                sig = b
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
        x_a, v_a, _acc = _eval(seg, 0.0)
        first = True
        ev_sig = -1.0
        ev_type = 0
        ev_target = 0.0
        overturned = 0
        while a_k < remaining and ev_type == 0:
            b_k = min(a_k + h, remaining)
            x_b, v_b, _ab = _eval(seg, b_k)
            ends = np.empty(2)
            n_sub = 1
            ends[0] = b_k
            if (v_a > 0.0 and v_b < 0.0) or (v_a < 0.0 and v_b > 0.0):
                ends[0] = _root(seg, a_k, b_k, 0.0, 1)
                ends[1] = b_k
                n_sub = 2
            p_k = a_k
            x_p = x_a
            for sub in range(n_sub):
                e_k = ends[sub]
                x_e, v_e, _ae = _eval(seg, e_k)
                if phase == 0:
                    for sgn in (1.0, -1.0):
                        fa = sgn * x_p - xc
                        fb = sgn * x_e - xc
                        if fa < 0.0 <= fb or (fa == 0.0 < fb and not (fresh and first)):
                            ev_sig = _root(seg, p_k, e_k, sgn * xc, 0)
                            ev_type = 1
                            ev_target = sgn * xc
                else:
                    s = 1.0 if phase > 0 else -1.0
                    fa = s * x_p - xc
                    fb = s * x_e - xc
                    if fb <= 0.0 < fa or (fa == 0.0 > fb and not (fresh and first)):
                        ev_sig = _root(seg, p_k, e_k, s * xc, 0)
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
                if phase != 0:
                    s = 1.0 if phase > 0 else -1.0
                    if s * v_e - lam2 * (s * x_e - x_star) > esc:
                        ev_sig = e_k
                        ev_type = 4
                        break
                p_k = e_k
                x_p = x_e
                first = False
            a_k = b_k
            x_a = x_b
            v_a = v_b
            if not (math.isfinite(x_b) and math.isfinite(v_b)):
                return K_NONFINITE, x_b, v_b, phase, n_lift, n_imp, peak, 0, t + b_k
        if ev_type == 0:
            if want_jac:
                _left_phi(jac, seg, remaining)
            x, v, _a = _eval(seg, remaining)
            t = t1
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
        if ev_type == 1:
            new_phase = 1 if ev_target > 0.0 else -1
            rho = 1.0
            n_lift += 1
            v = v_ev
        else:
            s = 1.0 if phase > 0 else -1.0
            rho = cr
            n_imp += 1
            v = cr * v_ev
            new_phase = 0 if xc > 0.0 else -int(s)
            if abs(v) <= v_eps:
                v = 0.0
                out, inward = _hold_margins(s, ag_now, prm)
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
