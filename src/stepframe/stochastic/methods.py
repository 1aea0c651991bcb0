"""Names of the stochastic method families, without importing them (cheap: typing only).

Each family is a registry ``{name: implementation}`` in the module that implements it:

- ω_g(t) estimators: :data:`stepframe.stochastic.features.FREQUENCY_ESTIMATORS`;
- evolutionary spectra: :data:`stepframe.stochastic.spectra.SPECTRUM_METHODS`;
- mean-square methods: :data:`stepframe.stochastic.mean_square.METHODS`.

The ``Literal`` types below name the registered methods (for type checkers and for the command
line's ``choices``, which must not import numpy to build ``stepframe --help``); a test asserts that
each ``Literal`` and its registry hold the same names. Everywhere a name is accepted, a callable
with the family's signature is accepted too (as ``scipy.integrate.solve_ivp`` accepts a solver
class).
"""

from __future__ import annotations

from typing import Literal, get_args

#: ω_g(t) estimators, fast to dear (the fidelity ladder of DESIGN.md; "multiwindow" costs about
#: what "zero-crossing" does and is the only one that resolves below 2π/window).
FrequencyMethod = Literal["zero-crossing", "ridge", "moment", "wavelet-ridge", "multiwindow"]
#: The default ω_g(t) estimator of the library. "multiwindow" recovers ω_p, ω_s, ω_r and ω_g(t)
#: better on synthetic motions with ω_g from 60 down to 0.5 rad/s at 1.1 × the cost, but the
#: fit's standard errors are calibrated for zero crossings (with multiwindow the truth lies
#: within 2 SE in 80-90 %, not ≥ 90 %, of synthetic records): docs/stochastic-features.md,
#: "Choosing the ω_g(t) estimator".
DEFAULT_FREQUENCY_METHOD: FrequencyMethod = "zero-crossing"
#: Evolutionary-spectrum methods.
SpectrumMethod = Literal["stft", "wavelet", "parametric"]
#: Mean-square response methods, cheap to dear.
MeanSquareMethod = Literal["scalar", "covariance", "monte-carlo"]

FREQUENCY_METHOD_NAMES: tuple[str, ...] = get_args(FrequencyMethod)
SPECTRUM_METHOD_NAMES: tuple[str, ...] = get_args(SpectrumMethod)
MEAN_SQUARE_METHOD_NAMES: tuple[str, ...] = get_args(MeanSquareMethod)

__all__ = [
    "DEFAULT_FREQUENCY_METHOD",
    "FREQUENCY_METHOD_NAMES",
    "MEAN_SQUARE_METHOD_NAMES",
    "SPECTRUM_METHOD_NAMES",
    "FrequencyMethod",
    "MeanSquareMethod",
    "SpectrumMethod",
]
