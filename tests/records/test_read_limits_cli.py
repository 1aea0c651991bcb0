"""The read limits (peak above 100 g, files above 256 MiB) are overridable from every command that
reads records through the shared record options, `--max-abs-g G` and `--max-file-mb MB`, and
each refusal names the option that overrides it (issue 16)."""

from __future__ import annotations

import contextlib
import io
import json
import shutil
from pathlib import Path

import numpy as np
import pytest

from stepframe.cli import main
from stepframe.structure.frame_file import frame_template

DATA = Path(__file__).parents[1] / "data"
AT2 = DATA / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"
V2_GZ = DATA / "formats" / "dmg" / "CE58667.V2.gz"


def _run(words: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(words)
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def strong(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """RSN 8883's 360 component scaled to a peak of 150 g, as (time [s], acceleration [g])."""
    lines = AT2.read_text().splitlines()[4:]
    values = np.array([float(w) for x in lines for w in x.split()])[:4000]
    values *= 150.0 / np.max(np.abs(values))
    time_s = np.arange(values.size) * 0.005
    path = tmp_path_factory.mktemp("limits") / "strong.txt"
    body = "\n".join(f"{t:.3f} {v!r}" for t, v in zip(time_s, values.tolist(), strict=True))
    path.write_text("Time (s)  Acceleration (g)\n" + body + "\n")
    return path


def _refused(words: list[str], option: str) -> str:
    code, out, err = _run(words)
    assert code == 2, err
    assert out == "" and err.startswith("stepframe: error: ") and err.count("\n") == 1
    assert option in err, err
    return err


def test_records_info_peak_limit(strong: Path) -> None:
    err = _refused(["records", "info", str(strong), "--json"], "--max-abs-g G")
    assert f"{strong}: peak 150 g, expected at most 100 g" in err
    code, out, err = _run(["records", "info", str(strong), "--max-abs-g", "200", "--json"])
    assert code == 0, err
    (row,) = json.loads(out)
    assert row["pga_g"] == pytest.approx(150.0, rel=1e-12)
    # a lower limit than the default refuses a record the default accepts
    err = _refused(["records", "info", str(AT2), "--max-abs-g", "0.01"], "--max-abs-g G")
    assert "expected at most 0.01 g" in err


@pytest.mark.parametrize(
    "command",
    [
        ["records", "spectrum", "--periods-s", "0.1,1"],
        ["stochastic", "fit"],
        ["stochastic", "amplify", "--f0-hz", "2", "--n-steps", "300", "--record"],
    ],
)
def test_every_reading_command_takes_the_peak_limit(strong: Path, command: list[str]) -> None:
    words = [*command, str(strong)]
    _refused([*words, "--json"], "--max-abs-g G")
    code, out, err = _run([*words, "--max-abs-g", "200", "--json"])
    assert code == 0, err
    assert json.loads(out)


def test_structure_simulate_takes_the_peak_limit(
    strong: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("FRAME.toml").write_text(frame_template(), encoding="utf-8")
    words = ["structure", "simulate", "--frame", "FRAME.toml", str(strong), "--tail-s", "1"]
    _refused([*words, "--json"], "--max-abs-g G")
    code, out, err = _run([*words, "--max-abs-g", "200", "--scale", "0.001", "--json"])
    assert code == 0, err
    data = json.loads(out)
    assert data["pga_m_s2"] == pytest.approx(0.001 * 150 * 9.80665, rel=1e-9)


def test_features_folder_takes_the_peak_limit(strong: Path, tmp_path: Path) -> None:
    folder = tmp_path / "records"
    folder.mkdir()
    shutil.copy(strong, folder)
    words = ["stochastic", "features", str(folder), "--jobs", "1", "-o", str(tmp_path / "f.csv")]
    code, _, err = _run([*words, "--json"])
    assert code == 2 and "0 components read, 1 failure (the first: " in err  # its one refused
    code, out, err = _run([*words, "--max-abs-g", "200", "--json"])
    assert code == 0, err
    assert json.loads(out)["n_components"] == 1


def test_file_size_limit(tmp_path: Path) -> None:
    size_mib = AT2.stat().st_size / 1024**2  # 0.24 MiB
    err = _refused(["records", "info", str(AT2), "--max-file-mb", "0.1"], "--max-file-mb MB")
    assert f"{AT2}: {AT2.stat().st_size} bytes ({size_mib:.4g} MiB)" in err
    assert "at most 104857 bytes (0.1 MiB" in err
    code, out, err = _run(["records", "info", str(AT2), "--max-file-mb", "1", "--json"])
    assert code == 0, err
    # a gzip file small enough whose content is not: the limit applies to what it holds
    assert V2_GZ.stat().st_size < 0.5 * 1024**2
    err = _refused(["records", "info", str(V2_GZ), "--max-file-mb", "0.5"], "--max-file-mb MB")
    assert "decompresses to more than" in err
    code, out, err = _run(["records", "info", str(V2_GZ), "--max-file-mb", "1", "--json"])
    assert code == 0, err
    assert len(json.loads(out)) == 3  # its three components
    # the other commands pass it on too
    err = _refused(["stochastic", "fit", str(AT2), "--max-file-mb", "0.1"], "--max-file-mb MB")
    assert "bytes (0.2379 MiB)" in err


@pytest.mark.parametrize(
    ("words", "message"),
    [
        (["--max-abs-g", "0"], "not positive"),
        (["--max-abs-g", "nan"], "not positive"),
        (["--max-file-mb", "-1"], "not positive"),
        (["--max-file-mb", "x"], "not a number"),
        (["--max-abs-g", "200", "--max-abs-g", "300"], "given twice"),
    ],
)
def test_limit_options_are_checked(words: list[str], message: str) -> None:
    code, out, err = _run(["records", "info", str(AT2), *words])
    assert code == 2 and out == "" and message in err
