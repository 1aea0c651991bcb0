"""make_amplification_report: the reproducing command line and the checks before any work."""

from __future__ import annotations

import shlex
from pathlib import Path

import pytest

from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import AmplificationReportOptions
from stepframe.pipeline.amplification.report import make_amplification_report
from stepframe.pipeline.reports.document import report_summary
from stepframe.pipeline.reports.provenance import command_line

SITE = {"fp_hz": 7.43, "fs_hz": 3.12, "fr_hz": 1.11, "xi_p": 0.096, "xi_r": 0.655}
TIMED = SITE | {"t_max_s": 5, "t_dur_s": 20}


def test_command_line_round_trips_through_the_shell() -> None:
    line = command_line(["stepframe", "report", "selection", "my picks/"], {"out": "a b.html"})
    assert line == "stepframe report selection 'my picks/' --out 'a b.html'"
    assert shlex.split(line) == [
        "stepframe",
        "report",
        "selection",
        "my picks/",
        "--out",
        "a b.html",
    ]


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"parameters": SITE}, "missing --t-max-s, expected all of --fp-hz"),
        ({"parameters": {"fp_hz": 7.43}, "records": "dir"}, "--records with --fp-hz"),
        ({"parameters": TIMED, "xi0": 1.0}, r"xi0 = 1.0, expected in \(0, 1\)"),
        ({"parameters": TIMED, "monte_carlo": 1}, r"monte_carlo = 1, expected 0 or in \[2, 100000"),
        ({"parameters": TIMED, "n_steps": 99}, r"n_steps = 99, expected in \[100, 1000000\]"),
        (
            {"parameters": SITE | {"t_max_s": 5, "t_dur_s": 20}, "delta_star_m": 0.2},
            "--delta-star-m without --frame",
        ),
        # before, accepted and read by nothing: the same report as without it
        ({"parameters": TIMED, "peak_intensity_m_s2": 3.0}, "--peak-intensity-m-s2 without"),
    ],
)
def test_bad_inputs_fail_before_anything_is_written(
    tmp_path: Path, kwargs: dict[str, object], message: str
) -> None:
    out = tmp_path / "r.html"
    with pytest.raises(InputError, match=message):
        parameters = dict(kwargs.pop("parameters"))  # type: ignore[call-overload]
        options = AmplificationReportOptions(**parameters, **kwargs)  # type: ignore[arg-type]
        make_amplification_report(str(out), options)
    assert list(tmp_path.iterdir()) == []


def test_report_summary_names_the_file_its_folder_and_size(tmp_path: Path) -> None:
    out = tmp_path / "x.html"
    out.write_text("a" * 2500)
    data, text = report_summary(out)
    assert data == {
        "report": str(out),
        "data_folder": str(tmp_path / "x_files"),
        "size_bytes": 2500,
    }
    assert text == f"report: {out} (2 kB); its numbers: {tmp_path / 'x_files'}/"


def test_the_summary_states_the_runs_correlations_with_their_intervals() -> None:
    from stepframe.pipeline.selection.report import _stated_correlations

    rows = [
        {"score": "s", "response": "peak_drift", "spearman": 0.194, "low": -0.083, "high": 0.437,
         "n": 53},
        {"score": "s", "response": "overturn_margin", "spearman": 0.314, "low": 0.049,
         "high": 0.537, "n": 53},
        {"score": "other", "response": "peak_drift", "spearman": 0.9, "low": 0.8, "high": 1.0},
        {"score": "s", "response": "constant", "spearman": None, "low": None, "high": None},
    ]  # fmt: skip
    line = _stated_correlations({"correlations": rows}, "s")
    assert line == (
        "Spearman, s, 95 % bootstrap intervals, at equal PSA(T_1): ρ = 0.19 [-0.08, 0.44] with "
        "peak drift (n = 53); ρ = 0.31 [0.05, 0.54] with overturn margin (n = 53)"
    )
    # with the run's stated intensities: the confirmation's level, and the ranking's when other
    stated = {
        "correlations": rows,
        "medians": {"equal_psa_t1_onset_ratio": 2.0, "equal_psa_t1_g": 1.2},
        "ranking_intensity": {"kind": "as-used", "text": "the records as recorded; ladder ×1"},
    }
    assert _stated_correlations(stated, "s").startswith(
        "Spearman, s, 95 % bootstrap intervals, at equal PSA(T_1) = 1.2 g, 2 × the onset of "
        "stepping (ranked at the records as recorded): ρ = 0.19"
    )
    assert _stated_correlations({}, "s") == ""
