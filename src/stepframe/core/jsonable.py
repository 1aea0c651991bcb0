"""JSON-ready values: the one conversion every JSON output goes through.

JSON has no tuples, numpy types, paths, NaN or infinities; :func:`to_jsonable` maps them to what
it has (lists, Python numbers, strings), so ``json.dumps(..., allow_nan=False)`` never fails on a
result's ``to_dict()``. A number that is not finite (undefined, such as Spearman's ρ of a constant
score, or infinite) is left out of its object: a key documented as a number is a number or
absent, never ``null`` (docs/cli.md). In an array, where a position means something (a row of a
table, a value per period), it becomes ``null``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any


def to_jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays, tuples and paths to JSON types; a NaN or ±inf value of a
    mapping is left out, one in a list becomes None.

    Mappings keep their order (keys become strings); anything else that is not a JSON type
    becomes its ``str``.
    """
    if isinstance(value, Mapping):
        items = ((str(k), to_jsonable(v)) for k, v in value.items() if not _non_finite(v))
        return dict(items)
    if isinstance(value, list | tuple):
        return [to_jsonable(v) for v in value]
    if hasattr(value, "tolist") and not isinstance(value, str):
        return to_jsonable(value.tolist())
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if value is None or isinstance(value, bool | int | str):
        return value
    return str(value)


def without_none(items: Iterable[tuple[str, Any]]) -> dict[str, Any]:
    """A dictionary of ``items`` without those whose value is None: the form of a result whose
    numbers may be undefined (a fixed point without a root, a plan without a cut), so that a key
    documented as a number is a number or absent. Also a ``dict_factory`` of
    :func:`dataclasses.asdict`, which applies it at every level."""
    return {key: value for key, value in items if value is not None}


def _non_finite(value: Any) -> bool:
    """A float (Python or numpy scalar) that is NaN or infinite."""
    if hasattr(value, "ndim") and getattr(value, "ndim", 1) == 0 and hasattr(value, "item"):
        value = value.item()
    return isinstance(value, float) and not math.isfinite(value)


__all__ = ["to_jsonable", "without_none"]
