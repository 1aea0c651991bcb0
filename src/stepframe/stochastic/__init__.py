"""Stochastic: evolutionary spectra, the Beck-Papadimitriou model, mean-square response.

Modules: :mod:`~stepframe.stochastic.model` (eqs. 6.10-6.12), :mod:`~stepframe.stochastic.spectra`
(evolutionary spectra), :mod:`~stepframe.stochastic.features` and :mod:`~stepframe.stochastic.fit`
(parameters of a record), :mod:`~stepframe.stochastic.synthetic` (synthetic motions),
:mod:`~stepframe.stochastic.catalog_features`, :mod:`~stepframe.stochastic.correlation` and
:mod:`~stepframe.stochastic.mean_square` (eqs. 6.1-6.9), :mod:`~stepframe.stochastic.amplification`
(eqs. 6.13-6.19).
"""

from stepframe.stochastic.model import GroundMotionModel

__all__ = ["GroundMotionModel"]
