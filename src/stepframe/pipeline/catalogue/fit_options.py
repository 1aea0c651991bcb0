"""How a record is fitted: :class:`FitOptions` (light: the command line builds its options here).

Kept apart from :mod:`stepframe.pipeline.catalogue.fitted` (which imports numpy) so that ``stepframe
--help`` can derive ``stochastic fit`` and ``features`` options from the fields without loading
the numerical stack.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from stepframe.core.options import option
from stepframe.errors import InputError
from stepframe.stochastic.methods import FREQUENCY_METHOD_NAMES

if TYPE_CHECKING:
    from stepframe.stochastic.features import FrequencyEstimator, TimeOrigin
    from stepframe.stochastic.methods import FrequencyMethod


@dataclass(frozen=True)
class FitOptions:
    """How a record is fitted (the options of ``stepframe stochastic fit`` and ``features``).

    ``frequency`` also accepts an estimator function (see docs/architecture.md).
    """

    frequency: FrequencyMethod | FrequencyEstimator = option(
        "zero-crossing",
        "ω_g(t) estimator, fast to dear (default zero-crossing)",
        choices=FREQUENCY_METHOD_NAMES,
    )
    t0: TimeOrigin = option(
        "auto",
        "time origin of eqs. 6.10-6.11: auto (default: the picked P onset when the pick is "
        "reliable, else the record start; t0_source says which), start, or p-pick (the pick "
        "whatever its confidence)",
        choices=("auto", "start", "p-pick"),
    )
    window_s: float = option(
        2.0, "STFT window and smoothing length [s] (default 2)", kind="positive", metavar="S"
    )
    omega_max_rad_s: float | None = option(
        None,
        "highest frequency of interest [rad/s]: error if above the record's Nyquist",
        kind="positive",
        metavar="W",
    )
    bootstrap: int = option(0, "bootstrap refits", kind="int", metavar="N")
    seed: int | None = option(None, "seed of the bootstrap", kind="int")
    corner: bool = option(
        False,
        "also estimate the source corner ω_c [rad/s] (indicative: biased 40-50 % low)",
        kind="flag",
    )

    def __post_init__(self) -> None:
        if self.bootstrap < 0:
            raise InputError(f"--bootstrap {self.bootstrap}, expected an integer ≥ 0")


__all__ = ["FitOptions"]
