"""`stochastic amplify` without --t-max-s/--t-dur-s: with the paper's α_g(t_max) = ω_r ξ_r the
spectral ratio (eq. 6.18) and eq. 6.19's approximations need no envelope; the response
amplification, which does, is absent from the same JSON shape (issue 15; issue 28: a number is a
number or absent, never null)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.pipeline.amplification.amplify import (
    ENVELOPE_KEYS,
    spectral_ratios,
    tracking_oscillator,
)
from stepframe.structure.frame_file import frame_template

FREQUENCIES = [
    "--fp-hz", "7.43", "--fs-hz", "3.12", "--fr-hz", "1.11", "--xi-p", "0.096", "--xi-r", "0.655",
]  # fmt: skip
PAPER = ["--alpha-at-tmax", "paper"]
ENVELOPE_FREE = ("spectral_ratio_eq_6_18", "approx_eq_6_19_first", "approx_eq_6_19_last")


def _run(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    code = main(["stochastic", "amplify", *args])
    out, err = capsys.readouterr()
    return code, out, err


def _json(args: list[str], capsys: pytest.CaptureFixture[str]) -> dict[str, object]:
    code, out, err = _run([*args, "--json"], capsys)
    assert code == 0, err
    data = json.loads(out)
    assert isinstance(data, dict)
    return data


@pytest.mark.parametrize("f0_hz", ["3.12", "7.43", "0.5"])
@pytest.mark.parametrize("times", [["5", "20"], ["2", "3"], ["11", "60"]])
def test_numbers_equal_those_of_a_run_with_times(
    f0_hz: str, times: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    free = _json([*FREQUENCIES, "--f0-hz", f0_hz, *PAPER], capsys)
    timed = _json(
        [*FREQUENCIES, "--t-max-s", times[0], "--t-dur-s", times[1], "--f0-hz", f0_hz, *PAPER,
         "--n-steps", "300"],
        capsys,
    )  # fmt: skip
    for key in ENVELOPE_FREE:
        assert free[key] == timed[key], key  # the same computation: equal to the last bit
    # eq. 6.19's last approximation is (f_p/f_s)²
    assert free["approx_eq_6_19_last"] == pytest.approx((7.43 / 3.12) ** 2, rel=1e-14)
    assert free["approx_eq_6_19_last"] == pytest.approx(5.6711, abs=1e-4)  # the paper's 5.67
    # the same top-level keys in the same order but the envelope's, absent; the rest as with times
    assert list(free) == [key for key in timed if key not in ENVELOPE_KEYS]
    assert all(timed[key] is not None for key in ENVELOPE_KEYS)
    for key, value in free.items():
        if key not in ("message", "inputs"):
            assert value == timed[key], key
    model = free["inputs"]["ground_motion_model"]  # type: ignore[index]
    assert "t_max_s" not in model and "t_dur_s" not in model
    assert {k: v for k, v in model.items() if k not in ("t_max_s", "t_dur_s")} == {
        k: v
        for k, v in timed["inputs"]["ground_motion_model"].items()  # type: ignore[index]
        if k not in ("t_max_s", "t_dur_s")
    }
    assert free["status"] == "ok" and free["lower_bound"] is False
    assert "--t-max-s" in str(free["message"]) and "not computed" in str(free["message"])


def test_eq_6_18_at_f_p_is_the_first_approximation(capsys: pytest.CaptureFixture[str]) -> None:
    free = _json([*FREQUENCIES, "--f0-hz", "7.43", *PAPER], capsys)
    assert free["spectral_ratio_eq_6_18"] == pytest.approx(free["approx_eq_6_19_first"], rel=1e-12)
    assert free["approx_eq_6_19_first"] == pytest.approx(5.5637, abs=1e-4)


def test_library_route_matches_the_command(capsys: pytest.CaptureFixture[str]) -> None:
    result = spectral_ratios(7.43, 3.12, 1.11, 0.096, 0.655, tracking_oscillator(2.0))
    assert result.to_dict() == _json([*FREQUENCIES, "--f0-hz", "2", *PAPER], capsys)


def test_text_says_what_was_not_computed_and_how(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run([*FREQUENCIES, "--f0-hz", "3.12", *PAPER], capsys)
    assert code == 0, err
    assert "spectral ratio eq. 6.18 at f0          18.23" in out
    assert "eq. 6.19 last approximation (ωp/ωs)²   5.671" in out
    assert "response amplification not computed" in out
    assert "--t-max-s" in out and "--t-dur-s" in out and "stochastic fit" in out
    assert "response amplification vs fixed" not in out
    assert "nan" not in out.lower() and "none" not in out.lower()


def test_frame_without_times(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    frame = tmp_path / "frame.toml"
    frame.write_text(frame_template(), encoding="utf-8")
    free = _json([*FREQUENCIES, "--frame", str(frame), *PAPER], capsys)
    timed = _json(
        [*FREQUENCIES, "--t-max-s", "5", "--t-dur-s", "20", "--frame", str(frame), *PAPER,
         "--n-steps", "300"],
        capsys,
    )  # fmt: skip
    assert free["omega_path"] == "frame" and free["f0_hz"] == timed["f0_hz"]
    for key in ENVELOPE_FREE:
        assert free[key] == timed[key], key
    assert "response_amplification_vs_fixed" not in free


@pytest.mark.parametrize(
    ("args", "message"),
    [
        # under eq. 6.11 as printed, α_g(t_max) depends on t_max/t_dur
        ([*FREQUENCIES, "--f0-hz", "2"], "--alpha-at-tmax paper for eqs. 6.18-6.19 alone"),
        ([*FREQUENCIES, "--f0-hz", "2", *PAPER, "--monte-carlo", "50"], "--monte-carlo without"),
        ([*FREQUENCIES, "--f0-hz", "2", *PAPER, "--plot", "a.png"], "--plot without"),
        # one time alone is still an error naming the other
        ([*FREQUENCIES, "--t-max-s", "5", "--f0-hz", "2", *PAPER], "missing --t-dur-s"),
        ([*FREQUENCIES[:-2], "--f0-hz", "2", *PAPER], "missing --xi-r"),
    ],
)
def test_errors_say_what_to_give(
    args: list[str], message: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, err = _run(args, capsys)
    assert code == 2 and out == ""
    assert err.startswith("stepframe: error: ") and err.count("\n") == 1
    assert message in err
