"""Stage: the site model, a Beck-Papadimitriou ground-motion model with its peak intensity.

A site is given by its parameters (the P-, S- and surface-wave dominant frequencies, bandwidth
ratios and times of eqs. 6.10-6.11) or estimated from a record (features, then the fit). Either
way the result is a :class:`SiteModel`, which can be written and read back
(:func:`write_site_model`, :func:`read_site_model`).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.errors import InputError

if TYPE_CHECKING:
    from obspy import Trace

    from stepframe.stochastic.features import TimeOrigin
    from stepframe.stochastic.model import AlphaReading, GroundMotionModel

#: Names of the site parameters, as the ``stochastic amplify`` options spell them.
SITE_PARAMETERS = ("fp_hz", "fs_hz", "fr_hz", "xi_p", "xi_r", "t_max_s", "t_dur_s")


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
    """

    model: GroundMotionModel
    peak_intensity_m_s2: float = 1.0
    source: dict[str, Any] = field(default_factory=lambda: {"site": "parameters"})

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready form (the model's fields, the intensity, the source)."""
        return {
            "ground_motion_model": self.model.to_dict(),
            "peak_intensity_m_s2": self.peak_intensity_m_s2,
            "source": dict(self.source),
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> SiteModel:
        """Inverse of :meth:`to_dict`."""
        from stepframe.stochastic.model import GroundMotionModel

        return cls(
            GroundMotionModel.from_dict(data["ground_motion_model"]),
            float(data["peak_intensity_m_s2"]),
            dict(data["source"]),
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
    "SITE_PARAMETERS",
    "SiteModel",
    "read_one_component",
    "read_site_model",
    "site_from_options",
    "site_from_parameters",
    "site_from_record",
    "write_site_model",
]
