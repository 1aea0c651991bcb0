"""Reports: self-contained HTML documents of a site's amplification and of a record selection.

Each report is one HTML file that needs no network (inline figures and style) plus the CSV/JSON of
every number it shows in ``<stem>_files/`` beside it, with its provenance. Library entry points:
:func:`write_amplification_report` and :func:`write_selection_report`. The names below are
imported when first used (module ``__getattr__``): the command line reads the light
:mod:`stepframe.pipeline.reports.make` options without loading pandas or matplotlib.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from stepframe._lazy import lazy_exports

if TYPE_CHECKING:
    from stepframe.pipeline.reports.amplification import (
        AmplificationOptions,
        write_amplification_report,
    )
    from stepframe.pipeline.reports.provenance import Provenance, collect_provenance

__all__ = [
    "AmplificationOptions",
    "Provenance",
    "collect_provenance",
    "write_amplification_report",
]

__getattr__ = lazy_exports(
    __name__,
    {
        "AmplificationOptions": "stepframe.pipeline.reports.amplification",
        "write_amplification_report": "stepframe.pipeline.reports.amplification",
        "Provenance": "stepframe.pipeline.reports.provenance",
        "collect_provenance": "stepframe.pipeline.reports.provenance",
    },
)
