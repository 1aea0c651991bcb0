"""`stepframe structure harmonic | bifurcation | ida`: wiring, JSON, plots and bad input."""

from __future__ import annotations

import json
import math
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.structure.frame import PortalFrame
from stepframe.structure.harmonic import simulate_harmonic


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_harmonic_json_matches_the_library_and_finds_a_stable_orbit(
    capsys: pytest.CaptureFixture[str], tmp_path: Path
) -> None:
    plot = tmp_path / "portrait.png"
    status, out, err = run(
        capsys,
        "structure",
        "harmonic",
        "--block",
        "0.25,1.0",
        "--amplitude-g",
        "0.3",
        "--omega-rad-s",
        "16",
        "--periods",
        "60",
        "--orbit",
        "1",
        "--json",
        "--plot",
        str(plot),
    )
    assert (status, err) == (0, "")
    data = json.loads(out)
    block = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0)
    ref = simulate_harmonic(block, 0.3 * 9.81, 16.0, 60 * 2 * math.pi / 16.0, samples_per_period=32)
    assert data["n_impacts"] == ref.n_impacts
    assert data["x_end_m"] == pytest.approx(float(ref.x_m[-1]), abs=1e-12)
    assert data["orbit"]["status"] == "ok"
    assert plot.stat().st_size > 1000


def test_bifurcation_and_ida_commands(capsys: pytest.CaptureFixture[str], tmp_path: Path) -> None:
    status, out, err = run(
        capsys,
        "structure",
        "bifurcation",
        "--block",
        "0.25,1.0",
        "--omega-rad-s",
        "16",
        "--amplitudes-g",
        "0.1,0.3,3",
        "--initial",
        "4",
        "--periods",
        "30",
        "--jobs",
        "1",
        "--json",
    )
    assert (status, err) == (0, "")
    rows = json.loads(out)["points"]
    assert [round(r["amplitude_g"], 6) for r in rows] == [0.1, 0.2, 0.3]
    status, out, err = run(
        capsys,
        "structure",
        "ida",
        "--block",
        "0.25,1.0",
        "--pulse",
        "cosine",
        "--omega-rad-s",
        "10.8",
        "--resolution-g",
        "0.001",
        "--json",
    )
    assert (status, err) == (0, "")
    data = json.loads(out)
    assert data["resurrected"] == 1
    assert data["simulations"] < data["fixed_step_simulations"]


@pytest.mark.parametrize(
    "argv",
    [
        ["structure", "harmonic", "--block", "0.25", "--amplitude-g", "0.1", "--omega-rad-s", "3"],
        ["structure", "harmonic", "--block", "0.25,1", "--amplitude-g", "-1", "--omega-rad-s", "3"],
        [
            "structure",
            "bifurcation",
            "--block",
            "0.25,1",
            "--omega-rad-s",
            "3",
            "--amplitudes-g",
            "0.5,0.1,3",
        ],
        ["structure", "bifurcation", "--block", "0.25,1", "--amplitude-g", "0.1"],
        ["structure", "ida", "--block", "0.25,1"],
        ["structure", "ida", "--block", "0.25,1", "--pulse", "cosine"],
        ["structure", "ida", "--frame", "/nonexistent/FRAME.toml", "--fema-p695", "1"],
    ],
)
def test_bad_input_is_one_line_and_exit_2(
    capsys: pytest.CaptureFixture[str], argv: list[str]
) -> None:
    with pytest.raises(SystemExit) as exc:  # argparse errors exit; ours return 2
        raise SystemExit(main(argv))
    out, err = capsys.readouterr()
    assert exc.value.code == 2
    assert out == ""
    assert "Traceback" not in err and err.strip()
