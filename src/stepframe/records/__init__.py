"""Records: reading accelerograms, processing, intensity measures and catalogues.

The record type is an ``obspy.Trace`` in m/s² with ``stats.stepframe`` metadata (see
:mod:`stepframe.records.trace`). Submodules import obspy lazily, and this package imports its
submodules on first use, so the light :mod:`stepframe.records.formats` names (used by
``stepframe --help``) cost no numpy import.
"""

from __future__ import annotations

import sys
import types
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from stepframe.records.catalog import catalog
    from stepframe.records.io import read

__all__ = ["catalog", "read"]


class _Records(types.ModuleType):
    """The package, whose ``catalog`` attribute stays the function.

    Importing the submodule ``stepframe.records.catalog`` sets the package's ``catalog`` attribute
    to the module; this property keeps the public name bound to the function instead.
    """

    @property
    def catalog(self) -> Any:
        from stepframe.records.catalog import catalog as function

        return function

    @catalog.setter
    def catalog(self, value: Any) -> None:
        # The import system binds the submodule here; the property already resolves the name.
        pass

    @property
    def read(self) -> Any:
        from stepframe.records.io import read as function

        return function


sys.modules[__name__].__class__ = _Records
