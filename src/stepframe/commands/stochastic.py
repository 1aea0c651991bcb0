"""``stepframe stochastic``: command-line front end of :mod:`stepframe.stochastic`."""

from __future__ import annotations

from typing import Any


def register(subparsers: Any) -> None:
    """Add the ``stochastic`` commands: fit/features and amplify."""
    from stepframe.commands import stochastic_amplify, stochastic_fit

    stochastic_fit.register(subparsers)
    stochastic_amplify.register(subparsers)
