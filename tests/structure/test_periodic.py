"""Periodic orbits, Floquet multipliers and continuation against eq. 5.15 and finite differences."""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.structure.continuation import continue_orbit
from stepframe.structure.frame import PortalFrame
from stepframe.structure.harmonic import simulate_harmonic, stroboscopic_map
from stepframe.structure.periodic import (
    find_periodic_orbit,
    finite_difference_jacobian,
    symmetric_orbit_guess,
)

BLOCK = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0, c_r=0.9)
P = BLOCK.omega_2_rad_s
G_ALPHA = BLOCK.gamma_1_m_s2 / BLOCK.p_2  # static uplift acceleration of the linearised block


def eq_5_15(omega_bar: float, c_r: float, n: int) -> float:
    """Eq. 5.15 as printed, with √ρ = C_r (ρ = C_r² is Housner's energy ratio)."""
    h = n * math.pi / omega_bar
    c, s = math.cosh(h), math.sinh(h)
    num = (1 + omega_bar**2) * (1 - c_r) * (c - 1)
    den = math.sqrt(omega_bar**2 * (1 - c_r) ** 2 * s**2 + (1 + c_r) ** 2 * (c + 1) ** 2)
    return num / den


@pytest.mark.parametrize("branch", [0, 1])
def test_closed_form_symmetric_orbit_is_a_fixed_point_with_exact_multipliers(branch: int) -> None:
    omega = 3.0 * P
    amp = 1.3 * eq_5_15(3.0, 0.9, 1) * G_ALPHA
    guess = symmetric_orbit_guess(BLOCK, amp, omega, branch=branch)
    assert guess is not None
    phase, x, v = guess
    orbit = find_periodic_orbit(BLOCK, amp, omega, x, v, phase_rad=phase)
    assert orbit.status == "ok" and orbit.iterations == 1  # the guess already solves P(z) = z
    assert orbit.residual_m < 1e-12
    assert orbit.symmetric and orbit.n_impacts == 2
    # ξ = 0: each phase conserves area, each impact scales it by C_r²: det J = C_r⁴.
    assert np.prod(orbit.multipliers).real == pytest.approx(0.9**4, rel=1e-10)
    fd = finite_difference_jacobian(BLOCK, amp, omega, x, v, phase_rad=phase)
    fd_mult = np.sort_complex(np.linalg.eigvals(fd))
    assert np.max(np.abs(fd_mult - np.sort_complex(orbit.multipliers))) < 1e-6


def test_stable_orbit_found_by_newton_is_reproduced_by_long_simulation() -> None:
    omega = 3.0 * P
    amp = 1.3 * eq_5_15(3.0, 0.9, 1) * G_ALPHA
    phase, x, v = symmetric_orbit_guess(BLOCK, amp, omega, branch=1)  # type: ignore[misc]
    # Newton from a poor guess (20 % off) lands on the orbit.
    orbit = find_periodic_orbit(BLOCK, amp, omega, 1.2 * x, 0.8 * v, phase_rad=phase)
    assert orbit.status == "ok" and orbit.stable
    assert abs(orbit.x_m - x) < 1e-12 and abs(orbit.v_m_s - v) < 1e-11
    period = 2 * math.pi / omega
    run = simulate_harmonic(
        BLOCK,
        amp,
        omega,
        200 * period,
        phase_rad=phase,
        x0_m=orbit.x_m,
        v0_m_s=orbit.v_m_s,
        samples_per_period=1,
    )
    assert run.status == "ok"
    assert np.max(np.abs(run.x_m - orbit.x_m)) < 1e-9
    # A perturbed start converges back at the rate of the largest multiplier.
    pert = simulate_harmonic(
        BLOCK,
        amp,
        omega,
        200 * period,
        phase_rad=phase,
        x0_m=orbit.x_m * 1.05,
        v0_m_s=orbit.v_m_s,
        samples_per_period=1,
    )
    assert abs(pert.x_m[-1] - orbit.x_m) < 1e-9


