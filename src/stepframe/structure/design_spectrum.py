"""Pseudo-acceleration design spectra for the quasi-dynamic design (paper §2, Fig. 2).

Two kinds, both with ``sa_m_s2(period_s)`` and ``branch(period_s)``:

- :class:`TwoPeriodSpectrum`: the "two-period" shape of AASHTO/ASCE 7 used by the paper,
  S_a = S_DS for T ≤ T_s = S_D1/S_DS, S_a = S_D1/T for T_s < T ≤ T_L, and, when the long-period
  transition T_L is given, S_a = S_D1·T_L/T² beyond it (constant spectral displacement). As in
  the paper, the plateau extends down to T = 0 (no rising branch below 0.2 T_s): the design
  iteration never reaches such short periods for a stepping frame except at δ → 0.
- :class:`TabulatedSpectrum`: any site-specific or multi-period spectrum given as a table,
  linear between points, held at its first value below the table and continued at constant
  spectral displacement (S_a ∝ 1/T²) beyond it.

Spectral ordinates are for 5 % damping; the damping reduction factor β is applied by the caller
(:mod:`stepframe.structure.damping`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal, Protocol

from stepframe.core import validation
from stepframe.errors import InputError

#: Name of a spectrum branch: plateau (S_DS), constant velocity (S_D1/T), constant displacement
#: (S_D1·T_L/T²), or a tabulated spectrum.
Branch = Literal["short", "long", "very-long", "table"]


class Spectrum(Protocol):
    """What the design iteration needs from a spectrum."""

    def sa_m_s2(self, period_s: float) -> float:
        """Pseudo-spectral acceleration [m/s²] at ``period_s`` [s] (5 % damping)."""
        ...

    def branch(self, period_s: float) -> Branch:
        """Name of the branch that holds at ``period_s`` [s]."""
        ...

    def to_dict(self) -> dict[str, Any]:
        """Plain dictionary (the TOML ``[spectrum]`` table)."""
        ...


@dataclass(frozen=True)
class TwoPeriodSpectrum:
    """Two-period design spectrum (S_DS, S_D1, optional T_L).

    Attributes
    ----------
    s_ds_m_s2
        Short-period (plateau) spectral acceleration S_DS [m/s²].
    s_d1_m_s
        Spectral acceleration at 1 s, S_D1 [m/s² · s = m/s]; S_a = S_D1/T on the long branch.
    t_l_s
        Long-period transition T_L [s] (None: the S_D1/T branch continues for ever).
    """

    s_ds_m_s2: float
    s_d1_m_s: float
    t_l_s: float | None = None

    def __post_init__(self) -> None:
        validation.positive("s_ds_m_s2", self.s_ds_m_s2)
        validation.positive("s_d1_m_s", self.s_d1_m_s)
        if self.t_l_s is not None:
            validation.positive("t_l_s", self.t_l_s)
            if not self.t_l_s > self.t_s_s:
                raise InputError(
                    f"t_l_s = {self.t_l_s} s, expected > T_s = S_D1/S_DS = {self.t_s_s:.6g} s"
                )

    @classmethod
    def from_g(
        cls, s_ds_g: float, s_d1_g: float, *, g_m_s2: float = 9.81, t_l_s: float | None = None
    ) -> TwoPeriodSpectrum:
        """Build from S_DS and S_D1 in units of g (the paper's examples use g = 9.81 m/s²)."""
        g = validation.positive("g_m_s2", g_m_s2)
        return cls(
            validation.positive("s_ds_g", s_ds_g) * g,
            validation.positive("s_d1_g", s_d1_g) * g,
            t_l_s,
        )

    @property
    def t_s_s(self) -> float:
        """Corner period T_s = S_D1/S_DS [s]."""
        return self.s_d1_m_s / self.s_ds_m_s2

    def branch(self, period_s: float) -> Branch:
        """``"short"`` for T ≤ T_s, ``"long"`` up to T_L, ``"very-long"`` beyond T_L."""
        if period_s <= self.t_s_s:
            return "short"
        if self.t_l_s is None or period_s <= self.t_l_s:
            return "long"
        return "very-long"

    def sa_m_s2(self, period_s: float) -> float:
        """S_a(T) [m/s²]; continuous at T_s and at T_L."""
        branch = self.branch(period_s)
        if branch == "short":
            return self.s_ds_m_s2
        if branch == "long":
            return self.s_d1_m_s / period_s
        assert self.t_l_s is not None  # "very-long" exists only with T_L
        return self.s_d1_m_s * self.t_l_s / period_s**2

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, g_m_s2: float = 9.81) -> TwoPeriodSpectrum:
        """Inverse of :meth:`to_dict` (values in g accepted too, see :func:`spectrum_from_dict`)."""
        spectrum = spectrum_from_dict(data, g_m_s2=g_m_s2)
        if not isinstance(spectrum, TwoPeriodSpectrum):
            raise InputError("a tabulated spectrum, expected s_ds and s_d1 of a two-period one")
        return spectrum

    def to_dict(self) -> dict[str, Any]:
        """``{"s_ds_m_s2": ..., "s_d1_m_s": ..., "t_l_s": ...}`` (t_l_s omitted when None)."""
        out: dict[str, Any] = {"s_ds_m_s2": self.s_ds_m_s2, "s_d1_m_s": self.s_d1_m_s}
        if self.t_l_s is not None:
            out["t_l_s"] = self.t_l_s
        return out


