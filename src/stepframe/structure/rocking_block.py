"""Housner's rigid block beyond small angles: the full nonlinear rocking equation.

The block is :class:`~stepframe.structure.frame.RockingBlock` (importable from here too).

Convention. θ is the block's rotation from upright [rad], positive when it rocks on the corner
on the +x side; α = atan(b/h) is its slenderness (b, h the half-width and half-height), R = √(b²
+ h²) the distance from a base corner to the centre of mass, p = √(3g/(4R)) its frequency
parameter (a rectangular block, I_o = 4mR²/3). Rocking on the corner of side s = sign θ (Housner
1963; Makris and Konstantinidis 2003)::

    θ̈ = -p² [sin(αs - θ) + (ẍ_g/g) cos(αs - θ)]

Its centre of mass is above the pivot at |θ| = α (static instability) and the block lies on its
side at |θ| = π/2: that is overturning here. At rest it lifts off when |ẍ_g| passes g·tan α (the
linearised block of :meth:`~stepframe.structure.frame.PortalFrame.housner_block`: g·α), on the
side opposite to the ground's push. At an impact (θ = 0) the angular velocity is multiplied by
the velocity ratio C_r (Housner's 1 - (3/2)sin²α by default, from angular momentum about the new
corner); Housner's energy ratio is r = C_r².

Integration: an embedded Runge-Kutta 5(4) pair (Dormand and Prince 1980) with step control on
a relative tolerance, restarted at every sample of a record (ẍ_g is linear between samples).
Events (the impact θ = 0, the extrema ẋ = 0 that give the peak, |θ| = π/2) are located on the
step's quintic Hermite interpolant (θ, θ̇, θ̈ at both ends) and the state at the event is a fresh
step of that length: exact to the tolerance. From rest the block leaves at the closed-form time
the ground crosses ±g·tan α; a rebound below 1e-7 pα ends an impact sequence seated.

Overturning is decided exactly. In free motion E = ½θ̇² + p²cos(αs - θ) is conserved between
impacts (an impact keeps θ = 0 and scales θ̇ by C_r), the top |θ| = α has E = p² and beyond it
gravity pushes outward, so a free block overturns iff, moving out, E > p² (or it is beyond the top
with E ≤ p² or moving out), or, moving in, its energy after the next impact still exceeds p².
Under forcing bounded by A, a block beyond α + atan(A/g) moving outward cannot return. A block
that did not overturn never passes α + atan(max|ẍ_g|/g): a result beyond it is "failed".
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.core import validation
from stepframe.core.jit import njit
from stepframe.core.results import Status
from stepframe.errors import InputError
from stepframe.structure.frame import RockingBlock

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: Default relative tolerance of the Runge-Kutta steps.
DEFAULT_RTOL = 1e-10

#: Forcing kinds of a kernel interval: linear between samples, or A cos(ωt + φ).
_LINEAR = 0
_HARMONIC = 1

# Dormand-Prince 5(4) tableau: nodes, stage coefficients (row i: stage i + 1; the last row is
# the fifth-order solution, whose derivative is the first stage of the next step) and the
# difference of the fifth- and fourth-order weights (the error estimate).
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = np.array(
    [
        [1 / 5, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3 / 40, 9 / 40, 0.0, 0.0, 0.0, 0.0],
        [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0, 0.0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0, 0.0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0.0],
        [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
    ]
)
_E = np.array([71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40])


def _params(block: RockingBlock) -> np.ndarray:
    """Kernel parameters (p, α, g, C_r) of a block."""
    return np.array([block.p_rad_s, block.alpha_rad, block.g_m_s2, block.restitution])


@dataclass(frozen=True)
class BlockRun:
    """Response of the nonlinear block (rotations in rad, times in s).

    Attributes
    ----------
    peak_rotation_rad, peak_time_s
        Largest |θ| (at the extrema of the motion) and its time; for a block that overturned,
        the rotation at the verdict.
    overturned, overturn_time_s
        Whether it overturned, and when (reached π/2, or certain to: see the module docstring).
    n_liftoffs, n_impacts
        Rocking episodes begun (from rest or through an impact) and impacts.
    residual_rotation_rad, residual_rate_rad_s
        State at the end.
    status, message
        One of :data:`stepframe.core.results.STATUSES`, and what went wrong.
    alpha_rad
        The block's α (for :attr:`peak_over_alpha`).
    history_rad
        θ at every output time when asked for, else None.
    """

    peak_rotation_rad: float
    peak_time_s: float
    overturned: bool
    overturn_time_s: float | None
    n_liftoffs: int
    n_impacts: int
    residual_rotation_rad: float
    residual_rate_rad_s: float
    status: Status
    message: str
    alpha_rad: float
    history_rad: np.ndarray | None = None

    @property
    def peak_over_alpha(self) -> float:
        """Largest |θ| relative to α (1: the centre of mass above the corner) [-]."""
        return self.peak_rotation_rad / self.alpha_rad

    def to_dict(self) -> dict[str, Any]:
        """Summary fields (not the history) as plain Python values."""
        return {
            "peak_rotation_rad": self.peak_rotation_rad,
            "peak_over_alpha": self.peak_over_alpha,
            "peak_time_s": self.peak_time_s,
            "overturned": self.overturned,
            "overturn_time_s": self.overturn_time_s,
            "n_liftoffs": self.n_liftoffs,
            "n_impacts": self.n_impacts,
            "residual_rotation_rad": self.residual_rotation_rad,
            "residual_rate_rad_s": self.residual_rate_rad_s,
            "status": self.status,
            "message": self.message,
        }


@njit(cache=True)
def _ground(kind: int, t: float, t_a: float, a0: float, slope: float, amp: float, om: float,
            phi: float) -> float:  # fmt: skip
    if kind == _LINEAR:
        return a0 + slope * (t - t_a)
    return amp * math.cos(om * t + phi)


@njit(cache=True)
def _acc(theta: float, ag: float, s: float, prm: np.ndarray) -> float:
    """θ̈ on the corner of side s."""
    p, alpha, g = prm[0], prm[1], prm[2]
    u = alpha * s - theta
    return float(-p * p * (math.sin(u) + ag / g * math.cos(u)))


@njit(cache=True)
def _hermite(
    y0: float, d0: float, a0: float, y1: float, d1: float, a1: float, h: float, u: float
) -> tuple[float, float]:
    """Quintic Hermite interpolant of θ and its derivative at u·h from θ, θ̇, θ̈ at both ends."""
    u2 = u * u
    u3 = u2 * u
    u4 = u3 * u
    u5 = u4 * u
    h0 = 1.0 - 10.0 * u3 + 15.0 * u4 - 6.0 * u5
    h1 = u - 6.0 * u3 + 8.0 * u4 - 3.0 * u5
    h2 = 0.5 * (u2 - 3.0 * u3 + 3.0 * u4 - u5)
    h3 = 10.0 * u3 - 15.0 * u4 + 6.0 * u5
    h4 = -4.0 * u3 + 7.0 * u4 - 3.0 * u5
    h5 = 0.5 * (u3 - 2.0 * u4 + u5)
    g0 = -30.0 * u2 + 60.0 * u3 - 30.0 * u4
    g1 = 1.0 - 18.0 * u2 + 32.0 * u3 - 15.0 * u4
    g2 = 0.5 * (2.0 * u - 9.0 * u2 + 12.0 * u3 - 5.0 * u4)
    g4 = -12.0 * u2 + 28.0 * u3 - 15.0 * u4
    g5 = 0.5 * (3.0 * u2 - 8.0 * u3 + 5.0 * u4)
    y = y0 * h0 + h * d0 * h1 + h * h * a0 * h2 + y1 * h3 + h * d1 * h4 + h * h * a1 * h5
    dy = (y0 - y1) * g0 / h + d0 * g1 + h * a0 * g2 + d1 * g4 + h * a1 * g5
    return y, dy


@njit(cache=True)
def _hermite_root(
    y0: float, d0: float, a0: float, y1: float, d1: float, a1: float, h: float, target: float,
    deriv: int,
) -> float:  # fmt: skip
    """u in (0, 1] where the interpolant (deriv 0) or its derivative (1) crosses ``target``."""
    lo = 0.0
    hi = 1.0
    f_lo = _hermite(y0, d0, a0, y1, d1, a1, h, lo)[deriv] - target
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        f = _hermite(y0, d0, a0, y1, d1, a1, h, mid)[deriv] - target
        if (f > 0.0) == (f_lo > 0.0) and f != 0.0:
            lo = mid
            f_lo = f
        else:
            hi = mid
    return hi


@njit(cache=True)
def _step(
    t: float, th: float, om_: float, k1: float, h: float, s: float, kind: int, t_a: float,
    a0: float, slope: float, amp: float, om: float, phi: float, prm: np.ndarray,
) -> tuple[float, float, float, float, float]:  # fmt: skip
    """One Dormand-Prince step from (θ, θ̇) with θ̈ = k1 at t: (θ, θ̇, θ̈ at t + h, err_θ, err_θ̇)."""
    vs = np.empty(7)
    ks = np.empty(7)
    vs[0] = om_
    ks[0] = k1
    y = th
    v = om_
    for i in range(6):
        y = th
        v = om_
        for j in range(i + 1):
            y += h * _A[i, j] * vs[j]
            v += h * _A[i, j] * ks[j]
        vs[i + 1] = v
        tt = t + _C[i + 1] * h
        ks[i + 1] = _acc(y, _ground(kind, tt, t_a, a0, slope, amp, om, phi), s, prm)
    e_y = 0.0
    e_v = 0.0
    for j in range(7):
        e_y += h * _E[j] * vs[j]
        e_v += h * _E[j] * ks[j]
    return y, v, ks[6], e_y, e_v


@njit(cache=True)
def _free_verdict(th: float, om_: float, prm: np.ndarray) -> tuple[bool, float]:
    """(overturns, largest |θ| still to come) of the free block at (θ, θ̇), exactly."""
    p, alpha, cr = prm[0], prm[1], prm[3]
    if th == 0.0 and om_ == 0.0:
        return False, 0.0
    s = 1.0 if (th > 0.0 or (th == 0.0 and om_ > 0.0)) else -1.0
    p2 = p * p
    e = 0.5 * om_ * om_ + p2 * math.cos(alpha * s - th)
    outward = s * om_ > 0.0
    beyond = s * th > alpha
    if beyond:
        if outward or e <= p2:
            return True, 0.5 * math.pi
    elif outward:
        if e > p2:
            return True, 0.5 * math.pi
        return False, alpha - math.acos(min(e / p2, 1.0))
    # Moving in (from within the top, or back over it): the impact keeps C_r² of the kinetic
    # energy at θ = 0, where the potential is p²cos α on either side.
    kin = e - p2 * math.cos(alpha)
    e2 = cr * cr * kin + p2 * math.cos(alpha)
    if e2 > p2:
        return True, 0.5 * math.pi
    return False, alpha - math.acos(min(e2 / p2, 1.0))


@njit(cache=True)
def _leave_time(
    kind: int, t: float, t_b: float, t_a: float, a0: float, slope: float, amp: float, om: float,
    phi: float, lim: float,
) -> tuple[float, float]:  # fmt: skip
    """(time, side) at which a seated block lifts off (|ẍ_g| > lim) in [t, t_b) (inf: it stays).

    ẍ_g > lim tips it to θ < 0 (side -1), ẍ_g < -lim to side +1; closed form for both kinds.
    """
    best = math.inf
    side = 0.0
    for sgn in (1.0, -1.0):
        # First time sgn·ẍ_g > lim.
        if kind == _LINEAR:
            now = sgn * (a0 + slope * (t - t_a))
            if now > lim:
                tl = t
            elif sgn * slope > 0.0:
                tl = t + (lim - now) / (sgn * slope)
            else:
                tl = math.inf
        else:
            c = sgn * amp
            if c <= lim or om == 0.0:
                tl = t if (om == 0.0 and c * math.cos(phi) > lim) else math.inf
            else:
                th0 = om * t + phi
                if c * math.cos(th0) > lim:
                    tl = t
                else:
                    enter = -math.acos(lim / c)
                    base = th0 - 2.0 * math.pi * math.floor(th0 / (2.0 * math.pi))
                    d = enter - base
                    d -= 2.0 * math.pi * math.floor(d / (2.0 * math.pi))
                    tl = t + d / om
        if tl < best:
            best = tl
            side = -sgn
    if best >= t_b:
        return math.inf, 0.0
    return best, side


@njit(cache=True)
def advance_block(
    prm: np.ndarray, kind: int, t: float, t_b: float, t_a: float, a0: float, slope: float,
    amp: float, om: float, phi: float, amp_bound: float, th: float, w: float, phase: int,
    h_try: float, rtol: float, counts: np.ndarray,
) -> tuple[int, float, float, int, float, float, float]:  # fmt: skip
    """Integrate the block from t to t_b under one smooth piece of ground motion.

    ``counts`` = [n_liftoffs, n_impacts, peak |θ|, t_peak, overturned, t_overturn] is updated.
    ``amp_bound`` bounds |ẍ_g| for the rest of the forcing (the certain-escape test).

    Returns
    -------
    (status, θ, θ̇, phase (0 seated, ±1 rocking), t, next step size, n steps)
    """
    p, alpha, g, cr = prm[0], prm[1], prm[2], prm[3]
    lim = g * math.tan(alpha)
    tol_a = 64.0 * 2.2e-16 * (lim + abs(amp) + abs(a0) + abs(slope) * (t_b - t_a))
    w_eps = 1e-7 * p * alpha
    h_max = 0.1 / p
    escape = alpha + math.atan(amp_bound / g)
    n_steps = 0.0
    h = min(h_try, h_max)
    s = float(phase)
    k1 = 0.0
    if phase != 0:
        k1 = _acc(th, _ground(kind, t, t_a, a0, slope, amp, om, phi), s, prm)
    while t < t_b:
        if n_steps > 1e7:
            return 2, th, w, phase, t, h, n_steps
        if phase == 0:
            tl, side = _leave_time(kind, t, t_b, t_a, a0, slope, amp, om, phi, lim + tol_a)
            if tl == math.inf:
                return 0, 0.0, 0.0, 0, t_b, h, n_steps
            t = tl
            phase = int(side)
            s = side
            th = 0.0
            w = 0.0
            counts[0] += 1
            k1 = _acc(th, _ground(kind, t, t_a, a0, slope, amp, om, phi), s, prm)
            # The first step no longer than a tenth of the time the push takes to build up.
            h = min(h_max, 1e-3 / p)
            continue
        h = min(h, t_b - t)
        n_steps += 1.0
        y1, v1, k7, e_y, e_v = _step(t, th, w, k1, h, s, kind, t_a, a0, slope, amp, om, phi, prm)
        sc_y = rtol * (alpha + max(abs(th), abs(y1)))
        sc_v = rtol * (p * alpha + max(abs(w), abs(v1)))
        err = max(abs(e_y) / sc_y, abs(e_v) / sc_v)
        if not (math.isfinite(y1) and math.isfinite(v1)):
            if h > 1e-300:
                h *= 0.1
                continue
            return 1, y1, v1, phase, t, h, n_steps
        if err > 1.0:
            h *= max(0.2, 0.9 * err**-0.2)
            continue
        h_next = h * min(5.0, max(0.2, 0.9 * (err if err > 1e-30 else 1e-30) ** -0.2))
        # Events inside the accepted step, on its interpolant: the first of the impact (s·θ
        # crossing 0) and |θ| = π/2; the extremum (θ̇ = 0) for the peak.
        ev = 0
        u_ev = 1.0
        if s * y1 < 0.0:
            ev = 1
            u_ev = _hermite_root(th, w, k1, y1, v1, k7, h, 0.0, 0)
        if abs(y1) >= 0.5 * math.pi:
            u_o = _hermite_root(s * th, s * w, s * k1, s * y1, s * v1, s * k7, h, 0.5 * math.pi, 0)
            if ev == 0 or u_o < u_ev:
                ev = 2
                u_ev = u_o
        if (w > 0.0 and v1 < 0.0) or (w < 0.0 and v1 > 0.0):
            u_e = _hermite_root(th, w, k1, y1, v1, k7, h, 0.0, 1)
            if ev == 0 or u_e < u_ev:
                y_e = _hermite(th, w, k1, y1, v1, k7, h, u_e)[0]
                if abs(y_e) > counts[2]:
                    counts[2] = abs(y_e)
                    counts[3] = t + u_e * h
        if ev != 0:
            # The state at the event: a fresh step of that length from the step's start.
            h_ev = u_ev * h
            _y_ev, v_ev, _k, _ey, _ev = _step(
                t, th, w, k1, h_ev, s, kind, t_a, a0, slope, amp, om, phi, prm
            )
            t += h_ev
            if ev == 2:
                counts[2] = max(counts[2], 0.5 * math.pi)
                counts[4] = 1.0
                counts[5] = t
                return 0, s * 0.5 * math.pi, v_ev, phase, t, h_next, n_steps
            counts[1] += 1
            w = cr * v_ev
            th = 0.0
            ag = _ground(kind, t, t_a, a0, slope, amp, om, phi)
            if abs(w) <= w_eps:
                # Too slow to follow: seated, unless the ground lifts it right away.
                w = 0.0
                phase = 0
                continue
            s = -s
            phase = int(s)
            counts[0] += 1
            k1 = _acc(0.0, ag, s, prm)
            # At most a tenth of the flight this rebound allows before the next extremum.
            h = min(h_next, 0.1 * abs(w / k1) if k1 != 0.0 else h_next)
            continue
        t += h
        th = y1
        w = v1
        k1 = k7
        h = h_next
        if abs(th) > counts[2]:
            counts[2] = abs(th)
            counts[3] = t
        if s * th > escape and s * w > 0.0:
            counts[4] = 1.0
            counts[5] = t
            return 0, th, w, phase, t, h, n_steps
    return 0, th, w, phase, t, h, n_steps


# ----------------------------------------------------------------------------- runs
def _start_phase(theta: float, rate: float) -> int:
    if theta != 0.0:
        return 1 if theta > 0.0 else -1
    if rate != 0.0:
        return 1 if rate > 0.0 else -1
    return 0


def _finish(
    prm: np.ndarray, counts: np.ndarray, code: int, th: float, w: float, t_end: float,
    free_after: bool, amp_bound: float, theta0: float,
) -> tuple[Status, str, bool, float | None, float]:  # fmt: skip
    """Status, message, overturned, its time and the peak after the free-motion verdict."""
    from stepframe.structure.status import STATUS_MESSAGES, STATUS_NAMES, run_invariant

    overturned = bool(counts[4])
    t_over = float(counts[5]) if overturned else None
    peak = float(counts[2])
    if code == 0 and not overturned and free_after:
        over, ahead = _free_verdict(th, w, prm)
        if over:
            overturned, t_over = True, t_end
        else:
            peak = max(peak, ahead)
    bound = max(abs(theta0), prm[1] + math.atan(amp_bound / prm[2])) * (1.0 + 1e-9)
    code = run_invariant(code, overturned, peak, bound, th, w)
    return STATUS_NAMES[code], STATUS_MESSAGES[code], overturned, t_over, peak


def simulate_block(
    block: RockingBlock,
    ground_acc_m_s2: ArrayLike,
    dt_s: float,
    *,
    scale: float = 1.0,
    tail_s: float = 10.0,
    theta0_rad: float = 0.0,
    rate0_rad_s: float = 0.0,
    rtol: float = DEFAULT_RTOL,
    record_history: bool = False,
) -> BlockRun:
    """Response of the nonlinear block to a record (linear between samples), then a free tail.

    At the end of the tail the free-motion verdict is exact (module docstring): a block still
    certain to overturn is reported overturned at the end, and a surviving one's peak includes
    the turning point still ahead of it.

    Parameters
    ----------
    block
        The :class:`RockingBlock`.
    ground_acc_m_s2, dt_s, scale
        Ground acceleration samples [m/s²], their interval [s] and a scale factor.
    tail_s
        Free motion after the record [s].
    theta0_rad, rate0_rad_s
        Initial rotation [rad] and angular velocity [rad/s].
    rtol
        Relative tolerance of the Runge-Kutta steps.
    record_history
        Keep θ at every sample time.
    """
    from stepframe.structure import work
    from stepframe.structure.simulator import _check_motion

    ag = _check_motion(ground_acc_m_s2, dt_s) * validation.finite("scale", scale)
    tail = validation.non_negative("tail_s", tail_s)
    th = validation.finite("theta0_rad", theta0_rad)
    w = validation.finite("rate0_rad_s", rate0_rad_s)
    if not abs(th) < 0.5 * math.pi:
        raise InputError(f"theta0_rad = {th}, expected |θ₀| < π/2 (the block on its base)")
    validation.in_range("rtol", rtol, 1e-14, 1e-3)
    n_tail = math.ceil(tail / dt_s - 1e-9)
    n = ag.size - 1 + n_tail
    what = f"a block run of {ag.size} samples at {dt_s:g} s with a {tail:g} s tail"
    work.check_work(n * 2.0, what, "shorten the tail or the record")
    prm = _params(block)
    counts = np.array([0.0, 0.0, abs(th), 0.0, 0.0, math.nan])
    phase = _start_phase(th, w)
    hist = np.full(n + 1 if record_history else 0, np.nan)
    if record_history:
        hist[0] = th
    suffix = np.maximum.accumulate(np.abs(ag)[::-1])[::-1]
    h = 1e-3 / block.p_rad_s
    code = 0
    for i in range(n):
        t_a = i * dt_s
        a0 = float(ag[i]) if i < ag.size - 1 else 0.0
        a1 = float(ag[i + 1]) if i < ag.size - 1 else 0.0
        bound = float(suffix[i]) if i < ag.size - 1 else 0.0
        code, th, w, phase, _t, h, _n = advance_block(
            prm, _LINEAR, t_a, t_a + dt_s, t_a, a0, (a1 - a0) / dt_s, 0.0, 0.0, 0.0, bound,
            th, w, phase, h, rtol, counts,
        )  # fmt: skip
        if code != 0 or counts[4]:
            break
        if record_history:
            hist[i + 1] = th
    amp_bound = float(np.max(np.abs(ag)))
    status, message, over, t_over, peak = _finish(
        prm, counts, int(code), th, w, n * dt_s, True, amp_bound, theta0_rad
    )
    return BlockRun(
        peak, float(counts[3]), over, t_over, int(counts[0]), int(counts[1]), float(th),
        float(w), status, message, block.alpha_rad, hist if record_history else None,
    )  # fmt: skip


def block_pulse(
    block: RockingBlock,
    amplitude_m_s2: float,
    omega_rad_s: float,
    *,
    kind: str = "cosine",
    rtol: float = DEFAULT_RTOL,
) -> BlockRun:
    """The block at rest hit by one cycle A cos(ωt + φ), 0 ≤ t ≤ 2π/ω, then free motion.

    The free motion after the pulse is decided exactly (no integration): overturning, and the
    largest rotation still ahead. ``kind`` is ``"cosine"`` (φ = 0) or ``"sine"`` (φ = -π/2), as
    :func:`stepframe.structure.harmonic.simulate_pulse`.
    """
    from stepframe.structure.harmonic import pulse_phase_rad

    amp = validation.non_negative("amplitude_m_s2", amplitude_m_s2)
    om = validation.positive("omega_rad_s", omega_rad_s)
    phi = pulse_phase_rad(kind)  # type: ignore[arg-type]
    validation.in_range("rtol", rtol, 1e-14, 1e-3)
    tp = 2.0 * math.pi / om
    from stepframe.structure import work

    work.check_work(
        tp * max(16.0 * om / (2.0 * math.pi), block.p_rad_s) * 10.0,
        f"a pulse of {tp:.6g} s", "ask for a higher pulse frequency",
    )  # fmt: skip
    prm = _params(block)
    counts = np.array([0.0, 0.0, 0.0, 0.0, 0.0, math.nan])
    code, th, w, _phase, t, _h, _n = advance_block(
        prm, _HARMONIC, 0.0, tp, 0.0, 0.0, 0.0, amp, om, phi, amp, 0.0, 0.0, 0, 1e-3 / prm[0],
        rtol, counts,
    )  # fmt: skip
    status, message, over, t_over, peak = _finish(prm, counts, int(code), th, w, t, True, amp, 0.0)
    return BlockRun(
        peak, float(counts[3]), over, t_over, int(counts[0]), int(counts[1]), float(th),
        float(w), status, message, block.alpha_rad,
    )  # fmt: skip


def block_harmonic(
    block: RockingBlock,
    amplitude_m_s2: float,
    omega_rad_s: float,
    duration_s: float,
    *,
    phase_rad: float = 0.0,
    samples_per_period: int = 32,
    rtol: float = DEFAULT_RTOL,
) -> BlockRun:
    """The block at rest under ẍ_g = A cos(ωt + φ) for ``duration_s`` (the forcing never stops:
    no free-motion verdict; θ at ``samples_per_period`` points a period in the history)."""
    from stepframe.structure import work

    amp = validation.non_negative("amplitude_m_s2", amplitude_m_s2)
    om = validation.positive("omega_rad_s", omega_rad_s)
    dur = validation.positive("duration_s", duration_s)
    phi = validation.finite("phase_rad", phase_rad)
    validation.in_range("rtol", rtol, 1e-14, 1e-3)
    periods = dur * om / (2.0 * math.pi)
    what = f"a block run of {dur:.6g} s ({periods:.6g} forcing periods)"
    n = max(1, math.ceil(periods * samples_per_period))
    work.check_samples(n, what, "lower samples_per_period or the duration")
    work.check_work(
        dur * max(16.0 * om / (2.0 * math.pi), block.p_rad_s) * 10.0 + work.SAMPLE_UNITS * n,
        what, "ask for fewer periods or a higher forcing frequency",
    )  # fmt: skip
    prm = _params(block)
    counts = np.array([0.0, 0.0, 0.0, 0.0, 0.0, math.nan])
    times = np.linspace(0.0, dur, n + 1)
    hist = np.full(n + 1, np.nan)
    hist[0] = 0.0
    th = w = 0.0
    phase = 0
    h = 1e-3 / block.p_rad_s
    code = 0
    for i in range(n):
        code, th, w, phase, _t, h, _n = advance_block(
            prm, _HARMONIC, times[i], times[i + 1], 0.0, 0.0, 0.0, amp, om, phi, amp, th, w,
            phase, h, rtol, counts,
        )  # fmt: skip
        if code != 0 or counts[4]:
            break
        hist[i + 1] = th
    status, message, over, t_over, peak = _finish(
        prm, counts, int(code), th, w, dur, False, amp, 0.0
    )
    return BlockRun(
        peak, float(counts[3]), over, t_over, int(counts[0]), int(counts[1]), float(th),
        float(w), status, message, block.alpha_rad, hist,
    )  # fmt: skip
