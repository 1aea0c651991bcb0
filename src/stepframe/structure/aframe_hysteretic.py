"""The stepping A-frame with its hysteretic damping (eqs. 4.1-4.2), integrated piecewise exactly.

In the unstepped phase the hysteretic term πξ₁ω₁² sign(ẋ)|x| equals πξ₁ω₁² σ_v σ_x x with
σ_v = sign ẋ and σ_x = sign x, so between the zeros of x and of ẋ eq. 4.1 is the *linear*
undamped oscillator ẍ + k x = -P₁ẍ_g with k = ω₁²(1 + πξ₁σ_vσ_x): stiffer moving away from
x = 0, softer moving back (the loop dissipates 2πξ₁ω₁²A² per cycle). The stepped phase (eq. 4.2)
is linear with k = -ω₂² sec θ. With ground acceleration linear between samples each piece has a
closed form (x = q₀/k + q₁σ/k + y₀C + y₁S, C, S = cos/sin or cosh/sinh), and the events (x = 0,
ẋ = 0, |x| = x_c, touchdown, cap) are located by bracketed root finding on it, as in
:mod:`stepframe.structure._harmonic_kernel`. The integrator is exact for the model up to rounding;
:func:`equivalent_viscous_error` measures what the simulator's substitute
(``AFrame.to_portal_frame(hysteretic="equivalent-viscous")``) gets wrong.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numba import njit

from stepframe.core.results import Status
from stepframe.errors import InputError

if TYPE_CHECKING:
    import pandas as pd

    from stepframe.structure.frame import AFrame

_PIECES = 16.0


@njit(cache=True)
def _cs(k: float, sig: float) -> tuple[float, float, float]:
    """C(σ), S(σ) and -kS(σ) = C'(σ) for ẍ + kx = 0."""
    if k > 0.0:
        w = math.sqrt(k)
        return math.cos(w * sig), math.sin(w * sig) / w, -w * math.sin(w * sig)
    w = math.sqrt(-k)
    return math.cosh(w * sig), math.sinh(w * sig) / w, w * math.sinh(w * sig)


@njit(cache=True)
def _state(k: float, q0: float, q1: float, x0: float, v0: float, sig: float) -> tuple[float, float]:
    a = q0 / k
    b = q1 / k
    y0 = x0 - a
    y1 = v0 - b
    c, s, dc = _cs(k, sig)
    return a + b * sig + y0 * c + y1 * s, b + y0 * dc + y1 * c


@njit(cache=True)
def _coeffs(phase: int, x: float, v: float, ag: float, prm: np.ndarray) -> tuple[float, float]:
    """(k, q₀ without ground term) of the current piece; the ground term is -P·ẍ_g."""
    w1, w2sec, g1sec, xi1 = prm[0], prm[1], prm[2], prm[5]
    if phase == 0:
        sx = 1.0 if x > 0.0 else (-1.0 if x < 0.0 else (1.0 if v > 0.0 else -1.0))
        sv = 1.0 if v > 0.0 else -1.0
        if v == 0.0:
            # At a turning point the motion continues the way the force pushes.
            acc = -w1 * w1 * x - prm[3] * ag
            sv = 1.0 if acc > 0.0 else -1.0
        return w1 * w1 * (1.0 + math.pi * xi1 * sv * sx), 0.0
    s = 1.0 if phase > 0 else -1.0
    return -w2sec * w2sec, -s * g1sec


