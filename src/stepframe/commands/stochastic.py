"""`stepframe stochastic`: command-line front end of :mod:`stepframe.stochastic`."""

from __future__ import annotations

from typing import Any


def register(subparsers: Any) -> None:
    """Add the `stochastic` commands to ``subparsers``."""
