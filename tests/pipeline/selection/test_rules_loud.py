"""Rules that never fail silently: exclusions, caps, verticals, amplitude filters from records."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import pytest

from stepframe.errors import InputError
from stepframe.pipeline.selection import SelectionOptions
from stepframe.pipeline.selection.band import frame_band
from stepframe.pipeline.selection.filters import apply_filters
from stepframe.pipeline.selection.path import strong_motion_paths
from stepframe.structure.frame import PortalFrame

BASE = {
    "omega_p_rad_s": 40.0,
    "omega_s_rad_s": 15.0,
    "omega_r_rad_s": 8.0,
    "xi_p": 0.3,
    "xi_r": 0.3,
    "t_max_s": 5.0,
    "t_dur_s": 20.0,
    "t0_s": 0.0,
    "plausible": True,
}
#: As ``select --example`` names the example's files, and as a workflow does (absolute paths).
NAMES = [
    "RSN174_IMPVALL_H-E11140.AT2",
    "RSN174_IMPVALL_H-E11230.AT2",
    "/ws/examples/fema-p695/RSN953_NORTHR_MUL009.AT2",
    "/ws/examples/fema-p695/RSN953_NORTHR_MUL279.AT2",
    "/ws/examples/fema-p695/RSN953_NORTHR_UP.AT2",
]


def _table(**columns: list[Any]) -> pd.DataFrame:
    rows = [
        {**BASE, "file": name, "component": name.rsplit("_", 1)[-1].split(".")[0]} for name in NAMES
    ]
    return pd.DataFrame(rows).assign(**columns)


def _filter(table: pd.DataFrame, example4: PortalFrame, **options: Any) -> Any:
    band = frame_band(example4)
    return apply_filters(
        table, SelectionOptions(n=1, **options), band, strong_motion_paths(table, 0.3)
    )


@pytest.mark.parametrize(
    ("entry", "dropped"),
    [
        ("RSN174", [0, 1]),
        ("174", [0, 1]),
        ("rsn953", [2, 3]),
        ("RSN174_IMPVALL_H-E11230.AT2", [1]),
        ("RSN174_IMPVALL_H-E11230", [1]),
        ("fema-p695/RSN953_NORTHR_MUL009.AT2", [2]),
        ("/ws/examples/fema-p695/RSN953_NORTHR_MUL279.AT2", [3]),
        ("./RSN174_IMPVALL_H-E11140.AT2", [0]),
    ],
)
def test_exclusion_matches_the_forms_users_write(
    entry: str, dropped: list[int], example4: PortalFrame
) -> None:
    result, reports = _filter(_table(), example4, exclude=(entry,))
    assert np.flatnonzero(result == "exclude").tolist() == dropped
    assert not any(r.warning for r in reports)


def test_unmatched_exclusion_is_an_error_naming_it(example4: PortalFrame) -> None:
    with pytest.raises(InputError) as error:
        _filter(_table(), example4, exclude=("RSN174", "RSN9999", "nothere.AT2"))
    line = error.value.one_line()
    assert line.startswith("exclude: RSN9999, nothere.AT2 matches no candidate, expected")
    assert "--exclude-unmatched warn" in line


def test_unmatched_exclusion_warns_when_asked(example4: PortalFrame) -> None:
    result, reports = _filter(
        _table(), example4, exclude=("RSN174", "RSN9999"), exclude_unmatched="warn"
    )
    assert (result == "exclude").sum() == 2
    (report,) = [r for r in reports if r.name == "exclude"]
    assert report.warning == "exclude: RSN9999 matched no candidate"
    assert report.to_dict()["warning"] == report.warning


def test_verticals_left_out_unless_asked(example4: PortalFrame) -> None:
    result, _ = _filter(_table(), example4)
    assert result.tolist() == ["", "", "", "", "vertical"]
    kept, reports = _filter(_table(), example4, verticals=True)
    assert kept.tolist() == [""] * 5 and "vertical" not in [r.name for r in reports]
    with pytest.raises(InputError, match="verticals = true with unit = 'record'"):
        SelectionOptions(n=1, verticals=True, unit="record")


def test_a_cap_without_its_information_is_an_error(example4: PortalFrame) -> None:
    with pytest.raises(InputError) as error:
        _filter(_table(), example4, max_per_event=1)
    line = error.value.one_line()
    assert line.startswith("max_per_event = 1 needs each record's event, but none of the 5")
    assert "--metadata CSV with columns file,event" in line
    text = _table(station=["x"] * 5, format=["text"] * 5)  # a text file's station is its name
    with pytest.raises(InputError, match="max_per_station = 2 needs each record's station"):
        _filter(text, example4, max_per_station=2)


def test_partial_metadata_a_record_without_event_is_its_own(example4: PortalFrame) -> None:
    table = _table(event=["Imperial Valley 1979", "Imperial Valley 1979", None, None, None])
    _filter(table, example4, max_per_event=1)
    assert table["event_key"].tolist() == ["Imperial Valley 1979"] * 2 + ["RSN953"] * 3
    assert table["has_event"].tolist() == [True, True, False, False, False]


def _sine(amplitude_m_s2: float, period_s: float, cycles: int, dt_s: float) -> np.ndarray:
    t = np.arange(round(cycles * period_s / dt_s) + 1) * dt_s
    return amplitude_m_s2 * np.sin(2 * np.pi * t / period_s)


def test_amplitude_filters_computed_from_the_records(example4: PortalFrame) -> None:
    # whole cycles of A sin(ωt) sampled at dt: PGA = A; Arias of the linear interpolant (the
    # project's exact integral of a piecewise-linear record) = π/(2g)·(A²/2)·duration·(2 +
    # cos ωdt)/3, since Σa_k² = NA²/2 and Σa_k·a_(k+1) = (NA²/2)·cos ωdt over whole cycles
    dt, period, cycles = 0.005, 0.5, 20
    amplitudes = [0.5, 1.0, 2.0, 4.0, 8.0]
    records = {
        (name, name.rsplit("_", 1)[-1].split(".")[0]): (_sine(a, period, cycles, dt), dt)
        for name, a in zip(NAMES, amplitudes, strict=True)
    }
    table = _table(pga_g=[np.nan, 1.5 / 9.80665, np.nan, np.nan, np.nan])  # one from metadata
    result, reports = apply_filters(
        table,
        SelectionOptions(n=1, pga_min_g=0.12, arias_max_m_s=1.0, verticals=True),
        frame_band(example4),
        strong_motion_paths(table, 0.3),
        (records, None),
    )
    np.testing.assert_allclose(table["pga_g"], [0.5, 1.5, 2.0, 4.0, 8.0] / np.float64(9.80665),
                               rtol=1e-9)  # fmt: skip
    linear = (2 + math.cos(2 * math.pi * dt / period)) / 3
    arias = math.pi / (2 * 9.80665) * np.square(amplitudes) / 2 * cycles * period * linear
    np.testing.assert_allclose(table["arias_m_s"], arias, rtol=1e-9)
    assert result.tolist() == ["pga", "", "arias", "arias", "arias"]
    rules = {r.name: r.rule for r in reports}
    assert rules["pga"] == "pga_g ≥ 0.12 g (1 from metadata, 4 from the records)"
    assert rules["arias"] == "arias_m_s ≤ 1 m/s (0 from metadata, 5 from the records)"


ASCE = {"target_s_ds_g": 1.0, "target_s_d1_g": 0.6}
EC8 = {"target_ec8": "type1", "target_ground": "B", "target_ag_g": 0.3}


@pytest.mark.parametrize(
    ("given", "context", "expected"),
    [
        ({"confirm_onset_ratio": 2.0}, {"confirm": True}, "confirm = true (--confirm)"),
        ({"spectral_weight": 2.0}, ASCE, "a target spectrum: it weighs"),
        ({"target_periods_s": (0.5, 2.0)}, ASCE, "a target spectrum: the misfit's periods"),
        ({"target_damping": 0.1}, EC8, "a target spectrum"),
        ({"target_importance": 1.2}, EC8, "a Eurocode 8 target"),
        ({"distance_metric": "rjb"}, {"distance_max_km": 50.0}, "a distance filter"),
        ({"n_bootstrap": 50}, {"rank_by": "omega_p_over_s_sq"}, "a ranking by a fitted score"),
        ({"scale_min": 0.5}, {"scale": "psa-at-t1"}, "a scaling policy"),
        ({"scale_max": 2.0}, {"scale": "target-mse", **ASCE}, "a scaling policy"),
        ({"seed": 5}, {"confirm": True}, "confirm = true (--confirm) or the bootstrap"),
        ({"seed": 5}, {"rank_by": "omega_p_over_s_sq"}, "confirm = true (--confirm) or the"),
        ({"exclude_unmatched": "warn"}, {"exclude": ("RSN174",)}, "exclude entries"),
        ({"pair_spectrum": "geomean"}, {"unit": "record"}, "unit = 'record' (--unit record)"),
    ],
)
def test_an_option_that_does_nothing_is_an_error(
    given: dict[str, Any], context: dict[str, Any], expected: str
) -> None:
    """Each option away from its default runs in its context and is refused without it (each of
    these ran and changed nothing before); at its default it is never refused."""
    SelectionOptions(n=3, **given, **context)
    name, value = next(iter(given.items()))
    with pytest.raises(InputError) as error:
        SelectionOptions(n=3, **given)
    assert error.value.what.startswith(
        f"{name} = {value!r} does nothing here, expected it only with {expected}"
    )
    SelectionOptions(n=3)  # every default: nothing refused
    # no bootstrap asked for, with a ranking that could not use one: fine
    SelectionOptions(n=3, n_bootstrap=0)
    # a ranking by a fit without its bootstrap draws nothing to seed
    with pytest.raises(InputError, match="seed = 5 does nothing here"):
        SelectionOptions(n=3, rank_by="omega_p_over_s_sq", n_bootstrap=0, seed=5)


def test_options_that_another_option_makes_idle_are_errors() -> None:
    """x_star_fraction beside a given A_max, and exact_budget_s with no automatic prefilter,
    ran and changed nothing (each recorded in the options as if used)."""
    SelectionOptions(n=3, x_star_fraction=0.5)
    with pytest.raises(InputError, match=r"x_star_fraction = 0\.5 does nothing here"):
        SelectionOptions(n=3, x_star_fraction=0.5, a_max_m=0.25)
    SelectionOptions(n=3, exact_budget_s=5.0)
    with pytest.raises(InputError, match=r"exact_budget_s = 5\.0 does nothing here"):
        SelectionOptions(n=3, exact_budget_s=5.0, prefilter="none")


def test_a_component_with_the_catalogue_alone_is_an_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """--component picks a component of each file read; with the embedded catalogue alone no
    file is read, and the run chose among all 100 components as if it had not been given."""
    from stepframe.cli import main
    from stepframe.structure.frame_file import FRAME_TEMPLATE

    frame = tmp_path / "FRAME.toml"
    frame.write_text(FRAME_TEMPLATE)
    out = tmp_path / "picks"
    words = ["select", "--frame", str(frame), "--example", "fema-p695", "-n", "2"]
    assert main([*words, "--component", "MUL009", "-o", str(out)]) == 2
    assert "--component MUL009 with the embedded catalogue alone" in capsys.readouterr().err
    assert not out.exists()


def test_a_metadata_filter_says_how_many_lack_a_value(example4: PortalFrame) -> None:
    """A candidate without a Vs30 fails the Vs30 filter: its report counts them; none with a
    value is an error like a missing column (every candidate dropped as out of range, "vs30 →
    0", when the metadata named the column otherwise)."""
    table = _table(vs30_m_s=[400.0, np.nan, 250.0, np.nan, 760.0])
    dropped, reports = _filter(table, example4, vs30_min_m_s=300.0, verticals=True)
    assert [bool(d) for d in dropped] == [False, True, True, True, False]
    rule = {r.name: r.rule for r in reports}["vs30"]
    assert rule.endswith("(2 without a value)")
    with pytest.raises(InputError, match="filter vs30 needs values in column 'vs30_m_s'"):
        _filter(_table(vs30_m_s=[np.nan] * 5), example4, vs30_min_m_s=300.0, verticals=True)
