"""Fixtures of the report tests: the two reports built once per module, and the browser.

The helper modules beside this file (``browser.py``, ``selection_fixture.py``) are loaded by path:
pytest runs with ``--import-mode=importlib``, where test folders are not on ``sys.path``.
"""

from __future__ import annotations

import importlib.util
import os
import shutil
import sys
from collections.abc import Callable
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

HERE = Path(__file__).parent


def _load(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(
        f"stepframe_report_tests_{name}", HERE / f"{name}.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


browser_module = _load("browser")
selection_fixture = _load("selection_fixture")

#: The paper's site (Section 6 worked example): f_p, f_s, f_r [Hz], ξ_p, ξ_r, t_max, t_dur [s].
PAPER_SITE = {
    "f_p_hz": 7.43,
    "f_s_hz": 3.12,
    "f_r_hz": 1.11,
    "xi_p": 0.096,
    "xi_r": 0.655,
    "t_max_s": 5.0,
    "t_dur_s": 20.0,
}


@pytest.fixture(scope="session")
def paper_model() -> Any:
    """The paper's site as a ground-motion model (the paper's α reading)."""
    from stepframe.stochastic.model import GroundMotionModel

    p = PAPER_SITE
    return GroundMotionModel.from_hz(
        p["f_p_hz"],
        p["f_s_hz"],
        p["f_r_hz"],
        p["xi_p"],
        p["xi_r"],
        t_max_s=p["t_max_s"],
        t_dur_s=p["t_dur_s"],
        alpha_reading="paper",
    )


@pytest.fixture(scope="session")
def frame_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Example 4's frame (the shipped template)."""
    from stepframe.structure.frame_file import frame_template

    path = tmp_path_factory.mktemp("frame") / "frame.toml"
    path.write_text(frame_template(), encoding="utf-8")
    return path


@pytest.fixture(scope="session")
def amplification_html(
    tmp_path_factory: pytest.TempPathFactory, paper_model: Any, frame_file: Path
) -> Path:
    """The paper's site's amplification report with Example 4's frame and δ* = 0.25 m."""
    from stepframe.pipeline.amplification.report import (
        AmplificationOptions,
        write_amplification_report,
    )
    from stepframe.pipeline.reports import collect_provenance
    from stepframe.structure.frame_file import read_frame_file

    out = tmp_path_factory.mktemp("amplification") / "paper_site.html"
    options = AmplificationOptions(
        site_name="paper's site", monte_carlo=40, seed=2, n_steps=1000, delta_star_m=0.25
    )
    provenance = collect_provenance(
        "pytest amplification", inputs=[frame_file], parameters={"monte_carlo": 40}
    )
    return write_amplification_report(
        paper_model,
        out,
        frame=read_frame_file(frame_file),
        options=options,
        provenance=provenance,
    )


#: Monte Carlo curves of the records report's band.
RECORDS_BAND_CURVES = 64

#: Example-catalogue rows of the site folder: Beverly Hills - Mulhol (both components, usable
#: fits) and Nishi-Akashi (its fit has ω_p at its bound: shown, flagged, not combined).
SITE_ROWS = (0, 1, 12)


@pytest.fixture(scope="session")
def site_records(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A site's record folder: three example-catalogue components written as SAC [m/s²]."""
    from stepframe.records.examples import fema_p695

    stream, _ = fema_p695()
    folder = tmp_path_factory.mktemp("site") / "beverly_hills"
    folder.mkdir()
    for row in SITE_ROWS:
        trace = stream[row]
        trace.write(str(folder / f"{row:02d}_{trace.stats.channel}.sac"), format="SAC")
    return folder


@pytest.fixture(scope="session")
def rsn8883_records(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The two horizontal components of RSN 8883 (tests/data); neither fit is usable."""
    source = HERE.parents[1] / "data" / "peer_nga_west2"
    folder = tmp_path_factory.mktemp("site") / "rsn8883"
    folder.mkdir()
    for path in sorted(source.glob("*.AT2")):
        shutil.copy(path, folder / path.name)
    return folder


@pytest.fixture(scope="session")
def records_amplification_html(
    tmp_path_factory: pytest.TempPathFactory, site_records: Path, frame_file: Path
) -> Path:
    """The amplification report of a site from its records, with Example 4's frame."""
    from stepframe.pipeline.amplification.report import (
        AmplificationOptions,
        write_amplification_report,
    )
    from stepframe.pipeline.amplification.site import site_from_records
    from stepframe.pipeline.catalogue.fit_options import FitOptions
    from stepframe.pipeline.reports import collect_provenance
    from stepframe.structure.frame_file import read_frame_file

    out = tmp_path_factory.mktemp("amplification_records") / "beverly_hills.html"
    # t0 = record start: Nishi-Akashi's fit then has ω_p at its bound (the unused-fit case)
    site = site_from_records(
        site_records, options=FitOptions(t0="start"), record_options={"units": "m/s2"}
    )
    # A Monte Carlo band of 64 curves: the default's 512 cost most of the report (the default
    # count is tested on the options), and the fixture is built on each worker that uses it.
    options = AmplificationOptions(
        site_name="Beverly Hills - Mulhol", monte_carlo=0, n_steps=1000, t0="start",
        band_samples=RECORDS_BAND_CURVES,
    )  # fmt: skip
    provenance = collect_provenance("pytest records", inputs=[site_records, frame_file])
    return write_amplification_report(
        site, out, frame=read_frame_file(frame_file), options=options, provenance=provenance
    )


@pytest.fixture(scope="session")
def arrivals_html(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The arrivals summary of a workflow run over two records of the example catalogue and
    RSN 8883's two AT2 files (three horizontal pairs), with their fits."""
    from stepframe.pipeline.catalogue.example_files import write_example_files
    from stepframe.pipeline.engine.runner import run_workflow
    from stepframe.pipeline.stages import shipped_stages

    folder = tmp_path_factory.mktemp("arrivals")
    write_example_files(folder / "inbox", count=4)
    for path in sorted((HERE.parents[1] / "data" / "peer_nga_west2").glob("*.AT2")):
        shutil.copy(path, folder / "inbox" / path.name)
    (folder / "wf.toml").write_text(
        'name = "nightly inbox"\n[records]\nfolder = "inbox"\n[outputs]\nfeatures = true\n'
        "measures = true\nrotd50 = true\narrivals_report = true\n",
        encoding="utf-8",
    )
    report = run_workflow(folder / "wf.toml", shipped_stages(), jobs=1)
    assert report.exit_code == 0, report.missing
    return folder / "stepframe-work" / "outputs" / "arrivals_report.html"


@pytest.fixture(scope="session")
def selection_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A selection output folder built from real example records (selection_fixture.py)."""
    return Path(
        selection_fixture.make_selection_folder(tmp_path_factory.mktemp("selection") / "out")
    )


@pytest.fixture(scope="session")
def selection_html(selection_dir: Path) -> Path:
    """The selection report of :func:`selection_dir`."""
    from stepframe.pipeline.reports import collect_provenance
    from stepframe.pipeline.selection.report import write_selection_report

    provenance = collect_provenance("pytest selection", inputs=[selection_dir / "selection.json"])
    return write_selection_report(selection_dir, provenance=provenance)


@pytest.fixture
def copy_of() -> Callable[[Path, Path], Path]:
    """Copy a folder (to damage it without touching the session's)."""

    def copy(source: Path, target: Path) -> Path:
        shutil.copytree(source, target)
        return target

    return copy


@pytest.fixture(scope="session")
def browser() -> str:
    """Path of headless Chromium; in CI (CI=true) its absence fails, elsewhere it skips."""
    found = browser_module.find_browser()
    if found is None:
        reason = "no Chromium browser found (install Debian's `chromium`; .ci/run does)"
        if os.environ.get("CI", "").lower() == "true":
            pytest.fail(reason + " and CI=true requires it")
        pytest.skip(reason)
    return str(found)


@pytest.fixture(scope="session")
def check_page() -> Callable[..., Any]:
    """browser.check_page: open a report in Chromium and report what it saw."""
    return browser_module.check_page  # type: ignore[no-any-return]


@pytest.fixture(scope="session")
def screenshot_dir(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """Where screenshots go: $STEPFRAME_SCREENSHOTS if set, else a pytest temporary folder."""
    given = os.environ.get("STEPFRAME_SCREENSHOTS")
    if given:
        path = Path(given)
        path.mkdir(parents=True, exist_ok=True)
        return path
    return tmp_path_factory.mktemp("screenshots")
