"""The site model: a Beck-Papadimitriou ground-motion model with its peak intensity.

A site is given by its parameters (the P-, S- and surface-wave dominant frequencies, bandwidth
ratios and times of eqs. 6.10-6.11), fitted to one record (features, then the fit), or combined
from the fits of many records: :func:`site_from_features` is the one combination, used by the
workflow's ``site`` stage (on its ``features`` table) and by ``stepframe report amplification
--records`` (:func:`site_from_records`, on the features of a folder from the same entry point
:func:`stepframe.stochastic.catalog_features.catalog_features`), so both give the same numbers.
The result is a :class:`SiteModel`, written and read back by :func:`write_site_model` and
:func:`read_site_model`.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import SITE_PARAMETERS

if TYPE_CHECKING:
    import pandas as pd
    from obspy import Trace

    from stepframe.pipeline.catalogue.fit_options import FitOptions
    from stepframe.stochastic.features import TimeOrigin
    from stepframe.stochastic.model import AlphaReading, GroundMotionModel

#: How the fits of a site's records are combined (:func:`site_from_features`).
SiteStatistic = Literal["median", "mean", "inverse-variance"]
SITE_STATISTICS: tuple[SiteStatistic, ...] = ("median", "mean", "inverse-variance")

#: The parameters combined with their standard errors; t_max, t_dur and the peak intensity are
#: combined by the median (the mean with ``statistic="mean"``).
COMBINED = ("omega_p_rad_s", "omega_s_rad_s", "omega_r_rad_s", "xi_p", "xi_r")

#: Asymptotic efficiency factor of the median of a normal sample: SE(median) ≈ 1.2533 σ/√n.
MEDIAN_SE_FACTOR = math.sqrt(math.pi / 2)


@dataclass(frozen=True)
class SiteModel:
    """A site's ground-motion model and where it came from.

    Attributes
    ----------
    model
        The Beck-Papadimitriou model (ω_g(t), α_g(t), eqs. 6.10-6.11).
    peak_intensity_m_s2
        max I_g [m/s²]: the record's, or 1 for a site given by parameters.
    source
        ``{"site": "parameters"}``, or ``record``, ``component``, ``fit_quality`` and ``flags``
        of the record it was fitted to.
    stderr
        Standard errors of the parameters of :data:`COMBINED` (rad/s or -) of a site combined
        from records (:func:`site_from_features`); empty for a site given by its parameters.
    """

    model: GroundMotionModel
    peak_intensity_m_s2: float = 1.0
    source: dict[str, Any] = field(default_factory=lambda: {"site": "parameters"})
    stderr: dict[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (the model's fields, the intensity, the source, standard errors)."""
        return {
            "ground_motion_model": self.model.to_dict(),
            "peak_intensity_m_s2": self.peak_intensity_m_s2,
            "source": dict(self.source),
            # JSON has no NaN: a parameter without a standard error is left out
            "stderr": {k: v for k, v in self.stderr.items() if math.isfinite(v)},
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> SiteModel:
        """Inverse of :meth:`to_dict`."""
        from stepframe.stochastic.model import GroundMotionModel

        return cls(
            GroundMotionModel.from_dict(data["ground_motion_model"]),
            float(data["peak_intensity_m_s2"]),
            dict(data["source"]),
            {str(k): float(v) for k, v in data.get("stderr", {}).items()},
        )


def site_from_parameters(
    fp_hz: float,
    fs_hz: float,
    fr_hz: float,
    xi_p: float,
    xi_r: float,
    *,
    t_max_s: float,
    t_dur_s: float,
    alpha_reading: AlphaReading = "eq-6-11",
) -> SiteModel:
    """The site of given dominant frequencies [Hz], bandwidth ratios and times [s]."""
    from stepframe.stochastic.model import GroundMotionModel

    model = GroundMotionModel.from_hz(
        fp_hz, fs_hz, fr_hz, xi_p, xi_r, t_max_s=t_max_s, t_dur_s=t_dur_s,
        alpha_reading=alpha_reading,
    )  # fmt: skip
    return SiteModel(model, 1.0, {"site": "parameters"})


@dataclass(frozen=True)
class CombinedSite:
    """A site combined from the fits of its records (:func:`site_from_features`).

    Attributes
    ----------
    site
        The site model, its peak intensity and its ``source`` (statistic, components used).
    stderr
        Standard error of each of :data:`COMBINED` (rad/s or -).
    used
        The features table's rows that entered the combination.
    """

    site: SiteModel
    stderr: dict[str, float]
    used: pd.DataFrame

    @property
    def model(self) -> GroundMotionModel:
        """The combined ground-motion model."""
        return self.site.model


def _statistic(values: Any, errors: Any, statistic: SiteStatistic) -> tuple[float, float]:
    """The combined value and its standard error (the fit's own when there is one value)."""
    import numpy as np

    x = np.asarray(values, dtype=np.float64)
    se = np.asarray(errors, dtype=np.float64)
    # In value order: the sums of the mean and the scatter round by their order, and the rows'
    # order follows the files' names, which do not change the site (a workspace whose folder
    # once held a copy of a file gave an xi_p stderr one unit of the last digit away from a
    # fresh run's).
    order = np.lexsort((se, x))
    x, se = x[order], se[order]
    if x.size == 1:
        return float(x[0]), float(se[0])
    scatter = float(np.std(x, ddof=1) / math.sqrt(x.size))
    if statistic == "median":
        return float(np.median(x)), MEDIAN_SE_FACTOR * scatter
    if statistic == "inverse-variance" and np.all(np.isfinite(se) & (se > 0)):
        weight = 1.0 / se**2
        return float(np.sum(weight * x) / np.sum(weight)), float(1.0 / math.sqrt(np.sum(weight)))
    # the mean (or an inverse-variance mean whose fits gave no standard error)
    return float(np.mean(x)), scatter


def site_from_features(
    features: pd.DataFrame,
    *,
    statistic: SiteStatistic = "median",
    plausible_only: bool = True,
    alpha_reading: AlphaReading = "eq-6-11",
    name: str = "records",
) -> CombinedSite:
    """The site of many records: each fitted parameter combined over the components used.

    Parameters
    ----------
    features
        A features table (:data:`stepframe.stochastic.catalog_features.COLUMNS`), fitted with
        ``alpha_reading``.
    statistic
        ``"median"`` (default; its standard error is 1.2533 times the scatter's), ``"mean"``
        (the scatter's standard error) or ``"inverse-variance"`` (weighted by each fit's own
        standard error; its error 1/√Σw ignores the scatter between records). The records of a
        site are different realisations: the scatter between them is most of the uncertainty,
        which the median states and the inverse-variance mean does not (docs/amplification.md).
    plausible_only
        Only components that pass the plausibility checks (column ``plausible``).
    alpha_reading
        The reading of eq. 6.11 the table was fitted with, given to the model.
    name
        What the site's ``source`` calls the records.

    Raises
    ------
    InputError
        No component to use, or combined parameters that break ω_p ≥ ω_s ≥ ω_r (possible with
        the inverse-variance mean only: the median and the mean are monotone).
    """
    from stepframe.stochastic.model import GroundMotionModel

    if statistic not in SITE_STATISTICS:
        raise InputError(f"statistic {statistic!r}, expected one of {', '.join(SITE_STATISTICS)}")
    used = features[features["plausible"].astype(bool)] if plausible_only else features
    if used.empty:
        raise InputError(
            "no component with fitted features"
            + " passing the plausibility checks" * plausible_only
            + f" ({len(features)} in the table), expected at least one for a site from records"
            + implausible_detail(features)
        )
    values: dict[str, float] = {}
    stderr: dict[str, float] = {}
    for key in COMBINED:
        values[key], stderr[key] = _statistic(
            used[key].astype(float), used[f"{key}_stderr"].astype(float), statistic
        )
    central = "mean" if statistic == "mean" else "median"
    for key in ("t_max_s", "t_dur_s", "max_intensity_m_s2"):  # in value order, as above
        values[key] = float(getattr(used[key].astype(float).sort_values(), central)())
    try:
        model = GroundMotionModel(
            **{key: values[key] for key in (*COMBINED, "t_max_s", "t_dur_s")},
            alpha_reading=alpha_reading,
        )
    except InputError as error:
        raise InputError(f"the combined parameters are inconsistent ({error.what})") from None
    source = {
        "site": name,
        "statistic": statistic,
        "plausible_only": plausible_only,
        "n_components": len(used),
    }
    site = SiteModel(model, values["max_intensity_m_s2"], source, stderr)
    return CombinedSite(site, stderr, used)


#: Components whose reasons an error names (the rest counted): a workflow's catalogue may hold
#: thousands, and the message is one line of its summary and run log.
MAX_REASONS = 10


def implausible_detail(features: pd.DataFrame) -> str:
    """Why each component of ``features`` that fails the plausibility checks fails them, as the
    tail of a one-line error (" (FILE [COMPONENT]: reason; ...)"), or "" for none: the same
    words for ``report amplification --records`` and a workflow's ``site`` stage (which said
    only "(3 in the table)")."""
    if "plausible" not in features or "implausible_reason" not in features:
        return ""
    flagged = features[~features["plausible"].astype(bool)]
    reasons = [
        f"{file} [{component}]: {reason}"
        for file, component, reason in zip(
            flagged["file"], flagged["component"], flagged["implausible_reason"], strict=True
        )
    ]
    if len(reasons) > MAX_REASONS:
        more = len(reasons) - MAX_REASONS
        reasons = [*reasons[:MAX_REASONS], f"and {more} more (the features table says why)"]
    return f" ({'; '.join(reasons)})" if reasons else ""


@dataclass(frozen=True)
class SiteFromRecords:
    """A site from a folder of its records: every component's features and fit, the failures,
    and the combination (:func:`site_from_records`).

    Attributes
    ----------
    combined
        :func:`site_from_features` of ``features``.
    features
        One row per component that gave a fit (the catalogue's features table).
    failures
        Components that could not be read, measured or fitted (item, stage, error, message).
    folder
        The records folder.
    options
        How the records were read and fitted (:class:`stepframe.pipeline.catalogue.fit_options.
        FitOptions`) and their read options.
    files_in_folder
        Whether the table's ``file`` is relative to ``folder`` (a workflow's features table,
        which names files inside the records folder) rather than a path as listed.
    """

    combined: CombinedSite
    features: pd.DataFrame
    failures: pd.DataFrame
    folder: Path
    options: FitOptions
    record_options: dict[str, Any]
    files_in_folder: bool = False

    def record_path(self, file: str) -> Path:
        """Where the record of a features row's ``file`` is read again."""
        return self.folder / file if self.files_in_folder else Path(file)

    @property
    def model(self) -> GroundMotionModel:
        """The combined ground-motion model."""
        return self.combined.model

    @property
    def stderr(self) -> dict[str, float]:
        """Standard errors of the combined parameters."""
        return self.combined.stderr

    @property
    def peak_intensity_m_s2(self) -> float:
        """The combined peak intensity [m/s²]."""
        return self.combined.site.peak_intensity_m_s2


def site_from_records(
    folder: str | PathLike[str],
    *,
    options: FitOptions | None = None,
    record_options: Mapping[str, Any] | None = None,
    statistic: SiteStatistic = "median",
    plausible_only: bool = True,
    jobs: int | None = 1,
) -> SiteFromRecords:
    """Fit every component of a folder of a site's records and combine the fits.

    The features come from the one entry point
    (:func:`stepframe.stochastic.catalog_features.catalog_features`, as the workflow's
    ``features`` stage) and the combination from :func:`site_from_features` (as its ``site``
    stage), so ``report amplification --records DIR`` and a workflow over ``DIR`` give the same
    site.

    Parameters
    ----------
    folder
        The site's record files (any format :func:`stepframe.records.read` sniffs).
    options
        How each component is fitted (estimator, time origin, window, α_g reading).
    record_options
        Keyword arguments of :func:`stepframe.records.read` (``format``, ``units``, ...).
    statistic, plausible_only
        As :func:`site_from_features`.
    jobs
        Worker processes.

    Raises
    ------
    InputError
        Not a folder, no record file, or no component to combine (each failure named).
    """
    from stepframe.pipeline.catalogue.fit_options import FitOptions
    from stepframe.stochastic.catalog_features import catalog_features

    opts = options or FitOptions()
    read_options = {k: v for k, v in (record_options or {}).items() if v is not None}
    from stepframe.records.catalog import record_files

    root = Path(folder)
    if not root.is_dir():
        raise InputError("not a folder, expected a folder of the site's record files", root)
    if not record_files(root):
        raise InputError("no record files, expected a folder of the site's records", root)
    # A copy of a record is read once (catalog_features lists it with the failures), as the
    # workflow's inventory: counted twice it would shrink the median's standard error by √2.
    table, failures = catalog_features(
        root, n_jobs=jobs, record_options=read_options, **opts.catalog_kwargs()
    )
    try:
        combined = site_from_features(
            table,
            statistic=statistic,
            plausible_only=plausible_only,
            alpha_reading=opts.alpha_reading,
            name=root.name,
        )
    except InputError as error:  # the fits' reasons are in it; the files that gave none too
        reasons = [f"{row.item}: {row.message}" for row in failures.itertuples()]
        detail = f" (not fitted: {'; '.join(reasons)})" if reasons else ""
        raise InputError(f"{error.what}{detail}", root) from None
    return SiteFromRecords(combined, table, failures, root, opts, read_options)


def site_from_record(
    trace: Trace,
    *,
    t0: TimeOrigin = "auto",
    alpha_reading: AlphaReading = "eq-6-11",
    name: str | PathLike[str] | None = None,
) -> SiteModel:
    """The site fitted to one record component (features, then the B-P fit).

    Parameters
    ----------
    trace
        The record, an ``obspy.Trace`` in m/s².
    t0
        Time origin of eqs. 6.10-6.11: record start or the picked P onset.
    alpha_reading
        Where the α_g ramp ends (eq. 6.11 as printed, or the paper's t_max).
    name
        The record's file, named in errors and in ``source``.
    """
    from stepframe.stochastic.features import record_features
    from stepframe.stochastic.fit import fit_model

    try:
        features = record_features(trace, t0=t0)
        fitted = fit_model(features, alpha_reading=alpha_reading)
    except InputError as error:
        raise InputError(error.what, name) from None
    source: dict[str, Any] = {
        "record": None if name is None else str(name),
        "component": trace.stats.channel,
        "fit_quality": fitted.fit_quality,
        "flags": list(fitted.flags),
    }
    return SiteModel(fitted.model, float(features.peak_intensity), source)


def read_one_component(
    path: str | PathLike[str], record_options: Mapping[str, Any] | None = None
) -> Trace:
    """The one component of a record file (an error names the file if it holds several)."""
    from stepframe.records import read

    stream = read(path, **dict(record_options or {}))
    if len(stream) != 1:
        raise InputError(
            f"{len(stream)} components in the file, expected one (choose it with --component)",
            path,
        )
    return stream[0]


def site_from_options(
    parameters: Mapping[str, float | None],
    *,
    record: str | PathLike[str] | None = None,
    record_options: Mapping[str, Any] | None = None,
    t0: TimeOrigin = "auto",
    alpha_reading: AlphaReading = "eq-6-11",
) -> SiteModel:
    """The site from either all of :data:`SITE_PARAMETERS` or a record file (not both).

    Parameters
    ----------
    parameters
        :data:`SITE_PARAMETERS` → value, or None where not given.
    record
        A record file to fit instead (one component).
    record_options
        Keyword arguments of :func:`stepframe.records.read` (``format``, ``units``, ``dt``, ...).
    t0, alpha_reading
        As :func:`site_from_record` (``alpha_reading`` applies to both routes).
    """
    given = [name for name in SITE_PARAMETERS if parameters.get(name) is not None]
    if record is not None:
        if given:
            raise InputError(
                f"--record with --{given[0].replace('_', '-')}, expected either the site "
                "parameters or --record"
            )
        trace = read_one_component(record, record_options)
        return site_from_record(trace, t0=t0, alpha_reading=alpha_reading, name=record)
    values: dict[str, float] = {}
    for name in SITE_PARAMETERS:
        value = parameters.get(name)
        if value is None:
            hint = (
                " (the envelope's times: `stepframe stochastic fit` prints t_max_s and t_dur_s of "
                "a record of the site; the paper's site has 5 and 20 s)"
                if name in ("t_max_s", "t_dur_s")
                else ""
            )
            raise InputError(
                f"missing --{name.replace('_', '-')}, expected all of "
                + ", ".join("--" + n.replace("_", "-") for n in SITE_PARAMETERS)
                + f" or --record FILE{hint}"
            )
        values[name] = float(value)
    return site_from_parameters(
        values["fp_hz"], values["fs_hz"], values["fr_hz"], values["xi_p"], values["xi_r"],
        t_max_s=values["t_max_s"], t_dur_s=values["t_dur_s"], alpha_reading=alpha_reading,
    )  # fmt: skip


def write_site_model(site: SiteModel, path: str | PathLike[str]) -> Path:
    """Write the site model as JSON (atomically); :func:`read_site_model` reads it back."""
    from stepframe.core.io import atomic_write  # not at import: the CLI reads SITE_PARAMETERS

    with atomic_write(path) as out:
        json.dump(site.to_dict(), out, indent=2, allow_nan=False)
        out.write("\n")
    return Path(path)


def read_site_model(path: str | PathLike[str]) -> SiteModel:
    """The site model written by :func:`write_site_model`."""
    target = Path(path)
    try:
        data = json.loads(target.read_text(encoding="utf-8"))
        return SiteModel.from_dict(data)
    except FileNotFoundError:
        raise InputError("no such file, expected a site model (JSON)", target) from None
    except (ValueError, KeyError, TypeError) as error:
        raise InputError(
            f"not a site model ({error}), expected a site model JSON", target
        ) from None


__all__ = [
    "COMBINED",
    "SITE_PARAMETERS",
    "SITE_STATISTICS",
    "CombinedSite",
    "SiteFromRecords",
    "SiteModel",
    "SiteStatistic",
    "read_one_component",
    "read_site_model",
    "site_from_features",
    "site_from_options",
    "site_from_parameters",
    "site_from_record",
    "site_from_records",
    "write_site_model",
]
