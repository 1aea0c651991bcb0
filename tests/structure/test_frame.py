"""Frame parameters: eqs. 4.6, 4.7, 4.10, 4.15-4.16 from Example 2/4 inputs, and validation."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from stepframe.errors import InputError
from stepframe.structure.frame import (
    AFrame,
    EquivalentViscousWarning,
    PortalFrame,
    onset_of_stepping_m,
    overturning_displacement_m,
    restitution_velocity_ratio,
)

# Example 2 (paper): W_S = 1.472e6 N, W_T = 2.807e6 N, L_F = 8.839 m, H_r = 29.944 m;
# Example 4: K_a = 1.159e9 N/m, K_b = 5.021e6 N/m, ξ₁ = 0.05, ξ₂ = 0.
W_S, W_T, L_F, H_R, K_A, K_B = 1.472e6, 2.807e6, 8.839, 29.944, 1.159e9, 5.021e6
W_COL = W_T - W_S


def example_4(**overrides: object) -> PortalFrame:
    inputs: dict[str, object] = {
        "w_s_n": W_S, "w_col_n": W_COL, "h_r_m": H_R, "l_f_m": L_F, "k_a_n_m": K_A, "k_b_n_m": K_B,
        "xi_1": 0.05, "xi_2": 0.0,
    }  # fmt: skip
    inputs.update(overrides)
    return PortalFrame.from_physical(**inputs)  # type: ignore[arg-type]


def test_example_4_printed_constants_follow_from_total_column_weight() -> None:
    frame = example_4()
    assert frame.omega_1_rad_s == pytest.approx(6.4581, abs=5e-5)
    assert frame.omega_2_rad_s == pytest.approx(0.6445, abs=5e-5)
    assert frame.p_2 == pytest.approx(1.2680, abs=5e-5)
    # The printed P₁ = 1.0901 is √P₁ of eq. 4.6 (docs/paper-notes.md, Example 4).
    assert frame.p_1 == pytest.approx(1.1884, abs=5e-5)
    assert math.sqrt(frame.p_1) == pytest.approx(1.0901, abs=5e-5)
    # γ₁ = 0.1387 needs l = 0.2263 m (not L_F/2): x* = 0.334 m.
    printed = example_4(l_m=0.22627)
    assert printed.gamma_1_m_s2 == pytest.approx(0.1387, abs=5e-5)
    assert printed.x_star_m == pytest.approx(0.1387 / 0.6445**2, rel=1e-3)
    # Default l = L_F/2.
    assert frame.gamma_1_m_s2 == pytest.approx(
        (W_S + 2 * W_COL) / (W_S + 5 / 9 * W_COL) * 9.81 / H_R * L_F / 2, rel=1e-14
    )


def test_per_column_convention_uses_half_the_column_weight_in_eqs_4_6_4_7() -> None:
    frame = example_4(w_col_convention="per-column")
    w = W_COL / 2
    assert frame.omega_1_rad_s**2 == pytest.approx(2 * K_B * 9.81 / (W_S + 2 / 3 * w), rel=1e-14)
    assert frame.p_2 == pytest.approx((W_S + w) / (W_S + 5 / 9 * w), rel=1e-14)
    # With one column's weight and l = L_F/2, x* equals the rigid-body overturning estimate.
    assert frame.x_star_m == pytest.approx(L_F / 2 * (W_S + W_COL) / (W_S + W_COL / 2), rel=1e-14)
    with pytest.raises(InputError, match="w_col_convention"):
        example_4(w_col_convention="half")


def test_x_c_is_the_smallest_root_of_eq_4_10() -> None:
    x_c = example_4().x_c_m
    load = W_S / 2 + W_COL / 2
    assert 0.5 * K_A * x_c * math.sin(2 * x_c / H_R) == pytest.approx(load, rel=1e-13)
    # Small-angle estimate √(H_r P_t / K_a) is within (x_c/H_r)² of it.
    assert x_c == pytest.approx(math.sqrt(H_R * load / K_A), rel=1e-4)
    assert x_c == pytest.approx(0.190426, abs=1e-6)
    # Nothing smaller satisfies it: the left side increases on [0, x_c].
    xs = np.linspace(0, x_c, 1000)
    assert np.all(np.diff(0.5 * K_A * xs * np.sin(2 * xs / H_R)) > 0)


def test_stiff_enough_leg_is_required() -> None:
    from stepframe.structure.frame import _U_MAX

    assert math.sin(_U_MAX) + _U_MAX * math.cos(_U_MAX) == pytest.approx(0, abs=1e-15)
    # Just stiff enough: the root sits below the peak of eq. 4.10 and still satisfies it.
    load = W_S / 2 + W_COL / 2
    k_a = 1.0001 * 2 * load / ((_U_MAX * H_R / 2) * math.sin(_U_MAX))
    x_c = onset_of_stepping_m(k_a, H_R, W_S, W_COL / 2)
    assert 0.5 * k_a * x_c * math.sin(2 * x_c / H_R) == pytest.approx(load, rel=1e-12)
    assert x_c < _U_MAX * H_R / 2
    with pytest.raises(InputError, match="k_a_n_m = 1000 N/m cannot lift a footing"):
        onset_of_stepping_m(1e3, H_R, W_S, W_COL / 2)


def test_c_r_agrees_with_the_papers_c1_c2_form() -> None:
    w_col_one = W_COL / 2
    c1, c2 = W_S / w_col_one, L_F / H_R
    expected = 1 - (3 + c1) / (2 + 3 * c1) * c2**2
    assert restitution_velocity_ratio(W_S, w_col_one, H_R, L_F) == pytest.approx(expected, 1e-14)
    assert example_4().c_r == pytest.approx(expected, rel=1e-14)
    with pytest.raises(InputError, match="too squat"):
        restitution_velocity_ratio(1e6, 1e6, 5.0, 8.0)


def test_overturning_displacement_against_explicit_geometry() -> None:
    # Rigid frame rotating about the right footing (origin) by φ: deck centre at (-L/2, H),
    # columns' centres at (0, H/2) and (-L, H/2). Find φ with the centre of mass over the pivot.
    half = L_F / 2
    w_one = W_COL / 2

    def rotated_x(x: float, y: float, phi: float) -> float:
        return x * math.cos(phi) + y * math.sin(phi)

    def moment(phi: float) -> float:
        return (
            W_S * rotated_x(-half, H_R, phi)
            + w_one * rotated_x(0.0, H_R / 2, phi)
            + w_one * rotated_x(-L_F, H_R / 2, phi)
        )

    phi = brentq(moment, 0.0, 1.0, xtol=1e-15)
    deck_moved = rotated_x(-half, H_R, phi) + half
    assert overturning_displacement_m(W_S, W_COL, H_R, L_F) == pytest.approx(deck_moved, 1e-12)
    assert example_4().x_cap_m == pytest.approx(deck_moved, rel=1e-12)


def test_derived_quantities() -> None:
    frame = example_4()
    # A constant ground acceleration equal to the uplift acceleration deflects the unstepped
    # frame by exactly x_c (eq. 4.11 at rest).
    a_up = frame.uplift_acceleration_m_s2
    assert frame.p_1 * a_up / frame.omega_1_rad_s**2 == pytest.approx(frame.x_c_m, rel=1e-14)
    assert frame.drift_ratio_per_m == pytest.approx(1 / H_R)
    assert frame.unstepped_period_s == pytest.approx(2 * math.pi / frame.omega_1_rad_s)
    assert PortalFrame.from_dict(frame.to_dict()) == frame


def test_from_constants_derives_x_c_c_r_and_cap_from_physical_inputs() -> None:
    constants = {
        "omega_1_rad_s": 6.4581, "omega_2_rad_s": 0.6445, "p_1": 1.1884, "p_2": 1.2680,
        "gamma_1_m_s2": 0.1387, "xi_1": 0.05, "xi_2": 0.0,
    }  # fmt: skip
    frame = PortalFrame.from_constants(
        **constants, w_s_n=W_S, w_col_n=W_COL, h_r_m=H_R, l_f_m=L_F, k_a_n_m=K_A
    )
    physical = example_4()
    assert frame.x_c_m == physical.x_c_m
    assert frame.c_r == physical.c_r
    assert frame.x_cap_m == physical.x_cap_m
    given = PortalFrame.from_constants(**constants, x_c_m=0.2, c_r=0.9)
    assert (given.x_c_m, given.c_r, given.x_cap_m, given.h_r_m) == (0.2, 0.9, None, None)
    with pytest.raises(InputError, match=r"x_c_m not given and cannot be derived.*k_a_n_m"):
        PortalFrame.from_constants(**constants, c_r=0.9)
    with pytest.raises(InputError, match=r"c_r not given.*l_f_m"):
        PortalFrame.from_constants(**constants, x_c_m=0.2, w_s_n=W_S, w_col_n=W_COL, h_r_m=H_R)


def test_housner_block_constants() -> None:
    b, h = 0.3, 1.5
    block = PortalFrame.housner_block(half_width_m=b, half_height_m=h, g_m_s2=9.81)
    alpha = math.atan(b / h)
    p = math.sqrt(3 * 9.81 / (4 * math.hypot(b, h)))
    assert block.is_rigid_block
    assert block.omega_2_rad_s == pytest.approx(p, rel=1e-15)
    assert block.x_star_m == pytest.approx(alpha * h, rel=1e-15)
    assert block.c_r == pytest.approx(1 - 1.5 * math.sin(alpha) ** 2, rel=1e-15)
    # P₂ ẍ_g / (p² h) = ẍ_g / g: the θ equation θ̈ - p²θ + p²α = -p² ẍ_g/g times h.
    assert block.p_2 == pytest.approx(p * p * h / 9.81, rel=1e-15)


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"x_c_m": 0.4}, r"x_c_m = 0\.4 m ≥ x\* = gamma_1/omega_2² = 0\.33"),
        ({"c_r": 1.2}, r"c_r = 1\.2, expected 0 ≤ c_r ≤ 1"),
        ({"xi_1": -0.01}, r"xi_1 = -0\.01, expected ≥ 0"),
        ({"omega_1_rad_s": 0.0}, r"omega_1_rad_s = 0\.0, expected > 0"),
        ({"p_2": float("nan")}, r"p_2 = nan, expected a finite number"),
        ({"x_cap_m": 0.1}, r"x_cap_m = 0\.1 m, expected > x_c_m"),
        ({"h_r_m": -3.0}, r"h_r_m = -3\.0, expected > 0"),
        ({"gamma_1_m_s2": "0.1"}, r"gamma_1_m_s2 = '0\.1', expected a finite number"),
    ],
)
def test_non_physical_frames_are_rejected(change: dict[str, object], message: str) -> None:
    values: dict[str, object] = {
        "omega_1_rad_s": 6.4581, "omega_2_rad_s": 0.6445, "p_1": 1.1884, "p_2": 1.2680,
        "gamma_1_m_s2": 0.1387, "xi_1": 0.05, "xi_2": 0.0, "x_c_m": 0.19, "c_r": 0.95,
    }  # fmt: skip
    values.update(change)
    with pytest.raises(InputError, match=message):
        PortalFrame(**values)  # type: ignore[arg-type]


def test_from_dict_rejects_unknown_and_missing_keys() -> None:
    data = example_4().to_dict()
    with pytest.raises(InputError, match="unknown key"):
        PortalFrame.from_dict({**data, "omega_1": 3.0})
    del data["c_r"]
    with pytest.raises(InputError, match=r"missing key.*c_r"):
        PortalFrame.from_dict(data)


def test_a_frame_hysteretic_damping_dissipates_like_viscous_at_resonance() -> None:
    frame = AFrame(
        omega_1_rad_s=5.0, omega_2_rad_s=0.7, p_1=1.1, p_2=1.2, gamma_1_m_s2=0.2,
        xi_1=0.04, theta_rad=0.3, x_c_m=0.1, c_r=0.9,
    )  # fmt: skip
    amplitude = 0.05
    w = frame.omega_1_rad_s

    def dissipated_power(t: float) -> float:
        x, v = amplitude * math.sin(w * t), amplitude * w * math.cos(w * t)
        elastic = -w * w * x
        damping = frame.acceleration_m_s2(x, v, 0.0, stepped=False) - elastic
        return -damping * v

    energy, _ = quad(dissipated_power, 0, 2 * math.pi / w, limit=200)
    assert energy == pytest.approx(2 * math.pi * frame.xi_1 * w * w * amplitude**2, rel=1e-9)
    # Stepped phase: eq. 4.2 with sec θ.
    sec = 1 / math.cos(0.3)
    acc = frame.acceleration_m_s2(0.2, 0.0, 1.0, stepped=True)
    assert acc == pytest.approx(0.49 * sec * 0.2 - 0.2 * sec - 1.2 * sec, rel=1e-14)
    assert frame.x_star_m == pytest.approx(0.2 / 0.49)
    with pytest.raises(InputError, match="theta_rad"):
        AFrame(**{**frame.to_dict(), "theta_rad": 2.0})


def test_a_frame_maps_onto_the_portal_form() -> None:
    frame = AFrame(
        omega_1_rad_s=5.0, omega_2_rad_s=0.7, p_1=1.1, p_2=1.2, gamma_1_m_s2=0.2,
        xi_1=0.0, theta_rad=0.3, x_c_m=0.1, c_r=0.9,
    )  # fmt: skip
    portal = frame.to_portal_frame()
    assert portal.x_star_m == pytest.approx(frame.x_star_m, rel=1e-15)
    # Same accelerations in both phases, at states on either side.
    for x, v, ag in ((0.05, 0.3, 1.0), (-0.08, -0.2, -2.0)):
        expected = -(portal.omega_1_rad_s**2) * x - portal.p_1 * ag
        assert frame.acceleration_m_s2(x, v, ag, stepped=False) == pytest.approx(expected)
    for x, ag in ((0.2, 1.0), (-0.3, 0.5)):
        w2, g1, p2 = portal.omega_2_rad_s, portal.gamma_1_m_s2, portal.p_2
        expected = w2 * w2 * x - math.copysign(g1, x) - p2 * ag
        assert frame.acceleration_m_s2(x, 0.1, ag, stepped=True) == pytest.approx(expected)
    damped = AFrame(**{**frame.to_dict(), "xi_1": 0.03})
    with pytest.raises(InputError, match=r"xi_1 = 0\.03 is hysteretic damping"):
        damped.to_portal_frame()
    # The substitute says what it costs: the error measured by bench/bench_structure_models.py.
    with pytest.warns(EquivalentViscousWarning, match=r"median 8\.1 % and up to \+567 %"):
        assert damped.to_portal_frame("equivalent-viscous").xi_1 == 0.03


def test_housners_restitution_of_a_squat_block_is_refused_with_the_reason() -> None:
    """C_r = 1 - 1.5 sin²α is negative beyond b/h = √2: "c_r = -0.2, expected 0 ≤ c_r ≤ 1"
    blamed a value the user never gave. A given c_r still builds the block."""
    with pytest.raises(InputError, match=r"too squat for Housner's C_r .* = -0\.2 \(b/h > √2\)"):
        PortalFrame.housner_block(half_width_m=2.0, half_height_m=1.0)
    just_slender = PortalFrame.housner_block(half_width_m=1.4, half_height_m=1.0)
    assert just_slender.c_r == pytest.approx(1 - 1.5 * 1.4**2 / (1 + 1.4**2), rel=1e-12)
    assert PortalFrame.housner_block(half_width_m=2.0, half_height_m=1.0, c_r=0.5).c_r == 0.5
