"""Records: reading accelerograms, processing, intensity measures and catalogues.

The record type is an ``obspy.Trace`` in m/s² with ``stats.stepframe`` metadata (see
:mod:`stepframe.records.trace`). Submodules import obspy lazily.
"""

from stepframe.records.catalog import catalog
from stepframe.records.io import read

__all__ = ["catalog", "read"]
