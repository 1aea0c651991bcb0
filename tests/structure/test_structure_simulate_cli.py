"""`stepframe structure simulate` and `frame-template`: wiring, outputs and bad input."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

from stepframe.cli import main
from stepframe.pipeline.dynamics.resonance import moving_resonance
from stepframe.pipeline.selection.band import frame_band
from stepframe.records import read
from stepframe.structure.frame_file import FRAME_TEMPLATE, read_frame_file
from stepframe.structure.simulator import simulate

RECORD = "peer_nga_west2/RSN8883_14383980_13849360.AT2"


@pytest.fixture
def frame_file(tmp_path: Path) -> Path:
    path = tmp_path / "FRAME.toml"
    path.write_text(FRAME_TEMPLATE, encoding="utf-8")
    return path


def run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_frame_template_prints_the_example_4_file(capsys: pytest.CaptureFixture[str]) -> None:
    status, out, err = run(capsys, "structure", "frame-template")
    assert (status, err) == (0, "")
    assert tomllib.loads(out)["constants"]["gamma_1_m_s2"] == 0.1387
    status, out, _ = run(capsys, "structure", "frame-template", "--json")
    assert json.loads(out)["frame_toml"] == FRAME_TEMPLATE


def test_simulate_json_matches_the_library(
    capsys: pytest.CaptureFixture[str], frame_file: Path, data_dir: Path, tmp_path: Path
) -> None:
    record = str(data_dir / RECORD)
    plot = tmp_path / "response.png"
    status, out, err = run(
        capsys, "structure", "simulate", "--frame", str(frame_file), record,
        "--scale", "6", "--tail-s", "5", "--json", "--plot", str(plot),
    )  # fmt: skip
    assert (status, err) == (0, "")
    summary = json.loads(out)
    trace = read(record)[0]
    expected = simulate(read_frame_file(frame_file), trace.data, trace.stats.delta, scale=6.0,
                        tail_s=5.0).summary  # fmt: skip
    for key in ("peak_abs_x_m", "residual_x_m", "n_stepping_episodes", "n_impacts", "overturned"):
        assert summary[key] == getattr(expected, key), key
    assert summary["overturn_time_s"] is None
    # Scaled to 0.96 g (uplift at 0.68 g), the frame steps once and returns: x_c < peak < x*.
    assert summary["n_stepping_episodes"] >= 1 and summary["n_impacts"] >= 1
    assert 0.190426 < summary["peak_abs_x_m"] < 0.333911
    assert summary["peak_drift_ratio"] == pytest.approx(summary["peak_abs_x_m"] / 29.944)
    assert summary["pga_m_s2"] == pytest.approx(6 * np.max(np.abs(trace.data)))
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["FRAME.toml", "response.png"]
    # The moving-resonance measures are the library's on the same run, over the frame's band.
    frame = read_frame_file(frame_file)
    measured = moving_resonance(frame, trace.data, trace.stats.delta, scale=6.0, tail_s=5.0)
    resonance = summary["moving_resonance"]
    for key, value in measured.to_dict().items():
        assert resonance[key] == (pytest.approx(value) if isinstance(value, float) else value), key
    band = frame_band(frame)
    assert resonance["band_rad_s"] == [band.omega_low_rad_s, frame.omega_1_rad_s]
    # One stepping excursion: one half-cycle stepped, ω_f left ω_1 for a moment only, so nearly
    # none of the ground's work arrived by moving resonance.
    assert resonance["n_stepping_half_cycles"] == 1
    assert resonance["lowest_omega_f_rad_s"] < frame.omega_1_rad_s / 2
    assert resonance["work_depth"] < 0.01 and resonance["moving_resonance_share"] < 0.01


def test_simulate_text_reports_overturning(
    capsys: pytest.CaptureFixture[str], frame_file: Path, data_dir: Path
) -> None:
    status, out, _ = run(
        capsys, "structure", "simulate", "--frame", str(frame_file), str(data_dir / RECORD),
        "--scale", "30",
    )  # fmt: skip
    assert status == 0
    assert "OVERTURNED at" in out
    assert "moving resonance: R_m " in out and "ω_f down to 0 rad/s" in out
    # The run stops where |x| passed the cap: that state is not a residual (it printed
    # "residual x 5.77319 m", the cap), so neither the text nor the JSON states one.
    assert "residual" not in out.replace("no residual state", "")
    status, out, _ = run(
        capsys, "structure", "simulate", "--frame", str(frame_file), str(data_dir / RECORD),
        "--scale", "30", "--json",
    )  # fmt: skip
    summary = json.loads(out)
    assert summary["overturned"] and "residual_x_m" not in summary
    assert "residual_v_m_s" not in summary


@pytest.mark.parametrize(
    ("change", "args", "message"),
    [
        (("p_2 = 1.2680", "p2 = 1.2680"), (), "FRAME.toml:39: unknown key 'p2' in [constants]"),
        (("xi_1 = 0.05", "xi_1 = -1"), (), "FRAME.toml:15: xi_1 = -1.0, expected ≥ 0"),
        (None, ("--scale", "-2"), "argument --scale: '-2' is not positive"),
        (None, ("--tail-s", "nan"), "argument --tail-s: 'nan', expected seconds ≥ 0"),
    ],
)
def test_bad_input_exits_2_with_one_line(
    capsys: pytest.CaptureFixture[str],
    frame_file: Path,
    data_dir: Path,
    change: tuple[str, str] | None,
    args: tuple[str, ...],
    message: str,
) -> None:
    if change is not None:
        frame_file.write_text(FRAME_TEMPLATE.replace(*change), encoding="utf-8")
    status, out, err = run(
        capsys, "structure", "simulate", "--frame", str(frame_file), str(data_dir / RECORD), *args
    )
    assert (status, out) == (2, "")
    assert err.startswith("stepframe: error: ") and err.count("\n") == 1
    assert message in err


def test_non_finite_record_names_the_file(
    capsys: pytest.CaptureFixture[str], frame_file: Path, tmp_path: Path
) -> None:
    record = tmp_path / "acc.txt"
    record.write_text("0.0\n0.1\nnan\n0.2\n", encoding="utf-8")
    status, out, err = run(
        capsys, "structure", "simulate", "--frame", str(frame_file), str(record),
        "--format", "text", "--units", "g", "--dt-s", "0.01",
    )  # fmt: skip
    assert (status, out) == (2, "")
    # Refused by the reader (issue 16: non-finite samples are a read error), naming file and line.
    assert f"{record}:3: value nan is not a finite number" in err


def test_missing_frame_option(capsys: pytest.CaptureFixture[str], data_dir: Path) -> None:
    status, out, err = run(capsys, "structure", "simulate", str(data_dir / RECORD))
    assert (status, out) == (2, "")
    assert "--frame" in err


def test_multi_component_file_needs_component(
    capsys: pytest.CaptureFixture[str], frame_file: Path, data_dir: Path
) -> None:
    record = str(data_dir / "formats/geonet/20180212_211557_WPWS_20.V2A.gz")
    status, out, err = run(capsys, "structure", "simulate", "--frame", str(frame_file), record)
    assert (status, out) == (2, "")
    assert "3 components (S16W, S74E, Up), expected one: pick it with --component NAME" in err
    status, out, _ = run(
        capsys, "structure", "simulate", "--frame", str(frame_file), record,
        "--component", "S16W", "--json",
    )  # fmt: skip
    summary = json.loads(out)
    assert status == 0 and summary["component"] == "S16W" and summary["npts"] == 5800
    # A weak record (PGA 0.004 g) leaves the frame linear: no stepping, no impacts.
    assert summary["n_stepping_episodes"] == 0 and summary["n_impacts"] == 0
    assert summary["peak_abs_x_m"] < 0.19
    # Unstepped, eq. 4.11 is a linear oscillator: P₁ times the spectral displacement at ω₁, ξ₁
    # (the records stage's Nigam-Jennings kernel, which interpolates the record band-limited
    # rather than linearly: agreement to a fraction of a percent, not to rounding).
    from stepframe.records.spectra import peak_displacements_m

    frame = read_frame_file(frame_file)
    trace = read(record, component="S16W")[0]
    period_s = 2 * np.pi / frame.omega_1_rad_s
    sd_m = peak_displacements_m(trace.data, trace.stats.delta, [period_s], frame.xi_1)[0]
    assert summary["peak_abs_x_m"] == pytest.approx(frame.p_1 * sd_m, rel=1e-2)


def test_a_motion_of_five_samples_is_simulated_and_measured(
    capsys: pytest.CaptureFixture[str], frame_file: Path, tmp_path: Path
) -> None:
    # 5 samples and a one-step tail: the resonator bank needs two samples (its frames at 0 and
    # 0.1 s, the motion followed by zeros), so the measures are made; one half-cycle that never
    # steps, so R_m has nothing to judge (n/a) and no work arrived down the band.
    record = tmp_path / "acc.txt"
    record.write_text("0.0\n0.1\n0.2\n0.1\n0.0\n", encoding="utf-8")
    plot = tmp_path / "short.png"
    args = ("structure", "simulate", "--frame", str(frame_file), str(record), "--format", "text",
            "--units", "g", "--dt-s", "0.01", "--tail-s", "0.01")  # fmt: skip
    status, out, err = run(capsys, *args, "--json", "--plot", str(plot))
    assert (status, err) == (0, "")
    resonance = json.loads(out)["moving_resonance"]
    assert resonance["status"] == "ok"
    assert (resonance["n_half_cycles"], resonance["n_stepping_half_cycles"]) == (1, 0)
    assert resonance["work_depth"] == 0.0 and "moving_resonance_index" not in resonance
    assert plot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    status, out, _ = run(capsys, *args)
    assert status == 0 and "moving resonance: R_m n/a (ω_f stayed near ω_1)" in out


def test_a_frame_without_a_band_is_simulated_and_says_so(
    capsys: pytest.CaptureFixture[str], tmp_path: Path, data_dir: Path
) -> None:
    """γ_1 = 0.07912 m/s² puts x* = γ_1/ω_2² at 0.190476 m, 5e-5 m above x_c: the default band's
    bottom, 0.8 x*, is below x_c, so there is no band to measure moving resonance over. The
    simulation stands (before, the command refused the whole run); the measures say why, and
    `select` on the frame names the options that give a band."""
    frame_file = tmp_path / "FRAME.toml"
    frame_file.write_text(
        FRAME_TEMPLATE.replace("gamma_1_m_s2 = 0.1387 ", "gamma_1_m_s2 = 0.07912"),
        encoding="utf-8",
    )
    frame = read_frame_file(frame_file)
    assert frame.x_c_m < frame.x_star_m < frame.x_c_m / 0.8
    record = str(data_dir / RECORD)
    status, out, err = run(
        capsys, "structure", "simulate", "--frame", str(frame_file), record, "--scale", "6",
        "--json",
    )  # fmt: skip
    assert (status, err) == (0, "")
    summary = json.loads(out)
    trace = read(record)[0]
    expected = simulate(frame, trace.data, trace.stats.delta, scale=6.0).summary
    assert summary["peak_abs_x_m"] == expected.peak_abs_x_m
    resonance = summary["moving_resonance"]
    assert resonance["status"] == "failed" and "band_rad_s" not in resonance
    assert resonance["message"].startswith("no band: A_max = 0.152381 m (fraction-of-x-star)")
    status, _, err = run(
        capsys, "select", "--frame", str(frame_file), "--example", "fema-p695", "-n", "1",
        "-o", str(tmp_path / "o"),
    )  # fmt: skip
    assert status == 2 and err.rstrip().endswith(
        "x_c is 0.9997 x*: give --a-max-m between them or a --x-star-fraction above that"
    )
    assert not (tmp_path / "o").exists()
