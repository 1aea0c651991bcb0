"""A site's ground-motion model from a folder of its records: per-record fits and their combination.

Each component of each record file is fitted on its own (eqs. 6.10-6.11 through
:func:`stepframe.stochastic.fit.fit_model`); a fit whose path is not usable (ω_p at its bound, ω_r
at its floor, ξ clipped, ω_g not decreasing) is reported with its flags and left out of the
combination. The combined parameters are inverse-variance weighted means of the usable fits, each
with the standard error of that mean; t_max and t_dur are the medians. Records that cannot be read
or fitted become failures (item, stage, error), never a stop.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any

import numpy as np

from stepframe.core.results import Failure
from stepframe.errors import InputError
from stepframe.stochastic.model import AlphaReading, GroundMotionModel

#: Fit flags that make ω_g(t) unusable as a site's path (as the selection filters them).
UNUSABLE_FLAGS = frozenset(
    {"omega_p_at_bound", "omega_r_at_bound", "xi_clipped", "omega_not_decreasing"}
)

#: The combined parameters.
COMBINED = ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r")


@dataclass(frozen=True)
class RecordFit:
    """One component's features, fit and the trace they came from."""

    name: str
    trace: Any
    features: Any
    fit: Any

    @property
    def usable(self) -> bool:
        """Whether the fitted path enters the site's combined parameters."""
        return not UNUSABLE_FLAGS.intersection(self.fit.flags)


@dataclass(frozen=True)
class SiteFromRecords:
    """Per-record fits, the combined model and its standard errors, and the failures."""

    fits: tuple[RecordFit, ...]
    model: GroundMotionModel
    stderr: dict[str, float]
    peak_intensity_m_s2: float
    failures: tuple[Failure, ...]


def record_files(folder: str | PathLike[str]) -> list[Path]:
    """The files of a site's record folder (sorted; hidden files and metadata skipped)."""
    root = Path(folder)
    if not root.is_dir():
        raise InputError("not a folder, expected a folder of the site's record files", root)
    skip = {".csv", ".json", ".md", ".txt.md", ".toml", ".xml", ".html", ".png"}
    return sorted(
        p
        for p in root.rglob("*")
        if p.is_file() and not p.name.startswith(".") and p.suffix.lower() not in skip
    )


def _combine(values: Sequence[float], errors: Sequence[float]) -> tuple[float, float]:
    x = np.asarray(values, dtype=np.float64)
    se = np.asarray(errors, dtype=np.float64)
    if x.size == 1:
        return float(x[0]), float(se[0])
    if np.all(np.isfinite(se) & (se > 0)):
        weight = 1.0 / se**2
        return float(np.sum(weight * x) / np.sum(weight)), float(1.0 / math.sqrt(np.sum(weight)))
    # some fit gave no standard error: the plain mean and its scatter-based error
    return float(np.mean(x)), float(np.std(x, ddof=1) / math.sqrt(x.size))


def site_from_records(
    folder: str | PathLike[str],
    *,
    alpha_reading: AlphaReading = "eq-6-11",
    t0: str = "auto",
    record_format: str | None = None,
    units: str | None = None,
) -> SiteFromRecords:
    """Fit every component in ``folder`` and combine the usable fits into one site model.

    Parameters
    ----------
    folder
        A folder of the site's record files (any format :func:`stepframe.records.read` sniffs).
    alpha_reading
        Where the α_g ramp ends (``"eq-6-11"``: t_dur; ``"paper"``: t_max).
    t0
        Time origin: ``"auto"`` (the picked P onset when reliable, else the record start),
        ``"start"`` or ``"p-pick"``.
    record_format, units
        Passed to :func:`stepframe.records.read` when the files do not say.

    Raises
    ------
    InputError
        Not a folder, no record files, or no component with a usable fit.
    """
    from stepframe.records import read
    from stepframe.stochastic.features import record_features
    from stepframe.stochastic.fit import fit_model

    files = record_files(folder)
    if not files:
        raise InputError("no record files, expected a folder of the site's records", folder)
    fits: list[RecordFit] = []
    failures: list[Failure] = []
    for path in files:
        try:
            stream = read(path, format=record_format, units=units)
        except InputError as error:
            failures.append(Failure(str(path), "read", type(error).__name__, error.what))
            continue
        for trace in stream:
            name = f"{path.name} [{trace.stats.channel}]" if len(stream) > 1 else path.name
            try:
                features = record_features(trace, t0=t0)  # type: ignore[arg-type]
                fit = fit_model(features, alpha_reading=alpha_reading)
            except InputError as error:
                failures.append(Failure(name, "fit", type(error).__name__, error.what))
                continue
            fits.append(RecordFit(name, trace, features, fit))
    usable = [f for f in fits if f.usable]
    if not usable:
        reasons = "; ".join(
            [f"{f.name}: {', '.join(sorted(UNUSABLE_FLAGS & set(f.fit.flags)))}" for f in fits]
            + [f"{x.item}: {x.message}" for x in failures]
        )
        raise InputError(
            f"no usable record ({len(files)} files; {reasons}), expected at least one record "
            "whose fitted ω_g(t) is usable",
            folder,
        )
    combined: dict[str, float] = {}
    stderr: dict[str, float] = {}
    for key in COMBINED:
        values = [float(getattr(f.fit.model, key)) for f in usable]
        errors = [float(f.fit.stderr.get(key, math.nan)) for f in usable]
        combined[key], stderr[key] = _combine(values, errors)
    t_max = float(np.median([f.fit.model.t_max_s for f in usable]))
    t_dur = float(np.median([f.fit.model.t_dur_s for f in usable]))
    try:
        model = GroundMotionModel(
            **combined, t_max_s=t_max, t_dur_s=max(t_dur, t_max), alpha_reading=alpha_reading
        )
    except InputError as error:
        raise InputError(
            f"the combined parameters are inconsistent ({error.what})", folder
        ) from None
    peak = float(np.median([f.features.peak_intensity for f in usable]))
    return SiteFromRecords(tuple(fits), model, stderr, peak, tuple(failures))
