"""Pseudo-arclength continuation of periodic orbits in the forcing amplitude or frequency.

Unknowns y = (x, ẋ, λ) with λ the forcing amplitude A or frequency ω; equations
G(y) = P^n(x, ẋ; λ) - (x, ẋ) = 0. The state columns of ∂G are the exact Jacobian of the map minus
I; the parameter column is a central difference. The
tangent is the null vector of the 2×3 matrix ∂G (the cross product of its rows); each step
predicts along it and corrects by Newton on G = 0 with the arclength condition
t·(y - y_pred) = 0 (Keller 1977), which passes folds where A turns back.

Along the branch: a fold (saddle-node) is where the A-component of the tangent changes sign
(a Floquet multiplier crosses +1, det(J - I) = 0); it is then located by Newton on the extended
system G = 0, det(J - I) = 0 in (x, ẋ, λ). A period doubling is where det(J + I) changes sign
(a multiplier crosses -1); its amplitude is interpolated. Where det(J - I) changes sign while A
keeps its sense the branch meets another (a pitchfork: for symmetric orbits of the rocking block,
the symmetry-breaking bifurcation to asymmetric orbits); it is located like a fold.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from stepframe.core.results import Status
from stepframe.errors import InputError
from stepframe.structure.harmonic import frame_parameters, stroboscopic_map


@dataclass(frozen=True)
class BranchPoint:
    """One orbit on a continued branch."""

    amplitude_m_s2: float
    omega_rad_s: float
    x_m: float
    v_m_s: float
    multipliers: np.ndarray
    stable: bool


@dataclass(frozen=True)
class Branch:
    """A continued family of period-n orbits and the bifurcations met on it.

    Attributes
    ----------
    points
        Orbits in arclength order.
    parameter
        The continued parameter: ``"amplitude_m_s2"`` (A) or ``"omega_rad_s"`` (ω); the
        bifurcation values below are in its unit.
    folds
        Parameter values of the folds (saddle-nodes) found, located by Newton.
    period_doublings
        Values where a multiplier crossed -1 (linear interpolation).
    branch_points
        Values where a multiplier crossed +1 while the parameter kept its sense: a pitchfork,
        for symmetric orbits the symmetry-breaking bifurcation (located like a fold).
    status
        ``ok``, or ``not_converged`` when a corrector failed and the branch stopped early
        (``message`` says where).
    """

    points: list[BranchPoint]
    parameter: str = "amplitude_m_s2"
    folds: list[float] = field(default_factory=list)
    period_doublings: list[float] = field(default_factory=list)
    branch_points: list[float] = field(default_factory=list)
    status: Status = "ok"
    message: str = ""

    def to_dict(self) -> dict[str, Any]:
        """Plain values."""
        return {
            "parameter": self.parameter,
            "amplitude_m_s2": [p.amplitude_m_s2 for p in self.points],
            "omega_rad_s": [p.omega_rad_s for p in self.points],
            "x_m": [p.x_m for p in self.points],
            "v_m_s": [p.v_m_s for p in self.points],
            "stable": [p.stable for p in self.points],
            "folds": self.folds,
            "period_doublings": self.period_doublings,
            "branch_points": self.branch_points,
            "status": self.status,
            "message": self.message,
        }


class _System:
    def __init__(
        self, frame: Any, omega: float, amp: float, phase: float, n: int, by_omega: bool
    ) -> None:
        self.frame = frame
        self.prm = frame_parameters(frame)
        self.om = omega
        self.amp = amp
        self.phase = phase
        self.n = n
        self.by_omega = by_omega
        # Scaled unknowns of comparable size, all in metres: ẋ/ω, and A by the stepped phase's
        # quasi-static response P₂A/(ω² + ω₂²) (eq. 5.6), or ω relative to its start times x*.
        x_star = self.prm[4] / self.prm[1] ** 2
        w3 = x_star / omega if by_omega else self.prm[3] / (omega**2 + self.prm[1] ** 2)
        self.w = np.array([1.0, 1.0 / omega, w3])

    def map(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool]:
        s = stroboscopic_map(
            self.frame,
            self.amp if self.by_omega else y[2],
            y[2] if self.by_omega else self.om,
            y[0],
            y[1],
            n_periods=self.n,
            phase_rad=self.phase,
            params=self.prm,
        )
        ok = s.status == "ok" and not s.overturned
        return np.array([s.x_m, s.v_m_s]) - y[:2], s.jacobian, ok

    def jacobian(self, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
        g, jm, ok = self.map(y)
        h = 1e-6 * max(abs(y[2]), 1e-3)
        gp, _, okp = self.map(y + np.array([0.0, 0.0, h]))
        gm, _, okm = self.map(y - np.array([0.0, 0.0, h]))
        d = np.empty((2, 3))
        d[:, :2] = jm - np.eye(2)
        d[:, 2] = (gp - gm) / (2 * h)
        return g, d, jm, ok and okp and okm


def _tangent(d: np.ndarray) -> np.ndarray:
    t = np.asarray(np.cross(d[0], d[1]), dtype=float)
    out: np.ndarray = t / float(np.linalg.norm(t))
    return out


def continue_orbit(
    frame: Any,
    omega_rad_s: float,
    amplitude_m_s2: float,
    x_m: float,
    v_m_s: float,
    *,
    n_periods: int = 1,
    phase_rad: float = 0.0,
    step_m: float | None = None,
    n_steps: int = 200,
    direction: float = -1.0,
    parameter: Literal["amplitude_m_s2", "omega_rad_s"] = "amplitude_m_s2",
    parameter_range: tuple[float, float] = (0.0, np.inf),
    tol: float = 1e-11,
) -> Branch:
    """Follow the period-n orbit through (x, ẋ) at (A, ω) by pseudo-arclength in A or ω.

    Parameters
    ----------
    frame
        A :class:`~stepframe.structure.frame.PortalFrame`.
    omega_rad_s, phase_rad
        Forcing frequency [rad/s] and the phase of the section [rad].
    amplitude_m_s2, x_m, v_m_s
        A point on (or near) the branch [m/s², m, m/s].
    n_periods
        n of the orbit.
    step_m
        Arclength step in the scaled unknowns (x, ẋ/ω and P₂A/(ω² + ω₂²), all in metres);
        None: x*/200.
    n_steps
        Steps taken at most.
    direction
        Initial sense of the parameter along the tangent (-1: decreasing).
    parameter
        ``"amplitude_m_s2"`` (continue in A at fixed ω) or ``"omega_rad_s"`` (in ω at fixed A;
        the section stays at the forcing phase ``phase_rad``).
    parameter_range
        The branch stops when the parameter leaves this range.
    tol
        Corrector tolerance on |G| [m].
    """
    if parameter not in ("amplitude_m_s2", "omega_rad_s"):
        raise InputError(f"parameter = {parameter!r}, expected 'amplitude_m_s2' or 'omega_rad_s'")
    by_omega = parameter == "omega_rad_s"
    sys_ = _System(
        frame, float(omega_rad_s), float(amplitude_m_s2), float(phase_rad), int(n_periods), by_omega
    )
    w = sys_.w
    step = sys_.prm[4] / sys_.prm[1] ** 2 / 200.0 if step_m is None else float(step_m)
    y = np.array([x_m, v_m_s, omega_rad_s if by_omega else amplitude_m_s2], dtype=float)
    # Correct the first point at fixed A.
    for _ in range(50):
        g, d, jm, ok = sys_.jacobian(y)
        if not ok:
            return Branch([], parameter, status="failed", message="the start point overturned")
        if np.linalg.norm(g * w[:2]) < tol:
            break
        y[:2] += np.linalg.solve(d[:, :2], -g)
    points: list[BranchPoint] = []
    folds: list[float] = []
    pds: list[float] = []
    t_prev = _tangent(d * (1.0 / w))  # tangent in scaled coordinates
    if np.sign(t_prev[2]) != np.sign(direction) and t_prev[2] != 0:
        t_prev = -t_prev
    pd_prev = float(np.linalg.det(jm + np.eye(2)))
    bp_prev = float(np.linalg.det(jm - np.eye(2)))
    bps: list[float] = []
    status: Status = "ok"
    message = ""
    ys = y * w
    for _ in range(n_steps):
        mult = np.linalg.eigvals(jm)
        points.append(
            BranchPoint(
                float(sys_.amp if by_omega else y[2]),
                float(y[2] if by_omega else sys_.om),
                float(y[0]),
                float(y[1]),
                mult,
                bool(np.all(np.abs(mult) < 1)),
            )
        )
        h = step
        for _attempt in range(8):
            pred = ys + h * t_prev
            z = pred.copy()
            converged = False
            for _it in range(30):
                g, d, jm_new, ok = sys_.jacobian(z / w)
                if not ok:
                    break
                ds = d / w
                big = np.vstack([ds, t_prev])
                rhs = -np.concatenate([g, [t_prev @ (z - pred)]])
                dz = np.linalg.solve(big, rhs)
                z = z + dz
                if np.linalg.norm(dz) < tol and np.linalg.norm(g) < 1e3 * tol:
                    converged = True
                    break
            if converged:
                break
            h *= 0.5
        else:
            status = "not_converged"
            message = f"corrector failed near {parameter} = {y[2]:.6g}"
            break
        g, d, jm_new, _ok = sys_.jacobian(z / w)
        t_new = _tangent(d / w)
        if t_new @ t_prev < 0:
            t_new = -t_new
        bp_new = float(np.linalg.det(jm_new - np.eye(2)))
        if np.sign(t_new[2]) != np.sign(t_prev[2]):
            fold = _locate_fold(sys_, z / w)
            if fold is not None:
                folds.append(fold)
        elif np.sign(bp_new) != np.sign(bp_prev):
            a0, a1 = ys[2] / w[2], z[2] / w[2]
            guess = a0 + (a1 - a0) * bp_prev / (bp_prev - bp_new)
            located = _locate_fold(sys_, z / w)
            ok_loc = located is not None and min(a0, a1) <= located <= max(a0, a1)
            bps.append(float(located) if ok_loc else float(guess))  # type: ignore[arg-type]
        bp_prev = bp_new
        pd_new = float(np.linalg.det(jm_new + np.eye(2)))
        if np.sign(pd_new) != np.sign(pd_prev):
            a0, a1 = ys[2] / w[2], z[2] / w[2]
            pds.append(float(a0 + (a1 - a0) * pd_prev / (pd_prev - pd_new)))
        pd_prev = pd_new
        ys, t_prev, jm = z, t_new, jm_new
        y = ys / w
        if not parameter_range[0] <= y[2] <= parameter_range[1]:
            break
    return Branch(points, parameter, folds, pds, bps, status, message)


def _locate_fold(sys_: _System, y0: np.ndarray) -> float | None:
    """Newton on G = 0, det(J - I) = 0 in (x, ẋ, A) with a finite-difference Jacobian."""

    def ext(y: np.ndarray) -> np.ndarray | None:
        g, jm, ok = sys_.map(y)
        if not ok:
            return None
        return np.array([g[0], g[1], np.linalg.det(jm - np.eye(2))])

    y = y0.copy()
    for _ in range(40):
        f = ext(y)
        if f is None:
            return None
        jac = np.empty((3, 3))
        for k in range(3):
            hk = 1e-7 * max(abs(y[k]), 1e-4)
            e = np.zeros(3)
            e[k] = hk
            fp, fm = ext(y + e), ext(y - e)
            if fp is None or fm is None:
                return None
            jac[:, k] = (fp - fm) / (2 * hk)
        try:
            dy = np.linalg.solve(jac, -f)
        except np.linalg.LinAlgError:
            return None
        y = y + dy
        if np.all(np.abs(dy) <= 1e-13 * np.maximum(np.abs(y), 1e-6)):
            break
    f = ext(y)
    if f is None or np.linalg.norm(f[:2] * sys_.w[:2]) > 1e-9:
        return None
    return float(y[2])
