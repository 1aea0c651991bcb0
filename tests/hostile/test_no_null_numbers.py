"""Issue 28: a JSON key documented as a number is a number or absent, never null, at any depth.

Runs whose numbers are undefined on purpose: an IDA that never overturns the frame (no
capacity, no last survival), a design whose formulas have no root (δ_2* of the paper's pier
has none: λ_1 > 1), and a selection's statistics of a constant score (the one conversion,
core/jsonable.py, leaves them out). tests/test_cli_schemas.py walks the documented shapes.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from stepframe.core.jsonable import to_jsonable

RECORD = Path(__file__).parents[1] / "data" / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"


def _nulls(value: Any, path: str = "") -> list[str]:
    if isinstance(value, dict):
        return [p for key, sub in value.items() for p in _nulls(sub, f"{path}.{key}")]
    if isinstance(value, list):
        return [p for sub in value for p in _nulls(sub, f"{path}[]")]
    return [path] if value is None else []


def test_ida_without_an_overturn(cli: Callable[..., Any], frame_file: Path) -> None:
    """Up to 0.05 g the paper's frame stands: the item has no capacity (absent, not null), its
    status says why, exit 0."""
    run = cli(["structure", "ida", "--frame", str(frame_file), "--max-g", "0.05", "--json",
               str(RECORD)])  # fmt: skip
    assert run.problem is None and run.status == 0, run.stderr
    data = json.loads(run.stdout)
    (item,) = data["items"]
    assert "first_overturning" not in item and "last_survival_below" not in item
    assert (item["status"], item["message"]) == ("lower_bound", "no overturning up to 0.05")
    assert _nulls(data) == []


def test_design_fixed_point_without_a_root(cli: Callable[..., Any], tmp_path: Path) -> None:
    """The template pier's δ_2* = (1 - λ_1)/w has no root (λ_1 > 1): its δ, T and multiplier
    are absent; the others are numbers."""
    template = cli(["structure", "design", "--template", "--json"])
    (tmp_path / "pier.toml").write_text(json.loads(template.stdout)["template"])
    run = cli(["structure", "design", "--input", str(tmp_path / "pier.toml"), "--json"])
    assert run.problem is None and run.status == 0, run.stderr
    data = json.loads(run.stdout)
    assert data["constants"]["lambda_1"] > 1
    points = {point["name"]: point for point in data["fixed_points"]}
    assert set(points["delta_2"]) == {"name", "formula", "branch", "stable", "on_branch"}
    assert all(isinstance(points["delta_3"][k], float) for k in ("delta_m", "multiplier"))
    assert [p for p in _nulls(data) if p.startswith((".fixed_points", ".design"))] == []


def test_undefined_statistics_are_left_out() -> None:
    """Spearman's ρ of a constant score and its interval (NaN) in the correlations and the
    tiers of a selection's summary: absent at their depth, the rest kept; NaN in an array
    (a value per period) stays a null in its place."""
    summary = {
        "correlations": [
            {"score": "pga_g", "response": "peak_drift", "spearman": math.nan,
             "low": math.nan, "high": math.nan, "n": 12, "delta": math.nan},
        ],
        "tiers": [{"tier": "n_p_band", "spearman": 0.5, "low": math.nan, "high": 0.7, "n": 9}],
        "psa_g": [0.1, math.nan],
    }  # fmt: skip
    assert to_jsonable(summary) == {
        "correlations": [{"score": "pga_g", "response": "peak_drift", "n": 12}],
        "tiers": [{"tier": "n_p_band", "spearman": 0.5, "high": 0.7, "n": 9}],
        "psa_g": [0.1, None],
    }
