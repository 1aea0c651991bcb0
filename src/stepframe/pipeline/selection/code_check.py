"""The chosen set against the code's suite rule (ASCE 7-22 §16.2, Eurocode 8 §3.2.3.1.2).

- **ASCE/SEI 7-22 §16.2** (ground-motion scaling for response history analysis): the average
  of the suite's spectra shall not fall below 90 % of the target over the period range, whose
  upper bound is at least twice the largest first-mode period and whose lower bound is at most
  20 % of it (§16.2.1). A stepping frame softens as it steps, so here the range is
  [0.2 T_1, max(2 T_1, T(A_max))]: stretched to the frame's elongated period. (§16.2.3 compares
  the maximum-direction spectra of pairs: ``pair_spectrum = "rotd100"`` does; the output names
  the measure used.)
- **EN 1998-1:2004 §3.2.3.1.2(4)**: the mean of the zero-period spectral accelerations (PGA)
  of the suite shall not be smaller than a_g S, and in the range 0.2 T_1 to 2 T_1 no value of
  the mean 5 %-damped elastic spectrum shall be less than 90 % of the elastic spectrum.

Both compare the arithmetic mean of the scaled spectra with the target at each period of a
grid (:data:`stepframe.pipeline.selection.set_spectra.SET_PERIODS_S` inside the range, and the
range's ends). The result says whether the set passes, where it does not (period intervals),
the worst ratio and the uniform factor on every scale factor that would make it pass.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

Floats = NDArray[np.float64]

#: The suite rules: code → (clause, the fraction of the target the mean must reach).
CODES = {
    "asce7-22": ("ASCE/SEI 7-22 §16.2", 0.9),
    "ec8": ("EN 1998-1:2004 §3.2.3.1.2", 0.9),
}


def period_range_s(code: str, period_1_s: float, period_a_max_s: float) -> tuple[float, float]:
    """The check's period range [s]: ASCE 7-22 [0.2 T_1, max(2 T_1, T(A_max))], Eurocode 8
    [0.2 T_1, 2 T_1]."""
    high = 2.0 * period_1_s
    if code == "asce7-22":
        high = max(high, period_a_max_s)
    return 0.2 * period_1_s, high


def check_periods_s(grid_s: Floats, period_range: tuple[float, float]) -> Floats:
    """The grid's periods inside the range, with the range's ends."""
    low, high = period_range
    inside = grid_s[(grid_s > low) & (grid_s < high)]
    return np.concatenate([[low], inside, [high]])


@dataclass(frozen=True)
class SuiteCheck:
    """The outcome of a suite rule.

    Attributes
    ----------
    code, clause
        ``asce7-22`` or ``ec8``, and the clause checked.
    fraction
        The share of the target the mean must reach (0.9).
    period_range_s
        The range checked [s].
    periods_s, ratio
        The periods checked and mean/target at each.
    passes
        Whether the rule holds (spectrum, and for Eurocode 8 the mean PGA too).
    measure
        What each unit's spectrum was (``component``, ``rotd50``, ...).
    n_units
        How many spectra the mean is over.
    pga
        Eurocode 8: ``{"mean_g", "required_g", "passes"}``; empty otherwise.
    notes
        What the reader should know (a range beyond Eurocode 8's 4 s, a measure other than
        the code's).
    """

    code: str
    clause: str
    fraction: float
    period_range_s: tuple[float, float]
    periods_s: Floats
    ratio: Floats
    passes: bool
    measure: str
    n_units: int
    pga: dict[str, Any] = field(default_factory=dict)
    notes: tuple[str, ...] = ()

    @property
    def worst(self) -> tuple[float, float]:
        """(lowest mean/target, its period [s])."""
        k = int(np.argmin(self.ratio))
        return float(self.ratio[k]), float(self.periods_s[k])

    @property
    def below(self) -> list[tuple[float, float]]:
        """Period intervals [s] (between checked periods) where mean < fraction·target."""
        low = self.ratio < self.fraction
        out, start = [], None
        for k, flag in enumerate(low):
            if flag and start is None:
                start = k
            if start is not None and (not flag or k == low.size - 1):
                end = k if flag else k - 1
                out.append((float(self.periods_s[start]), float(self.periods_s[end])))
                start = None
        return out

    @property
    def factor_to_pass(self) -> float:
        """The factor on every scale factor that makes the spectrum rule hold (1 when it does)."""
        return max(1.0, self.fraction / self.worst[0])

    def line(self) -> str:
        """The outcome in one line (the command's output and the report say this)."""
        worst, at = self.worst
        low, high = self.period_range_s
        head = (
            f"{self.clause}: mean of {self.n_units} {self.measure} spectra ≥ "
            f"{self.fraction:.0%} of the target over {low:.3g}-{high:.3g} s"
        )
        if self.passes:
            text = f"{head}: passes (lowest {worst:.0%} at {at:.3g} s)"
        else:
            # A span of one period (the range's end only) is that period, not "1.95-1.95 s".
            spans = ", ".join(
                f"{a:.3g} s" if f"{a:.3g}" == f"{b:.3g}" else f"{a:.3g}-{b:.3g} s"
                for a, b in self.below
            )
            text = f"{head}: FAILS" + (
                f" below it at {spans}, lowest {worst:.0%} at {at:.3g} s (scale every record by "
                f"{self.factor_to_pass:.3g} to pass)"
                if spans
                else ""
            )
        if self.pga:
            verdict = "passes" if self.pga["passes"] else "FAILS"
            text += (
                f"; mean PGA {self.pga['mean_g']:.3g} g ≥ a_g S {self.pga['required_g']:.3g} g: "
                f"{verdict}"
            )
        return text

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready (``selection.json``'s ``code_check``)."""
        worst, at = self.worst
        return {
            "code": self.code,
            "clause": self.clause,
            "fraction": self.fraction,
            "period_range_s": list(self.period_range_s),
            "measure": self.measure,
            "n_units": self.n_units,
            "passes": self.passes,
            "lowest_ratio": worst,
            "lowest_at_s": at,
            "below_s": [list(span) for span in self.below],
            "factor_to_pass": self.factor_to_pass,
            "periods_s": [float(t) for t in self.periods_s],
            "ratio": [float(r) for r in self.ratio],
            "pga": self.pga,
            "notes": list(self.notes),
            "line": self.line(),
        }


def check_suite(
    code: str,
    periods_s: Floats,
    mean_psa_g: Floats,
    target_psa_g: Floats,
    period_range: tuple[float, float],
    *,
    measure: str,
    n_units: int,
    mean_pga_g: float | None = None,
    target_pga_g: float | None = None,
) -> SuiteCheck:
    """Check the mean spectrum ``mean_psa_g`` against ``target_psa_g`` at ``periods_s`` (the
    periods of :func:`check_periods_s`) by ``code``'s rule; Eurocode 8 also needs the mean PGA
    and a_g S."""
    clause, fraction = CODES[code]
    ratio = np.asarray(mean_psa_g, dtype=np.float64) / np.asarray(target_psa_g, dtype=np.float64)
    passes = bool(np.all(ratio >= fraction))
    pga: dict[str, Any] = {}
    notes: list[str] = []
    if code == "ec8":
        if mean_pga_g is not None and target_pga_g is not None:
            pga = {
                "mean_g": float(mean_pga_g),
                "required_g": float(target_pga_g),
                "passes": bool(mean_pga_g >= target_pga_g),
            }
            passes = passes and pga["passes"]
        if period_range[1] > 4.0:
            notes.append(
                "the range passes 4 s, where EN 1998-1 §3.2.2.2 ends: the 1/T² branch continued"
            )
    if code == "asce7-22" and measure != "rotd100":
        notes.append(f"§16.2.3 asks for maximum-direction spectra (rotd100); {measure} used")
    return SuiteCheck(
        code,
        clause,
        fraction,
        (float(period_range[0]), float(period_range[1])),
        np.asarray(periods_s, dtype=np.float64),
        ratio,
        passes,
        measure,
        n_units,
        pga,
        tuple(notes),
    )
