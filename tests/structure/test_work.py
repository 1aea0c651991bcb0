"""Work estimates refuse, before integrating, what would run for hours or exhaust memory."""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.structure import work
from stepframe.structure.bifurcation import bifurcation_diagram, frequency_diagram
from stepframe.structure.frame import PortalFrame
from stepframe.structure.harmonic import frame_parameters, harmonic_work_units, simulate_pulse
from stepframe.structure.periodic import find_periodic_orbit
from stepframe.structure.simulator import simulate, simulate_batch

BLOCK = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0)


def test_the_estimate_counts_pieces_of_the_forcing_and_of_the_frame() -> None:
    prm = frame_parameters(BLOCK)
    # Fast forcing: sixteen pieces per forcing period, plus four per output sample.
    assert harmonic_work_units(prm, 100.0, 2 * math.pi, 10) == pytest.approx(16 * 100 + 40)
    # Slow forcing: the stepped phase's growth time 1/p sets the pieces.
    assert harmonic_work_units(prm, 1e-3, 10.0, 0) == pytest.approx(10 * BLOCK.omega_2_rad_s)


def test_refusals_are_one_line_with_the_estimate() -> None:
    with pytest.raises(InputError, match=r"without end .* expected at most 3e\+07"):
        work.check_work(math.inf, "forever", "stop")
    with pytest.raises(InputError, match=r"1\.44 days"):
        work.check_work(1.244e11, "a long run", "shorten it")
    work.check_work(work.MAX_WORK_UNITS, "just enough", "")


def test_library_calls_refuse_before_allocating_or_integrating() -> None:
    with pytest.raises(InputError, match="tail"):
        simulate(BLOCK, np.zeros(10), 0.01, tail_s=1e12)
    with pytest.raises(InputError, match="output samples"):
        simulate(BLOCK, np.zeros(10), 0.01, tail_s=1e6)  # 1e8 samples of history
    with pytest.raises(InputError, match="runs"):
        simulate_batch(BLOCK, [(np.zeros(100_000), 0.01)], np.ones(100_000))
    with pytest.raises(InputError, match="pulse"):
        simulate_pulse(BLOCK, 3.0, 1e-9)
    with pytest.raises(InputError, match="Newton"):
        find_periodic_orbit(BLOCK, 3.0, 16.0, 0.0, 0.0, n_periods=10**9)
    with pytest.raises(InputError, match="initial states"):
        bifurcation_diagram(BLOCK, [3.0], 16.0, n_initial=1000, n_periods=10**6, jobs=1)
    with pytest.raises(InputError, match="frequencies"):
        frequency_diagram(BLOCK, 3.0, [1e-6, 16.0], n_initial=2, n_periods=100, jobs=1)
