"""Lazy exports for package ``__init__`` modules (PEP 562 module ``__getattr__``).

A package lists ``{name: module}`` and sets ``__getattr__ = lazy_exports(__name__, EXPORTS)``:
the module is imported the first time one of its names is used, and the name is then cached in
the package, so ``import stepframe.stochastic`` stays cheap (``stepframe --help`` imports no
numpy).
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping
from typing import Any


def lazy_exports(package: str, exports: Mapping[str, str]) -> Callable[[str], Any]:
    """A module ``__getattr__`` for ``package`` resolving ``exports`` (name → module) on use."""

    def __getattr__(name: str) -> Any:
        if name not in exports:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(exports[name]), name)
        setattr(sys.modules[package], name, value)
        return value

    return __getattr__
