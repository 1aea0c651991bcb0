"""One declaration, one check: an option's range serves the library, the command line and the
workflow file with the same words."""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.core.options import (
    Range,
    add_fields,
    arguments_of,
    check_fields,
    option,
    options_from,
    value_type,
)
from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import AmplificationAnalysis
from stepframe.pipeline.engine.stage import params_from_options


@dataclass(frozen=True)
class Toy:
    xi: float = option(0.05, "damping", kind="float", valid=Range(0, 1, low_open=True))
    count: int = option(0, "motions", kind="int", valid=Range(2, also=(0,)))
    limit: float | None = option(None, "a limit [s]", kind="positive", valid=Range(0, 10))
    switch: bool = option(False, "a switch")

    def __post_init__(self) -> None:
        check_fields(self)


@pytest.mark.parametrize(
    ("valid", "inside", "outside", "words"),
    [
        (Range(0, 1, low_open=True, high_open=True), [1e-9, 0.5], [0, 1, math.nan], "in (0, 1)"),
        (Range(100), [100, 1e9], [99.9, math.inf], "≥ 100"),
        (Range(2, also=(0,)), [0, 2, 3], [1, -1], "0 or ≥ 2"),
        (Range(high=5, high_open=True), [-1e300, 4.99], [5, math.inf], "< 5"),
    ],
)
def test_a_range_accepts_what_it_says(
    valid: Range, inside: list[float], outside: list[float], words: str
) -> None:
    assert valid.describe() == words
    assert all(valid.contains(v) for v in inside)
    assert not any(valid.contains(v) for v in outside)


def test_the_check_names_the_field_and_its_range() -> None:
    assert Toy(xi=1.0, count=0).xi == 1.0  # closed at 1
    with pytest.raises(InputError) as error:
        Toy(count=1)
    assert error.value.what == "count = 1, expected 0 or ≥ 2"
    assert error.value.key == "count"
    with pytest.raises(InputError, match=r"limit = 11.0, expected in \[0, 10\]"):
        Toy(limit=11.0)
    with pytest.raises(InputError, match="xi = 'a', expected in"):
        Toy(xi="a")  # type: ignore[arg-type]


def test_the_command_line_names_the_flag() -> None:
    parser = argparse.ArgumentParser()
    add_fields(parser, Toy)
    with pytest.raises(InputError) as error:
        options_from(parser.parse_args(["--xi", "0"]), Toy)
    assert error.value.what == "--xi 0.0, expected in (0, 1]"
    assert options_from(parser.parse_args(["--count", "3"]), Toy) == Toy(count=3)


def test_arguments_reproduce_the_options() -> None:
    assert arguments_of(Toy(count=4, switch=True)) == {"xi": 0.05, "count": 4, "switch": True}


def test_a_workflow_table_has_the_options_keys_types_and_defaults() -> None:
    params = params_from_options(AmplificationAnalysis, ("xi0", "n_steps", "alpha_reading"))
    assert params["n_steps"].type == "int" and params["n_steps"].default == 4000
    assert params["xi0"].type == "float" and params["xi0"].default is None
    assert params["alpha_reading"].choices == ("eq-6-11", "paper")
    assert value_type(Toy, "switch") == "bool"


