"""Channel names: which components of a record are vertical.

One rule for every job (the selection's grouping of components into records, the catalogue's
record spectra): two copies once disagreed on ``H-UP`` and ``RIO-UP``, vertical to one and
horizontal to the other.
"""

from __future__ import annotations

import re

#: Vertical channels: SEED codes ending in Z (HNZ, BHZ), NIED's UD/UD1/UD2, PEER's and COSMOS's
#: UP/DWN/DOWN/V/VER/VERT (``RSN8883_..._UP``, ``H-UP``), possibly after a prefix and separator.
_VERTICAL = re.compile(
    r"(?:^|[^A-Z])(?:UP|DWN|DOWN|UD[12]?|V|VER|VERT|VERTICAL|Z)$|^[A-Z]{2}Z$", re.IGNORECASE
)


def is_vertical(channel: str) -> bool:
    """Whether a channel name is a vertical component (``HNZ``, ``UD2``, ``UP``, ``H-UP``,
    ``DWN``, ``V``); azimuths (``090``, ``H-E11230``), ``E``/``N``/``EW``/``NS`` and SEED's
    ``HN1``/``HN2`` are horizontal."""
    name = channel.strip().upper()
    return bool(_VERTICAL.search(name)) or name in {"Z", "UD", "UP", "V"}


__all__ = ["is_vertical"]
