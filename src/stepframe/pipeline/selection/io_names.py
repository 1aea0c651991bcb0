"""Names of the selection's input and output choices (no heavy imports: --help reads them)."""

from __future__ import annotations

from typing import Literal

PairSpectrum = Literal["rotd50", "geomean", "rotd100"]
PAIR_SPECTRA: tuple[PairSpectrum, ...] = ("rotd50", "geomean", "rotd100")
Unmatched = Literal["error", "warn"]
UNMATCHED: tuple[Unmatched, ...] = ("error", "warn")
Code = Literal["asce7-22", "ec8"]
CODES: tuple[Code, ...] = ("asce7-22", "ec8")
Ec8Type = Literal["type1", "type2"]
EC8_TYPES: tuple[Ec8Type, ...] = ("type1", "type2")
Ec8Ground = Literal["A", "B", "C", "D", "E"]
EC8_GROUNDS: tuple[Ec8Ground, ...] = ("A", "B", "C", "D", "E")
