"""FRAME.toml: the project's one frame file (read by the structure, stochastic and pipeline stages).

Tables (keys carry their units; see docs/frame-file.md)::

    [frame]        xi_1, xi_2 (required); c_r, x_c_m, x_cap_m (optional overrides)
    [physical]     w_s_n, w_col_n, h_r_m, l_f_m, k_a_n_m, k_b_n_m
    [constants]    omega_1_rad_s, omega_2_rad_s, p_1, p_2, gamma_1_m_s2
    [block]        half_width_m, half_height_m (the rigid-block route)
    [conventions]  w_col_convention, l_m, g_m_s2

Two routes: with ``[constants]`` the model constants are taken as given and ``[physical]`` (if
present) only supplies what eqs. 4.10 and 4.15-4.16 need for x_c, C_r and the overturning cap
(:meth:`PortalFrame.from_constants`); without it, all constants follow from ``[physical]``
through eqs. 4.6, 4.7, 4.10 and 4.15-4.16 (:meth:`PortalFrame.from_physical`). A ``[block]``
table instead describes the linearised rigid (Housner) block (:meth:`PortalFrame.housner_block`;
``[frame]`` then takes only c_r, xi_2 and x_cap_m, all optional). Unknown tables and
keys, wrong types and non-physical values raise :class:`InputError` naming the file, the line and
the key.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Mapping
from os import PathLike
from typing import Any

from stepframe.core.io import read_toml
from stepframe.core.options import Range
from stepframe.core.validation import damping_fraction
from stepframe.errors import InputError
from stepframe.structure.frame import W_COL_CONVENTIONS, PortalFrame

#: Allowed keys of each table, with a short description for error messages.
TABLES: dict[str, dict[str, str]] = {
    "frame": {
        "name": "a label (text)",
        "xi_1": "damping ratio of the unstepped phase [-]",
        "xi_2": "damping ratio of the stepped phase [-]",
        "c_r": "velocity ratio at impact (eq. 4.3) [-]",
        "x_c_m": "onset of stepping [m]",
        "x_cap_m": "overturning displacement [m]",
    },
    "physical": {
        "w_s_n": "weight of the superstructure W_S [N]",
        "w_col_n": "total weight of both columns [N]",
        "h_r_m": "height of the superstructure H_r [m]",
        "l_f_m": "distance between footings L_F [m]",
        "k_a_n_m": "axial stiffness of one leg K_a [N/m]",
        "k_b_n_m": "bending stiffness of one leg K_b [N/m]",
    },
    "constants": {
        "omega_1_rad_s": "unstepped frequency [rad/s]",
        "omega_2_rad_s": "stepped-phase frequency parameter [rad/s]",
        "p_1": "participation factor, unstepped [-]",
        "p_2": "participation factor, stepped [-]",
        "gamma_1_m_s2": "stepped-phase restoring term [m/s²]",
    },
    "block": {
        "half_width_m": "half-width b of a rigid block [m]",
        "half_height_m": "half-height h of a rigid block [m]",
    },
    "conventions": {
        "w_col_convention": f"W_col in eqs. 4.6-4.7, one of {W_COL_CONVENTIONS}",
        "l_m": "the length l in gamma_1 (eq. 4.7) [m]",
        "g_m_s2": "gravity [m/s²]",
    },
}

_TEXT_KEYS = {("frame", "name"), ("conventions", "w_col_convention")}

#: The plausible range of each number of a frame file, as the record readers check their
#: headers: a bridge pier between a lab model (10 kg, 0.1 m) and the largest piers built.
#: A value outside is refused with the range (10⁴⁰⁰, 1e308, NaN, 5 N of superstructure).
PLAUSIBLE: dict[tuple[str, str], Range] = {
    ("frame", "c_r"): Range(0, 1),
    ("frame", "x_c_m"): Range(0, 10),
    ("frame", "x_cap_m"): Range(0, 100, low_open=True),
    ("physical", "w_s_n"): Range(1e2, 1e10),
    ("physical", "w_col_n"): Range(0, 1e10, low_open=True),
    ("physical", "h_r_m"): Range(0.1, 300),
    ("physical", "l_f_m"): Range(0.05, 300),
    ("physical", "k_a_n_m"): Range(1e3, 1e13),
    ("physical", "k_b_n_m"): Range(1e2, 1e13),
    ("constants", "omega_1_rad_s"): Range(0, 2000, low_open=True),
    ("constants", "omega_2_rad_s"): Range(0, 2000, low_open=True),
    ("constants", "p_1"): Range(0, 10, low_open=True),
    ("constants", "p_2"): Range(0, 10, low_open=True),
    ("constants", "gamma_1_m_s2"): Range(0, 1e4, low_open=True),
    ("block", "half_width_m"): Range(0, 100, low_open=True),
    ("block", "half_height_m"): Range(0, 100, low_open=True),
    ("conventions", "l_m"): Range(0, 300, low_open=True),
    ("conventions", "g_m_s2"): Range(9.7, 9.9),
}


class FrameFileWarning(UserWarning):
    """A frame file gives a value that the route it takes does not use."""


def _ignored_on_constants(values: dict[str, dict[str, Any]]) -> list[str]:
    """The keys a ``[constants]`` frame gives but does not use: eqs. 4.10 and 4.15-4.16 derive
    only what ``[frame]`` does not give. (``k_b_n_m`` is not named: the template keeps it so
    that removing ``[constants]`` switches to the physical route.)"""
    frame, physical, conventions = values["frame"], values["physical"], values["conventions"]
    unused: list[tuple[str, str, str]] = []
    if "x_c_m" in frame:
        unused.append(("physical", "k_a_n_m", "x_c_m"))
    if "c_r" in frame:
        unused.append(("conventions", "g_m_s2", "c_r"))
    if {"x_c_m", "c_r", "x_cap_m"} <= set(frame):
        unused += [("physical", key, "x_c_m, c_r and x_cap_m") for key in ("w_s_n", "w_col_n",
                   "l_f_m")]  # fmt: skip
    given = {"physical": physical, "conventions": conventions}
    return [f"[{table}] {key} ({by} given)" for table, key, by in unused if key in given[table]]


class _Where:
    """Locates ``key = ...`` lines of a TOML text, per table, for error messages."""

    _HEADER = re.compile(r"^\s*\[\s*([A-Za-z0-9_.\-]+)\s*\]")
    _KEY = re.compile(r"^\s*([A-Za-z0-9_\-]+)\s*=")

    def __init__(self, path: str | None, text: str | None) -> None:
        self.path = path
        self.lines: dict[tuple[str, str], int] = {}
        self.tables: dict[str, int] = {}
        table = ""
        for number, line in enumerate((text or "").splitlines(), start=1):
            header = self._HEADER.match(line)
            if header:
                table = header.group(1)
                self.tables.setdefault(table, number)
                continue
            key = self._KEY.match(line)
            if key:
                self.lines.setdefault((table, key.group(1)), number)

    def error(self, what: str, table: str, key: str | None = None) -> InputError:
        line = self.tables.get(table) if key is None else self.lines.get((table, key))
        return InputError(what, self.path, line)


def _number(value: Any, table: str, key: str, where: _Where) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise where.error(
            f"[{table}] {key} = {value!r}, expected a number: {TABLES[table][key]}", table, key
        )
    try:
        number = float(value)
    except OverflowError:
        raise where.error(
            f"[{table}] {key} = {str(value)[:20]}... ({len(str(value))} digits), expected a "
            f"number: {TABLES[table][key]}",
            table,
            key,
        ) from None
    plausible = PLAUSIBLE.get((table, key))
    if plausible is not None and not plausible.contains(number):
        raise where.error(
            f"[{table}] {key} = {number:g}, expected {plausible.describe()}: {TABLES[table][key]}",
            table,
            key,
        )
    return number


def frame_from_mapping(
    data: Mapping[str, Any],
    *,
    path: str | PathLike[str] | None = None,
    text: str | None = None,
) -> PortalFrame:
    """Build a :class:`PortalFrame` from the parsed tables of a FRAME.toml.

    Parameters
    ----------
    data
        The parsed TOML document (or the same tables embedded in a workflow file).
    path
        File the tables came from, for error messages.
    text
        The TOML text, to give line numbers in error messages.

    Raises
    ------
    InputError
        Unknown table or key, wrong type, missing key, or a non-physical frame, naming the file,
        line and key.
    """
    where = _Where(None if path is None else str(path), text)
    unknown_tables = sorted(set(data) - set(TABLES))
    if unknown_tables:
        name = unknown_tables[0]
        raise where.error(
            f"unknown table or key {name!r}, expected tables {sorted(TABLES)}",
            name if name in where.tables else "",
            None if name in where.tables else name,
        )
    values: dict[str, dict[str, Any]] = {}
    for table, allowed in TABLES.items():
        content = data.get(table, {})
        if not isinstance(content, Mapping):
            raise where.error(f"{table} = {content!r}, expected a table [{table}]", "", table)
        values[table] = {}
        for key, value in content.items():
            if key not in allowed:
                raise where.error(
                    f"unknown key {key!r} in [{table}], expected one of {sorted(allowed)}",
                    table,
                    key,
                )
            if (table, key) in _TEXT_KEYS:
                if not isinstance(value, str):
                    raise where.error(
                        f"[{table}] {key} = {value!r}, expected text: {allowed[key]}", table, key
                    )
                values[table][key] = value
            else:
                values[table][key] = _number(value, table, key, where)
    frame_table, physical = values["frame"], values["physical"]
    constants, conventions = values["constants"], values["conventions"]
    if "block" in data:
        return _block(values, where)
    if "frame" not in data:
        raise where.error("missing table [frame], expected [frame] with xi_1 and xi_2", "")
    for key in ("xi_1", "xi_2"):
        if key not in frame_table:
            raise where.error(f"missing key {key} in [frame]: {TABLES['frame'][key]}", "frame")
        try:  # a frame file takes fractions below 1 only: 5 is a percentage, not a ratio
            damping_fraction(key, frame_table[key])
        except InputError as error:
            raise where.error(error.what, "frame", key) from None
    common: dict[str, Any] = {key: frame_table.get(key) for key in ("c_r", "x_c_m", "x_cap_m")}
    common.update(xi_1=frame_table["xi_1"], xi_2=frame_table["xi_2"])
    try:
        if constants:
            missing = sorted(set(TABLES["constants"]) - set(constants))
            if missing:
                raise where.error(
                    f"missing key(s) {', '.join(missing)} in [constants], expected all of "
                    f"{sorted(TABLES['constants'])} (or no [constants]: the physical route)",
                    "constants",
                )
            for key in ("l_m", "w_col_convention"):
                if key in conventions:
                    raise where.error(
                        f"[conventions] {key} is only used to derive the constants from "
                        "[physical], expected no [constants] table or no " + key,
                        "conventions",
                        key,
                    )
            ignored = _ignored_on_constants(values)
            if ignored:
                warnings.warn(
                    f"{where.path or 'frame'}: {', '.join(ignored)} not used: the model constants "
                    "are given in [constants]",
                    FrameFileWarning,
                    stacklevel=2,
                )
            kwargs: dict[str, Any] = {**constants, **common, **conventions}
            kwargs.update((k, v) for k, v in physical.items() if k != "k_b_n_m")
            return PortalFrame.from_constants(**kwargs)
        missing = sorted(set(TABLES["physical"]) - set(physical))
        if missing:
            raise where.error(
                f"missing key(s) {', '.join(missing)} in [physical], expected all of "
                f"{sorted(TABLES['physical'])} (or a [constants] table)",
                "physical" if "physical" in data else "",
            )
        return PortalFrame.from_physical(**physical, **common, **conventions)
    except InputError as error:
        if error.path is not None:
            raise
        line = _line_of_message(error.what, where)
        raise InputError(error.what, where.path, line) from None


def _block(values: dict[str, dict[str, Any]], where: _Where) -> PortalFrame:
    """The rigid-block route: ``[block]`` with ``[frame]`` c_r, xi_2, x_cap_m and ``g_m_s2``."""
    import dataclasses

    for table in ("physical", "constants"):
        if values[table]:
            raise where.error(
                f"[{table}] given with [block], expected one route: a rigid block or a frame",
                table,
            )
    for key in ("xi_1", "x_c_m", "w_col_convention", "l_m"):
        table = "conventions" if key in TABLES["conventions"] else "frame"
        if key in values[table]:
            raise where.error(
                f"[{table}] {key} given with [block], expected none (a rigid block has no "
                "unstepped phase: x_c = 0)",
                table,
                key,
            )
    block, frame_table = values["block"], values["frame"]
    missing = sorted(set(TABLES["block"]) - set(block))
    if missing:
        raise where.error(f"missing key(s) {', '.join(missing)} in [block]", "block")
    try:
        frame = PortalFrame.housner_block(
            **block,
            c_r=frame_table.get("c_r"),
            xi=frame_table.get("xi_2", 0.0),
            **{k: v for k, v in values["conventions"].items() if k == "g_m_s2"},
        )
        if "x_cap_m" in frame_table:
            frame = dataclasses.replace(frame, x_cap_m=frame_table["x_cap_m"])
    except InputError as error:
        raise InputError(error.what, where.path, _line_of_message(error.what, where)) from None
    return frame


def _line_of_message(what: str, where: _Where) -> int | None:
    """The line of the first key named at the start of a frame validation message."""
    first = what.split(" ", 1)[0]
    for table in TABLES:
        if (table, first) in where.lines:
            return where.lines[(table, first)]
    return None


def read_frame_file(path: str | PathLike[str]) -> PortalFrame:
    """Read a FRAME.toml into a :class:`PortalFrame`.

    Parameters
    ----------
    path
        The file (see :data:`FRAME_TEMPLATE` and docs/frame-file.md).

    Raises
    ------
    InputError
        Missing or unreadable, not TOML, unknown table or key, wrong type, missing key, or a
        non-physical frame.
    """
    data, text = read_toml(path, "a FRAME.toml")
    return frame_from_mapping(data, path=path, text=text)


FRAME_TEMPLATE = """\
# FRAME.toml: a stepping portal frame for stepframe (SI units; keys name their unit).
# This is the frame of the paper's Example 4 (Alimoradi and Beck 2025), built on Example 2's
# weights and geometry. Docs: docs/frame-file.md. Check it with
#   stepframe structure simulate --frame FRAME.toml RECORD
#
# Two routes:
#   * [constants] present: the model constants of eqs. 4.11-4.12 are taken as given; [physical]
#     (optional) then only supplies x_c (eq. 4.10), C_r (eqs. 4.15-4.16), the overturning cap and
#     H_r for drift ratios.
#   * no [constants]: every constant follows from [physical] through eqs. 4.6, 4.7, 4.10 and
#     4.15-4.16, with the [conventions] below.

