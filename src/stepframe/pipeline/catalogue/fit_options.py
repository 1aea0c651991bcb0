"""How a record is fitted: :class:`FitOptions`, declared once for ``stochastic fit``,
``stochastic features`` and the workflow's ``[features]`` table.

Light (no numpy at import), so that ``stepframe --help`` can derive the options from the fields.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from stepframe.core.options import SEEDS, Range, check_fields, option
from stepframe.errors import InputError
from stepframe.stochastic.methods import DEFAULT_FREQUENCY_METHOD, FREQUENCY_METHOD_NAMES

if TYPE_CHECKING:
    from stepframe.stochastic.features import FrequencyEstimator, TimeOrigin
    from stepframe.stochastic.methods import FrequencyMethod
    from stepframe.stochastic.model import AlphaReading
    from stepframe.stochastic.transforms import FftBackend


#: Most bootstrap refits: each refits the record's features (about a second for a long record),
#: and 1,000 already give percentile intervals to a few per cent.
MAX_BOOTSTRAP = 10_000


@dataclass(frozen=True)
class FitOptions:
    """How a record is fitted (the options of ``stepframe stochastic fit`` and ``features``).

    ``frequency`` also accepts an estimator function (see docs/architecture.md).
    """

    frequency: FrequencyMethod | FrequencyEstimator = option(
        DEFAULT_FREQUENCY_METHOD,
        "ω_g(t) estimator, fast to dear (default %(default)s; docs/stochastic-features.md)",
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
        2.0,
        "STFT window and smoothing length [s] (default 2)",
        kind="positive",
        metavar="S",
        valid=Range(0.01, 600),
    )
    omega_max_rad_s: float | None = option(
        None,
        "highest frequency of interest [rad/s]: error if above the record's Nyquist",
        kind="positive",
        metavar="W",
        valid=Range(0, 1e6, low_open=True),
    )
    fft: FftBackend = option("scipy", "FFT backend (default scipy)", choices=("scipy", "pyfftw"))
    alpha_reading: AlphaReading = option(
        "eq-6-11",
        "α_g ramp of the fit ends at t_dur (eq. 6.11 as printed, default) or at t_max (the paper)",
        choices=("eq-6-11", "paper"),
        flag="--alpha-at-tmax",
    )
    bootstrap: int = option(
        0, "bootstrap refits", kind="int", metavar="N", valid=Range(0, MAX_BOOTSTRAP)
    )
    seed: int | None = option(None, "seed of the bootstrap", kind="int", valid=SEEDS)
    corner: bool = option(
        False,
        "also estimate the source corner ω_c [rad/s] (indicative: biased 40-50 % low)",
        kind="flag",
    )

    def __post_init__(self) -> None:
        check_fields(self)
        # One refit has no spread (its standard error was printed as nan), and a seed drives
        # nothing without refits: both would be silent no-ops.
        if self.bootstrap == 1:
            raise InputError("--bootstrap 1, expected 0 (none) or at least 2 refits")
        if self.seed is not None and self.bootstrap == 0:
            raise InputError(
                f"--seed {self.seed} without --bootstrap, expected --bootstrap N (the seed "
                "drives the bootstrap refits only)"
            )

    def catalog_kwargs(self) -> dict[str, Any]:
        """The estimation options as keyword arguments of
        :func:`stepframe.stochastic.catalog_features.catalog_features` (a catalogue's fit runs
        no bootstrap and no corner)."""
        return {name: getattr(self, name) for name in ESTIMATION_FIELDS}


#: The fields that shape a record's features and fit (the workflow's ``[features]`` table).
ESTIMATION_FIELDS = ("frequency", "t0", "window_s", "fft", "omega_max_rad_s", "alpha_reading")


__all__ = ["ESTIMATION_FIELDS", "FitOptions"]