def point_problem(period_s: float, sa: float, previous_s: float | None) -> str | None:
    """What is wrong with one point (T, S_a) of a tabulated spectrum, the point before it at
    ``previous_s`` (None for the first); None when nothing (the table's rule, which the target
    CSV's reader applies line by line)."""
    if not (math.isfinite(period_s) and period_s >= 0):
        return "expected a finite period ≥ 0"
    if not (math.isfinite(sa) and sa > 0):
        return "expected a spectral acceleration > 0"
    if previous_s is not None and not period_s > previous_s:
        return f"expected strictly increasing periods (after {previous_s:g} s)"
    return None


@dataclass(frozen=True)
class TabulatedSpectrum:
    """A spectrum given as points (T_k, S_a,k), linear between them.

    Attributes
    ----------
    periods_s
        Strictly increasing periods [s], at least two, the first ≥ 0.
    sa_m_s2
        Pseudo-spectral accelerations at those periods [m/s²], all > 0.
    """

    periods_s: tuple[float, ...]
    sa_m_s2_values: tuple[float, ...]

    def __post_init__(self) -> None:
        periods = tuple(float(p) for p in self.periods_s)
        values = tuple(float(v) for v in self.sa_m_s2_values)
        if len(periods) != len(values):
            raise InputError(
                f"{len(periods)} periods and {len(values)} spectral values, expected equal counts"
            )
        if len(periods) < 2:
            raise InputError(f"{len(periods)} spectrum points, expected at least 2")
        for k, (p, v) in enumerate(zip(periods, values, strict=True)):
            problem = point_problem(p, v, periods[k - 1] if k else None)
            if problem:
                raise InputError(f"point {k}: periods_s = {p}, sa_m_s2 = {v}, {problem}")
        object.__setattr__(self, "periods_s", periods)
        object.__setattr__(self, "sa_m_s2_values", values)

    def branch(self, period_s: float) -> Branch:
        """Always ``"table"``: a tabulated spectrum has no closed-form branches."""
        return "table"

    def sa_m_s2(self, period_s: float) -> float:
        """S_a(T) [m/s²]: linear in the table, held below it, ∝ 1/T² beyond it."""
        periods, values = self.periods_s, self.sa_m_s2_values
        if period_s <= periods[0]:
            return values[0]
        if period_s >= periods[-1]:
            return values[-1] * (periods[-1] / period_s) ** 2
        # Binary search: the design iteration calls this in a loop, keep it O(log n).
        lo, hi = 0, len(periods) - 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if periods[mid] <= period_s:
                lo = mid
            else:
                hi = mid
        frac = (period_s - periods[lo]) / (periods[hi] - periods[lo])
        return values[lo] + frac * (values[hi] - values[lo])

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], *, g_m_s2: float = 9.81) -> TabulatedSpectrum:
        """Inverse of :meth:`to_dict` (``sa_g`` also accepted, see :func:`spectrum_from_dict`)."""
        spectrum = spectrum_from_dict(data, g_m_s2=g_m_s2)
        if not isinstance(spectrum, TabulatedSpectrum):
            raise InputError("a two-period spectrum, expected periods_s and sa_m_s2 of a table")
        return spectrum

    def to_dict(self) -> dict[str, Any]:
        """``{"periods_s": [...], "sa_m_s2": [...]}``."""
        return {"periods_s": list(self.periods_s), "sa_m_s2": list(self.sa_m_s2_values)}


