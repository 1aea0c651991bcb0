"""Hysteretic A-frame integrator: closed-form free decay, ξ₁ = 0 against the exact simulator."""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.structure.aframe_hysteretic import equivalent_viscous_error, simulate_aframe
from stepframe.structure.frame import AFrame
from stepframe.structure.simulator import simulate

FRAME = AFrame(
    omega_1_rad_s=6.0, omega_2_rad_s=0.7, p_1=1.1, p_2=1.2, gamma_1_m_s2=0.15, xi_1=0.05,
    theta_rad=0.2, x_c_m=0.04, c_r=0.9, x_cap_m=0.6,
)  # fmt: skip


def free_decay(a0: float, t: float, w1: float, xi: float) -> float:
    """x(t) of ẍ + πξω₁² sign(ẋ)|x| + ω₁²x = 0 from (a0, 0): quarter cycles in closed form.

    Moving back to 0 the stiffness is k₋ = ω₁²(1 - πξ), moving away k₊ = ω₁²(1 + πξ); each half
    cycle scales the amplitude by √(k₋/k₊).
    """
    wm, wp = w1 * math.sqrt(1 - math.pi * xi), w1 * math.sqrt(1 + math.pi * xi)
    amp, sign = a0, 1.0
    while True:
        q1 = math.pi / (2 * wm)
        if t <= q1:
            return sign * amp * math.cos(wm * t)
        t -= q1
        speed = amp * wm
        q2 = math.pi / (2 * wp)
        if t <= q2:
            return -sign * speed / wp * math.sin(wp * t)
        t -= q2
        amp, sign = speed / wp, -sign


@pytest.mark.parametrize("t_end", [0.1, 0.4, 0.9, 2.3, 5.0])
def test_free_decay_matches_the_quarter_cycle_closed_form(t_end: float) -> None:
    dt = 0.01
    n = round(t_end / dt)
    run = simulate_aframe(FRAME, np.zeros(n + 1), dt, tail_s=0.0, x0_m=0.03)
    expected = free_decay(0.03, n * dt, FRAME.omega_1_rad_s, FRAME.xi_1)
    assert run.status == "ok" and run.n_liftoffs == 0
    assert run.residual_x_m == pytest.approx(expected, abs=1e-13)


def test_without_hysteresis_it_is_the_portal_frame() -> None:
    from stepframe.records.examples import fema_p695

    stream, _ = fema_p695()
    tr = stream[2]
    plain = AFrame(**{**FRAME.to_dict(), "xi_1": 0.0})
    portal = plain.to_portal_frame()
    for scale in (0.05, 0.1, 0.2):
        ours = simulate_aframe(plain, tr.data, tr.stats.delta, scale=scale, tail_s=5.0)
        ref = simulate(
            portal, tr.data, tr.stats.delta, scale=scale, tail_s=5.0, record_history=False
        ).summary
        assert ours.overturned == ref.overturned
        assert ours.n_liftoffs == ref.n_stepping_episodes
        if not ref.overturned:
            assert ours.peak_abs_x_m == pytest.approx(ref.peak_abs_x_m, rel=1e-8)


def test_equivalent_viscous_error_table() -> None:
    from stepframe.records.examples import fema_p695

    stream, _ = fema_p695()
    tr = stream[2]
    table = equivalent_viscous_error(FRAME, [(tr.data, tr.stats.delta)], [0.02], tail_s=2.0)
    row = table.iloc[0]
    # Below uplift the frame is a linear oscillator in both models: same order, not equal.
    assert row["peak_hysteretic_m"] > 0 and row["peak_viscous_m"] > 0
    assert abs(row["rel_error"]) < 0.5
    with pytest.raises(InputError):
        simulate_aframe(FRAME, [0.0], 0.01)


def test_equivalent_viscous_summary_is_the_median_and_worst_of_the_table() -> None:
    import pandas as pd

    from stepframe.structure.aframe_hysteretic import equivalent_viscous_summary

    table = pd.DataFrame(
        {
            "record": [0, 1, 2, 3],
            "rel_error": [0.1, -0.3, 0.05, 9.0],
            "overturned_hysteretic": [False, False, False, True],
            "overturned_viscous": [False, False, False, False],
            "status": ["ok"] * 4,
        }
    )
    s = equivalent_viscous_summary(table)
    assert (s["all_runs"], s["runs"], s["verdicts_differing"]) == (4, 3, 1)
    assert s["median_abs_rel_error"] == pytest.approx(0.1)
    assert (s["worst_rel_error"], s["worst_record"]) == (-0.3, 1)