@pytest.mark.parametrize(("omega_bar", "n"), [(3.0, 1), (5.0, 1), (5.0, 3), (2.0, 1)])
def test_continuation_fold_is_the_saddle_node_of_eq_5_15(omega_bar: float, n: int) -> None:
    r_sn = eq_5_15(omega_bar, 0.9, n)
    omega = omega_bar * P
    amp = 1.3 * r_sn * G_ALPHA
    phase, x, v = symmetric_orbit_guess(BLOCK, amp, omega, n=n, branch=1)  # type: ignore[misc]
    branch = continue_orbit(BLOCK, omega, amp, x, v, phase_rad=phase, n_periods=n, n_steps=150)
    assert branch.folds, branch.message
    assert branch.folds[0] / G_ALPHA == pytest.approx(r_sn, rel=1e-9)
    # Below the fold there is no symmetric orbit.
    assert symmetric_orbit_guess(BLOCK, 0.999 * r_sn * G_ALPHA, omega, n=n) is None


def test_floquet_multiplier_crosses_plus_one_at_the_fold() -> None:
    omega = 3.0 * P
    r_sn = eq_5_15(3.0, 0.9, 1)
    mults = []
    for branch in (0, 1):
        amp = (1 + 1e-6) * r_sn * G_ALPHA
        phase, x, v = symmetric_orbit_guess(BLOCK, amp, omega, branch=branch)  # type: ignore[misc]
        step = stroboscopic_map(BLOCK, amp, omega, x, v, phase_rad=phase)
        mults.append(np.linalg.eigvals(step.jacobian))
    # Both orbits of the pair have a multiplier near +1 just above the saddle-node.
    for m in mults:
        assert np.min(np.abs(m - 1.0)) < 0.02


def test_symmetry_breaking_branch_point_is_where_stability_is_lost() -> None:
    omega_bar = 2.0
    omega = omega_bar * P
    amp = 1.05 * eq_5_15(omega_bar, 0.9, 1) * G_ALPHA
    phase, x, v = symmetric_orbit_guess(BLOCK, amp, omega, branch=1)  # type: ignore[misc]
    branch = continue_orbit(
        BLOCK,
        omega,
        amp,
        x,
        v,
        phase_rad=phase,
        n_steps=300,
        direction=1.0,
        parameter_range=(0.0, 3.0 * G_ALPHA),
    )
    assert branch.branch_points, branch.message
    a_bp = branch.branch_points[0]
    # Independently: the closed-form symmetric orbit's multipliers from finite differences of the
    # simulated map are inside the unit circle just below and outside just above.
    radii = []
    for factor in (1 - 1e-4, 1 + 1e-4):
        ph, xs, vs = symmetric_orbit_guess(BLOCK, a_bp * factor, omega, branch=1)  # type: ignore[misc]
        fd = finite_difference_jacobian(BLOCK, a_bp * factor, omega, xs, vs, phase_rad=ph)
        radii.append(np.max(np.abs(np.linalg.eigvals(fd))))
    assert radii[0] < 1.0 < radii[1]


def test_continuation_in_frequency_finds_the_eq_5_15_fold() -> None:
    # Eq. 5.15 (n = 1) rises with ω̄: at fixed r the symmetric (2, 1) orbits exist below the
    # ω̄ where eq. 5.15 = r, and the family folds there.
    r = 0.115
    omega_bar = 1.5
    amp = r * G_ALPHA
    assert eq_5_15(omega_bar, 0.9, 1) < r
    phase, x, v = symmetric_orbit_guess(BLOCK, amp, omega_bar * P, branch=1)  # type: ignore[misc]
    branch = continue_orbit(
        BLOCK,
        omega_bar * P,
        amp,
        x,
        v,
        phase_rad=phase,
        parameter="omega_rad_s",
        n_steps=300,
        direction=1.0,
    )
    assert branch.parameter == "omega_rad_s" and branch.folds, branch.message
    omega_fold_bar = branch.folds[0] / P
    assert eq_5_15(omega_fold_bar, 0.9, 1) == pytest.approx(r, rel=1e-8)
