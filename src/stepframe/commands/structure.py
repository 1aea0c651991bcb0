"""`stepframe structure`: command-line front end of :mod:`stepframe.structure`."""

from __future__ import annotations

from typing import Any


def register(subparsers: Any) -> None:
    """Add the `structure` commands to ``subparsers``."""
