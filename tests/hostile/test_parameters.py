"""Hostile parameters: every bad frame-file value, frame file and option gives exit 2, one line.

``{record}`` is a real AT2 file, ``{frame}`` the frame template; a frame edit replaces one key's
line of the template (or the whole file's bytes). Each case runs in-process through
``stepframe.cli.main`` and must end in exit 2 with exactly one ``stepframe: error:`` line: no
traceback, no MemoryError, no exit 0 with NaN.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

RECORD = Path(__file__).parents[1] / "data" / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"

#: (frame key, value written in TOML) pairs: each must be refused by ``structure simulate``.
FRAME_EDITS: tuple[tuple[str, str], ...] = (
    ("xi_1", "1" + "0" * 400),
    ("xi_1", "5"),
    ("xi_1", "-0.1"),
    ("xi_1", "nan"),
    ("xi_1", "inf"),
    ("xi_1", '"five"'),
    ("xi_2", "1.0"),
    ("omega_2_rad_s", "1e-300"),
    ("omega_1_rad_s", "1e308"),
    ("omega_1_rad_s", "0"),
    ("omega_1_rad_s", "-6.4"),
    ("p_1", "nan"),
    ("p_2", "1e308"),
    ("gamma_1_m_s2", "-inf"),
    ("w_s_n", "1e400"),
    ("h_r_m", "0"),
    ("l_f_m", "1e-300"),
    ("k_a_n_m", "-1"),
)

#: Whole frame files that are not TOML text.
FRAME_BYTES: tuple[tuple[str, bytes], ...] = (
    ("latin-1", '[frame]\nname = "Pont d\'\xe9t\xe9"\nxi_1 = 0.05\n'.encode("latin-1")),
    ("utf-16", "[frame]\nxi_1 = 0.05\n".encode("utf-16")),
    ("binary", bytes(range(256)) * 4),
    ("empty", b""),
    ("not toml", b"xi_1 == 0.05\n[[[\n"),
)

#: Command lines (after ``stepframe``) that must exit 2 with one line.
COMMANDS: tuple[tuple[str, ...], ...] = (
    ("records", "spectrum", "--periods-s", "1e-300", "{record}"),
    ("records", "spectrum", "--periods-s", "1e308", "{record}"),
    ("records", "spectrum", "--periods-s", "nan", "{record}"),
    ("records", "spectrum", "--periods-s", "-1", "{record}"),
    ("records", "spectrum", "--damping", "5", "{record}"),
    ("records", "spectrum", "--damping", "nan", "{record}"),
    ("stochastic", "fit", "--window-s", "1e308", "{record}"),
    ("stochastic", "fit", "--window-s", "0", "{record}"),
    ("stochastic", "fit", "--window-s", "nan", "{record}"),
    ("stochastic", "fit", "--seed", "-1", "{record}"),
    ("stochastic", "fit", "--bootstrap", "1000000000", "{record}"),
    ("stochastic", "fit", "--bootstrap", "-5", "{record}"),
    ("stochastic", "fit", "--omega-max-rad-s", "inf", "{record}"),
    ("structure", "simulate", "--frame", "{frame}", "--tail-s", "1e308", "{record}"),
    ("structure", "simulate", "--frame", "{frame}", "--tail-s", "nan", "{record}"),
    ("structure", "simulate", "--frame", "{frame}", "--scale", "inf", "{record}"),
    ("structure", "simulate", "--frame", "{frame}", "--scale", "1e308", "{record}"),
    ("stochastic", "amplify", "--fp-hz", "7", "--fs-hz", "3", "--fr-hz", "1", "--xi-p", "0.5",
     "--xi-r", "0.5", "--t-max-s", "5", "--t-dur-s", "20", "--f0-hz", "2", "--n-steps", "1e12"),
    ("stochastic", "amplify", "--fp-hz", "7", "--fs-hz", "3", "--fr-hz", "1", "--xi-p", "0.5",
     "--xi-r", "0.5", "--t-max-s", "5", "--t-dur-s", "20", "--f0-hz", "2",
     "--monte-carlo", "1000000000"),
    ("stochastic", "amplify", "--fp-hz", "7", "--fs-hz", "3", "--fr-hz", "1", "--xi-p", "0.5",
     "--xi-r", "0.5", "--t-max-s", "5", "--t-dur-s", "20", "--f0-hz", "2", "--xi0", "5"),
    ("stochastic", "amplify", "--fp-hz", "nan", "--fs-hz", "3", "--fr-hz", "1", "--xi-p", "0.5",
     "--xi-r", "0.5", "--t-max-s", "5", "--t-dur-s", "20", "--f0-hz", "2"),
    ("stochastic", "amplify", "--fp-hz", "7", "--fs-hz", "3", "--fr-hz", "1", "--xi-p", "0.5",
     "--xi-r", "0.5", "--t-max-s", "1e308", "--t-dur-s", "20", "--f0-hz", "2"),
    ("stochastic", "amplify", "--fp-hz", "7", "--fs-hz", "3", "--fr-hz", "1", "--xi-p", "0.5",
     "--xi-r", "0.5", "--t-max-s", "5", "--t-dur-s", "20", "--f0-hz", "1e-300"),
)  # fmt: skip


def _assert_refused(run: Any) -> None:
    assert run.problem is None, (run.argv, run.problem)
    assert run.status == 2, (run.argv, run.status, run.stdout[:300])


def _edited(template: Path, folder: Path, key: str, value: str) -> Path:
    text = template.read_text()
    pattern = re.compile(rf"^#?\s*{re.escape(key)}\s*=.*$", re.M)
    assert pattern.search(text), key
    path = folder / f"{key}.toml"
    path.write_text(pattern.sub(f"{key} = {value}", text, count=1))
    return path


@pytest.mark.parametrize(
    ("key", "value"), FRAME_EDITS, ids=[f"{k}={v[:12]}" for k, v in FRAME_EDITS]
)
def test_frame_value_refused(
    cli: Callable[..., Any], frame_file: Path, tmp_path: Path, key: str, value: str
) -> None:
    edited = _edited(frame_file, tmp_path, key, value)
    _assert_refused(cli(["structure", "simulate", "--frame", str(edited), str(RECORD)]))


@pytest.mark.parametrize(("name", "content"), FRAME_BYTES, ids=[n for n, _ in FRAME_BYTES])
def test_frame_file_refused(
    cli: Callable[..., Any], tmp_path: Path, name: str, content: bytes
) -> None:
    path = tmp_path / "frame.toml"
    path.write_bytes(content)
    _assert_refused(cli(["structure", "simulate", "--frame", str(path), str(RECORD)]))


@pytest.mark.parametrize(
    "argv", COMMANDS, ids=[" ".join(a[:4]) + " " + a[-1][:8] for a in COMMANDS]
)
def test_option_refused(cli: Callable[..., Any], frame_file: Path, argv: tuple[str, ...]) -> None:
    filled = [a.format(record=RECORD, frame=frame_file) for a in argv]
    _assert_refused(cli(filled))


def test_percent_damping_hint(cli: Callable[..., Any], frame_file: Path, tmp_path: Path) -> None:
    edited = _edited(frame_file, tmp_path, "xi_1", "5")
    run = cli(["structure", "simulate", "--frame", str(edited), str(RECORD)])
    assert run.status == 2 and "0.05" in run.stderr, run.stderr
