"""Reports: self-contained HTML documents of a site's amplification and of a record selection.

Each report is one HTML file that needs no network (inline figures and style) plus the CSV/JSON of
every number it shows in ``<stem>_files/`` beside it, with its provenance. Library entry points:
:func:`write_amplification_report` and :func:`write_selection_report`.
"""

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