[frame]
name = "Example 4 (paper), printed constants"
xi_1 = 0.05           # viscous damping ratio, unstepped phase [-] (a fraction, not a percent)
xi_2 = 0.0            # viscous damping ratio, stepped phase [-]
# c_r = 0.9474        # velocity ratio at impact C_r (eq. 4.3) [-]; Housner's energy ratio is C_r².
#                     #   Default: eqs. 4.15-4.16 from [physical].
# x_c_m = 0.1904      # displacement at the onset of stepping [m]. Default: eq. 4.10 from
#                     #   [physical].
# x_cap_m = 5.773     # |x| at which the frame is declared overturned [m]. Default: the geometric
#                     #   overturning displacement (centre of mass above the pivot footing).

[physical]
w_s_n = 1.472e6       # weight of the superstructure W_S [N] (331 kip)
w_col_n = 1.335e6     # TOTAL weight of both columns [N] (W_T - W_S = 631 - 331 kip)
h_r_m = 29.944        # height of the superstructure above the footings H_r [m]
l_f_m = 8.839         # distance between the footings L_F [m]
k_a_n_m = 1.159e9     # resultant axial stiffness of each leg K_a [N/m]
k_b_n_m = 5.021e6     # resultant bending stiffness of each leg K_b [N/m] (physical route only)

