"""The command-line conventions: one-line errors with exit 2, --json, --version, --help."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from stepframe import __version__
from stepframe.cli import main


def run_cli(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "stepframe.cli", *args], capture_output=True, text=True, timeout=120
    )


def test_version_in_process(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"stepframe {__version__}"


def test_help_lists_groups_and_examples(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--help"]) == 0
    out = capsys.readouterr().out
    for group in ("records", "stochastic", "structure", "demo", "examples:"):
        assert group in out


def test_unknown_option_is_one_line_exit_2(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["--no-such-option"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1
    assert lines[0].startswith("stepframe: error: ")
    assert "--no-such-option" in lines[0]


def test_missing_file_subprocess_has_no_traceback(tmp_path: Path) -> None:
    missing = tmp_path / "nope.AT2"
    result = run_cli("records", "info", str(missing))
    assert result.returncode == 2
    assert result.stdout == ""
    assert (
        result.stderr.strip()
        == f"stepframe: error: {missing}: no such file, expected an existing record file"
    )
    assert "Traceback" not in result.stderr


def test_debug_shows_traceback(tmp_path: Path) -> None:
    result = run_cli("records", "info", str(tmp_path / "nope"), "--debug")
    assert result.returncode == 2
    assert "Traceback" in result.stderr
    assert result.stderr.strip().splitlines()[-1].startswith("stepframe: error: ")


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory: pytest.TempPathFactory) -> tuple[dict[str, object], Path]:
    """One ``stepframe --json demo`` run: the shipped selection workflow (features, selection
    and confirmation of 100 records, the report) with its workspace in the folder."""
    out = tmp_path_factory.mktemp("demo") / "demo"
    result = subprocess.run(
        [sys.executable, "-m", "stepframe.cli", "--json", "demo", "-o", str(out)],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert result.returncode == 0, result.stderr
    return json.loads(result.stdout), out  # stdout is only JSON


def test_demo_selects_for_example_4(demo_run: tuple[dict[str, object], Path]) -> None:
    import math

    import numpy as np
    import pandas as pd

    from stepframe.structure.frame import PortalFrame
    from stepframe.structure.period_amplitude import period_amplitude

    payload, out = demo_run
    # Example 4's printed constants: x* = γ1/ω2², band bottom at A_max = 0.8 x*.
    frame = PortalFrame(6.4581, 0.6445, 1.1884, 1.268, 0.1387, 0.05, 0.0, 0.19043, 0.95)
    low = 2 * math.pi / period_amplitude(frame, 0.8 * 0.1387 / 0.6445**2)
    assert payload["band_rad_s"] == pytest.approx([low, 6.4581], rel=1e-4)
    assert payload["n_candidates"] == 100
    # an empty reason is read as NaN: read the column as text
    candidates = pd.read_csv(
        out / "selection" / "candidates.csv", dtype={"dropped_by": str}, keep_default_na=False
    )
    assert payload["n_filtered"] == int((candidates["dropped_by"] != "").sum())
    passed = candidates[candidates["dropped_by"] == ""]
    rank_by = str(payload["rank_by"])  # the library's default ranking
    assert rank_by == "simulated_response"
    # Independent order: overturning within the ladder first (lower factor first), then the
    # ladder's mean peak (docs/selection.md).
    key = passed.assign(factor=passed["overturn_factor"].fillna(np.inf))
    top = key.sort_values(["factor", rank_by], ascending=[True, False], kind="stable").head(10)
    selected = payload["selected"]
    assert [s["rank"] for s in selected] == list(range(1, 11))
    assert [s["component"] for s in selected] == top["component"].astype(str).tolist()
    assert [s["score"] for s in selected] == pytest.approx(top[rank_by].tolist())
    assert all(s["scale_factor"] == 1.0 for s in selected)
    # The ranking's tie across the chosen set's edge, recomputed from candidates.csv: Example 4
    # at the onset of stepping overturns as soon as it steps under many records (factor ×1),
    # whose ladder means differ by less than the bisection's resolution.
    resolution = (1 - 1 / math.sqrt(2)) / 256
    inside = passed[passed["selected"]]
    outside = passed[~passed["selected"]]

    def close(a: object, b: object) -> np.ndarray:
        a, b = np.asarray(a, dtype=float)[:, None], np.asarray(b, dtype=float)[None, :]
        return np.abs(a - b) <= resolution * np.minimum(a, b)

    pairs = close(inside["simulated_response"], outside["simulated_response"]) & close(
        inside["overturn_factor"], outside["overturn_factor"]
    )
    assert (
        candidates["ranking_tie"].astype(str).eq("True").sum()
        == pairs.any(1).sum() + pairs.any(0).sum()
    )
    tie = payload["ranking"]["tie"]
    assert (tie["n_chosen"], tie["n_other"]) == (int(pairs.any(1).sum()), int(pairs.any(0).sum()))
    assert tie["n_chosen"] == 10 and tie["n_other"] > 0 and tie["overturn_factor"] == 1.0
    entry = next(
        e
        for e in payload["correlations"]
        if e["score"] == rank_by and e["response"] == "peak_drift"
    )
    assert entry["n"] == len(passed)
    assert entry["low"] <= entry["spearman"] <= entry["high"]
    confirmation = pd.read_csv(out / "selection" / "confirmation.csv")
    equal = confirmation[confirmation["case"] == "equal-psa-t1"]
    assert len(equal) == len(passed)
    # Recompute the selected-vs-control medians from the table.
    chosen = set(top["file"] + "|" + top["component"].astype(str))
    key = equal["file"] + "|" + equal["component"].astype(str)
    assert payload["medians"]["equal_psa_t1_peak_x_m_selected"] == pytest.approx(
        float(np.median(equal.loc[key.isin(chosen), "peak_abs_x_m"]))
    )
    # ... and at the chosen scale, the selected and their controls, peaks and overturned counts
    # (the confirmation's intensity named in g: ω_1²·x_c/P_1 at the onset, Example 4's 0.681).
    at_scale = confirmation[confirmation["case"] == "chosen-scale"]
    for group, name in (("selected", "selected"), ("control", "control")):
        rows = at_scale[at_scale["group"] == group]
        assert len(rows) == 10
        assert payload["medians"][f"chosen_scale_peak_x_m_{name}"] == pytest.approx(
            float(np.median(rows["peak_abs_x_m"]))
        )
        assert payload["medians"][f"chosen_scale_overturned_{name}"] == rows["overturned"].sum()
    onset_g = frame.omega_1_rad_s**2 * frame.x_c_m / frame.p_1 / 9.80665
    # (the printed constants above have five digits; the frame file's are exact)
    assert payload["medians"]["equal_psa_t1_g"] == pytest.approx(onset_g, rel=1e-4)
    assert onset_g == pytest.approx(0.681, abs=5e-4)
    assert not list(out.rglob("*.part")) and not list(out.rglob(".*.tmp"))


def test_demo_is_the_shipped_selection_workflow(demo_run: tuple[dict[str, object], Path]) -> None:
    """The run went through the runner: every stage of the shipped selection.toml, its outputs
    and the report (with the three best records' accelerograms) in the folder."""
    import pandas as pd

    from stepframe.pipeline.engine.shipped import SHIPPED_DIR

    payload, out = demo_run
    assert payload["workflow"] == str(SHIPPED_DIR / "selection.toml")
    stages = payload["stages"]
    assert isinstance(stages, list)
    assert [(s["name"], s["computed"], s["cached"]) for s in stages] == [
        ("inventory", 100, 0),
        ("features", 100, 0),
        ("responses", 100, 0),
        ("selection", 1, 0),
        ("selection_report", 1, 0),
    ]
    assert payload["report"] == str(out / "selection_report.html")
    assert payload["missing"] == {}
    outputs = payload["outputs"]
    assert isinstance(outputs, dict) and outputs["selection_report"][0] == payload["report"]
    numbers = json.loads((out / "selection_report_files" / "numbers.json").read_text())
    chosen = pd.read_csv(out / "selection" / "selection.csv")
    names = zip(chosen["file"], chosen["component"], strict=True)
    best = [f"{file.rsplit('/', 1)[-1]} [{component}]" for file, component in names]
    assert numbers["accelerogram_records"] == best[:3]
    # the report simulates the frame the run ranked with (selection.json carries it): the
    # moving-resonance section runs on the three best records at the ranking intensity
    summary = json.loads((out / "selection" / "selection.json").read_text())
    assert [summary["frame"][k] for k in ("omega_1_rad_s", "x_c_m")] == pytest.approx(
        [6.4581, 0.19043], rel=1e-4
    )  # Example 4's printed constants
    drawn = numbers["moving_resonance"]
    assert [row["record"] for row in drawn] == best[:3]
    assert [row["scale"] for row in drawn] == pytest.approx(chosen["ranking_scale"][:3].tolist())
    features = pd.read_parquet(out / "features.parquet")
    assert len(features) == 100
    assert (out / "store").is_dir() and (out / "lock").is_file()


def test_demo_summary_text(demo_run: tuple[dict[str, object], Path]) -> None:
    from stepframe.pipeline.demo import run_demo

    payload, out = demo_run
    again = run_demo(out)  # the store has everything: nothing is computed
    assert [s.computed for s in again.run.stages] == [0, 0, 0, 0, 0]
    lines = again.describe().splitlines()
    assert lines[0].startswith("band: 0.654 to 6.46 rad/s (T 0.973 to 9.61 s); 100 candidates")
    # the tables line names every file of the run's selection folder, motions/ on a line of its own
    (tables,) = [line for line in lines if line.startswith("tables: ")]
    written = sorted(p.name for p in (out / "selection").iterdir() if p.is_file())
    assert sorted(tables.partition(" (")[2].rstrip(")").split(", ")) == written
    assert "spectra.csv" in written and (out / "selection" / "motions" / "manifest.csv").is_file()
    motions = f"the chosen motions, scaled: {out / 'selection' / 'motions'}/ (manifest.csv, "
    assert lines[lines.index(tables) + 1].startswith(motions)
    assert sum(1 for line in lines if line.startswith("  ") and ". RSN" in line) == 10
    # The confirmation names its intensity (here the ranking's own), then ρ and the medians.
    start = lines.index(
        "confirmation, every candidate at equal PSA(T_1) = 0.681 g, 1 × the onset of stepping "
        "(the ranking's own intensity):"
    )
    assert lines[start + 1].startswith(f"  Spearman({payload['rank_by']}, peak_drift) = ")
    assert "], n = 100" in lines[start + 1]
    medians = payload["medians"]
    assert lines[start + 3] == (
        f"  median peak |x|: the 10 selected {medians['equal_psa_t1_peak_x_m_selected']:.3g} m "
        f"({medians['equal_psa_t1_overturned_selected']} overturn), 10 controls "
        f"{medians['equal_psa_t1_peak_x_m_control']:.3g} m "
        f"({medians['equal_psa_t1_overturned_control']} overturn)"
    )
    assert lines[start + 4].startswith(
        "confirmation at the chosen scale (the records as recorded): median peak |x| of the 10 "
        f"selected {medians['chosen_scale_peak_x_m_selected']:.3g} m "
        f"({medians['chosen_scale_overturned_selected']} overturn)"
    )
    # the stated intensity, the chosen set against the rest, the peers and the tiers
    assert "ranked at: every record at equal PSA(T_1) = 0.681 g, 1 × the onset of stepping" in (
        "\n".join(lines)
    )
    # Each response line says at which scale: the ranking's and the chosen set's differ.
    assert any(
        line.startswith(
            "at the ranking intensity (every record at equal PSA(T_1) = 0.681 g, 1 × the onset "
            "of stepping): the chosen reach"
        )
        for line in lines
    )
    assert any(
        line.startswith("at the chosen scale (the records as recorded): of 10 components")
        for line in lines
    )
    assert any(line.startswith("ρ with overturn margin at equal PSA(T_1)") for line in lines)
    tie = payload["ranking"]["tie"]  # type: ignore[index]
    assert (
        f"tie: the ranking does not tell {tie['n_chosen']} of the chosen from {tie['n_other']} "
        "other candidates (each overturns the frame from ×1 of its ranking scale"
    ) in "\n".join(lines)
    assert any(line.startswith("tiers closest to the exact ranking") for line in lines)
    outputs = [line for line in lines if line.startswith(("report: ", "tables: ", "features: "))]
    assert outputs[0] == f"report: {out}/selection_report.html"


def test_report_selection_reads_the_demo_folder(
    demo_run: tuple[dict[str, object], Path], tmp_path: Path
) -> None:
    """``stepframe report selection stepframe-demo/``: the folder's selection/ is the one read."""
    _, out = demo_run
    html = tmp_path / "again.html"
    done = run_cli("report", "selection", str(out), "-o", str(html), "--json")
    assert done.returncode == 0, done.stderr
    numbers = json.loads((tmp_path / "again_files" / "numbers.json").read_text())
    shown = json.loads((out / "selection_report_files" / "numbers.json").read_text())
    assert numbers["selected"] == shown["selected"] and len(numbers["selected"]) == 10


def test_the_demo_report_says_why_a_tier_row_is_empty(
    demo_run: tuple[dict[str, object], Path],
) -> None:
    """At equal S_a(T_1) the tier sa_t1_g gives every candidate the same value (and no fitted
    ω_g path reaches Example 4's band, so band_coverage is 0 for all): no ρ, no recall. The
    tiers table's caption names the empty rows and says why."""
    import html

    import pandas as pd

    _, out = demo_run
    tiers = pd.read_csv(out / "selection_report_files" / "tiers.csv")
    empty = list(tiers.loc[tiers["spearman"].isna(), "tier"])
    assert "sa_t1_g" in empty
    page = html.unescape((out / "selection_report.html").read_text(encoding="utf-8"))
    expected = f"{', '.join(empty)}: the same value for every candidate at the ranking intensity"
    assert expected in page


def test_the_demo_report_says_the_tie_in_its_summary_and_its_ranking(
    demo_run: tuple[dict[str, object], Path],
) -> None:
    """The ranking's tie is in the page's summary box (its own row) and in the ranking section,
    in the words of the command's summary line."""
    import html

    from stepframe.pipeline.selection.ranking import tie_line

    payload, out = demo_run
    line = tie_line(payload)  # type: ignore[arg-type]
    assert line is not None and line.startswith("tie: the ranking does not tell 10 of the chosen")
    page = html.unescape((out / "selection_report.html").read_text(encoding="utf-8"))
    assert f"<dt>Tie</dt><dd>{line.removeprefix('tie: ')}</dd>" in page
    assert "Tie: the ranking does not tell 10" in page


def test_help_cold_start_avoids_heavy_imports() -> None:
    code = (
        "import sys; from stepframe.cli import build_parser; build_parser();"
        "heavy = ('obspy', 'xarray', 'numba', 'matplotlib', 'pandas', 'scipy');"
        "print(sorted(m for m in heavy if m in sys.modules))"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60
    )
    assert result.stdout.strip() == "[]"


def test_reader_warning_is_one_line(data_dir: Path, tmp_path: Path) -> None:
    """A header peak disagreeing with the data: the record is read, the warning is one line."""
    import gzip

    source = data_dir / "formats" / "esm" / "HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz"
    lines = gzip.decompress(source.read_bytes()).decode("latin-1").splitlines()
    assert "0.300022" in lines[39]
    lines[39] = lines[39].replace("0.300022", "0.400022")
    edited = tmp_path / "edited.ASC"
    edited.write_text("\n".join(lines) + "\n", encoding="latin-1")
    completed = run_cli("records", "info", str(edited), "--json")
    assert completed.returncode == 0, completed.stderr
    assert json.loads(completed.stdout)[0]["npts"] > 0
    warning_lines = completed.stderr.strip().splitlines()
    assert len(warning_lines) == 1
    assert warning_lines[0].startswith("stepframe: warning: ")
    assert "edited.ASC:40: PGA_CM/S^2: header peak" in warning_lines[0]


def test_the_command_tree_builds_whatever_module_is_imported_first() -> None:
    """GROUPS names modules instead of importing them: no import-order dependence."""
    for first in (
        "stepframe.commands.records",
        "stepframe.commands.stochastic",
        "stepframe.commands.store",
        "stepframe.commands.structure",
    ):
        probe = (
            f"import {first}; from stepframe.cli import build_parser; "
            "print(sorted(build_parser()._subparsers._group_actions[0].choices))"
        )
        done = subprocess.run(
            [sys.executable, "-c", probe], capture_output=True, text=True, check=True
        )
        assert done.stdout.strip() == (
            "['demo', 'records', 'report', 'run', 'select', 'stochastic', 'store', 'structure']"
        )


def test_the_cached_parser_keeps_no_state_between_runs() -> None:
    """build_parser is built once per process: a repeated option's list from one parse must not
    reach the next (argparse's append action copies the default list)."""
    from stepframe.cli import build_parser

    parser = build_parser()
    assert build_parser() is parser
    select = ["select", "--frame", "f.toml", "-n", "3", "-o", "picks"]
    first = parser.parse_args([*select, "--exclude", "RSN1", "--exclude", "RSN2"])
    second = parser.parse_args(select)
    assert first.exclude == ["RSN1", "RSN2"]
    assert second.exclude == []
