"""Brute-force bifurcation diagrams and basins against the map and the free-rocking separatrix."""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.structure.bifurcation import (
    basin_of_overturning,
    bifurcation_diagram,
    initial_states,
    orbit_period,
)
from stepframe.structure.frame import PortalFrame
from stepframe.structure.harmonic import stroboscopic_map

BLOCK = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0, c_r=0.9)


def test_diagram_points_are_the_iterated_map() -> None:
    amps = np.array([0.3, 0.5]) * 9.81
    x0, v0 = initial_states(BLOCK, 3, seed=1)
    ds = bifurcation_diagram(BLOCK, amps, 16.0, x0_m=x0, v0_m_s=v0, n_periods=12, n_keep=4, jobs=1)
    for a, amp in enumerate(amps):
        for j in range(3):
            step = stroboscopic_map(BLOCK, amp, 16.0, x0[j], v0[j], n_periods=12)
            if ds["outcome"].values[a, j] == 1:
                assert step.overturned
                continue
            assert not step.overturned
            assert ds["x_m"].values[a, j, -1] == pytest.approx(step.x_m, abs=1e-12)


def test_free_rocking_basin_is_the_separatrix() -> None:
    p, x_star = BLOCK.omega_2_rad_s, BLOCK.x_star_m
    xs = np.linspace(-0.9, 0.9, 13) * x_star
    vs = np.linspace(-1.5, 1.5, 11) * p * x_star
    basin = basin_of_overturning(BLOCK, 0.0, 5.0, xs, vs, n_periods=20, jobs=1)
    for i, v in enumerate(vs):
        for j, x in enumerate(xs):
            side = 1.0 if (x > 0 or (x == 0 and v > 0)) else -1.0
            # Escapes in its first excursion iff s·ẋ + p(s·x - x*) > 0; after an impact the
            # energy only falls (ξ = 0, C_r < 1), so no later escape.
            z = side * v + p * (side * x - x_star)
            if abs(z) < 1e-9:
                continue
            first = z > 0
            if not first and side * v < 0:
                # Moving inwards it reaches x = 0 with speed √(v² + p²(x*² - (x* - |x|)²)) and
                # leaves the impact with C_r times that: escape there needs C_r·speed > p·x*.
                speed = math.sqrt(v * v - p * p * ((x_star - abs(x)) ** 2 - x_star**2))
                first = BLOCK.c_r * speed > p * x_star
            assert basin.values[i, j] == int(first), (x, v)


def test_orbit_period_and_bad_input() -> None:
    assert orbit_period(np.array([1.0, 2.0, 1.0, 2.0, 1.0, 2.0])) == 2
    assert orbit_period(np.array([1.0, 1.0, 1.0])) == 1
    assert orbit_period(np.array([1.0, 2.0, 3.0, 4.0])) == 0
    assert orbit_period(np.array([1.0, np.nan])) == 0
    with pytest.raises(InputError):
        bifurcation_diagram(BLOCK, [-1.0], 1.0)
    with pytest.raises(InputError):
        bifurcation_diagram(BLOCK, [1.0], 0.0)


def test_frequency_diagram_points_are_the_iterated_map() -> None:
    from stepframe.structure.bifurcation import frequency_diagram

    oms = np.array([8.0, 16.0, 30.0])
    x0, v0 = initial_states(BLOCK, 2, seed=3)
    ds = frequency_diagram(
        BLOCK, 0.3 * 9.81, oms, x0_m=x0, v0_m_s=v0, n_periods=10, n_keep=2, jobs=1
    )
    assert list(ds["omega"].values) == list(oms)
    for k, om in enumerate(oms):
        for j in range(2):
            step = stroboscopic_map(BLOCK, 0.3 * 9.81, om, x0[j], v0[j], n_periods=10)
            assert (ds["outcome"].values[k, j] == 1) == step.overturned
            if not step.overturned:
                assert ds["x_m"].values[k, j, -1] == pytest.approx(step.x_m, abs=1e-12)


def test_a_cap_below_x_star_bounds_the_starts() -> None:
    """The template frame derived from its physical parameters (no [constants]) has its
    geometric cap x_cap = 5.773 m below x* = 6.521 m: a start between them never crosses the
    cap, so it had no overturning verdict (the harmonic run ended "failed"). The starts are
    spread below the cap, and a harmonic run from past it is refused like `simulate`'s."""
    import re
    import tomllib

    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping
    from stepframe.structure.harmonic import simulate_harmonic

    physical = re.sub(r"\[constants\].*?(?=\[conventions\])", "", FRAME_TEMPLATE, flags=re.S)
    frame = frame_from_mapping(tomllib.loads(physical))
    assert frame.x_cap_m is not None and frame.x_cap_m < frame.x_star_m
    x0, _ = initial_states(frame, 2000, seed=3)
    assert np.max(np.abs(x0)) < frame.x_cap_m < frame.x_star_m
    assert np.max(np.abs(x0)) > 0.99 * frame.x_cap_m  # spread up to it, not below x* only
    with pytest.raises(InputError, match=r"expected \|x0_m\| < x_cap_m"):
        simulate_harmonic(frame, 0.0, 5.0, 5.0, x0_m=0.5 * (frame.x_cap_m + frame.x_star_m))


def test_the_diagram_draws_the_survivors_only() -> None:
    """An overturning run's last strobes are its escape, metres out; drawn, they squeezed the
    survivors' attractors into a line near 0 (Example 4's frame at 0.405 g, 7.854 rad/s: one
    run strobed at -3.87 m on its way over). The points drawn are the survivors' finite ones."""
    import tomllib

    from stepframe.structure.dynamics_plots import bifurcation_figure
    from stepframe.structure.frame_file import FRAME_TEMPLATE, frame_from_mapping

    frame = frame_from_mapping(tomllib.loads(FRAME_TEMPLATE))
    x0, v0 = initial_states(frame, 10, seed=0)
    amps = np.array([0.3, 0.05 + 15 * 0.45 / 19]) * 9.81
    ds = bifurcation_diagram(frame, amps, 7.854, x0_m=x0, v0_m_s=v0, n_periods=50, n_keep=20,
                             jobs=1)  # fmt: skip
    outcome, x = ds["outcome"].values, ds["x_m"].values
    assert (outcome == 1).any() and (outcome == 0).any()
    escapes = x[outcome == 1]
    assert np.nanmin(escapes) < -1.0  # the escape the figure used to draw
    drawn = bifurcation_figure(ds).axes[0].lines[0].get_ydata()
    survivors = x[outcome == 0]
    assert len(drawn) == np.isfinite(survivors).sum()
    assert np.max(np.abs(drawn)) == np.nanmax(np.abs(survivors)) < frame.x_star_m
