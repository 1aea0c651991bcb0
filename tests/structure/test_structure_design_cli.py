"""`stepframe structure design`: options, input file, template, --json, --plot, errors."""

from __future__ import annotations

import json
import math
import re
import tomllib
from pathlib import Path

import pytest

from stepframe.cli import main

EXAMPLE_2 = [
    "structure", "design", "--weight-super-n", "1.472e6", "--weight-col-n", "0",
    "--weight-total-n", "2.807e6", "--footing-length-m", "8.839", "--block-width-m", "1.166",
    "--height-m", "29.944", "--sds-g", "1.038", "--sd1-g", "0.456", "--beta", "0.8",
    "--delta0-m", "0.00254,0.3048",
]  # fmt: skip


def run_json(args: list[str], capsys: pytest.CaptureFixture[str]) -> dict[str, object]:
    assert main([*args, "--json"]) == 0
    out = capsys.readouterr().out
    data = json.loads(out)
    assert isinstance(data, dict)
    return data


def test_example_2_from_options(capsys: pytest.CaptureFixture[str]) -> None:
    data = run_json(EXAMPLE_2, capsys)
    constants = data["constants"]
    assert isinstance(constants, dict)
    w = 2 * 1.472e6 / (2.807e6 * (8.839 - 1.166))
    assert constants["w_per_m"] == pytest.approx(w, rel=1e-12)
    # λ_2 of eq. 2.5 with W_col = 0, written out.
    lam2 = 0.8 * 0.456 * 9.81 / (2 * math.pi * math.sqrt(9.81))
    lam2 *= math.sqrt(1.472e6 / 2.807e6 * 2 * 29.944 / (8.839 - 1.166))
    assert constants["lambda_2_sqrt_m"] == pytest.approx(lam2, rel=1e-12)
    design = data["design"]
    assert isinstance(design, dict)
    s = math.sqrt(1 - 4 * w * lam2**2)
    assert design["delta_m"] == pytest.approx((1 - s) / (2 * w), rel=1e-9)
    assert design["branch"] == "long" and design["status"] == "ok"
    iterations = data["iterations"]
    assert isinstance(iterations, list) and len(iterations) == 2
    for trace in iterations:
        assert trace["status"] == "ok"
        assert trace["delta_m"] == pytest.approx(design["delta_m"], rel=1e-9)
    assert iterations[0]["rows"][0]["branch"] == "short"  # 0.1 in starts on the plateau


