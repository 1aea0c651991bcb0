"""Records: reading accelerograms, processing, intensity measures and catalogues.

The record type is an ``obspy.Trace`` in m/s² with ``stats.stepframe`` metadata (see
:mod:`stepframe.records.trace`). The names below are imported when first used (module
``__getattr__``), so importing this package stays cheap; submodules import obspy lazily.
"""

from __future__ import annotations

import sys
import types
from typing import TYPE_CHECKING, Any

from stepframe._lazy import lazy_exports

if TYPE_CHECKING:
    from stepframe.records.catalog import catalog, intensity_table, write_catalog
    from stepframe.records.examples import fema_p695
    from stepframe.records.intensity import intensity_measures, trace_intensity_measures
    from stepframe.records.io import read
    from stepframe.records.plots import response_spectra_figure
    from stepframe.records.processing import process
    from stepframe.records.rotd import RotDSpectrum, rotd_spectrum
    from stepframe.records.spectra import ResponseSpectrum, response_spectrum
    from stepframe.records.trace import make_trace

_EXPORTS = {
    "read": "stepframe.records.io",
    "make_trace": "stepframe.records.trace",
    "process": "stepframe.records.processing",
    "intensity_measures": "stepframe.records.intensity",
    "trace_intensity_measures": "stepframe.records.intensity",
    "ResponseSpectrum": "stepframe.records.spectra",
    "response_spectrum": "stepframe.records.spectra",
    "RotDSpectrum": "stepframe.records.rotd",
    "rotd_spectrum": "stepframe.records.rotd",
    "intensity_table": "stepframe.records.catalog",
    "write_catalog": "stepframe.records.catalog",
    "fema_p695": "stepframe.records.examples",
    "response_spectra_figure": "stepframe.records.plots",
}


__getattr__ = lazy_exports(__name__, _EXPORTS)


class _Records(types.ModuleType):
    """The package, whose ``catalog`` attribute stays the function.

    ``catalog`` shares its name with its submodule: importing ``stepframe.records.catalog`` sets
    the package's ``catalog`` attribute to the module. This property keeps the public name bound
    to the function, so it too can be imported lazily (``stepframe --help`` imports no numpy).
    """

    @property
    def catalog(self) -> Any:
        from stepframe.records.catalog import catalog as function

        return function

    @catalog.setter
    def catalog(self, value: Any) -> None:
        # The import system binds the submodule here; the property already resolves the name.
        pass


sys.modules[__name__].__class__ = _Records


__all__ = [
    "ResponseSpectrum",
    "RotDSpectrum",
    "catalog",
    "fema_p695",
    "intensity_measures",
    "intensity_table",
    "make_trace",
    "process",
    "read",
    "response_spectra_figure",
    "response_spectrum",
    "rotd_spectrum",
    "trace_intensity_measures",
    "write_catalog",
]
