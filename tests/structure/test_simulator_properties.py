"""Property test of the exact simulator over random frames and random scaled real records.

Frames range from the rigid-block limit (x_c = 0) to x_c near x*, with any C_r in [0, 1]
(C_r = 0 and 1 included), with and without a cap; records are windows of the embedded FEMA P695
catalogue scaled between a third of and four times the frame's uplift acceleration. Every run
must either overturn or stay within the bound a non-escaping frame respects, and every sampled
state and every event must lie on the side of its phase.
"""

from __future__ import annotations

import math
from functools import cache
from typing import Any

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from stepframe.records.examples import fema_p695
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure.frame import PortalFrame
from stepframe.structure.simulator import model_of, simulate


@cache
def _catalogue() -> list[tuple[np.ndarray, float]]:
    stream, _ = fema_p695()
    return [
        (trace.data.astype(float) * STANDARD_GRAVITY_M_S2, float(trace.stats.delta))
        for trace in stream
    ]


@st.composite
def cases(draw: Any) -> tuple[PortalFrame, np.ndarray, float]:
    omega_2 = draw(st.floats(0.5, 3.0))
    x_star = draw(st.floats(0.02, 0.5))
    ratio = draw(st.one_of(st.just(0.0), st.floats(0.0, 0.95)))
    cap = draw(st.one_of(st.none(), st.floats(1.2, 3.0)))
    frame = PortalFrame(
        omega_1_rad_s=draw(st.floats(2.0, 40.0)),
        omega_2_rad_s=omega_2,
        p_1=draw(st.floats(0.7, 1.4)),
        p_2=draw(st.floats(0.7, 1.4)),
        gamma_1_m_s2=omega_2**2 * x_star,
        xi_1=draw(st.floats(0.0, 0.3)),
        xi_2=draw(st.one_of(st.just(0.0), st.floats(0.0, 0.1))),
        x_c_m=ratio * x_star,
        c_r=draw(st.one_of(st.sampled_from([0.0, 1.0]), st.floats(0.0, 1.0))),
        x_cap_m=None if cap is None else cap * x_star,
    )
    records = _catalogue()
    ag, dt = records[draw(st.integers(0, len(records) - 1))]
    length = draw(st.integers(300, 1500))
    start = draw(st.integers(0, max(0, ag.size - length)))
    window = ag[start : start + length]
    # Scale relative to the ground acceleration that starts stepping (unstepped frame) or
    # rocking (rigid block): the larger of ω₁²x_c/P₁ and (γ₁ - ω₂²x_c)/P₂.
    uplift = max(
        frame.omega_1_rad_s**2 * frame.x_c_m / frame.p_1,
        (frame.gamma_1_m_s2 - omega_2**2 * frame.x_c_m) / frame.p_2,
    )
    peak = float(np.abs(window).max())
    scale = draw(st.floats(0.33, 4.0)) * uplift / peak if peak > 0 else 1.0
    return frame, window * scale, dt


@settings(max_examples=200, deadline=None, derandomize=True, database=None)
@given(cases())
def test_every_run_overturns_or_stays_on_the_side_of_its_phase(
    case: tuple[PortalFrame, np.ndarray, float],
) -> None:
    frame, ag, dt = case
    result = simulate(frame, ag, dt, tail_s=5.0)
    summary = result.summary
    assert summary.status == "ok", summary.message
    assert math.isfinite(summary.peak_abs_x_m)
    x_c = model_of(frame).x_c_m  # x_c below 1e-9 x* is the rigid-block limit
    assert x_c in (0.0, frame.x_c_m)
    slack = 1e-9 * max(x_c, frame.x_star_m)
    reach = (frame.gamma_1_m_s2 + frame.p_2 * np.abs(ag).max()) / frame.omega_2_rad_s**2
    if not summary.overturned:
        assert summary.peak_abs_x_m <= reach * (1 + 1e-9)
        assert abs(summary.residual_x_m) <= reach * (1 + 1e-9)
        if frame.x_cap_m is not None:
            assert summary.peak_abs_x_m < frame.x_cap_m
    elif frame.x_cap_m is not None:
        assert summary.peak_abs_x_m == frame.x_cap_m
    history = result.history
    assert history is not None
    x = history["x"].to_numpy()
    v = history["v"].to_numpy()
    phase = history["phase"].to_numpy()
    side = np.sign(phase)
    assert np.all(np.abs(x[phase == 0]) <= x_c + slack)
    stepped = np.abs(phase) == 1
    assert np.all(side[stepped] * x[stepped] >= x_c - slack)
    held = np.abs(phase) == 2
    np.testing.assert_array_equal(x[held], side[held] * x_c)
    np.testing.assert_array_equal(v[held], 0.0)
    # Events: impacts apply C_r to an inward velocity; every switch leaves the way it should.
    events = result.events
    touch = events[events["kind"] == "touchdown"]
    np.testing.assert_allclose(
        np.abs(touch["v_out_m_s"]), frame.c_r * np.abs(touch["v_in_m_s"]), rtol=1e-12
    )
    assert np.all(touch["v_in_m_s"].to_numpy() * touch["v_out_m_s"].to_numpy() >= 0.0)
    settle = events[events["kind"] == "settle"]
    np.testing.assert_array_equal(settle["v_out_m_s"], 0.0)
    assert np.all(np.diff(events["time_s"].to_numpy()) >= 0.0)
