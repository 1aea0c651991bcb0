"""An independent solution of Housner's nonlinear rocking block under a one-cycle pulse, for tests.

Written from the equation, not from :mod:`stepframe.structure.rocking_block`: scipy's
``solve_ivp`` (DOP853) on θ̈ = -p²[sin(αs - θ) + (ẍ_g/g)cos(αs - θ)], s = sign θ, restarted at
every event its own event finder locates: lift-off from rest when |ẍ_g| first exceeds g·tan α
(found on a fine grid and refined by brentq), the impact θ = 0 (θ̇ → C_rθ̇, the other corner),
the end of the pulse, and |θ| = π/2 (overturned). After the pulse the free motion is integrated
for ``free_s`` seconds (no closed-form verdict): the block either reaches π/2 or keeps rocking
with decaying energy.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq


def block_pulse_reference(
    b: float, h: float, amplitude: float, omega: float, *, g: float = 9.81, free_s: float = 30.0
) -> tuple[bool, float]:
    """(overturned, largest |θ| [rad] before overturning) under A cos(ωt), 0 ≤ t ≤ 2π/ω."""
    alpha = math.atan2(b, h)
    p = math.sqrt(3 * g / (4 * math.hypot(b, h)))
    c_r = 1 - 1.5 * math.sin(alpha) ** 2
    t_p = 2 * math.pi / omega

    def ground(t: float) -> float:
        return amplitude * math.cos(omega * t) if t <= t_p else 0.0

    lim = g * math.tan(alpha)

    def lift(after: float) -> float | None:
        """The first time from ``after`` that |ẍ_g| exceeds g·tan α (None: not in the pulse)."""
        grid = np.linspace(after, t_p, 20001)
        above = np.abs(amplitude * np.cos(omega * grid)) > lim
        if not above.any():
            return None
        k = int(np.argmax(above))
        if k == 0:
            return after
        return float(brentq(lambda tt: abs(ground(tt)) - lim, grid[k - 1], grid[k]))

    start = lift(0.0)
    if start is None:
        return False, 0.0
    t = start
    side = -math.copysign(1.0, ground(t + 1e-12))
    y = np.array([0.0, 0.0])
    peak = 0.0
    end = t_p + free_s
    while t < end:

        def rhs(tt: float, z: np.ndarray, s: float = side) -> list[float]:
            u = alpha * s - z[0]
            return [z[1], -p * p * (math.sin(u) + ground(tt) / g * math.cos(u))]

        def impact(tt: float, z: np.ndarray) -> float:
            return float(z[0])

        def toppled(tt: float, z: np.ndarray) -> float:
            return abs(z[0]) - 0.5 * math.pi

        def turning(tt: float, z: np.ndarray) -> float:
            return float(z[1])

        impact.terminal = toppled.terminal = True  # type: ignore[attr-defined]
        impact.direction = -side  # type: ignore[attr-defined]
        stop = t_p if t < t_p else end
        sol = solve_ivp(
            rhs, (t, stop), y, method="DOP853", rtol=1e-12, atol=1e-15,
            events=[impact, toppled, turning], dense_output=True, first_step=1e-6,
        )  # fmt: skip
        ends = np.concatenate([sol.t[[0, -1]], sol.t_events[2]])
        peak = max(peak, float(np.max(np.abs(sol.sol(ends)[0]))))
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.t_events[1].size:
            return True, peak
        if sol.t_events[0].size:
            y = np.array([0.0, c_r * y[1]])
            side = -side
            if abs(y[1]) < 1e-9 * p * alpha:
                # At rest on its base: until the ground lifts it again, if it does.
                again = lift(t) if t < t_p else None
                if again is None:
                    return False, peak
                t, y = again, np.array([0.0, 0.0])
                side = -math.copysign(1.0, ground(t + 1e-12))
    return False, peak
