"""Acceleration units accepted by the readers and their factors to m/s².

Standard gravity (9.80665 m/s², CGPM 1901) converts records given in g. The paper's worked
examples use g = 9.81; functions reproducing them take ``g`` as a parameter instead.
"""

from __future__ import annotations

from stepframe.errors import InputError

STANDARD_GRAVITY_M_S2 = 9.80665

#: Factor that multiplies a value in the named unit to give m/s².
ACCELERATION_UNITS_TO_M_S2: dict[str, float] = {
    "g": STANDARD_GRAVITY_M_S2,
    "m/s2": 1.0,
    "cm/s2": 0.01,
    "gal": 0.01,
    "mm/s2": 0.001,
    # SAC's IACC files are in nm/s²; no strong-motion format uses it for values in g ranges.
    "nm/s2": 1e-9,
}

_ALIASES = {
    "m/s**2": "m/s2",
    "m/s^2": "m/s2",
    "m/sec2": "m/s2",
    "m/sec/sec": "m/s2",
    "cm/s**2": "cm/s2",
    "cm/s^2": "cm/s2",
    "cm/sec2": "cm/s2",
    "cm/sec/sec": "cm/s2",
    "cm/sec^2": "cm/s2",
    "gals": "gal",
    "mm/s**2": "mm/s2",
    "mm/s^2": "mm/s2",
    "mm/sec2": "mm/s2",
    "mm/sec/sec": "mm/s2",
    "g's": "g",
    "m/s/s": "m/s2",
    "cm/s/s": "cm/s2",
    "mm/s/s": "mm/s2",
    "cm/sec**2": "cm/s2",
    "m/sec**2": "m/s2",
    "nm/s**2": "nm/s2",
    "nm/s^2": "nm/s2",
}


def units_help() -> str:
    """The accepted unit names for a help text, from :data:`ACCELERATION_UNITS_TO_M_S2`
    (``"g, m/s2, cm/s2 (= gal), mm/s2, nm/s2"``): a name with the factor of an earlier one is
    given as its synonym."""
    named: dict[float, list[str]] = {}
    for name, factor in ACCELERATION_UNITS_TO_M_S2.items():
        named.setdefault(factor, []).append(name)
    return ", ".join(
        names[0] + (f" (= {', '.join(names[1:])})" if len(names) > 1 else "")
        for names in named.values()
    )


def normalize_units(units: str) -> str:
    """Canonical name of an acceleration unit (``"cm/sec/sec"`` → ``"cm/s2"``).

    Raises
    ------
    InputError
        If the unit is not an acceleration unit the project knows.
    """
    key = units.strip().lower()
    key = _ALIASES.get(key, key)
    if key not in ACCELERATION_UNITS_TO_M_S2:
        known = ", ".join(ACCELERATION_UNITS_TO_M_S2)
        raise InputError(f"unknown acceleration unit {units!r}, expected one of {known}")
    return key


def factor_to_m_s2(units: str) -> float:
    """Factor converting acceleration in ``units`` (see :func:`normalize_units`) to m/s²."""
    return ACCELERATION_UNITS_TO_M_S2[normalize_units(units)]
