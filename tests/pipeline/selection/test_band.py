"""The frame's band [ω(A_max), ω_1] from the period-amplitude law."""

from __future__ import annotations

import math

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.pipeline.selection.band import frame_band
from stepframe.structure.frame import PortalFrame
from stepframe.structure.period_amplitude import period_amplitude


def test_default_band_is_fraction_of_x_star(example4: PortalFrame) -> None:
    band = frame_band(example4)
    assert band.a_max_source == "fraction-of-x-star"
    assert band.a_max_m == pytest.approx(0.8 * example4.x_star_m)
    assert band.omega_1_rad_s == 6.4581
    # Independent: T(A_max) from the closed-form law; Example 4 x* = γ1/ω2² = 0.1387/0.6445².
    assert example4.x_star_m == pytest.approx(0.1387 / 0.6445**2)
    assert band.omega_low_rad_s == pytest.approx(
        2 * math.pi / period_amplitude(example4, band.a_max_m)
    )
    assert band.omega_low_rad_s == pytest.approx(0.65361, rel=1e-4)


def test_levels_lie_on_the_backbone(example4: PortalFrame) -> None:
    band = frame_band(example4, n_levels=5)
    omegas = band.level_omegas_rad_s
    assert omegas[0] == pytest.approx(example4.omega_1_rad_s)
    assert omegas[-1] == pytest.approx(band.omega_low_rad_s)
    assert np.allclose(np.diff(np.log(omegas)), np.log(omegas[-1] / omegas[0]) / 4)
    periods = period_amplitude(example4, band.level_amplitudes_m[1:])
    assert np.allclose(2 * math.pi / periods, omegas[1:], rtol=1e-9)
    assert band.level_amplitudes_m[0] == example4.x_c_m


def test_user_and_design_amplitudes_take_precedence(example4: PortalFrame) -> None:
    assert frame_band(example4, a_max_m=0.25, design_displacement_m=0.3).a_max_source == "user"
    design = frame_band(example4, design_displacement_m=0.3)
    assert design.a_max_source == "design"
    assert design.a_max_m == 0.3


@pytest.mark.parametrize("a_max", [0.1, 0.334, 1.0])
def test_amplitude_outside_the_stepping_range_is_refused(
    example4: PortalFrame, a_max: float
) -> None:
    with pytest.raises(InputError, match="expected x_c"):
        frame_band(example4, a_max_m=a_max)


def test_reach_is_amplitude_aware(example4: PortalFrame) -> None:
    band = frame_band(example4)
    assert band.reach_rad_s(0.1) == pytest.approx(example4.omega_1_rad_s)
    assert band.reach_rad_s(band.a_max_m) == pytest.approx(band.omega_low_rad_s)
    assert band.reach_rad_s(0.9 * example4.x_star_m) < band.omega_low_rad_s
    assert band.reach_rad_s(example4.x_star_m) == 0.0
