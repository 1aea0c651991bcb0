"""Reports made from a user's inputs (``stepframe report amplification | selection``).

Each function checks the inputs, builds what the report needs (the site from its parameters or
its records, the frame), records the provenance (the command line that reproduces the report,
the input files with their SHA-256, the parameters) and writes the report;
:func:`report_summary` describes the file written.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.options import option
from stepframe.errors import InputError
from stepframe.pipeline.site import SITE_PARAMETERS

if TYPE_CHECKING:
    from stepframe.stochastic.model import AlphaReading


def command_line(words: list[str], parameters: Mapping[str, Any]) -> str:
    """The command line ``words --name value ...`` that reproduces a report (shell-quoted)."""
    import shlex

    for name, value in parameters.items():
        words = [*words, f"--{name.replace('_', '-')}", str(value)]
    return shlex.join(words)


@dataclass(frozen=True)
class AmplificationReportOptions:
    """The site (its parameters or a folder of its records), the optional frame and the analysis
    of an amplification report (``stepframe report amplification``)."""

    fp_hz: float | None = option(None, "P-wave dominant f_p [Hz]", kind="positive", metavar="F")
    fs_hz: float | None = option(None, "S-wave dominant f_s [Hz]", kind="positive", metavar="F")
    fr_hz: float | None = option(None, "surface-wave f_r [Hz]", kind="positive", metavar="F")
    xi_p: float | None = option(None, "bandwidth ratio ξ_p", kind="positive", metavar="X")
    xi_r: float | None = option(None, "bandwidth ratio ξ_r", kind="positive", metavar="X")
    t_max_s: float | None = option(None, "time of peak I_g [s]", kind="positive", metavar="T")
    t_dur_s: float | None = option(None, "strong duration [s]", kind="positive", metavar="T")
    records: str | None = option(None, "a folder of the site's record files", metavar="DIR")
    t0: str = option(
        "auto",
        "with --records: time origin, the picked P onset when reliable, else the record "
        "start (auto, the default), or one of them",
        choices=("auto", "start", "p-pick"),
    )
    record_format: str | None = option(
        None, "with --records: file format if not sniffed", metavar="NAME", flag="--format"
    )
    units: str | None = option(None, "with --records: units if the files lack them", metavar="UNIT")
    site_name: str | None = option(None, "named in titles", metavar="NAME")
    frame: str | None = option(None, "frame file: band and frame-driven run", metavar="FRAME.toml")
    delta_star_m: float | None = option(
        None,
        "the frame's design displacement δ* [m] (stepframe structure design)",
        kind="positive",
        metavar="D",
    )
    alpha_reading: AlphaReading = option(
        "eq-6-11",
        "α_g ramp ends at t_dur (eq. 6.11 as printed, default) or at t_max (the paper)",
        choices=("eq-6-11", "paper"),
        flag="--alpha-at-tmax",
    )
    xi0: float = option(0.05, "oscillator damping (default 0.05)", kind="float", metavar="X")
    monte_carlo: int = option(
        50,
        "synthetic motions at each of 4 Monte Carlo frequencies (default 50; 0: none)",
        kind="int",
        metavar="N",
    )
    seed: int | None = option(1, "Monte Carlo seed (default 1)", kind="int")
    n_steps: int = option(2000, "time steps (default 2000)", kind="int", metavar="N")
    peak_intensity_m_s2: float | None = option(
        None,
        "peak I_g [m/s²] of the frame-driven run (default: the records' median, else 1)",
        kind="positive",
        metavar="I",
    )


def make_amplification_report(out_html: str, options: AmplificationReportOptions) -> Path:
    """The amplification report of a site given by its parameters or by a folder of its records.

    Parameters
    ----------
    out_html
        The HTML file.
    options
        :class:`AmplificationReportOptions`: all of
        :data:`~stepframe.pipeline.site.SITE_PARAMETERS`, or none with ``records`` (fitted
        with ``t0``, ``record_format`` and ``units``:
        :func:`~stepframe.pipeline.reports.site.site_from_records`); the name in titles
        (default: the records folder's name, else ``site``); an optional frame file and its
        design displacement δ* [m]; the analysis
        (:class:`~stepframe.pipeline.reports.amplification.AmplificationOptions`).

    Returns
    -------
    pathlib.Path
        The HTML file.
    """
    from stepframe.pipeline.reports.amplification import (
        AmplificationOptions,
        write_amplification_report,
    )
    from stepframe.pipeline.reports.provenance import collect_provenance

    o = options
    parameters = {name: getattr(o, name) for name in SITE_PARAMETERS}
    given = [name for name in SITE_PARAMETERS if parameters[name] is not None]
    if o.records is not None and given:
        raise InputError(
            f"--records with --{given[0].replace('_', '-')}, expected either the site "
            "parameters or --records"
        )
    missing = [name for name in SITE_PARAMETERS if parameters[name] is None]
    if o.records is None and missing:
        raise InputError(
            f"missing --{missing[0].replace('_', '-')}, expected all of "
            + ", ".join("--" + n.replace("_", "-") for n in SITE_PARAMETERS)
            + " or --records DIR"
        )
    if not (math.isfinite(o.xi0) and 0 < o.xi0 < 1):
        raise InputError(f"--xi0 {o.xi0}, expected a damping fraction 0 < ξ0 < 1 (e.g. 0.05)")
    if o.monte_carlo < 0 or o.monte_carlo == 1:
        raise InputError(f"--monte-carlo {o.monte_carlo}, expected 0 (none) or N ≥ 2")
    if o.n_steps < 100:
        raise InputError(f"--n-steps {o.n_steps}, expected at least 100")
    if o.frame is None and o.delta_star_m is not None:
        raise InputError("--delta-star-m without --frame, expected --frame FRAME.toml with it")
    site: Any
    inputs: list[str] = []
    if o.records is not None:
        from stepframe.pipeline.reports.site import site_from_records

        site = site_from_records(
            o.records, alpha_reading=o.alpha_reading, t0=o.t0, record_format=o.record_format,
            units=o.units,
        )  # fmt: skip
        inputs.append(o.records)
        name = o.site_name or Path(o.records).resolve().name
    else:
        from stepframe.stochastic.model import GroundMotionModel

        values = {key: float(value) for key, value in parameters.items() if value is not None}
        site = GroundMotionModel.from_hz(
            values["fp_hz"], values["fs_hz"], values["fr_hz"], values["xi_p"], values["xi_r"],
            t_max_s=values["t_max_s"], t_dur_s=values["t_dur_s"], alpha_reading=o.alpha_reading,
        )  # fmt: skip
        name = o.site_name or "site"
    portal = None
    if o.frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        portal = read_frame_file(o.frame)
        inputs.append(o.frame)
    analysis = AmplificationOptions(
        site_name=name, xi0=o.xi0, monte_carlo=o.monte_carlo, seed=o.seed, n_steps=o.n_steps,
        peak_intensity_m_s2=o.peak_intensity_m_s2, delta_star_m=o.delta_star_m, t0=o.t0,
    )  # fmt: skip
    recorded = {
        **parameters,
        "records": o.records,
        "t0": o.t0,
        "frame": o.frame,
        "delta_star_m": o.delta_star_m,
        "alpha_at_tmax": o.alpha_reading,
        "xi0": o.xi0,
        "monte_carlo": o.monte_carlo,
        "seed": o.seed,
        "n_steps": o.n_steps,
        "peak_intensity_m_s2": o.peak_intensity_m_s2,
    }
    recorded = {key: value for key, value in recorded.items() if value is not None}
    command = command_line(["stepframe", "report", "amplification"], recorded | {"out": out_html})
    provenance = collect_provenance(command, inputs=inputs, parameters=recorded)
    return write_amplification_report(
        site, out_html, frame=portal, options=analysis, provenance=provenance
    )


def make_selection_report(selection_dir: str, out_html: str | None = None) -> Path:
    """The selection report of a selection output folder (default file: its
    ``selection_report.html``); the folder is checked before anything is hashed."""
    from stepframe.pipeline.reports.provenance import collect_provenance
    from stepframe.pipeline.reports.selection import write_selection_report
    from stepframe.pipeline.reports.selection_folder import read_selection_folder

    outputs = read_selection_folder(selection_dir)
    command = command_line(
        ["stepframe", "report", "selection", selection_dir],
        {} if out_html is None else {"out": out_html},
    )
    provenance = collect_provenance(
        command, inputs=outputs.files, parameters={"outdir": selection_dir}
    )
    return write_selection_report(selection_dir, out_html, provenance=provenance)


def report_summary(out_html: str | PathLike[str]) -> tuple[dict[str, Any], str]:
    """What was written: ``{"report", "data_folder", "size_bytes"}`` and a line of text."""
    from stepframe.pipeline.reports.document import data_folder_of

    out = Path(out_html)
    folder = data_folder_of(out)
    size = out.stat().st_size
    data = {"report": str(out), "data_folder": str(folder), "size_bytes": size}
    return data, f"report: {out} ({size / 1e3:.0f} kB); its numbers: {folder}/"


__all__ = [
    "AmplificationReportOptions",
    "command_line",
    "make_amplification_report",
    "make_selection_report",
    "report_summary",
]
