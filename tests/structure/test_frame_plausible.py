"""A frame file's numbers have plausible ranges (as the record headers do), a TOML file that
breaks the parser's limits is one line, and keys the chosen route ignores are named."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.errors import InputError
from stepframe.structure.frame_file import (
    FRAME_TEMPLATE,
    PLAUSIBLE,
    FrameFileWarning,
    read_frame_file,
)


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "FRAME.toml"
    path.write_text(text, encoding="utf-8")
    return path


def _line_of(text: str, start: str) -> int:
    return next(i for i, line in enumerate(text.splitlines(), 1) if line.startswith(start))


@pytest.mark.parametrize(
    ("key", "value", "expected"),
    [
        ("k_b_n_m", "nan", "expected in [100, 1e+13]"),
        ("h_r_m", "1e308", "expected in [0.1, 300]"),
        ("l_f_m", "1e308", "expected in [0.05, 300]"),
        ("w_s_n", "5", "expected in [100, 1e+10]"),
        ("w_col_n", "0", "expected in (0, 1e+10]"),
        ("k_a_n_m", "1e308", "expected in [1000, 1e+13]"),
        ("g_m_s2", "1e-12", "expected in [9.7, 9.9]"),
        ("omega_1_rad_s", "inf", "expected in (0, 2000]"),
    ],
)
def test_values_outside_the_plausible_range_are_refused_at_their_line(
    tmp_path: Path, key: str, value: str, expected: str
) -> None:
    start = f"{key} = "
    line = _line_of(FRAME_TEMPLATE, start)
    lines = FRAME_TEMPLATE.splitlines()
    lines[line - 1] = start + value
    path = _write(tmp_path, "\n".join(lines) + "\n")
    with pytest.raises(InputError) as error:
        read_frame_file(path)
    assert error.value.line == line
    assert expected in error.value.what and key in error.value.what


def test_every_physical_and_constant_key_has_a_range() -> None:
    for table in ("physical", "constants", "block"):
        from stepframe.structure.frame_file import TABLES

        assert all((table, key) in PLAUSIBLE for key in TABLES[table])


def test_the_template_reads_without_a_warning(tmp_path: Path) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        frame = read_frame_file(_write(tmp_path, FRAME_TEMPLATE))
    assert frame.x_c_m == pytest.approx(0.19043, rel=1e-4)


def test_keys_the_constants_route_ignores_are_named(tmp_path: Path) -> None:
    text = FRAME_TEMPLATE.replace("# x_c_m = 0.1904 ", "x_c_m = 0.1904   ").replace(
        "# c_r = 0.9474 ", "c_r = 0.9474   "
    )
    with pytest.warns(FrameFileWarning) as caught:
        read_frame_file(_write(tmp_path, text))
    message = str(caught[0].message)
    assert "[physical] k_a_n_m (x_c_m given)" in message
    assert "[conventions] g_m_s2 (c_r given)" in message


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("[frame]\nxi_1 = " + "[" * 5000 + "]" * 5000 + "\n", "nested too deeply"),
        ("[frame]\nxi_1 = " + "9" * 5001 + "\n", "an integer of more than 4,300 digits"),
        ("# " + "x" * (1 << 20) + "\n", "expected a FRAME.toml of at most 1,048,576 bytes"),
    ],
)
def test_toml_past_the_parsers_limits_is_one_line(
    tmp_path: Path, text: str, expected: str, capsys: pytest.CaptureFixture[str]
) -> None:
    path = _write(tmp_path, text)
    code = main(["structure", "simulate", "--frame", str(path), "--example", "fema-p695",
                 "--component", "MUL009"])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert expected in err and str(path) in err
