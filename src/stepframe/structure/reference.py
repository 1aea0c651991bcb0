"""Independent cross-check of the exact integrator with ``scipy.integrate.solve_ivp``.

The same model (eqs. 4.11-4.12, impact at touchdown) integrated by a general-purpose solver,
restarted at every sample (so the linear interpolation of the ground acceleration is followed
exactly and no step straddles a kink of the forcing) and after every switch, with terminal events
whose direction is set per side: from the unstepped phase x = +x_c upward and x = -x_c downward;
from the stepped phase on side s, s·x = x_c inward (touchdown) and s·x = x_cap outward. A
non-terminal event on ẋ = 0 gives the true peaks. It shares no code with
:mod:`stepframe.structure._exact` and is used by tests and benchmarks, never by default: it is
orders of magnitude slower.

It follows the same model rules, written here afresh: an impact rebound below
``CHATTER_EPS·ω·x_ref`` is summed in closed form (one excursion and lift-off, or the whole
accumulating sequence and then seated); C_r = 0 is the limit C_r → 0+; without a cap, a stepped
state that cannot return whatever the rest of the record does is an overturn from that sample;
a state on the wrong side of its phase, or a peak past the bound a non-escaping frame respects,
ends the run with a failure status (docs/paper-notes.md, "Chatter").
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

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
    STATUS_OK,
    STATUS_SOLVER_FAILED,
    Model,
    RawRun,
)


def _rhs(model: Model, phase: int, t0: float, a0: float, slope: float) -> Any:
    w1, w2, p1, p2, g1, xi1, xi2 = model[:7]
    if phase == 0:

        def f(t: float, y: np.ndarray) -> list[float]:
            ag = a0 + slope * (t - t0)
            return [y[1], -2.0 * xi1 * w1 * y[1] - w1 * w1 * y[0] - p1 * ag]

        return f
    s = 1.0 if phase > 0 else -1.0

    def g(t: float, y: np.ndarray) -> list[float]:
        ag = a0 + slope * (t - t0)
        return [y[1], -2.0 * xi2 * w2 * y[1] + w2 * w2 * y[0] - s * g1 - p2 * ag]

    return g


def _event(offset: float, sign: float, direction: float) -> Any:
    def e(t: float, y: np.ndarray) -> float:
        return float(sign * y[0] - offset)

    e.terminal = True  # type: ignore[attr-defined]
    e.direction = direction  # type: ignore[attr-defined]
    return e


def _velocity_zero(t: float, y: np.ndarray) -> float:
    return float(y[1])


def integrate_reference(
    model: Model,
    ag: np.ndarray,
    dt_s: float,
    n_tail: int,
    x0: float,
    v0: float,
    method: str,
    rtol: float,
    atol: float,
    record_history: bool,
) -> RawRun:
    """Integrate with ``solve_ivp`` (see the module docstring); same outputs as the kernel."""
    from scipy.integrate import solve_ivp

    w1, w2, p1, p2, g1, _xi1, xi2, xc, cr, xcap = model
    x_star = g1 / (w2 * w2)
    lam2 = -w2 * (xi2 + math.sqrt(1.0 + xi2 * xi2))
    n_rec = ag.size - 1
    n_total = n_rec + n_tail
    hist_x: list[float] = [x0]
    hist_v: list[float] = [v0]
    hist_p: list[int] = []
    ev_t: list[float] = []
    ev_kind: list[int] = []
    ev_v_in: list[float] = []
    ev_v_out: list[float] = []
    ev_peak: list[float] = []

    def surface(side: float, agv: float) -> int:
        if w2 * w2 * xc - g1 - side * p2 * agv > 0:
            return int(side)
        if xc > 0 and -w1 * w1 * xc - side * p1 * agv < 0:
            return 0
        if xc == 0 and -g1 + side * p2 * agv > 0:
            return -int(side)
        return 2 * int(side)

    x, v = x0, v0
    if abs(x) < xc:
        phase = 0
    elif abs(x) > xc:
        phase = 1 if x > 0 else -1
    else:
        side0 = 1.0 if x >= 0 else -1.0
        phase = int(side0) if v * side0 > 0 else (0 if v * side0 < 0 else surface(side0, ag[0]))
    hist_p.append(phase)
    peak, t_peak = abs(x), 0.0
    n_lift = n_imp = 0
    overturned, t_over = False, math.nan
    status = STATUS_OK
    cur_lift, ep_peak = -1, abs(x)
    if phase in (1, -1) and abs(x) == xc:
        n_lift, cur_lift = 1, 0
        ev_t.append(0.0)
        ev_kind.append(EVENT_LIFTOFF)
        ev_v_in.append(v)
        ev_v_out.append(v)
        ev_peak.append(math.copysign(xc, phase))
    x_ref = max(xc, x_star)
    w_small = CHATTER_EPS * max(w1, w2) * x_ref
    # Largest |ẍ_g| from each sample to the end of the record (certain-escape test, no cap).
    ahead = np.maximum.accumulate(np.abs(ag[::-1]))[::-1] if ag.size else np.zeros(0)

    def after_impact(
        side: float, w: float, agv: float, rate: float, left: float
    ) -> tuple[str, float, float]:
        """("follow", 0, w), ("lift", delay, speed) or ("seat", delay, 0) after an impact."""
        # Accelerations at rest on the surface: into the inner region (unstepped, or the far
        # side for the block) and back out into the stepped phase on this side.
        into = (w1**2 * xc + side * p1 * agv) if xc > 0 else (side * p2 * agv - g1)
        out = w2**2 * xc - g1 - side * p2 * agv
        # Within rounding of zero an acceleration's sign is noise: seated decides instead.
        noise = INVARIANT_RTOL * max(w1, w2) ** 2 * x_ref
        if w > w_small or into > noise:
            return "follow", 0.0, w
        if abs(into) <= noise:
            return ("seat", 0.0, 0.0) if w == 0 else ("follow", 0.0, w)
        first = 2 * w / abs(into)
        block = xc == 0
        # How fast each acceleration changes: the closed form assumes both constant.
        d_into = abs((p2 if block else p1) * rate)
        d_out = abs(p2 * rate)
        # Below w_small/10 the sum is used even where the forcing drifts (flights that small
        # would sink below the rounding of x).
        forced = w <= 0.1 * w_small
        if out > noise or (abs(out) <= noise and w > 0):
            steady = forced or d_into * first <= CHATTER_DRIFT * abs(into)
            lift = first <= left and steady
            return ("lift", first, cr * w if block else w) if lift else ("follow", 0, w)
        if abs(out) <= noise:
            return "seat", 0.0, 0.0
        # The rebound speeds after each impact form a geometric series: w, C_r w, C_r² w, ...
        # (the block strikes at both ends of a cycle, the portal frame once).
        per_cycle = cr**2 if block else cr
        one = first + 2 * w * (cr if block else 1.0) / abs(out)
        total = one / (1 - per_cycle) if per_cycle < 1 else one
        steady = forced or max(d_into / abs(into), d_out / abs(out)) * total <= CHATTER_DRIFT
        return ("seat", total, 0.0) if total <= left and steady else ("follow", 0.0, w)

    def liftoff(t: float, vel: float) -> None:
        nonlocal n_lift, cur_lift, ep_peak
        n_lift += 1
        cur_lift = len(ev_t)
        ep_peak = xc
        side = 1.0 if phase > 0 else -1.0
        ev_t.append(t)
        ev_kind.append(EVENT_LIFTOFF)
        ev_v_in.append(vel)
        ev_v_out.append(vel)
        ev_peak.append(side * xc)

    def close_episode() -> None:
        if cur_lift >= 0:
            ev_peak[cur_lift] = math.copysign(ep_peak, ev_peak[cur_lift])

    i = 0
    done = False
    while not done:
        if i >= n_total and not (overturned and xcap < math.inf and math.isnan(t_over)):
            break
        t0 = i * dt_s
        t1 = t0 + dt_s
        a0, a1 = (ag[i], ag[i + 1]) if i < n_rec else (0.0, 0.0)
        slope = (a1 - a0) / dt_s
        if xcap == math.inf and phase in (1, -1) and not overturned:
            # Beyond reach of return whatever the rest of the record does: overturned now.
            side = 1.0 if phase > 0 else -1.0
            reach = (g1 + p2 * (ahead[i] if i < n_rec else 0.0)) / w2**2
            if side * v - lam2 * (side * x - reach) > 0:
                overturned, t_over = True, t0
                ev_t.append(t0)
                ev_kind.append(EVENT_ESCAPE)
                ev_v_in.append(v)
                ev_v_out.append(v)
                ev_peak.append(x)
                break
        if i == n_rec and phase in (1, -1) and not overturned:
            side = 1.0 if phase > 0 else -1.0
            if side * v - lam2 * (side * x - x_star) > 0:
                overturned = True
                ev_t.append(t0)
                ev_kind.append(EVENT_ESCAPE)
                ev_v_in.append(v)
                ev_v_out.append(v)
                ev_peak.append(x)
        t = t0
        fresh = False
        while t < t1:
            agv = a0 + slope * (t - t0)
            if phase in (2, -2):
                side = 1.0 if phase > 0 else -1.0
                # Held on the surface until a phase's acceleration changes sign.
                o2 = w2 * w2 * xc - g1 - side * p2 * agv
                o2_s = -side * p2 * slope
                o1 = -w1 * w1 * xc - side * p1 * agv
                o1_s = -side * p1 * slope
                leave, new = math.inf, phase
                if o2_s > 0 and -o2 / o2_s < t1 - t:
                    leave, new = max(-o2 / o2_s, 0.0), int(side)
                if xc > 0 and o1_s < 0 and max(-o1 / o1_s, 0.0) < min(leave, t1 - t):
                    leave, new = max(-o1 / o1_s, 0.0), 0
                if xc == 0 and side * p2 * slope > 0:
                    other = (g1 - side * p2 * agv) / (side * p2 * slope)
                    if max(other, 0.0) < min(leave, t1 - t):
                        leave, new = max(other, 0.0), -int(side)
                if new == phase:
                    t = t1
                    break
                t += leave
                phase = new
                fresh = True
                if phase != 0:
                    liftoff(t, 0.0)
                continue
            if phase == 0:
                events = [_event(xc, 1.0, 1.0), _event(xc, -1.0, 1.0)]
            else:
                side = 1.0 if phase > 0 else -1.0
                events = [_event(xc, side, -1.0)]
                if xcap < math.inf:
                    events.append(_event(xcap, side, 1.0))
            sol = solve_ivp(
                _rhs(model, phase, t0, a0, slope),
                (t, t1),
                [x, v],
                method=method,
                rtol=rtol,
                atol=atol,
                events=[*events, _velocity_zero],
            )
            if sol.status == -1:
                status = STATUS_SOLVER_FAILED
                done = True
                break
            for ye in sol.y_events[-1]:
                if abs(ye[0]) > peak:
                    peak = abs(ye[0])
                    t_peak = float(sol.t_events[-1][0])
                if phase != 0:
                    ep_peak = max(ep_peak, abs(ye[0]))
            hit = None
            for k in range(len(events)):
                if sol.t_events[k].size:
                    te = float(sol.t_events[k][0])
                    # A root at the restart point is the event just handled, not a new one.
                    if fresh and te == t:
                        continue
                    if hit is None or te < hit[1]:
                        hit = (k, te, sol.y_events[k][0])
            if hit is None:
                x, v = float(sol.y[0, -1]), float(sol.y[1, -1])
                if abs(x) > peak:
                    peak, t_peak = abs(x), float(sol.t[-1])
                if phase != 0:
                    ep_peak = max(ep_peak, abs(x))
                t = t1
                slack = INVARIANT_RTOL * x_ref
                side = 1.0 if phase > 0 else -1.0
                inside = abs(x) <= xc + slack if phase == 0 else side * x >= xc - slack
                if not inside:
                    status, done = STATUS_INVARIANT, True
                break
            k, te, ye = hit
            t = te
            fresh = True
            vel = float(ye[1])
            touch = phase != 0 and k == 0
            cap = phase != 0 and k != 0
            if phase == 0:
                x = xc if k == 0 else -xc
                phase = 1 if k == 0 else -1
                v = vel
                peak = max(peak, xc)
                liftoff(te, vel)
                side = float(phase)
                back = w2**2 * xc - g1 - side * p2 * (a0 + slope * (te - t0))
                if abs(vel) <= w_small and back < 0 and te + 2 * abs(vel) / -back <= t1:
                    # Grazing lift-off: pulled straight back, touchdown at the same speed.
                    te += 2 * abs(vel) / -back
                    t = te
                    vel = -vel
                    touch = True
                elif i >= n_rec and side * v - lam2 * (side * x - x_star) > 0 and not overturned:
                    overturned = True
                    if xcap == math.inf:
                        t_over = te
                        done = True
                        break
            if touch:
                side = 1.0 if phase > 0 else -1.0
                x = side * xc
                v = cr * vel
                n_imp += 1
                close_episode()
                ev_t.append(te)
                ev_kind.append(EVENT_TOUCHDOWN)
                ev_v_in.append(vel)
                ev_v_out.append(v)
                ev_peak.append(ep_peak)
                cur_lift = -1
                agv_te = a0 + slope * (te - t0)
                what, delay, speed = after_impact(side, abs(v), agv_te, slope, t1 - te)
                if what == "follow" and xc > 0:
                    phase = 0
                elif what == "follow":
                    phase = -int(side)
                    liftoff(te, v)
                elif what == "lift":
                    t = te + delay
                    if xc == 0:
                        n_imp += 1
                        ev_t.append(t)
                        ev_kind.append(EVENT_TOUCHDOWN)
                        ev_v_in.append(side * abs(v))
                        ev_v_out.append(side * speed)
                        ev_peak.append(0.0)
                    phase = int(side)
                    v = side * speed
                    liftoff(t, v)
                else:
                    t = te + delay
                    ev_t.append(t)
                    ev_kind.append(EVENT_SETTLE)
                    ev_v_in.append(v)
                    ev_v_out.append(0.0)
                    ev_peak.append(0.0)
                    v = 0.0
                    phase = 2 * int(side)
            elif cap:
                x = float(ye[0])
                v = vel
                peak = max(peak, abs(x))
                overturned = True
                t_over = te
                ev_t.append(te)
                ev_kind.append(EVENT_CAP)
                ev_v_in.append(vel)
                ev_v_out.append(vel)
                ev_peak.append(x)
                done = True
                break
        if done:
            break
        i += 1
        hist_x.append(x)
        hist_v.append(v)
        hist_p.append(phase)
    close_episode()
    if status == STATUS_OK and not overturned:
        no_escape = (g1 + p2 * (ahead[0] if ag.size else 0.0)) / w2**2
        limit = xcap if xcap < math.inf else max(abs(x0), no_escape) * (1 + INVARIANT_RTOL)
        if peak > limit:
            status = STATUS_IMPOSSIBLE
    n_hist = n_total + 1 if record_history else 0
    hx = np.full(n_hist, x)
    hv = np.full(n_hist, v)
    hp = np.full(n_hist, phase, dtype=np.int8)
    m = min(len(hist_x), n_hist)
    hx[:m] = hist_x[:m]
    hv[:m] = hist_v[:m]
    hp[:m] = hist_p[:m]
    return RawRun(
        status=status,
        n_liftoffs=n_lift,
        n_impacts=n_imp,
        peak_abs_x=peak,
        peak_time_s=t_peak,
        overturned=overturned,
        overturn_time_s=t_over,
        x_end=x,
        v_end=v,
        phase_end=phase,
        ev_t=np.asarray(ev_t, dtype=float),
        ev_kind=np.asarray(ev_kind, dtype=np.int8),
        ev_v_in=np.asarray(ev_v_in, dtype=float),
        ev_v_out=np.asarray(ev_v_out, dtype=float),
        ev_peak=np.asarray(ev_peak, dtype=float),
        hist_x=hx,
        hist_v=hv,
        hist_p=hp,
    )
