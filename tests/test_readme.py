"""The README's Python example runs as printed and gives the values its last comment states."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from stepframe.structure.frame_file import frame_template

README = Path(__file__).parents[1] / "README.md"


def _python_block() -> str:
    text = README.read_text(encoding="utf-8")
    section = text[text.index("## Python") :]
    match = re.search(r"```python\n(.*?)```", section, flags=re.DOTALL)
    assert match is not None, "README has no Python example"
    return match.group(1)


def test_readme_python_example_runs(data_dir: Path, tmp_path: Path) -> None:
    code = _python_block()
    record = data_dir / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"
    frame = tmp_path / "FRAME.toml"
    frame.write_text(frame_template(), encoding="utf-8")
    code = code.replace('"RSN8883_14383980_13849090.AT2"', repr(str(record)))
    code = code.replace('"FRAME.toml"', repr(str(frame)))
    namespace: dict[str, object] = {}
    exec(compile(code, str(README), "exec"), namespace)
    stated = re.search(r"# ([0-9.]+) m, (True|False)", code)
    assert stated is not None
    summary = namespace["result"].summary  # type: ignore[attr-defined]
    assert summary.peak_abs_x_m == pytest.approx(float(stated.group(1)), abs=5e-5)
    assert str(summary.overturned) == stated.group(2)
    assert len(namespace["stream"]) == 100  # type: ignore[arg-type]
    picks = namespace["picks"].selection  # type: ignore[attr-defined]
    assert picks["rank"].tolist() == [1, 2, 3, 4, 5]
    assert picks["score"].is_monotonic_decreasing
