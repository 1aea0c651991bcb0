"""Periodic orbits of a stepping frame under harmonic forcing: Newton on the stroboscopic map.

A period-n orbit is a fixed point of P^n, the state map over n forcing periods
(:func:`stepframe.structure.harmonic.stroboscopic_map`). Newton's method uses the map's exact
Jacobian J (phase transition matrices composed with saltation matrices), and the Floquet
multipliers of the orbit are the eigenvalues of J at the fixed point: the orbit is stable when
all have modulus < 1, and a multiplier through +1 (fold, saddle-node) or -1 (period doubling)
marks a bifurcation.

Classification follows the rocking literature (Hogan 1989; Bruhn and Koch 1991): an (m, n)
orbit has n forcing periods and m impacts; it is symmetric when the state half a period later is
the mirror image (-x, -ẋ), possible only for odd n (the forcing changes sign over nT/2).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from stepframe.core.results import Status
from stepframe.structure.harmonic import check_harmonic_work, frame_parameters, stroboscopic_map

if TYPE_CHECKING:
    from stepframe.structure.simulator import FrameLike


@dataclass(frozen=True)
class PeriodicOrbit:
    """A periodic orbit found by Newton on the stroboscopic map.

    Attributes
    ----------
    x_m, v_m_s
        State on the orbit at t ≡ 0 (mod nT) [m, m/s].
    n_periods
        Forcing periods per orbit period n.
    n_impacts
        Impacts per orbit period m.
    multipliers
        Floquet multipliers (eigenvalues of the exact Jacobian of P^n), complex.
    jacobian
        The 2×2 Jacobian of P^n at the orbit.
    stable
        All multipliers inside the unit circle.
    symmetric
        The state nT/2 later is (-x, -ẋ) (odd n only).
    residual_m
        |P^n(z) - z| scaled to metres (velocity divided by ω) at the returned state.
    iterations
        Newton iterations used.
    status
        ``ok``; ``not_converged`` when Newton stalled; ``failed`` when the map overturned or
        stopped; ``degraded`` for a state held on the switching surface (multipliers not
        meaningful).
    """

    x_m: float
    v_m_s: float
    n_periods: int
    n_impacts: int
    multipliers: np.ndarray
    jacobian: np.ndarray
    stable: bool
    symmetric: bool
    residual_m: float
    iterations: int
    status: Status
    message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """Plain values (multipliers as [real, imag] pairs)."""
        return {
            "x_m": self.x_m,
            "v_m_s": self.v_m_s,
            "n_periods": self.n_periods,
            "n_impacts": self.n_impacts,
            "multipliers": [[float(m.real), float(m.imag)] for m in self.multipliers],
            "stable": self.stable,
            "symmetric": self.symmetric,
            "residual_m": self.residual_m,
            "iterations": self.iterations,
            "status": self.status,
            "message": self.message,
        }


def find_periodic_orbit(
    frame: FrameLike,
    amplitude_m_s2: float,
    omega_rad_s: float,
    x_m: float,
    v_m_s: float,
    *,
    n_periods: int = 1,
    phase_rad: float = 0.0,
    tol_m: float = 1e-12,
    max_iter: int = 60,
) -> PeriodicOrbit:
    """Newton's method on P^n(z) - z = 0 from the guess (x, v), with the exact Jacobian.

    Steps are halved while they do not reduce the residual (a damped Newton), so a guess near
    the orbit converges quadratically and a poor one fails with a status, never silently.

    Parameters
    ----------
    frame
        A :class:`~stepframe.structure.frame.PortalFrame`.
    amplitude_m_s2, omega_rad_s, phase_rad
        Forcing ẍ_g = A cos(ωt + φ) [m/s², rad/s, rad].
    x_m, v_m_s
        Initial guess at t = 0 [m, m/s].
    n_periods
        n of the orbit.
    tol_m
        Residual target [m] (velocity residual divided by ω).
    max_iter
        Newton iterations.
    """
    prm = frame_parameters(frame)
    om = float(omega_rad_s)
    check_harmonic_work(
        prm, om, max_iter * n_periods * 2.0 * math.pi / om, 0,
        f"a period-{n_periods} orbit ({max_iter} Newton steps of {n_periods} forcing periods)",
    )  # fmt: skip
    scale = np.array([1.0, 1.0 / om])

    def residual(z: np.ndarray) -> tuple[np.ndarray, np.ndarray, Any]:
        step = stroboscopic_map(
            frame,
            amplitude_m_s2,
            om,
            z[0],
            z[1],
            n_periods=n_periods,
            phase_rad=phase_rad,
            params=prm,
        )
        f = np.array([step.x_m, step.v_m_s]) - z
        return f, step.jacobian - np.eye(2), step

    z = np.array([x_m, v_m_s], dtype=float)
    f, jf, step = residual(z)
    it = 0
    status: Status = "not_converged"
    message = ""
    for it in range(1, max_iter + 1):  # noqa: B007 - the count is reported
        if step.status != "ok" or step.overturned:
            status = "failed"
            message = "the map overturned or stopped from this guess"
            break
        norm = float(np.linalg.norm(f * scale))
        if norm <= tol_m:
            status = "ok"
            break
        try:
            dz = np.linalg.solve(jf, -f)
        except np.linalg.LinAlgError:
            message = "singular Jacobian (a fold or a hold on the surface)"
            break
        lam = 1.0
        for _ in range(30):
            z_new = z + lam * dz
            f_new, jf_new, step_new = residual(z_new)
            ok = step_new.status == "ok" and not step_new.overturned
            if ok and float(np.linalg.norm(f_new * scale)) < norm:
                break
            lam *= 0.5
        else:
            message = "line search failed"
            break
        z, f, jf, step = z_new, f_new, jf_new, step_new
    else:
        message = f"{max_iter} iterations"
    final = stroboscopic_map(
        frame, amplitude_m_s2, om, z[0], z[1], n_periods=n_periods, phase_rad=phase_rad, params=prm
    )
    mults = np.linalg.eigvals(final.jacobian)
    res = float(np.linalg.norm((np.array([final.x_m, final.v_m_s]) - z) * scale))
    if status == "ok" and not res <= 10 * tol_m:
        status = "not_converged"
    xc = prm[7]
    if (
        status == "ok"
        and final.n_impacts == 0
        and final.n_liftoffs == 0
        and abs(z[0]) == xc
        and z[1] == 0.0
        and all(abs(ph) == 2 for ph in final.phases)
    ):
        # Held on the switching surface (at rest on the base for x_c = 0) the whole time: the map
        # is the identity there but a perturbation off the surface starts motion, so the
        # multipliers say nothing about stability.
        status = "degraded"
        message = "held on the switching surface: multipliers not meaningful"
    symmetric = False
    if n_periods % 2 == 1 and status == "ok":
        symmetric = _is_symmetric(prm, amplitude_m_s2, om, phase_rad, z, n_periods, tol_m)
    return PeriodicOrbit(
        x_m=float(z[0]),
        v_m_s=float(z[1]),
        n_periods=n_periods,
        n_impacts=final.n_impacts,
        multipliers=mults,
        jacobian=final.jacobian,
        stable=bool(np.all(np.abs(mults) < 1.0)),
        symmetric=symmetric,
        residual_m=res,
        iterations=it,
        status=status,
        message=message,
    )


def _is_symmetric(
    prm: np.ndarray, amp: float, om: float, phi: float, z: np.ndarray, n: int, tol_m: float
) -> bool:
    from stepframe.structure import _harmonic_kernel as hk

    half = n * math.pi / om
    jac = np.eye(2)
    phase = int(hk.start_phase(z[0], z[1], amp * math.cos(phi), prm))
    st, x, v, *_ = hk.advance(
        prm, amp, om, phi, 0.0, half, z[0], z[1], phase, jac, False, 200_000, amp
    )
    if st != hk.K_OK:
        return False
    size = max(abs(z[0]), abs(z[1]) / om, prm[7], 1e-300)
    return bool(abs(x + z[0]) + abs(v + z[1]) / om <= 1e-7 * size + 100 * tol_m)


def finite_difference_jacobian(
    frame: FrameLike,
    amplitude_m_s2: float,
    omega_rad_s: float,
    x_m: float,
    v_m_s: float,
    *,
    n_periods: int = 1,
    phase_rad: float = 0.0,
    step_m: float = 1e-7,
) -> np.ndarray:
    """Central differences of the simulated map P^n: the independent check of the exact J.

    ``step_m`` perturbs x [m]; ẋ is perturbed by ``step_m·ω``.
    """
    prm = frame_parameters(frame)
    jac = np.empty((2, 2))
    steps = (step_m, step_m * omega_rad_s)
    for col in range(2):
        pts = []
        for sign in (1.0, -1.0):
            z = [x_m, v_m_s]
            z[col] += sign * steps[col]
            s = stroboscopic_map(
                frame,
                amplitude_m_s2,
                omega_rad_s,
                z[0],
                z[1],
                n_periods=n_periods,
                phase_rad=phase_rad,
                params=prm,
            )
            pts.append(np.array([s.x_m, s.v_m_s]))
        jac[:, col] = (pts[0] - pts[1]) / (2.0 * steps[col])
    return jac


def symmetric_orbit_guess(
    frame: FrameLike, amplitude_m_s2: float, omega_rad_s: float, *, n: int = 1, branch: int = 0
) -> tuple[float, float, float] | None:
    """Closed-form symmetric (2, n) orbit of Housner's linearised block (x_c = 0), n odd.

    In u = x/x*, τ = pt (p = ω₂), the block obeys u'' - u + sign(u) = -r sin(ω̄τ + ψ) with
    r = A P₂/γ₁ (A in units of the static uplift acceleration γ₁/P₂ = gα) and ω̄ = ω/p. A
    symmetric orbit with impacts at τ = 0 and nπ/ω̄ solves the linear conditions derived in
    docs/paper-notes.md ("Eq. 5.15"), which reduce to
    R[ω̄(1 - e)s cos ψ + (1 + e)(c + 1) sin ψ] = -(c - 1)(1 - e), R = r/(1 + ω̄²),
    c = cosh(nπ/ω̄), s = sinh(nπ/ω̄), e = C_r: two solutions ψ above the saddle-node amplitude of
    eq. 5.15, none below.

    Returns
    -------
    (phase_rad, x_m, v_m_s) or None
        The forcing phase φ (ẍ_g = A cos(ωt + φ)) for which the orbit's state at t = 0 is
        (x, v), a quarter period after an impact; None below the saddle-node.
    """
    from stepframe.structure import _harmonic_kernel as hk

    prm = frame_parameters(frame)
    if prm[7] != 0.0 or n % 2 == 0:
        return None
    p = prm[1]
    x_star = prm[4] / p**2
    r = amplitude_m_s2 * prm[3] / prm[4]
    wb = omega_rad_s / p
    e = prm[8]
    hh = n * math.pi / wb
    c, s = math.cosh(hh), math.sinh(hh)
    big_r = r / (1.0 + wb * wb)
    a_coef = wb * (1.0 - e) * s
    b_coef = (1.0 + e) * (c + 1.0)
    rhs = -(c - 1.0) * (1.0 - e)
    amp = big_r * math.hypot(a_coef, b_coef)
    if amp < abs(rhs):
        return None
    base = math.atan2(b_coef, a_coef)  # a cos ψ + b sin ψ = amp cos(ψ - base)
    delta = math.acos(rhs / amp)
    psi = base + (delta if branch == 0 else -delta)
    sin_p, cos_p = math.sin(psi), math.cos(psi)
    b = ((c - 1.0) + big_r * sin_p * (c + 1.0)) / s
    v0 = (big_r * wb * cos_p + b) * x_star * p
    # u'' - u + 1 = -ẍ_g/(gα) = -r sin(ω̄τ + ψ) is the forcing ẍ_g = A sin(ωt + ψ), i.e.
    # A cos(ωt + ψ - π/2) with t = 0 at the impact that starts the half-orbit.
    phi0 = psi - 0.5 * math.pi
    quarter = 0.5 * math.pi / omega_rad_s
    jac = np.eye(2)
    st, x, v, *_ = hk.advance(
        prm,
        amplitude_m_s2,
        omega_rad_s,
        phi0,
        0.0,
        quarter,
        0.0,
        v0,
        1,
        jac,
        False,
        200_000,
        amplitude_m_s2,
    )
    if st != hk.K_OK:
        return None
    return phi0 + omega_rad_s * quarter, float(x), float(v)
