"""The HTML machinery every report shares: the document, its figures, its provenance, templates.

Each report is one HTML file that needs no network (inline figures and style) plus the CSV/JSON of
every number it shows in ``<stem>_files/`` beside it, with its provenance
(:mod:`.document`, :mod:`.figures`, :mod:`.provenance`, ``templates/``). The reports themselves
live with their jobs: :func:`stepframe.pipeline.amplification.report.write_amplification_report`
and :func:`stepframe.pipeline.selection.report.write_selection_report`. The names below are
imported when first used (module ``__getattr__``).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from stepframe._lazy import lazy_exports

if TYPE_CHECKING:
    from stepframe.pipeline.reports.provenance import Provenance, collect_provenance

__all__ = ["Provenance", "collect_provenance"]

__getattr__ = lazy_exports(
    __name__,
    {
        "Provenance": "stepframe.pipeline.reports.provenance",
        "collect_provenance": "stepframe.pipeline.reports.provenance",
    },
)
