"""FRAME.toml: both routes, the template, and one clear error per kind of bad input."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from stepframe.errors import InputError
from stepframe.structure.frame import PortalFrame
from stepframe.structure.frame_file import (
    FRAME_TEMPLATE,
    frame_from_mapping,
    frame_template,
    read_frame_file,
)

PHYSICAL = {
    "w_s_n": 1.472e6,
    "w_col_n": 1.335e6,
    "h_r_m": 29.944,
    "l_f_m": 8.839,
    "k_a_n_m": 1.159e9,
}


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "FRAME.toml"
    path.write_text(text, encoding="utf-8")
    return path


def without_table(text: str, table: str) -> str:
    """The template with one table (header to the next header) removed."""
    return re.sub(rf"\n\[{table}\]\n.*?(?=\n\[|\Z)", "\n", text, flags=re.S)


def test_template_is_example_4_through_the_constants_route(tmp_path: Path) -> None:
    assert frame_template() == FRAME_TEMPLATE
    frame = read_frame_file(write(tmp_path, FRAME_TEMPLATE))
    expected = PortalFrame.from_constants(
        omega_1_rad_s=6.4581, omega_2_rad_s=0.6445, p_1=1.1884, p_2=1.2680,
        gamma_1_m_s2=0.1387, xi_1=0.05, xi_2=0.0, g_m_s2=9.81, **PHYSICAL,
    )  # fmt: skip
    assert frame == expected
    assert frame.x_c_m == pytest.approx(0.190426, abs=1e-6)
    assert frame.x_star_m == pytest.approx(0.33391, abs=1e-5)
    assert frame.h_r_m == 29.944


def test_physical_route_and_conventions(tmp_path: Path) -> None:
    text = without_table(FRAME_TEMPLATE, "constants")
    frame = read_frame_file(write(tmp_path, text))
    expected = PortalFrame.from_physical(
        **PHYSICAL, k_b_n_m=5.021e6, xi_1=0.05, xi_2=0.0, g_m_s2=9.81
    )
    assert frame == expected
    assert frame.omega_1_rad_s == pytest.approx(6.4581, abs=5e-5)
    text = text.replace('# w_col_convention = "total"', 'w_col_convention = "per-column"')
    text = text.replace("# l_m = 4.4195", "l_m = 0.2263")
    frame = read_frame_file(write(tmp_path, text))
    expected = PortalFrame.from_physical(
        **PHYSICAL, k_b_n_m=5.021e6, xi_1=0.05, xi_2=0.0, l_m=0.2263,
        w_col_convention="per-column",
    )  # fmt: skip
    assert frame == expected


def test_overrides_in_frame_table(tmp_path: Path) -> None:
    text = FRAME_TEMPLATE.replace("# c_r = 0.9474 ", "c_r = 0.8    ")
    text = text.replace("# x_c_m = 0.1904 ", "x_c_m = 0.2    ").replace("# x_cap_m", "x_cap_m")
    frame = read_frame_file(write(tmp_path, text))
    assert (frame.c_r, frame.x_c_m, frame.x_cap_m) == (0.8, 0.2, 5.773)


def test_mapping_without_file() -> None:
    frame = frame_from_mapping(
        {
            "frame": {"xi_1": 0.02, "xi_2": 0.0, "c_r": 1.0, "x_c_m": 0.1},
            "constants": {
                "omega_1_rad_s": 5.0,
                "omega_2_rad_s": 0.5,
                "p_1": 1.0,
                "p_2": 1.0,
                "gamma_1_m_s2": 0.1,
            },
        }
    )
    assert frame.x_star_m == pytest.approx(0.4)
    assert frame.x_cap_m is None and frame.h_r_m is None


def line_of(text: str, needle: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), 1) if needle in line)


@pytest.mark.parametrize(
    ("old", "new", "needle", "message"),
    [
        ("\n[conventions]", "\n[convention]", "[convention]", "unknown table or key 'convention'"),
        ("p_2 = 1.2680", "p2 = 1.2680", "p2 =", "unknown key 'p2' in [constants]"),
        ("h_r_m = 29.944", 'h_r_m = "29.944"', "h_r_m =", "[physical] h_r_m = '29.944', expected"),
        ("# x_c_m = 0.1904 ", "x_c_m = 0.5 ", "x_c_m = 0.5", "x_c_m = 0.5 m ≥ x"),
        ("xi_2 = 0.0 ", "xi_2 = -0.1", "xi_2 = -0.1", "xi_2 = -0.1, expected ≥ 0"),
        ("# l_m = 4.4195", "l_m = 4.4195", "l_m = 4.4195", "[conventions] l_m is only used"),
        ("p_1 = 1.1884", "p_1 = 1.1884\np_1 = 2.0", None, "not valid TOML"),
        ("xi_1 = 0.05", "xi_1 = 0.05 xx", "xi_1 = 0.05 xx", "not valid TOML"),
    ],
)  # fmt: skip
def test_bad_files_name_file_line_and_key(
    tmp_path: Path, old: str, new: str, needle: str | None, message: str
) -> None:
    assert old in FRAME_TEMPLATE
    text = FRAME_TEMPLATE.replace(old, new, 1)
    path = write(tmp_path, text)
    with pytest.raises(InputError, match=re.escape(message)) as caught:
        read_frame_file(path)
    assert caught.value.path == str(path)
    if needle is not None:
        assert caught.value.line == line_of(text, needle)
    assert "\n" not in str(caught.value)


def test_missing_keys(tmp_path: Path) -> None:
    text = FRAME_TEMPLATE.replace("xi_1 = 0.05", "")
    with pytest.raises(InputError, match="missing key xi_1 in"):
        read_frame_file(write(tmp_path, text))
    text = FRAME_TEMPLATE.replace("gamma_1_m_s2 = 0.1387", "")
    with pytest.raises(InputError, match=r"missing key\(s\) gamma_1_m_s2 in \[constants\]"):
        read_frame_file(write(tmp_path, text))
    text = without_table(FRAME_TEMPLATE, "constants").replace("k_b_n_m = 5.021e6", "")
    with pytest.raises(InputError, match=r"missing key\(s\) k_b_n_m in \[physical\]"):
        read_frame_file(write(tmp_path, text))
    text = without_table(without_table(FRAME_TEMPLATE, "physical"), "constants")
    with pytest.raises(InputError, match=r"missing key\(s\) h_r_m, k_a_n_m"):
        read_frame_file(write(tmp_path, text))
    # Constants route without the physical inputs that x_c would need.
    text = without_table(FRAME_TEMPLATE, "physical")
    with pytest.raises(InputError, match="x_c_m not given and cannot be derived"):
        read_frame_file(write(tmp_path, text))
    with pytest.raises(InputError, match="missing table"):
        frame_from_mapping({"constants": {}})


BLOCK = """\
[frame]
name = "rigid block"
c_r = 0.9
[block]
half_width_m = 0.25
half_height_m = 1.0
[conventions]
g_m_s2 = 9.81
"""


def test_rigid_block_route(tmp_path: Path) -> None:
    frame = read_frame_file(write(tmp_path, BLOCK))
    assert frame == PortalFrame.housner_block(
        half_width_m=0.25, half_height_m=1.0, g_m_s2=9.81, c_r=0.9
    )
    assert frame.x_c_m == 0.0
    housner = read_frame_file(write(tmp_path, BLOCK.replace("c_r = 0.9\n", "x_cap_m = 0.3\n")))
    assert housner.c_r == pytest.approx(1 - 1.5 * (0.25**2 / (0.25**2 + 1.0)), rel=1e-14)
    assert housner.x_cap_m == 0.3


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("c_r = 0.9", "c_r = 0.9\nxi_1 = 0.02", "[frame] xi_1 given with [block], expected none"),
        ("half_height_m = 1.0", "", "missing key(s) half_height_m in [block]"),
        ("half_width_m = 0.25", "half_width_m = -0.25", "half_width_m = -0.25, expected in (0"),
        ("c_r = 0.9", "c_r = 1.9", "[frame] c_r = 1.9, expected in [0, 1]"),
        ("[block]", "[physical]\nh_r_m = 3.0\n[block]", "[physical] given with [block]"),
    ],
)
def test_bad_rigid_block_files(tmp_path: Path, old: str, new: str, message: str) -> None:
    text = BLOCK.replace(old, new)
    path = write(tmp_path, text)
    with pytest.raises(InputError, match=re.escape(message)) as caught:
        read_frame_file(path)
    assert caught.value.path == str(path) and caught.value.line is not None
