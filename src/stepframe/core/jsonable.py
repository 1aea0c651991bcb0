"""JSON-ready values: the one conversion every JSON output goes through.

JSON has no tuples, numpy types, paths, NaN or infinities; :func:`to_jsonable` maps them to what
it has (lists, Python numbers, strings, ``null``), so ``json.dumps(..., allow_nan=False)`` never
fails on a result's ``to_dict()``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any


def to_jsonable(value: Any) -> Any:
    """Convert numpy scalars/arrays, tuples and paths to JSON types; NaN and ±inf become None.

    Mappings keep their order (keys become strings); anything else that is not a JSON type
    becomes its ``str``.
    """
    if isinstance(value, Mapping):
        return {str(k): to_jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [to_jsonable(v) for v in value]
    if hasattr(value, "tolist") and not isinstance(value, str):
        return to_jsonable(value.tolist())
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if value is None or isinstance(value, bool | int | str):
        return value
    return str(value)


__all__ = ["to_jsonable"]
