"""The options of reading a record file, as one frozen dataclass (light: no numpy, no obspy).

Every command that reads a record takes these options (DESIGN.md, Command line); the fields
carry their help (:func:`stepframe.core.options.option`), so ``--format``, ``--units``, ...
are declared once. :meth:`RecordReadOptions.read_kwargs` gives the keyword arguments of
:func:`stepframe.records.read`, :meth:`~RecordReadOptions.catalog_kwargs` those of
:func:`stepframe.records.catalog.catalog`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from stepframe.core.options import option
from stepframe.records.formats import format_names_help


@dataclass(frozen=True)
class RecordReadOptions:
    """How to read a record file (None: what the file says, or :func:`~stepframe.records.read`'s
    default).

    Attributes
    ----------
    format
        The format's name; None sniffs the file.
    units
        Units of the values when the file does not state them.
    dt_s
        Sampling interval [s] when the file does not state it.
    inventory
        StationXML file for response removal.
    component
        The channel of a multi-channel file.
    max_abs_g
        Refuse a record whose peak exceeds this [g].
    max_file_mb
        Refuse a record file larger than this [MiB].
    """

    format: str | None = option(
        None, f"file format ({format_names_help()}); default: sniffed", metavar="NAME"
    )
    units: str | None = option(
        None,
        "units of the values if the file does not say: g, m/s2, cm/s2 (= gal), mm/s2",
        metavar="UNIT",
    )
    dt_s: float | None = option(
        None, "sampling interval [s] if the file does not say", kind="float", metavar="DT"
    )
    inventory: str | None = option(None, "StationXML file for response removal", metavar="XML")
    component: str | None = option(None, "which channel of a multi-channel file", metavar="NAME")
    max_abs_g: float | None = option(
        None,
        "refuse a record whose peak exceeds G [g] (default 100: wrong units or damage)",
        kind="positive",
        metavar="G",
    )
    max_file_mb: float | None = option(
        None,
        "refuse a record file larger than MB [MiB] (default 256)",
        kind="positive",
        metavar="MB",
    )

    def read_kwargs(self) -> dict[str, Any]:
        """The keyword arguments of :func:`stepframe.records.read` (the read limits only when
        given: ``read(max_abs_g=None)`` would turn the peak check off)."""
        kwargs: dict[str, Any] = {
            "format": self.format,
            "units": self.units,
            "dt": self.dt_s,
            "inventory": self.inventory,
            "component": self.component,
        }
        if self.max_abs_g is not None:
            kwargs["max_abs_g"] = float(self.max_abs_g)
        if self.max_file_mb is not None:
            kwargs["max_bytes"] = max(1, int(self.max_file_mb * 1024**2))
        return kwargs

    def catalog_kwargs(self) -> dict[str, Any]:
        """The record options of :func:`stepframe.records.catalog.catalog` (the read limits as
        its ``limits``)."""
        kwargs = self.read_kwargs()
        kwargs["dt_s"] = kwargs.pop("dt")
        kwargs["limits"] = {k: kwargs.pop(k) for k in ("max_abs_g", "max_bytes") if k in kwargs}
        return kwargs
