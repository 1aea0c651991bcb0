"""Stochastic: evolutionary spectra, the Beck-Papadimitriou model, mean-square response.

Modules: :mod:`~stepframe.stochastic.model` (eqs. 6.10-6.12),
:mod:`~stepframe.stochastic.transforms` (STFT and wavelet power),
:mod:`~stepframe.stochastic.spectra` (evolutionary spectra),
:mod:`~stepframe.stochastic.features` and :mod:`~stepframe.stochastic.fit` (parameters of a
record), :mod:`~stepframe.stochastic.synthetic` (synthetic motions),
:mod:`~stepframe.stochastic.catalog_features`, :mod:`~stepframe.stochastic.correlation` and
:mod:`~stepframe.stochastic.mean_square` (eqs. 6.1-6.9), :mod:`~stepframe.stochastic.amplification`
(eqs. 6.13-6.19), :mod:`~stepframe.stochastic.methods` (names of the method families) and
:mod:`~stepframe.stochastic.plots`. The names below are imported when first used (module
``__getattr__``), so importing this package does not import numpy.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from stepframe._lazy import lazy_exports

if TYPE_CHECKING:
    from stepframe.stochastic.amplification import (
        ResponseAmplification,
        response_amplification,
        spectral_ratio_eq_6_18,
    )
    from stepframe.stochastic.catalog_features import catalog_features
    from stepframe.stochastic.features import (
        FREQUENCY_ESTIMATORS,
        RecordFeatures,
        record_features,
    )
    from stepframe.stochastic.fit import FitResult, fit_model
    from stepframe.stochastic.mean_square import METHODS, MeanSquareResult, mean_square_response
    from stepframe.stochastic.model import GroundMotionModel
    from stepframe.stochastic.spectra import SPECTRUM_METHODS, evolutionary_spectrum
    from stepframe.stochastic.synthetic import synthetic_motions

_EXPORTS = {
    "GroundMotionModel": "stepframe.stochastic.model",
    "evolutionary_spectrum": "stepframe.stochastic.spectra",
    "SPECTRUM_METHODS": "stepframe.stochastic.spectra",
    "record_features": "stepframe.stochastic.features",
    "RecordFeatures": "stepframe.stochastic.features",
    "FREQUENCY_ESTIMATORS": "stepframe.stochastic.features",
    "fit_model": "stepframe.stochastic.fit",
    "FitResult": "stepframe.stochastic.fit",
    "synthetic_motions": "stepframe.stochastic.synthetic",
    "catalog_features": "stepframe.stochastic.catalog_features",
    "mean_square_response": "stepframe.stochastic.mean_square",
    "MeanSquareResult": "stepframe.stochastic.mean_square",
    "METHODS": "stepframe.stochastic.mean_square",
    "response_amplification": "stepframe.stochastic.amplification",
    "ResponseAmplification": "stepframe.stochastic.amplification",
    "spectral_ratio_eq_6_18": "stepframe.stochastic.amplification",
}


__getattr__ = lazy_exports(__name__, _EXPORTS)


__all__ = [
    "FREQUENCY_ESTIMATORS",
    "METHODS",
    "SPECTRUM_METHODS",
    "FitResult",
    "GroundMotionModel",
    "MeanSquareResult",
    "RecordFeatures",
    "ResponseAmplification",
    "catalog_features",
    "evolutionary_spectrum",
    "fit_model",
    "mean_square_response",
    "record_features",
    "response_amplification",
    "spectral_ratio_eq_6_18",
    "synthetic_motions",
]
