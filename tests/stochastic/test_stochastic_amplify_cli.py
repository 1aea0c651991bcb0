"""`stepframe stochastic amplify`: JSON keys and values, frame and record routes, errors, plot."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.structure.frame_file import frame_template, read_frame_file
from stepframe.structure.period_amplitude import period_amplitude

SITE = [
    "--fp-hz", "7.43", "--fs-hz", "3.12", "--fr-hz", "1.11", "--xi-p", "0.096",
    "--xi-r", "0.655", "--t-max-s", "5", "--t-dur-s", "20",
]  # fmt: skip
FAST = ["--n-steps", "600"]


def _run(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(["stochastic", "amplify", *args])
    out, err = capsys.readouterr()
    return code, out, err


def test_json_for_the_papers_site_at_f_p(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(
        [*SITE, "--f0-hz", "7.43", "--alpha-at-tmax", "paper", "--json", *FAST], capsys
    )
    assert code == 0, err
    data = json.loads(out)
    assert data["approx_eq_6_19_last"] == pytest.approx((7.43 / 3.12) ** 2, rel=1e-12)
    assert data["approx_eq_6_19_first"] == pytest.approx(5.5637, abs=1e-4)
    # eq. 6.18 at f0 = f_p is the first approximation under the paper's reading
    assert data["spectral_ratio_eq_6_18"] == pytest.approx(data["approx_eq_6_19_first"], rel=1e-12)
    assert data["omega_path"] == "tracking" and data["alpha_reading"] == "paper"
    assert data["response_amplification_vs_fixed"] > 5
    assert data["response_amplification_vs_stationary"] > 1
    assert data["inputs"]["ground_motion_model"]["xi_r"] == 0.655
    assert data["f0_hz"] == 7.43 and data["xi0"] == 0.05 and data["status"] == "ok"


def test_text_output_names_each_quantity(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run([*SITE, "--f0-hz", "2", *FAST], capsys)
    assert code == 0
    assert "spectral ratio eq. 6.18" in out and "response amplification vs fixed" in out
    assert "alpha reading: eq-6-11" in out


def test_frame_route_uses_the_period_law(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = tmp_path / "frame.toml"
    path.write_text(frame_template(), encoding="utf-8")
    frame = read_frame_file(path)
    code, out, err = _run(
        [*SITE, "--frame", str(path), "--peak-intensity-m-s2", "0.5", "--json", *FAST], capsys
    )
    assert code == 0, err
    data = json.loads(out)
    assert data["omega_path"] == "frame"
    assert data["f0_hz"] == pytest.approx(1 / period_amplitude(frame, 0.0), rel=1e-12)
    assert data["f0_hz"] == pytest.approx(frame.omega_1_rad_s / (2 * math.pi), rel=1e-12)
    assert data["peak_intensity_m_s2"] == pytest.approx(0.5 * frame.p_1, rel=1e-12)
    assert data["xi0"] == frame.xi_1
    assert data["lower_bound"] is (data["status"] != "ok")


def test_record_route_fits_the_site(data_dir: Path, capsys: pytest.CaptureFixture[str]) -> None:
    record = data_dir / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"
    code, out, err = _run(["--record", str(record), "--f0-hz", "2", "--json", *FAST], capsys)
    assert code == 0, err
    data = json.loads(out)
    assert data["inputs"]["record"] == str(record)
    model = data["inputs"]["ground_motion_model"]
    assert model["omega_p_rad_s"] >= model["omega_s_rad_s"] >= model["omega_r_rad_s"] > 0
    assert data["peak_intensity_m_s2"] > 0
    assert math.isfinite(data["response_amplification_vs_fixed"])


def test_monte_carlo_confirmation(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(
        [*SITE, "--f0-hz", "2", "--monte-carlo", "100", "--seed", "4", "--json", *FAST], capsys
    )
    assert code == 0, err
    mc = json.loads(out)["monte_carlo"]
    lo, hi = mc["response_amplification_vs_fixed_band"]
    assert lo < mc["response_amplification_vs_fixed"] < hi
    assert mc["n_realisations"] == 100 and mc["seed"] == 4


def test_plot_is_written_whole(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    target = tmp_path / "amp.png"
    code, _, err = _run([*SITE, "--f0-hz", "2", "--plot", str(target), *FAST], capsys)
    assert code == 0, err
    assert target.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["amp.png"]


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--f0-hz", "2", "--fp-hz", "7"], "missing --fs-hz"),
        ([*SITE], "exactly one of --f0-hz"),
        ([*SITE, "--f0-hz", "2", "--frame", "f.toml"], "exactly one of --f0-hz"),
        ([*SITE, "--f0-hz", "2", "--record", "r.AT2"], "either the site parameters or --record"),
        ([*SITE, "--f0-hz", "2", "--xi0", "0"], "--xi0 0"),
        ([*SITE, "--f0-hz", "-2"], "not positive"),
        ([*SITE[:-2], "--t-dur-s", "3", "--f0-hz", "2"], "t_max"),
        # options nothing reads in that run (each printed the same numbers before)
        ([*SITE, "--f0-hz", "2", "--units", "g", "--t0", "start"],
         "--units, --t0 do nothing here, expected them only with --record FILE or --example"),
        ([*SITE, "--f0-hz", "2", "--peak-intensity-m-s2", "2"],
         "--peak-intensity-m-s2 does nothing here, expected it only with --frame"),
        ([*SITE, "--f0-hz", "2", "--seed", "3"],
         "--seed does nothing here, expected it only with --monte-carlo N"),
        ([*SITE, "--f0-hz", "2", "--f-min-hz", "0.2", "--n-frequencies", "30"],
         "--f-min-hz, --n-frequencies do nothing here, expected them only with --plot"),
    ],
)  # fmt: skip
def test_user_errors_are_one_line_exit_2(
    args: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, err = _run([*args, "--json"], capsys)
    assert code == 2
    assert out == ""
    assert err.startswith("stepframe: error: ") and err.count("\n") == 1
    assert message in err


def test_help_shows_an_example_and_the_module_imports_nothing_heavy() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "stepframe.cli", "stochastic", "amplify", "--help"],
        capture_output=True,
        text=True,
        check=True,
    )
    assert "stepframe stochastic amplify --fp-hz 7.43" in done.stdout
    probe = (
        "import sys, stepframe.commands.stochastic; "
        "print([m for m in ('numpy', 'scipy', 'numba', 'matplotlib', 'xarray') "
        "if m in sys.modules])"
    )
    done = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