[constants]
# As printed in Example 4, except p_1: the paper prints 1.0901, which is √P₁; eq. 4.6 with these
# weights gives P₁ = 1.1884 (docs/paper-notes.md, Example 4). Remove this table to derive all
# constants from [physical] instead.
omega_1_rad_s = 6.4581   # unstepped circular frequency ω₁ [rad/s]
omega_2_rad_s = 0.6445   # stepped-phase frequency parameter ω₂ [rad/s] (stiffness -ω₂²)
p_1 = 1.1884             # participation factor of ẍ_g, unstepped [-]
p_2 = 1.2680             # participation factor of ẍ_g, stepped [-]
gamma_1_m_s2 = 0.1387    # stepped-phase restoring term γ₁ [m/s²]; x* = γ₁/ω₂² = 0.334 m

[conventions]
# Used by the physical route (no [constants]); g also by the derivations of the constants route.
# w_col_convention = "total"  # what W_col means in eqs. 4.6-4.7: "total" (both columns; this
#                             #   reproduces Example 4's ω₁, ω₂, P₂) or "per-column". Eqs. 4.10 and
#                             #   4.15-4.16 always use one column's weight (w_col_n / 2).
# l_m = 4.4195                # the length l in γ₁ (eq. 4.7) [m]; default L_F/2. Example 4's
#                             #   γ₁ = 0.1387 corresponds to l = 0.2263 m.
g_m_s2 = 9.81                 # gravity [m/s²] (the paper's examples use 9.81)
"""


def frame_template() -> str:
    """The commented FRAME.toml template (Example 4's frame, units, conventions)."""
    return FRAME_TEMPLATE
