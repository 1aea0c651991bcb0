"""Reports made from a user's inputs (``stepframe report amplification | selection``).

Each function checks the inputs, builds what the report needs (the site from its parameters or
its records, the frame), records the provenance (the command line that reproduces the report,
the input files with their SHA-256, the parameters) and writes the report;
:func:`report_summary` describes the file written.
"""

from __future__ import annotations

import math
import shlex
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from stepframe.errors import InputError
from stepframe.pipeline.site import SITE_PARAMETERS


def command_line(words: list[str], parameters: Mapping[str, Any]) -> str:
    """The command line ``words --name value ...`` that reproduces a report (shell-quoted)."""
    for name, value in parameters.items():
        words = [*words, f"--{name.replace('_', '-')}", str(value)]
    return shlex.join(words)


def make_amplification_report(
    out_html: str,
    *,
    parameters: Mapping[str, float | None],
    records: str | None = None,
    t0: str = "auto",
    record_format: str | None = None,
    units: str | None = None,
    site_name: str | None = None,
    frame: str | None = None,
    delta_star_m: float | None = None,
    alpha_reading: Any = "eq-6-11",
    xi0: float = 0.05,
    monte_carlo: int = 50,
    seed: int | None = 1,
    n_steps: int = 2000,
    peak_intensity_m_s2: float | None = None,
) -> Path:
    """The amplification report of a site given by its parameters or by a folder of its records.

    Parameters
    ----------
    out_html
        The HTML file.
    parameters
        :data:`~stepframe.pipeline.site.SITE_PARAMETERS` → value (None: not given); all of
        them, or none with ``records``.
    records, t0, record_format, units
        A folder of the site's record files, the fits' time origin and the read options
        (:func:`~stepframe.pipeline.reports.site.site_from_records`).
    site_name
        Named in titles (default: the records folder's name, else ``site``).
    frame, delta_star_m
        Optional frame file, and its design displacement δ* [m] (needs ``frame``).
    alpha_reading, xi0, monte_carlo, seed, n_steps, peak_intensity_m_s2
        As :class:`~stepframe.pipeline.reports.amplification.AmplificationOptions`.

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

    given = [name for name in SITE_PARAMETERS if parameters.get(name) is not None]
    if records is not None and given:
        raise InputError(
            f"--records with --{given[0].replace('_', '-')}, expected either the site "
            "parameters or --records"
        )
    missing = [name for name in SITE_PARAMETERS if parameters.get(name) is None]
    if records is None and missing:
        raise InputError(
            f"missing --{missing[0].replace('_', '-')}, expected all of "
            + ", ".join("--" + n.replace("_", "-") for n in SITE_PARAMETERS)
            + " or --records DIR"
        )
    if not (math.isfinite(xi0) and 0 < xi0 < 1):
        raise InputError(f"--xi0 {xi0}, expected a damping fraction 0 < ξ0 < 1 (e.g. 0.05)")
    if monte_carlo < 0 or monte_carlo == 1:
        raise InputError(f"--monte-carlo {monte_carlo}, expected 0 (none) or N ≥ 2")
    if n_steps < 100:
        raise InputError(f"--n-steps {n_steps}, expected at least 100")
    if frame is None and delta_star_m is not None:
        raise InputError("--delta-star-m without --frame, expected --frame FRAME.toml with it")
    site: Any
    inputs: list[str] = []
    if records is not None:
        from stepframe.pipeline.reports.site import site_from_records

        site = site_from_records(
            records, alpha_reading=alpha_reading, t0=t0, record_format=record_format, units=units
        )
        inputs.append(records)
        name = site_name or Path(records).resolve().name
    else:
        from stepframe.stochastic.model import GroundMotionModel

        values = {key: float(value) for key, value in parameters.items() if value is not None}
        site = GroundMotionModel.from_hz(
            values["fp_hz"], values["fs_hz"], values["fr_hz"], values["xi_p"], values["xi_r"],
            t_max_s=values["t_max_s"], t_dur_s=values["t_dur_s"], alpha_reading=alpha_reading,
        )  # fmt: skip
        name = site_name or "site"
    portal = None
    if frame is not None:
        from stepframe.structure.frame_file import read_frame_file

        portal = read_frame_file(frame)
        inputs.append(frame)
    options = AmplificationOptions(
        site_name=name, xi0=xi0, monte_carlo=monte_carlo, seed=seed, n_steps=n_steps,
        peak_intensity_m_s2=peak_intensity_m_s2, delta_star_m=delta_star_m, t0=t0,
    )  # fmt: skip
    recorded = {
        **parameters,
        "records": records,
        "t0": t0,
        "frame": frame,
        "delta_star_m": delta_star_m,
        "alpha_at_tmax": alpha_reading,
        "xi0": xi0,
        "monte_carlo": monte_carlo,
        "seed": seed,
        "n_steps": n_steps,
        "peak_intensity_m_s2": peak_intensity_m_s2,
    }
    recorded = {key: value for key, value in recorded.items() if value is not None}
    command = command_line(["stepframe", "report", "amplification"], recorded | {"out": out_html})
    provenance = collect_provenance(command, inputs=inputs, parameters=recorded)
    return write_amplification_report(
        site, out_html, frame=portal, options=options, provenance=provenance
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


__all__ = ["command_line", "make_amplification_report", "make_selection_report", "report_summary"]
