"""The options of reading a record file, as one frozen dataclass (light: no numpy, no obspy).

Every command that reads a record takes these options (DESIGN.md, Command line); the fields
carry their help (:func:`stepframe.core.options.option`), so ``--format``, ``--units``, ...
are declared once. :meth:`RecordReadOptions.read_kwargs` gives the keyword arguments of
:func:`stepframe.records.read`, :meth:`~RecordReadOptions.catalog_kwargs` those of
:func:`stepframe.records.catalog.catalog`. :class:`RecordSource` adds the embedded example
catalogue (``--example``) as the alternative to a file, and reads either.
"""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any

from stepframe.core.options import Range, check_fields, option
from stepframe.errors import InputError
from stepframe.records.formats import format_names_help
from stepframe.records.formats._header import MAX_DT_S, MIN_DT_S
from stepframe.records.units import units_help

if TYPE_CHECKING:
    from obspy import Stream

#: Embedded example catalogues that ``--example`` names.
EXAMPLE_NAMES = ("fema-p695",)
#: Largest ``--max-file-mb`` [MiB]: 64 GiB, past any accelerogram file (the memory budget
#: refuses a file whose reading would not fit long before).
MAX_FILE_MB = 65536.0
#: Record options that apply to files only, not to the embedded example catalogue.
_FILE_ONLY = (
    "format",
    "units",
    "dt_s",
    "inventory",
    "max_abs_g",
    "max_file_mb",
    "allow_short",
)


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
    allow_short
        Read a record cut short (fewer samples than declared, components missing), flagged in
        ``stats.stepframe.incomplete``, instead of refusing it.
    """

    format: str | None = option(
        None, f"file format ({format_names_help()}); default: sniffed", metavar="NAME"
    )
    units: str | None = option(
        None,
        f"units of the values if the file does not say: {units_help()}",
        metavar="UNIT",
    )
    dt_s: float | None = option(
        None,
        "sampling interval [s] if the file does not say",
        kind="float",
        metavar="DT",
        valid=Range(MIN_DT_S, MAX_DT_S),
    )
    inventory: str | None = option(None, "StationXML file for response removal", metavar="XML")
    component: str | None = option(None, "which channel of a multi-channel file", metavar="NAME")
    max_abs_g: float | None = option(
        None,
        "refuse a record whose peak exceeds G [g] (default 100: wrong units or damage)",
        kind="positive",
        metavar="G",
        valid=Range(0, 1e4, low_open=True),
    )
    max_file_mb: float | None = option(
        None,
        "refuse a record file larger than MB [MiB] (default 256)",
        kind="positive",
        metavar="MB",
        valid=Range(0, MAX_FILE_MB, low_open=True),
    )

    allow_short: bool = option(
        False,
        "read a record cut short (fewer samples than its header declares, or a component "
        "missing) with a warning, flagged in stats.stepframe.incomplete; default: refused",
        kind="flag",
    )

    def __post_init__(self) -> None:
        check_fields(self)

    def given_flags(self, names: tuple[str, ...] | None = None) -> list[str]:
        """The command-line flags of the read options set (not None, not False), of ``names``
        or of all of them: what a command that reads no record must refuse rather than
        ignore."""
        chosen = names if names is not None else tuple(f.name for f in fields(RecordReadOptions))
        return [
            "--" + name.replace("_", "-")
            for name in chosen
            if getattr(self, name) not in (None, False)
        ]

    def read_kwargs(self) -> dict[str, Any]:
        """The keyword arguments of :func:`stepframe.records.read` (the read limits only when
        given: ``read(max_abs_g=None)`` would turn the peak check off; ``allow_short`` only
        when set, so the default reads and cache keys stay as they were)."""
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
        if self.allow_short:
            kwargs["allow_short"] = True
        return kwargs

    def catalog_kwargs(self) -> dict[str, Any]:
        """The record options of :func:`stepframe.records.catalog.catalog` (the read limits as
        its ``limits``)."""
        kwargs = self.read_kwargs()
        kwargs["dt_s"] = kwargs.pop("dt")
        kwargs["limits"] = {k: kwargs.pop(k) for k in ("max_abs_g", "max_bytes") if k in kwargs}
        return kwargs


@dataclass(frozen=True)
class RecordSource(RecordReadOptions):
    """Record files read with the options, or the embedded example catalogue instead.

    Attributes
    ----------
    example
        The embedded example catalogue (:data:`EXAMPLE_NAMES`); ``component`` picks one of its
        components, such as ``MUL009``.
    """

    example: str | None = option(
        None,
        "read the embedded example catalogue instead of a file (100 FEMA P695 components; "
        "--component picks one, such as MUL009)",
        choices=EXAMPLE_NAMES,
    )

    def __post_init__(self) -> None:
        super().__post_init__()
        # The embedded catalogue is not read from a file: of the record options only
        # ``component`` applies to it; any other would be silently ignored.
        if self.example is None:
            return
        given = self.given_flags(_FILE_ONLY)
        if given:
            raise InputError(
                f"{', '.join(given)} with --example {self.example}, expected only --component "
                "with the embedded catalogue (the other record options apply to files)"
            )

    def read(self, path: str | None) -> Stream:
        """The record file ``path`` (or, with ``path`` None, the example) as an
        ``obspy.Stream`` in m/s², a record made from raw counts after the standard processing
        (:func:`stepframe.records.processing.measured`)."""
        if self.example is not None:
            if path is not None:
                message = f"a record file and --example {self.example}, expected one of them"
                raise InputError(message)
            from stepframe.records.examples import example_stream

            return example_stream(self.example, self.component)
        if path is None:
            raise InputError("no record file, expected a record file or --example fema-p695")
        from stepframe.records import read
        from stepframe.records.processing import measured_stream

        # One processing policy for every output a command makes of a record read from raw
        # counts (info, spectrum, fit, simulate...): the processed copy, with a warning.
        return measured_stream(read(path, **self.read_kwargs()))

    def paths(self, paths: list[str]) -> list[str | None]:
        """The files to read, or ``[None]`` (the example, for :meth:`read`) with no file and an
        example."""
        if self.example is not None and not paths:
            return [None]
        if not paths:
            raise InputError("no record file, expected record files or --example fema-p695")
        return list(paths)

    def folder_or_example(self, folder: str | None) -> str | Stream:
        """The folder of record files to walk, or the example catalogue read (exactly one of
        them given)."""
        if (folder is None) == (self.example is None):
            raise InputError("give a folder DIR or --example fema-p695, expected exactly one")
        return folder if folder is not None else self.read(None)

    def name(self, path: str | None) -> str:
        """How a record read from ``path`` is named in results: the path, or the example."""
        if path is not None:
            return path
        return " ".join(["example", str(self.example), *filter(None, [self.component])])
