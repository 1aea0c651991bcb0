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


IDA = ["structure", "ida", "--block", "0.25,1"]
PULSES = [*IDA, "--pulse", "cosine", "--omega-rad-s", "10.8,16"]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        ([*IDA, "--fema-p695", "2", "--omega-rad-s", "10,16"],
         "--omega-rad-s without --pulse, expected it only with --pulse cosine|sine"),
        ([*PULSES, "--fema-p695", "2"],
         "--pulse with --fema-p695, expected pulses or records, not both"),
        ([*PULSES, "--tail-s", "3"], "--pulse with --tail-s, expected pulses or records"),
        ([*IDA, "--fema-p695", "2", "--units", "g"],
         "--units without RECORD files, expected record options only with RECORD files"),
    ],
)  # fmt: skip
def test_ida_options_the_run_does_not_read_are_refused(
    capsys: pytest.CaptureFixture[str], argv: list[str], message: str
) -> None:
    """Each ran and ignored the option (the pulses' run printed no record; the records' run no
    pulse): one line, exit 2, before any simulation."""
    assert main(argv) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.startswith(f"stepframe: error: {message}") and err.count("\n") == 1


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


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        # Once hanging for more than a minute: a forcing frequency near 0 (6e12 s of motion)...
        (["--omega-rad-s", "1e-12", "--periods", "1"], "1.68e+13 closed-form pieces"),
        # ... and a million periods at 10⁴ rad/s (3.2e7 output samples).
        (["--omega-rad-s", "1e4", "--periods", "1000000"], "1.44e+08 closed-form pieces"),
        (["--omega-rad-s", "1e-300", "--periods", "1"], "5.32e+287 years"),
        (["--omega-rad-s", "1e-320", "--periods", "1"], "more than 1e308 s would take without end"),
    ],
)
def test_work_beyond_the_limit_is_refused_before_integrating(
    capsys: pytest.CaptureFixture[str], argv: list[str], said: str
) -> None:
    base = ["structure", "harmonic", "--block", "0.25,1.0", "--amplitude-g", "0.3"]
    status, out, err = run(capsys, *base, *argv)
    assert (status, out) == (2, "")
    assert err.count("\n") == 1 and said in err and "expected at most 3e+07" in err


def test_an_orbit_of_a_hundred_million_periods_is_out_of_range(
    capsys: pytest.CaptureFixture[str],
) -> None:
    """Once refused by its work (10⁸-period Newton steps), now by the option's range."""
    base = ["structure", "harmonic", "--block", "0.25,1.0", "--amplitude-g", "0.3"]
    status, out, err = run(capsys, *base, "--omega-rad-s", "16", "--orbit", "100000000")
    assert (status, out) == (2, "")
    assert err == "stepframe: error: --orbit 100000000, expected in [1, 64]\n"


def test_the_threshold_case_answers_with_a_tiny_rocking(capsys: pytest.CaptureFixture[str]) -> None:
    # The uplift threshold g·α × (1 + 1e-9): was status ok with peak 1.5e8 m.
    status, out, _err = run(
        capsys, "structure", "harmonic", "--block", "0.25,1.0", "--amplitude-g",
        "0.2449786633718428", "--omega-rad-s", "16", "--periods", "20", "--json",
    )  # fmt: skip
    data = json.loads(out)
    assert status == 0 and data["status"] == "ok" and not data["overturned"]
    # It lifts at each of the 41 crests and troughs and lands again (the last one at the end).
    assert data["peak_abs_x_m"] < 1e-15 and data["n_liftoffs"] == 41 and data["n_impacts"] == 40


def test_pulse_ida_finds_the_survival_band_by_default(capsys: pytest.CaptureFixture[str]) -> None:
    # ω = 2p: the linearised block overturns from 1.414 gα, survives 4.17-5.23 gα and overturns
    # again (solve_ivp in test_ida.py); probing only to twice the first overturning missed it.
    p = PortalFrame.housner_block(half_width_m=0.25, half_height_m=1.0).omega_2_rad_s
    status, out, _err = run(
        capsys, "structure", "ida", "--block", "0.25,1.0", "--pulse", "cosine",
        "--omega-rad-s", repr(2 * p), "--json",
    )  # fmt: skip
    (item,) = json.loads(out)["items"]
    assert status == 0 and item["status"] == "ok" and item["resurrected"]
    assert item["first_overturning"] == pytest.approx(1.4065, abs=0.01)
    over, survive = (float(v) for v in item["resurrections"].split("->"))
    assert over <= 4.1738 <= survive and survive - over <= 0.01
    # Asked to probe only to twice the first overturning, it does not see the band.
    status, out, _err = run(
        capsys, "structure", "ida", "--block", "0.25,1.0", "--pulse", "cosine",
        "--omega-rad-s", repr(2 * p), "--probe-factor", "2", "--probes", "8", "--json",
    )  # fmt: skip
    assert not json.loads(out)["items"][0]["resurrected"]
