"""An independent integrator of the stepping A-frame (eqs. 4.1-4.2) with sticking, for tests.

Written from the equations, not from :mod:`stepframe.structure.aframe_hysteretic`: scipy's
``solve_ivp`` (DOP853) restarted at every sample of the record (the ground acceleration is
linear between samples) and at every event, each located by ``solve_ivp``'s own event finder:

- unstepped, moving in direction d: ẍ = -πξ₁ω₁² d|x| - ω₁²x - P₁ẍ_g; events ẋ = 0 (it stops),
  x = 0 (|x| has a kink: restart there), |x| = x_c moving out (lift-off);
- stepped on side s: ẍ = ω₂'²x - sγ₁' - P₂'ẍ_g; events s·x = x_c moving in (impact: ẋ → C_rẋ),
  |x| = x_cap;
- at rest at x: F = -ω₁²x - P₁ẍ_g must stay within ±W, W = πξ₁ω₁²|x| (sign(0) ∈ [-1, 1] in
  eq. 4.1, the Filippov sliding state); events F = ±W (it moves that way), and on the surface
  |x| = x_c the stepped phase's outward push m = ω₂'²x_c - γ₁' - sP₂'ẍ_g = 0 (it lifts off).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from stepframe.structure.frame import AFrame


@dataclass
class Reference:
    """x at the sample times (NaN after the cap), the peak |x|, the times the frame stuck,
    the events, and whether it reached the cap."""

    x_m: np.ndarray
    peak_abs_x_m: float
    stick_times_s: list[float] = field(default_factory=list)
    n_impacts: int = 0
    n_liftoffs: int = 0
    overturned: bool = False


def aframe_reference(
    frame: AFrame, ag: np.ndarray, dt: float, *, x0: float = 0.0, v0: float = 0.0
) -> Reference:
    """Integrate the A-frame under ``ag`` [m/s²] sampled at ``dt`` [s] from (x0, v0)."""
    w1, p1, xi, xc, cr = frame.omega_1_rad_s, frame.p_1, frame.xi_1, frame.x_c_m, frame.c_r
    w2, g1, p2 = frame.stepped_constants
    cap = math.inf if frame.x_cap_m is None else frame.x_cap_m
    h = math.pi * xi * w1 * w1

    def rest_mode(x: float, a: float) -> tuple[str, float]:
        f = -w1 * w1 * x - p1 * a
        s = 1.0 if x >= 0 else -1.0
        if abs(abs(x) - xc) <= 1e-12 * xc:
            if w2 * w2 * xc - g1 - s * p2 * a > 0:
                return "stepped", s
            return ("move", -s) if s * f < -h * abs(x) else ("rest", 0.0)
        if f > h * abs(x):
            return "move", 1.0
        if f < -h * abs(x):
            return "move", -1.0
        return "rest", 0.0

    n = ag.size
    xs = np.empty(n)
    xs[0] = x0
    x, v = x0, v0
    if abs(x) > xc:
        mode, par = "stepped", math.copysign(1.0, x)
    elif v != 0:
        mode, par = "move", math.copysign(1.0, v)
    else:
        mode, par = rest_mode(x, ag[0])
    out = Reference(xs, abs(x0))
    for i in range(n - 1):
        t, t_end = i * dt, (i + 1) * dt
        slope = (ag[i + 1] - ag[i]) / dt

        def acc(tt: float, i: int = i, slope: float = slope) -> float:
            return float(ag[i] + slope * (tt - i * dt))

        while t < t_end - 1e-15:
            if mode == "rest":
                xr, s = x, (1.0 if x >= 0 else -1.0)
                on_surface = abs(abs(xr) - xc) <= 1e-12 * xc
                exits = []  # (event function, mode, parameter) in no particular order
                for d in (1.0, -1.0):
                    if on_surface and d == s:
                        continue  # pushed out on the surface: the stepped phase decides
                    exits.append(
                        (lambda tt, y, d=d, xr=xr: d * (-w1 * w1 * xr - p1 * acc(tt)) - h * abs(xr),
                         "move", d)
                    )  # fmt: skip
                if on_surface:
                    exits.append(
                        (lambda tt, y, s=s: w2 * w2 * xc - g1 - s * p2 * acc(tt), "stepped", s)
                    )
                for ev, _m, _p in exits:
                    ev.terminal = True  # type: ignore[attr-defined]
                    ev.direction = 1  # type: ignore[attr-defined]
                sol = solve_ivp(
                    lambda tt, y: [0.0, 0.0], (t, t_end), [x, 0.0],
                    events=[e for e, _m, _p in exits], rtol=1e-12, atol=1e-15,
                )  # fmt: skip
                hits = [(te[0], k) for k, te in enumerate(sol.t_events) if te.size]
                if not hits:
                    t = t_end
                    break
                t, k = min(hits)
                _ev, mode, par = exits[k]
                if mode == "stepped":
                    out.n_liftoffs += 1
                v = 0.0
                continue
            if mode == "move":
                d = par

                def rhs(tt: float, y: np.ndarray, d: float = d) -> list[float]:
                    return [y[1], -h * d * abs(y[0]) - w1 * w1 * y[0] - p1 * acc(tt)]

                def stop(tt: float, y: np.ndarray) -> float:
                    return float(y[1])

                def zero(tt: float, y: np.ndarray) -> float:
                    return float(y[0])

                def out_pos(tt: float, y: np.ndarray) -> float:
                    return float(y[0] - xc)

                def out_neg(tt: float, y: np.ndarray) -> float:
                    return float(-y[0] - xc)

                # x crosses 0 only in the direction of motion; from x = 0 it cannot again
                # before it stops.
                stop.direction = -d  # type: ignore[attr-defined]
                zero.direction = d  # type: ignore[attr-defined]
                out_pos.direction = out_neg.direction = 1  # type: ignore[attr-defined]
                events = [stop, zero if x != 0.0 else stop, out_pos, out_neg]
                for ev in events:
                    ev.terminal = True  # type: ignore[attr-defined]
                sol = solve_ivp(
                    rhs, (t, t_end), [x, v], method="DOP853", events=events, rtol=1e-12,
                    atol=1e-15, dense_output=True,
                )  # fmt: skip
                out.peak_abs_x_m = max(out.peak_abs_x_m, float(np.max(np.abs(sol.y[0]))))
                hits = [(te[0], k) for k, te in enumerate(sol.t_events) if te.size and te[0] > t]
                t_new = sol.t[-1]
                x, v = sol.y[:, -1]
                if not hits:
                    t = t_new
                    continue
                t, k = min(hits)
                x, v = sol.sol(t)
                if k == 0:
                    v = 0.0
                    out.peak_abs_x_m = max(out.peak_abs_x_m, abs(x))
                    mode, par = rest_mode(x, acc(t))
                    if mode == "rest":
                        out.stick_times_s.append(t)
                    elif mode == "stepped":
                        out.n_liftoffs += 1
                elif k == 1:
                    x = 0.0
                else:
                    x = xc if k == 2 else -xc
                    mode, par = "stepped", math.copysign(1.0, x)
                    out.n_liftoffs += 1
                continue
            s = par

            def rhs2(tt: float, y: np.ndarray, s: float = s) -> list[float]:
                return [y[1], w2 * w2 * y[0] - s * g1 - p2 * acc(tt)]

            def land(tt: float, y: np.ndarray, s: float = s) -> float:
                return float(s * y[0] - xc)

            def top(tt: float, y: np.ndarray, s: float = s) -> float:
                return float(s * y[0] - cap)

            def turn(tt: float, y: np.ndarray) -> float:
                return float(y[1])

            land.terminal = top.terminal = True  # type: ignore[attr-defined]
            land.direction = -1  # type: ignore[attr-defined]
            top.direction = 1  # type: ignore[attr-defined]
            sol = solve_ivp(
                rhs2, (t, t_end), [x, v], method="DOP853", events=[land, top, turn], rtol=1e-12,
                atol=1e-15, dense_output=True,
            )  # fmt: skip
            # Peaks at the extrema (ẋ = 0, located as events) and at the ends.
            ends = np.concatenate([sol.t[[0, -1]], sol.t_events[2]])
            out.peak_abs_x_m = max(out.peak_abs_x_m, float(np.max(np.abs(sol.sol(ends)[0]))))
            hits = [(te[0], k) for k, te in enumerate(sol.t_events[:2]) if te.size and te[0] > t]
            x, v = sol.y[:, -1]
            if not hits:
                t = sol.t[-1]
                continue
            t, k = min(hits)
            x, v = sol.sol(t)
            if k == 1:
                out.overturned = True
                xs[i + 1 :] = math.nan
                return out
            x, v = s * xc, cr * v
            out.n_impacts += 1
            mode, par = "move", -s
        xs[i + 1] = x
    return out
