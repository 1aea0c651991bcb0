"""Every flag the features and the fit can raise is explained, and bound-pinned fits fail."""

from __future__ import annotations

import math
import re
from pathlib import Path

from stepframe.stochastic import flags as flag_module
from stepframe.stochastic.catalog_features import plausibility
from stepframe.stochastic.flags import FLAGS, describe, implausible

SRC = Path(flag_module.__file__).resolve().parent
DOCS = Path(__file__).resolve().parents[2] / "docs" / "stochastic-features.md"


def _raised_flags() -> set[str]:
    names: set[str] = set()
    for path in SRC.glob("*.py"):
        names.update(re.findall(r'flags\.append\("([a-z_]+)"\)', path.read_text()))
    return names


def test_every_raised_flag_is_in_the_dictionary_and_the_docs() -> None:
    raised = _raised_flags()
    assert {"omega_p_at_bound", "xi_clipped", "duration_at_floor"} <= raised
    assert raised <= set(FLAGS), raised - set(FLAGS)
    docs = DOCS.read_text()
    for flag in FLAGS:
        assert f"`{flag}`" in docs, flag


def test_bound_pinned_fit_is_not_plausible() -> None:
    row = {
        "dt_s": 0.005,
        "omega_p_rad_s": 120.0,
        "omega_s_rad_s": 60.0,
        "omega_r_rad_s": 20.0,
        "flags": "band_limited;omega_p_at_bound",
    }
    reason = plausibility(row, math.pi, None)
    assert reason.startswith("omega_p_at_bound (omega_p at its bound")
    assert "band_limited" not in reason  # a caveat, not a bound
    row["flags"] = "band_limited"
    assert plausibility(row, math.pi, None) == ""
    assert implausible(["omega_c_not_fitted", "xi_clipped", "unknown"]) == ["xi_clipped"]
    assert describe(["xi_clipped"]) == [f"xi_clipped: {FLAGS['xi_clipped'][1]}"]
