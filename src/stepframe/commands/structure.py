"""``stepframe structure``: command-line front end of :mod:`stepframe.structure`."""

from __future__ import annotations

from typing import Any


def register(subparsers: Any) -> None:
    """Add the ``structure`` commands: design (quasi-dynamic) and frame/simulation commands."""
    from stepframe.commands import structure_design, structure_dynamics, structure_simulate

    structure_design.register(subparsers)
    structure_simulate.register(subparsers)
    structure_dynamics.register(subparsers)
