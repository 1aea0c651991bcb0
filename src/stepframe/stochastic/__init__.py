"""Stochastic: evolutionary spectra, the Beck-Papadimitriou model, mean-square response."""

from stepframe.stochastic.model import GroundMotionModel

__all__ = ["GroundMotionModel"]