_TWO_PERIOD_KEYS = {"s_ds_m_s2", "s_d1_m_s", "s_ds_g", "s_d1_g", "t_l_s"}
_TABLE_KEYS = {"periods_s", "sa_m_s2", "sa_g"}


def spectrum_from_dict(
    data: Mapping[str, Any], *, g_m_s2: float = 9.81, where: str = "[spectrum]"
) -> TwoPeriodSpectrum | TabulatedSpectrum:
    """Build a spectrum from a TOML-like table.

    Two-period: ``s_ds_m_s2`` or ``s_ds_g``, ``s_d1_m_s`` or ``s_d1_g``, optional ``t_l_s``.
    Tabulated: ``periods_s`` and ``sa_m_s2`` or ``sa_g``. Values in g use ``g_m_s2``.
    Unknown keys are an error naming the key and ``where``.
    """
    keys = set(data)
    if keys & _TABLE_KEYS:
        unknown = keys - _TABLE_KEYS
        if unknown:
            raise InputError(
                f"{where}: unknown key(s) {sorted(unknown)} in a tabulated spectrum, "
                f"expected {sorted(_TABLE_KEYS)}"
            )
        if "periods_s" not in data or ("sa_m_s2" in data) == ("sa_g" in data):
            raise InputError(f"{where}: expected periods_s and one of sa_m_s2 or sa_g")
        periods = _number_list(data["periods_s"], f"{where} periods_s")
        if "sa_m_s2" in data:
            values = _number_list(data["sa_m_s2"], f"{where} sa_m_s2")
        else:
            values = [v * g_m_s2 for v in _number_list(data["sa_g"], f"{where} sa_g")]
        return TabulatedSpectrum(tuple(periods), tuple(values))
    unknown = keys - _TWO_PERIOD_KEYS
    if unknown:
        raise InputError(
            f"{where}: unknown key(s) {sorted(unknown)}, expected {sorted(_TWO_PERIOD_KEYS)} "
            f"or {sorted(_TABLE_KEYS)}"
        )
    s_ds = _one_of(data, "s_ds_m_s2", "s_ds_g", g_m_s2, where)
    s_d1 = _one_of(data, "s_d1_m_s", "s_d1_g", g_m_s2, where)
    t_l = data.get("t_l_s")
    return TwoPeriodSpectrum(s_ds, s_d1, None if t_l is None else t_l)


def _one_of(data: Mapping[str, Any], si: str, in_g: str, g_m_s2: float, where: str) -> float:
    if (si in data) == (in_g in data):
        raise InputError(f"{where}: expected exactly one of {si} or {in_g}")
    if si in data:
        return validation.positive(si, data[si])
    return validation.positive(in_g, data[in_g]) * g_m_s2


def _number_list(value: object, what: str) -> list[float]:
    if not isinstance(value, Sequence) or isinstance(value, str):
        raise InputError(f"{what} = {value!r}, expected a list of numbers")
    out = []
    for item in value:
        if isinstance(item, bool) or not isinstance(item, int | float):
            raise InputError(f"{what} holds {item!r}, expected numbers")
        out.append(float(item))
    return out
