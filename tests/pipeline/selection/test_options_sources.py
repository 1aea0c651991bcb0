"""selection_options (a [selection] file under the command line) and design_displacement_m."""

from __future__ import annotations

from pathlib import Path

import pytest

from stepframe.errors import InputError
from stepframe.pipeline.dynamics.design import DESIGN_TEMPLATE, design_displacement_m
from stepframe.pipeline.selection.options import SelectionOptions, selection_options


def test_overrides_lay_over_the_file_and_the_defaults(tmp_path: Path) -> None:
    path = tmp_path / "sel.toml"
    path.write_text('[selection]\nn = 4\nscale = "psa-at-t1"\nconfirm = true\nseed = 7\n')
    options = selection_options(str(path), {"seed": 3, "magnitude_min": 6})
    assert options == SelectionOptions(
        n=4, scale="psa-at-t1", confirm=True, seed=3, magnitude_min=6.0
    )
    assert selection_options(None, {"n": 2}) == SelectionOptions(n=2)


def test_a_file_without_the_table_is_one_error(tmp_path: Path) -> None:
    path = tmp_path / "sel.toml"
    path.write_text("[other]\nn = 4\n")
    with pytest.raises(InputError, match="no \\[selection\\] table"):
        selection_options(str(path), {})


def test_design_displacement_of_the_template_is_example_1(tmp_path: Path) -> None:
    path = tmp_path / "pier.toml"
    path.write_text(DESIGN_TEMPLATE)
    # Example 1 recomputed (tests/structure/test_structure_design_cli.py, docs/paper-notes.md).
    assert design_displacement_m(path) == pytest.approx(0.7373367, abs=1e-7)