@njit(cache=True)
def integrate_aframe(
    ag: np.ndarray,
    dt: float,
    n_tail: int,
    prm: np.ndarray,
    max_events: int,
    x0: float,
    v0: float,
) -> tuple[int, float, float, int, int, int, float, float]:
    """Eqs. 4.1-4.2 through ``ag`` [m/s²] (linear between samples) and n_tail free samples.

    ``prm`` = (ω₁, ω₂√sec θ, γ₁ sec θ, P₁, P₂ sec θ, ξ₁, x_c, C_r, x_cap).

    Returns
    -------
    (status 0 ok / 2 too many events, peak |x|, t_peak, overturned, n_liftoffs, n_impacts,
    x_end, v_end)
    """
    p1, p2, xc, cr, xcap = prm[3], prm[4], prm[6], prm[7], prm[8]
    x_star = prm[2] / (prm[1] * prm[1])
    lam = prm[1]
    v_eps = 1e-7 * prm[1] * x_star
    x = x0
    v = v0
    phase = 0 if abs(x0) < xc else (1 if x0 > 0.0 else -1)
    peak = abs(x0)
    t_peak = 0.0
    n_lift = 0
    n_imp = 0
    n_ev = 0
    n_rec = ag.shape[0] - 1
    for i in range(n_rec + n_tail):
        a0 = ag[i] if i < n_rec else 0.0
        a1 = ag[i + 1] if i < n_rec else 0.0
        slope = (a1 - a0) / dt
        tau = 0.0
        while tau < dt:
            n_ev += 1
            if n_ev > max_events:
                return 2, peak, t_peak, 0, n_lift, n_imp, x, v
            ag_now = a0 + slope * tau
            k, qc = _coeffs(phase, x, v, ag_now, prm)
            pp = p1 if phase == 0 else p2
            q0 = qc - pp * ag_now
            q1 = -pp * slope
            rem = dt - tau
            h = min(rem, 2.0 * math.pi / math.sqrt(abs(k)) / _PIECES)
            lo = 0.0
            xl, vl = x, v
            found = 0
            s_ev = rem
            while lo < rem and found == 0:
                hi = min(lo + h, rem)
                xh, vh = _state(k, q0, q1, x, v, hi)
                # Candidate events on [lo, hi]: sign changes of the event functions.
                kinds = 0
                if phase == 0:
                    if (xl > 0.0 and xh <= 0.0) or (xl < 0.0 and xh >= 0.0):
                        kinds = 1
                    elif (vl > 0.0 and vh <= 0.0) or (vl < 0.0 and vh >= 0.0):
                        kinds = 2
                    elif abs(xl) < xc <= abs(xh):
                        kinds = 3
                else:
                    s = 1.0 if phase > 0 else -1.0
                    if s * xl > xc >= s * xh:
                        kinds = 4
                    elif s * xl < xcap <= s * xh:
                        kinds = 5
                if kinds != 0:
                    # Bisection on the first event function that changed sign on this piece;
                    # the other functions are re-checked on the shortened piece each round.
                    a_s = lo
                    b_s = hi
                    for _ in range(200):
                        m = 0.5 * (a_s + b_s)
                        xm, vm = _state(k, q0, q1, x, v, m)
                        if kinds == 1:
                            hit = (xl > 0.0 and xm <= 0.0) or (xl < 0.0 and xm >= 0.0)
                        elif kinds == 2:
                            hit = (vl > 0.0 and vm <= 0.0) or (vl < 0.0 and vm >= 0.0)
                        elif kinds == 3:
                            hit = abs(xm) >= xc
                        elif kinds == 4:
                            hit = (1.0 if phase > 0 else -1.0) * xm <= xc
                        else:
                            hit = (1.0 if phase > 0 else -1.0) * xm >= xcap
                        if hit:
                            b_s = m
                        else:
                            a_s = m
                        if b_s - a_s <= 4.4e-16 * max(b_s, 1e-300):
                            break
                    found = kinds
                    s_ev = b_s
                    break
                if abs(xh) > peak:
                    peak = abs(xh)
                    t_peak = i * dt + tau + hi
                if phase != 0:
                    s = 1.0 if phase > 0 else -1.0
                    if i >= n_rec and s * vh + lam * (s * xh - x_star) > 1e-11 * lam * x_star:
                        return 0, peak, t_peak, 1, n_lift, n_imp, xh, vh
                lo = hi
                xl, vl = xh, vh
            x, v = _state(k, q0, q1, x, v, s_ev)
            tau += s_ev
            if abs(x) > peak:
                peak = abs(x)
                t_peak = i * dt + tau
            if found == 1:
                x = 0.0
            elif found == 2:
                v = 0.0
            elif found == 3:
                x = xc if x > 0.0 else -xc
                phase = 1 if x > 0.0 else -1
                n_lift += 1
            elif found == 4:
                s = 1.0 if phase > 0 else -1.0
                x = s * xc
                v = cr * v
                n_imp += 1
                phase = 0
                if abs(v) <= v_eps:
                    v = 0.0
            elif found == 5:
                return 0, max(peak, xcap), i * dt + tau, 1, n_lift, n_imp, x, v
    return 0, peak, t_peak, 0, n_lift, n_imp, x, v


def _params(frame: AFrame) -> np.ndarray:
    w2, g1, p2 = frame.stepped_constants
    cap = math.inf if frame.x_cap_m is None else float(frame.x_cap_m)
    return np.array(
        [frame.omega_1_rad_s, w2, g1, frame.p_1, p2, frame.xi_1, frame.x_c_m, frame.c_r, cap]
    )


@dataclass(frozen=True)
class AFrameRun:
    """Summary of one hysteretic A-frame run (SI units)."""

    peak_abs_x_m: float
    peak_time_s: float
    overturned: bool
    n_liftoffs: int
    n_impacts: int
    residual_x_m: float
    status: Status


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
    """
    ag = np.asarray(ground_acc_m_s2, dtype=float) * float(scale)
    if ag.ndim != 1 or ag.size < 2 or not np.all(np.isfinite(ag)):
        raise InputError("ground_acc_m_s2 must be a finite 1-D series, expected ≥ 2 samples")
    if not (math.isfinite(dt_s) and dt_s > 0):
        raise InputError(f"dt_s = {dt_s}, expected > 0")
    n_tail = math.ceil(max(tail_s, 0.0) / dt_s)
    st, peak, t_peak, over, nl, ni, x_end, _v = integrate_aframe(
        ag, float(dt_s), n_tail, _params(frame), int(max_events), float(x0_m), float(v0_m_s)
    )
    return AFrameRun(
        float(peak),
        float(t_peak),
        bool(over),
        int(nl),
        int(ni),
        float(x_end),
        "ok" if st == 0 else "too_many_events",
    )


def equivalent_viscous_error(
    frame: AFrame, records: list[tuple[Any, float]], scales: Any, *, tail_s: float = 10.0
) -> pd.DataFrame:
    """Peak |x| and overturning by the hysteretic model against its equivalent-viscous substitute.

    One row per (record, scale): ``peak_hysteretic_m``, ``peak_viscous_m``, ``rel_error`` (viscous
    over hysteretic minus 1), and both overturning verdicts.
    """
    import pandas as pd

    from stepframe.structure.simulator import simulate

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
                    "status": hyst.status,
                }
            )
    return pd.DataFrame(rows)
