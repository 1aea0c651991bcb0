"""Record selection by moving resonance (docs/selection.md).

Modules: :mod:`.band` (the frame's band from its period-amplitude law), :mod:`.path` (the
record's ω_g(t) in strong motion), :mod:`.scores`, :mod:`.filters`, :mod:`.spectral` (target
spectrum, misfit, scaling), :mod:`.choose` (greedy plus swaps), :mod:`.confirm` (simulation),
:mod:`.result`, :mod:`.inputs`, and the entry :func:`select_records`. The entry points are
imported on first use, so that the command line's ``--help`` (which reads :mod:`.names`) stays
fast.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from stepframe.pipeline.selection.options import SelectionOptions
    from stepframe.pipeline.selection.result import SelectionResult, read_selection
    from stepframe.pipeline.selection.run import select_records

__all__ = ["SelectionOptions", "SelectionResult", "read_selection", "select_records"]

_WHERE = {
    "SelectionOptions": "options",
    "SelectionResult": "result",
    "read_selection": "result",
    "select_records": "run",
}


def __getattr__(name: str) -> Any:
    if name in _WHERE:
        import importlib

        module = importlib.import_module(f"stepframe.pipeline.selection.{_WHERE[name]}")
        return getattr(module, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
