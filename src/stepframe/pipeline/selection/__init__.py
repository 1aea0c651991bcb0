"""Record selection by moving resonance (docs/selection.md).

Modules: :mod:`.band` (the frame's band from its period-amplitude law), :mod:`.path` (the
record's ω_g(t) in strong motion), :mod:`.scores`, :mod:`.filters`, :mod:`.spectral` (target
spectrum, misfit, scaling), :mod:`.choose` (greedy plus swaps), :mod:`.confirm` (simulation),
:mod:`.result`, and the entry :func:`select_records`.
"""

from stepframe.pipeline.selection.options import SelectionOptions
from stepframe.pipeline.selection.result import SelectionResult, read_selection
from stepframe.pipeline.selection.run import select_records

__all__ = ["SelectionOptions", "SelectionResult", "read_selection", "select_records"]
