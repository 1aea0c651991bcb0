"""stepframe: seismic analysis of stepping (rocking) frames under nonstationary ground motion.

The package is organised by stage (see DESIGN.md):

- :mod:`stepframe.records`: reading accelerograms, processing, intensity measures, catalogues;
- :mod:`stepframe.stochastic`: evolutionary spectra, the Beck-Papadimitriou ground-motion model,
  mean-square (Liapunov) response and moving-resonance amplification;
- :mod:`stepframe.structure`: frame parameters, quasi-dynamic design, the stepping simulator;
- :mod:`stepframe.pipeline`: the jobs (catalogue, site amplification, selection, dynamics),
  their reports and the workflow engine.

Importing :mod:`stepframe` is cheap on purpose: heavy libraries (obspy, xarray, numba,
matplotlib) are imported by the modules that need them, so the command line starts fast.
"""

from stepframe.errors import InputError, StepframeError

__version__ = "0.1.0"

__all__ = ["InputError", "StepframeError", "__version__"]