def test_the_workflow_refuses_at_parse_time_at_the_keys_line(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    workflow = tmp_path / "wf.toml"
    workflow.write_text(
        "[site]\nfp_hz = 7.43\nfs_hz = 3.12\nfr_hz = 1.11\nxi_p = 0.096\nxi_r = 0.655\n"
        "t_max_s = 5\nt_dur_s = 20\n\n[amplification]\nn_frequencies = 5\nn_steps = 50\n\n"
        "[outputs]\namplification = true\n",
        encoding="utf-8",
    )
    assert main(["run", str(workflow), "--dry-run"]) == 2
    err = capsys.readouterr().err
    expected = "[amplification] n_steps = 50, expected in [100, 1000000]"
    assert err == f"stepframe: error: {workflow}:12: {expected}\n"
    assert not (tmp_path / "stepframe-work").exists()


def test_the_same_check_refuses_the_command_line(capsys: pytest.CaptureFixture[str]) -> None:
    site = ["--fp-hz", "7.43", "--fs-hz", "3.12", "--fr-hz", "1.11", "--xi-p", "0.096"]
    code = main(["stochastic", "amplify", *site, "--xi-r", "0.655", "--f0-hz", "1",
                 "--n-steps", "50"])  # fmt: skip
    assert code == 2
    assert capsys.readouterr().err == "stepframe: error: --n-steps 50, expected in [100, 1000000]\n"


def test_a_features_table_value_out_of_range_is_a_parse_error(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    (tmp_path / "records").mkdir()
    (tmp_path / "records" / "a.txt").write_text("0.1\n0.2\n", encoding="utf-8")
    workflow = tmp_path / "wf.toml"
    workflow.write_text(
        '[records]\nfolder = "records"\n[features]\nwindow_s = -2.0\n[outputs]\nfeatures = true\n',
        encoding="utf-8",
    )
    assert main(["run", str(workflow)]) == 2
    err = capsys.readouterr().err
    assert err == (
        f"stepframe: error: {workflow}:4: [features] window_s = -2.0, expected in [0.01, 600]\n"
    )


#: Values for the required fields of the options dataclasses (those without a default).
_REQUIRED = {
    "SimulateOptions": {"frame": "frame.toml"},
    "HarmonicOptions": {"amplitude_g": 0.1, "omega_rad_s": 10.0},
}


def _checked_options_classes() -> list[type]:
    """Every dataclass of the package with a field declared by ``option`` and a
    ``__post_init__`` (those that check themselves; mixins without one are checked as part of
    the classes made of them)."""
    import dataclasses
    import importlib
    import pkgutil

    import stepframe

    found: dict[str, type] = {}
    for info in pkgutil.walk_packages(stepframe.__path__, "stepframe."):
        module = importlib.import_module(info.name)
        for cls in vars(module).values():
            if not (
                isinstance(cls, type)
                and dataclasses.is_dataclass(cls)
                and cls.__module__ == module.__name__
                and hasattr(cls, "__post_init__")
                and any("help" in f.metadata for f in dataclasses.fields(cls))
            ):
                continue
            found[f"{cls.__module__}.{cls.__qualname__}"] = cls
    return [found[name] for name in sorted(found)]


def test_every_options_field_of_a_plain_type_refuses_a_string() -> None:
    """A string where a switch or a number belongs is refused, naming the key, in every options
    dataclass: ``confirm = "false"`` of a ``[selection]`` table ran the confirmation (a
    non-empty string is true) before the type was checked for fields without a range."""
    import dataclasses

    classes = _checked_options_classes()
    names = {cls.__name__ for cls in classes}
    assert {"SelectionOptions", "RunOptions", "AmplificationReportOptions"} <= names
    swept = []
    for cls in classes:
        required = _REQUIRED.get(cls.__name__, {})
        cls(**required)  # the defaults pass
        for f in dataclasses.fields(cls):
            kind = value_type(cls, f.name)
            if kind not in ("bool", "int", "float"):
                continue
            expected = {"bool": "true or false", "int": "an integer", "float": "a number"}[kind]
            with pytest.raises(InputError) as error:
                cls(**{**required, f.name: "false"})
            assert error.value.key == f.name, (cls.__name__, f.name)
            if f.metadata.get("valid") is None:  # else the range's words, as above
                assert error.value.what == f"{f.name} = 'false', expected {expected}"
            swept.append((cls.__name__, f.name))
    # the four switches of the selection, the report's grid_only and plausible_only among them
    for name in ("confirm", "require_plausible", "verticals", "lowest_usable_below_band"):
        assert ("SelectionOptions", name) in swept
    assert ("AmplificationReportOptions", "plausible_only") in swept
    assert ("SelectionOptions", "n") in swept and ("SelectionOptions", "spectral_weight") in swept
