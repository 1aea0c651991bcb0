"""core.options.add_fields: options derived from dataclass fields (core.options.option)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import pytest

from stepframe.commands import Parser, UserError
from stepframe.core.options import add_fields, fields_given, option


@dataclass(frozen=True)
class Demo:
    amplitude_g: float = option(help="amplitude [g]", kind="non_negative", metavar="R")
    periods: int = option(100, "periods (default %(default)s), 100 % of them", kind="positive_int")
    mode: Literal["fast", "exact"] = "fast"
    verbose: bool = option(False, "say more", kind="flag")
    omegas_rad_s: tuple[float, ...] | None = option(
        None, "frequencies [rad/s]", kind="positive_floats", flag="--omega-rad-s"
    )


def _parser() -> Parser:
    parser = Parser(prog="demo")
    add_fields(parser, Demo)
    return parser


def test_given_options_lay_over_the_dataclass_defaults() -> None:
    args = _parser().parse_args(["--amplitude-g", "0.3", "--omega-rad-s", "10,16", "--verbose"])
    given = fields_given(args, Demo)
    assert given == {"amplitude_g": 0.3, "verbose": True, "omegas_rad_s": [10.0, 16.0]}
    assert Demo(**given) == Demo(0.3, 100, "fast", True, [10.0, 16.0])  # type: ignore[arg-type]


def test_help_types_choices_and_required() -> None:
    parser = _parser()
    text = parser.format_help()
    assert "periods (default 100), 100 % of them" in text
    assert "{fast,exact}" in text and "--omega-rad-s OMEGAS_RAD_S" in text
    with pytest.raises(UserError, match="--amplitude-g"):
        parser.parse_args([])  # no default: required
    with pytest.raises(UserError, match="expected a finite number ≥ 0"):
        parser.parse_args(["--amplitude-g", "-1"])
    with pytest.raises(UserError, match="invalid choice"):
        parser.parse_args(["--amplitude-g", "1", "--mode", "slow"])


def test_an_unknown_kind_is_refused() -> None:
    with pytest.raises(ValueError, match="option kind 'positive_number'"):
        option(1.0, "x", kind="positive_number")


@dataclass(frozen=True)
class Run:
    force: list[str] | None = option(None, "recompute a stage", kind="repeated", metavar="STAGE")
    jobs: int | None = option(None, "worker processes", kind="int", metavar="N")


def test_option_rows_sit_among_the_fields_and_are_not_read_back() -> None:
    parser = Parser(prog="run")
    add_fields(parser, Run, ["jobs", ("--template", bool, None, "print a template"), "force"])
    text = parser.format_help()
    assert text.index("--jobs N") < text.index("--template") < text.index("--force STAGE")
    args = parser.parse_args(["--force", "fit", "--force", "select", "--template"])
    assert args.template is True
    names = ["jobs", ("--template", bool, None, "print a template"), "force"]
    assert fields_given(args, names) == {"force": ["fit", "select"]}
    assert Run(**fields_given(args, Run)) == Run(force=["fit", "select"])