def test_text_output_and_plot(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tmp_path / "cobweb.png"
    assert main([*EXAMPLE_2, "--plot", str(out)]) == 0
    text = capsys.readouterr().out
    assert "delta_3" in text and "design (closed-form): delta* = 0.137951 m" in text
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["cobweb.png"]  # no temporary left


def test_template_round_trip(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["structure", "design", "--template"]) == 0
    template = capsys.readouterr().out
    tomllib.loads(template)  # valid TOML
    path = tmp_path / "pier.toml"
    path.write_text(template)
    data = run_json(["structure", "design", "--input", str(path)], capsys)
    design = data["design"]
    assert isinstance(design, dict)
    assert design["delta_m"] == pytest.approx(0.7373367, abs=1e-7)  # Example 1, recomputed
    # An option overrides the file: --c-r 1 gives ξ = 0 and β = √2 (Eurocode 8).
    data = run_json(["structure", "design", "--input", str(path), "--c-r", "1"], capsys)
    constants = data["constants"]
    assert isinstance(constants, dict)
    assert constants["beta"] == pytest.approx(math.sqrt(2))
    assert constants["xi"] == 0.0


def test_tabulated_spectrum_uses_search(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "table.toml"
    path.write_text(
        "[pier]\nweight_super_n = 8e6\nweight_col_n = 2.12e5\nweight_total_n = 9.6e6\n"
        "footing_length_m = 7.0\nheight_m = 27.0\nblock_width_m = 1.3714\n"
        "[spectrum]\nperiods_s = [0.0, 0.5, 2.0, 4.0, 8.0]\nsa_g = [0.4, 0.9, 0.25, 0.12, 0.05]\n"
        "[damping]\nxi = 0.1\nmethod = 'ec8-1998'\n"
    )
    data = run_json(["structure", "design", "--input", str(path)], capsys)
    assert data["fixed_points"] == []
    design = data["design"]
    assert isinstance(design, dict) and design["method"] == "search"
    assert design["status"] == "ok"


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--height-m", "-3"], "--height-m -3.0, expected in (0, 300]"),
        (["--xi", "0.1"], "--beta, --xi given, expected exactly one of --beta, --xi or --c-r"),
        (["--plot", "out.txt"], "expected .png, .pdf or .svg"),
        (["--template"], "--template with --weight-super-n, --weight-col-n"),
    ],
)
def test_bad_input_is_one_line_exit_2(
    extra: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    args = [*EXAMPLE_2, *extra]
    if "--xi" in extra:  # --xi together with --beta
        args = [*EXAMPLE_2, "--xi", "0.1"]
    assert main(args) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("stepframe: error: ")
    assert message in lines[0]


def test_two_damping_options_are_named_as_options(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--c-r and --beta over a file whose [damping] has beta only: the error blamed the file
    ('pier.toml [damping]: ... found ['beta', 'c_r']'), which holds one of them."""
    path = tmp_path / "pier.toml"
    assert main(["structure", "design", "--template"]) == 0
    path.write_text(capsys.readouterr().out)
    assert main(["structure", "design", "--input", str(path), "--c-r", "0.9", "--beta", "0.8"]) == 2
    assert capsys.readouterr().err == (
        "stepframe: error: --beta, --c-r given, expected exactly one of --beta, --xi or --c-r "
        "(it replaces the whole [damping] of the input)\n"
    )
    # one of them replaces the file's [damping] (beta = 1.0 in the template): β from C_r
    data = run_json(["structure", "design", "--input", str(path), "--c-r", "0.9"], capsys)
    assert data["inputs"]["xi"] == pytest.approx(0.48 * (1 - 0.9**2))  # eq. 4.17


def test_unknown_toml_key_names_file_and_key(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "bad.toml"
    path.write_text("[pier]\nW_s = 1\n[spectrum]\ns_ds_g = 1\ns_d1_g = 0.4\n[damping]\nbeta = 1\n")
    assert main(["structure", "design", "--input", str(path)]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and "unknown key(s) ['W_s']" in err


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (("beta = 1.0 ", "beta = -1.0 "), "beta = -1.0, expected > 0"),
        (("footing_length_m = 7.0 ", 'footing_length_m = "7" '), "footing_length_m = '7'"),
        (("delta0_m = [0.05, 2.0]", "delta0_m = []"), "delta0_m = [], expected at least one"),
    ],
)
def test_a_bad_value_in_the_file_names_its_line(
    change: tuple[str, str], message: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Values checked after the file is parsed named neither file nor line (and an empty
    delta0_m fell back to the default starts without a word)."""
    assert main(["structure", "design", "--template"]) == 0
    template = capsys.readouterr().out
    old, new = change
    assert old in template
    path = tmp_path / "pier.toml"
    path.write_text(template.replace(old, new, 1))
    number = next(n for n, text in enumerate(path.read_text().splitlines(), 1) if new in text)
    assert main(["structure", "design", "--input", str(path)]) == 2
    error = capsys.readouterr().err.strip()
    assert error.startswith(f"stepframe: error: {path}:{number}: {message}"), error


def test_paper_table_from_map_constants(capsys: pytest.CaptureFixture[str]) -> None:
    # Example 2's caption constants in SI, the long-branch formula forced as in Table 1.
    w = 0.0416774 / 0.3048
    lam2 = 0.691857 * math.sqrt(0.3048)
    args = ["structure", "design", "--w-per-m", repr(w), "--lambda-2-sqrt-m", repr(lam2),
            "--sds-g", "1.038", "--sd1-g", "0.456", "--beta", "0.8", "--delta0-m", "0.00254",
            "--branch", "long", "--max-iterations", "19"]  # fmt: skip
    data = run_json(args, capsys)
    (trace,) = data["iterations"]  # type: ignore[misc]
    inches = [row["delta_m"] / 0.0254 for row in trace["rows"]]
    assert len(inches) == 20
    # Table 1, Case I, first and last printed iterates (2.2e-4: see docs/paper-notes.md).
    assert inches[1] == pytest.approx(0.75794068, rel=2.5e-4)
    assert inches[19] == pytest.approx(5.8620055, rel=2.5e-4)
    assert "lies on the 'short' branch" in trace["notes"][0]
    assert main([*args, "--trace"]) == 0
    text = capsys.readouterr().out
    assert "    19  1.4892" in text  # the full trace table


def test_help_shows_worked_example(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["structure", "design", "--help"]) == 0
    out = capsys.readouterr().out
    assert "examples:" in out and "stepframe structure design --weight-super-n" in out


def test_pier_and_map_options_together_is_an_error(capsys: pytest.CaptureFixture[str]) -> None:
    assert main([*EXAMPLE_2, "--w-per-m", "0.1", "--lambda-2-sqrt-m", "0.3"]) == 2
    assert "expected one" in capsys.readouterr().err


def test_an_iteration_that_does_not_converge_says_it_once(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """The help's Table 1 example stops at --max-iterations 19: its line read 'no convergence
    in 19 iterations after 19 steps'; a converged one still counts its steps."""
    table_1 = ["structure", "design", "--w-per-m", "0.136737", "--lambda-2-sqrt-m", "0.381964",
               "--sds-g", "1.038", "--sd1-g", "0.456", "--beta", "0.8", "--delta0-m", "0.00254",
               "--branch", "long"]  # fmt: skip
    assert main([*table_1, "--max-iterations", "19"]) == 0
    (line,) = [x for x in capsys.readouterr().out.splitlines() if x.startswith("iteration from")]
    assert line.startswith("iteration from delta0 = 0.00254 m: no convergence in 19 iterations, ")
    assert main(table_1) == 0
    (line,) = [x for x in capsys.readouterr().out.splitlines() if x.startswith("iteration from")]
    assert re.match(r"iteration from delta0 = 0\.00254 m: converged after \d+ steps, ", line)
