"""The amplification report's headlines hold (issue 30): maxima only where they are maxima, the
frame's stepping and the intensity at which it steps, δ* against x_c and x*, the band from the
parameters' standard errors, the site's frequencies on the figures, titles that fit."""

from __future__ import annotations

import html
import json
import math
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from stepframe.errors import InputError
from stepframe.pipeline.amplification.analysis import AmplificationOptions
from stepframe.pipeline.amplification.headlines import (
    ReportNumbers,
    curve_maxima,
    design_limits,
    extend_past_edges,
)
from stepframe.pipeline.reports.document import data_folder_of

from .conftest import RECORDS_BAND_CURVES


def _numbers(html: Path) -> dict[str, Any]:
    return dict(json.loads((data_folder_of(html) / "numbers.json").read_text()))


# -- maxima -------------------------------------------------------------------------------------


def _bump(f0_hz: np.ndarray, at_hz: float) -> np.ndarray:
    """A smooth curve with one maximum, 3 at ``at_hz``, on a log axis."""
    return 3.0 - (np.log10(f0_hz) - math.log10(at_hz)) ** 2


def test_a_maximum_beyond_the_grid_is_an_edge_not_a_maximum() -> None:
    f0 = np.geomspace(0.1, 10.0, 30)
    [edge] = curve_maxima(f0, _bump(f0, 15.0))
    assert edge.kind == "high-edge" and not edge.interior
    assert edge.f0_hz == pytest.approx(10.0) and "at the edge of the range, rising" in (
        edge.describe()
    )
    # inside the grid it is one: interior, with lower values on both sides
    [inside] = curve_maxima(f0, _bump(f0, 1.0))
    assert inside.interior and inside.f0_hz == pytest.approx(1.0, rel=0.09)


def test_the_grid_is_extended_until_the_curve_turns() -> None:
    f0 = np.geomspace(0.1, 10.0, 30)
    extended = extend_past_edges(f0, _bump(f0, 15.0), lambda f: _bump(f, 15.0))
    assert extended.added > 0 and extended.on_grid.sum() == 30
    [found] = curve_maxima(extended.f0_hz, extended.values)
    ratio = f0[1] / f0[0]
    assert found.interior and found.f0_hz == pytest.approx(15.0, rel=ratio - 1)
    # a maximum beyond a decade is not chased: the search stops at 100 Hz, an edge
    far = extend_past_edges(f0, _bump(f0, 500.0), lambda f: _bump(f, 500.0))
    assert far.f0_hz[-1] <= 100.0 * (1 + 1e-9)
    assert curve_maxima(far.f0_hz, far.values)[0].kind == "high-edge"


@pytest.fixture(scope="module")
def paper_reports(tmp_path_factory: pytest.TempPathFactory, paper_model: Any) -> dict[str, Path]:
    """The paper's site on its 0.1-10 Hz grid, as asked (grid only) and extended."""
    from stepframe.pipeline.amplification.report import write_amplification_report
    from stepframe.pipeline.reports import collect_provenance

    folder = tmp_path_factory.mktemp("headlines")
    out = {}
    for name, grid_only in (("grid_only", True), ("extended", False)):
        options = AmplificationOptions(
            site_name="paper's site", monte_carlo=0, n_steps=1000, n_frequencies=30,
            grid_only=grid_only,
        )  # fmt: skip
        out[name] = write_amplification_report(
            paper_model, folder / f"{name}.html", options=options,
            provenance=collect_provenance("pytest headlines"),
        )  # fmt: skip
    return out


def test_paper_site_its_largest_value_is_at_the_grids_edge(paper_reports: dict[str, Path]) -> None:
    numbers = _numbers(paper_reports["grid_only"])
    # 14.6 at 10 Hz, the "largest" (the paper's α reading): the curve still rises there
    assert numbers["max_response_vs_fixed_at_hz"] == pytest.approx(10.0)
    assert numbers["max_response_vs_fixed"] == pytest.approx(14.63, abs=0.01)
    assert numbers["max_response_vs_fixed_is_maximum"] is False
    kinds = {m["kind"] for m in numbers["response_maxima"]}
    assert kinds == {"low-edge", "high-edge"}  # it rises towards both edges
    html = paper_reports["grid_only"].read_text(encoding="utf-8")
    assert "14.6 at 10 Hz (at the edge of the range, rising)" in html


def test_paper_site_extended_grid_finds_both_maxima(
    paper_reports: dict[str, Path], paper_model: Any
) -> None:
    from stepframe.pipeline.amplification.amplify import amplification_curve
    from stepframe.pipeline.amplification.site import SiteModel

    numbers = _numbers(paper_reports["extended"])
    maxima = numbers["response_maxima"]
    assert [m["kind"] for m in maxima] == ["interior", "interior"]
    high, low = maxima  # largest first
    # the grid's last point turns out to be the maximum once the point past it is known
    assert 10.0 <= high["f0_hz"] < 13.0 and high["value"] >= 14.626
    assert 0.04 < low["f0_hz"] < 0.08
    # each is a maximum of the curve recomputed on its own, a grid step either side
    ratio = (10.0 / 0.1) ** (1 / 29)
    for found in (high, low):
        f = found["f0_hz"] * np.array([1 / ratio, 1.0, ratio])
        curve = amplification_curve(SiteModel(paper_model), f, 0.05, n_steps=1000)
        values = curve["response_amplification_vs_fixed"].values
        assert values[1] == pytest.approx(found["value"], rel=1e-9)
        assert values[1] > values[0] and values[1] > values[2]
    assert numbers["f0_grid_hz"] == [pytest.approx(0.1), pytest.approx(10.0)]
    assert numbers["f0_range_hz"][0] < 0.1 and numbers["f0_range_hz"][1] > 10.0
    table = (data_folder_of(paper_reports["extended"]) / "amplification.csv").read_text()
    assert table.count(",False,") > 0 and table.count(",True,") == 30


# -- the frame ----------------------------------------------------------------------------------


def test_a_frame_that_never_steps_says_so_and_when_it_would(
    paper_model: Any, frame_file: Path
) -> None:
    """At the default intensity (1 m/s²) Example 4's frame stays linear: amplification exactly
    1, and the onset intensity from the linear response is where stepping starts."""
    from stepframe.pipeline.amplification.frame_section import frame_part
    from stepframe.stochastic.mean_square import Constant, analysis_grid, mean_square_response
    from stepframe.structure.frame_file import read_frame_file

    frame = read_frame_file(frame_file)
    options = AmplificationOptions(n_steps=1000)
    stated = ReportNumbers()
    part = frame_part(frame, paper_model, 1.0, options, stated)
    assert not part.stepping.stepped and part.point[1] == 1.0
    assert stated.numbers["frame_stepped"] is False
    line = dict(stated.summary)["Frame-driven response amplification"]
    assert "did not step" in line and "it steps from I_g" in line
    # the onset recomputed: the frame held linear at ω_1 (a fixed oscillator, damping ξ_1) under
    # the site at I_g·p_1 reaches √2·σ_x = x_c at I_g = onset
    grid = analysis_grid(paper_model, n_steps=1000)
    linear = mean_square_response(
        paper_model, Constant(frame.omega_1_rad_s), frame.xi_1, time_s=grid,
        peak_intensity=frame.p_1,
    )  # fmt: skip
    onset = frame.x_c_m / (math.sqrt(2) * float(linear.peak_rms_m[0]))
    assert part.stepping.onset_intensity_m_s2 == pytest.approx(onset, rel=1e-9)
    below = frame_part(frame, paper_model, 0.97 * onset, options, ReportNumbers())
    above = frame_part(frame, paper_model, 1.03 * onset, options, ReportNumbers())
    assert not below.stepping.stepped and below.point[1] == 1.0
    assert above.stepping.stepped and above.point[1] > 1.0


def test_adjusted_design_displacement_beyond_x_star_is_a_warning(amplification_html: Path) -> None:
    """The conftest report: δ* = 0.25 m, Example 4's frame (x_c = 0.190 m, x* = 0.334 m)."""
    numbers = _numbers(amplification_html)
    limits = numbers["design_limits"]
    assert limits["x_star_m"] == pytest.approx(0.334, abs=5e-4)
    assert limits["delta_star"] == "between x_c and x*"
    # (ω_p/ω_s)² = (7.43/3.12)² adjusts δ* by its square root: 0.25·7.43/3.12 = 0.595 m > x*
    adjusted = numbers["adjusted_design_displacement_m"]["eq-6-19-last"]
    assert adjusted == pytest.approx(0.25 * 7.43 / 3.12, rel=1e-9)
    assert limits["eq-6-19-last"] == "at or beyond x*"
    [warning] = numbers["warnings"]
    assert "beyond failure" in warning and "eq-6-19-last gives 0.595 m" in warning
    html = amplification_html.read_text(encoding="utf-8")
    assert '<p class="warning"><strong>Warning.</strong> Adjusted design displacement' in html


def test_design_limits_place_each_value() -> None:
    states = {d.name: d.state for d in design_limits({"a": 0.1, "b": 0.2, "c": 0.334}, 0.19, 0.334)}
    assert states == {"a": "below x_c", "b": "between x_c and x*", "c": "at or beyond x*"}


def test_delta_star_at_or_beyond_x_star_is_refused(paper_model: Any, frame_file: Path) -> None:
    from stepframe.pipeline.amplification.frame_section import frame_part
    from stepframe.structure.frame_file import read_frame_file

    with pytest.raises(InputError, match=r"delta_star_m = 0.4 m ≥ x\* = 0.3339 m"):
        frame_part(read_frame_file(frame_file), paper_model, 1.0,
                   AmplificationOptions(delta_star_m=0.4), ReportNumbers())  # fmt: skip


def test_delta_star_beyond_x_star_is_refused_before_any_work(
    tmp_path: Path, frame_file: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The command refuses δ* ≥ x* before it reads the records (an empty folder would be the
    error otherwise), and a workflow names the key's line before anything runs."""
    from stepframe.cli import main

    empty = tmp_path / "no_records"
    empty.mkdir()
    out = tmp_path / "r.html"
    argv = ["report", "amplification", "--records", str(empty), "--frame", str(frame_file)]
    assert main([*argv, "--delta-star-m", "0.4", "-o", str(out)]) == 2
    assert "delta_star_m = 0.4 m ≥ x* = 0.3339 m" in capsys.readouterr().err
    assert main([*argv, "--delta-star-m", "0.3", "-o", str(out)]) == 2  # below x*: the folder
    assert "delta_star_m" not in capsys.readouterr().err
    workflow = tmp_path / "wf.toml"
    workflow.write_text(
        f'[site]\nfrom = "parameters"\nfp_hz = 7.43\nfs_hz = 3.12\nfr_hz = 1.11\nxi_p = 0.096\n'
        f'xi_r = 0.655\nt_max_s = 5.0\nt_dur_s = 20.0\n[frame]\nfile = "{frame_file}"\n'
        "[amplification_report]\ndelta_star_m = 0.4\n[outputs]\namplification_report = true\n",
        encoding="utf-8",
    )
    assert main(["run", str(workflow)]) == 2
    err = capsys.readouterr().err
    assert "wf.toml:13: [amplification_report] delta_star_m = 0.4 m ≥ x* = 0.3339 m" in err
    assert not (tmp_path / "stepframe-work").exists()


# -- the band -----------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def rsn8883_site() -> Any:
    from stepframe.pipeline.amplification.site import site_from_records

    return site_from_records(Path(__file__).parents[2] / "data" / "peer_nga_west2")


def test_delta_band_agrees_with_monte_carlo_when_the_errors_are_small(paper_model: Any) -> None:
    """Standard errors of 3 % on each parameter: the curve is near linear over them, and the
    delta method on ln A (11 curves) gives the Monte Carlo band (512 Sobol sets) within 5 %."""
    from stepframe.pipeline.amplification.band import VARIED, parameter_band

    stderr = {name: 0.03 * float(getattr(paper_model, name)) for name in VARIED}
    f0 = np.geomspace(0.1, 10.0, 8)
    delta = parameter_band(paper_model, stderr, f0, 0.05, n_steps=500, method="delta")
    mc = parameter_band(paper_model, stderr, f0, 0.05, n_steps=500, seed=5)
    assert delta is not None and mc is not None
    assert (delta.method, delta.n_curves) == ("delta", 11)
    assert (mc.method, mc.n_curves) == ("monte-carlo", 512)
    np.testing.assert_allclose(delta.low, mc.low, rtol=0.05)
    np.testing.assert_allclose(delta.high, mc.high, rtol=0.05)


def test_monte_carlo_band_sees_the_curvature_the_delta_method_misses(rsn8883_site: Any) -> None:
    """RSN 8883's two records give ω_p a standard error of 18 %: at 0.1 Hz the amplification
    runs from 2.1 to 6.3 over ω_p ± 2 SE around 4.6, concave even in ln A, so the lower edge
    of the band lies well below the delta method's."""
    from dataclasses import replace

    from stepframe.pipeline.amplification.band import parameter_band, vs_fixed_curve

    model, stderr = rsn8883_site.model, rsn8883_site.stderr
    f0 = np.array([0.1])
    se = stderr["omega_p_rad_s"]
    ends = [vs_fixed_curve(replace(model, omega_p_rad_s=model.omega_p_rad_s + z * se), f0,
                           0.05, 500)[0] for z in (-2.0, 0.0, 2.0)]  # fmt: skip
    assert ends[1] - ends[0] > 1.3 * (ends[2] - ends[1])  # a long lower tail: 2.49 against 1.71
    delta = parameter_band(model, stderr, f0, 0.05, n_steps=500, method="delta")
    mc = parameter_band(model, stderr, f0, 0.05, n_steps=500, seed=5)
    assert delta is not None and mc is not None
    assert mc.low[0] < 0.85 * delta.low[0]
    assert mc.low[0] < ends[1] < mc.high[0]


def test_monte_carlo_curves_are_the_same_on_workers(rsn8883_site: Any) -> None:
    """The parameter sets are drawn in this process and each curve computed whole by one
    worker: two workers give the curves of one process bit for bit, and each curve is the
    curve of its parameter set (the first set's, recomputed here)."""
    from stepframe.pipeline.amplification.band import VARIED, monte_carlo_curves

    model, stderr = rsn8883_site.model, rsn8883_site.stderr
    varied = tuple(name for name in VARIED if stderr.get(name, 0) > 0)
    f0 = np.array([0.2, 1.0, 5.0])
    args = (model, stderr, varied, f0, 0.05, 200, 6, 3)
    here, rejected_here = monte_carlo_curves(*args, jobs=1)
    # a started pool takes every curve (2 --jobs would keep curves this short in this process)
    with ProcessPoolExecutor(max_workers=2) as pool:
        spread, rejected_spread = monte_carlo_curves(*args, executor=pool)
    assert here.shape == (6, 3) and rejected_here == rejected_spread
    np.testing.assert_array_equal(here, spread)
    assert np.unique(here[:, 0]).size == 6  # six different parameter sets
    with pytest.raises(InputError, match="jobs"):
        monte_carlo_curves(*args, jobs=0)


def test_the_band_on_its_coarser_grids_is_the_band_on_the_analysis_grid(
    rsn8883_site: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    """RSN 8883's site (the widest standard errors of the documented sites), f0 over 0.1-25 Hz
    (its report's curve runs past the grid to 25.5 Hz): each f0 on the coarsest of 4,000, 2,000,
    1,000 and 500 steps with four steps a period of it over the analysis's 34.86 s, and the
    same parameter sets' curves there and on 4,000 steps everywhere differ by at most 1.3e-4,
    the most over the report's 512 sets and 78 f0 (docs/benchmarks.md; 1.03e-4 here since
    t_max's envelope fit keeps to the motion's frames and its standard error is undiluted);
    the band says which grids."""
    from stepframe.pipeline.amplification import band as band_module

    model, stderr = rsn8883_site.model, rsn8883_site.stderr
    varied = tuple(name for name in band_module.VARIED if stderr.get(name, 0) > 0)
    f0 = np.array([0.1, 1.0, 3.5, 3.6, 7.0, 7.2, 14.0, 14.4, 25.0])
    grids = band_module.band_grids(model, f0, 0.05, 4000)
    # 4 × f0 × 34.86 s steps at least: 3.5 Hz needs 488, 3.6 Hz 502, 7.2 Hz 1,004, 14.4 Hz 2,008.
    assert list(grids) == [500, 500, 500, 1000, 1000, 2000, 2000, 4000, 4000]
    coarse, _ = band_module.monte_carlo_curves(model, stderr, varied, f0, 0.05, grids, 16, 2)
    fine, _ = band_module.monte_carlo_curves(model, stderr, varied, f0, 0.05, 4000, 16, 2)
    np.testing.assert_allclose(coarse, fine, rtol=1.3e-4)
    # Each f0's curve is its own run's: f0 = 7.0 Hz alone on 1,000 steps.
    alone = band_module.vs_fixed_curve(model, f0[4:5], 0.05, 1000)[0]
    assert band_module.grid_curve(model, f0, 0.05, grids)[4] == alone
    band = band_module.parameter_band(model, stderr, f0, 0.05, n_steps=4000, n_samples=16, seed=2)
    assert band is not None and band.grid_steps == (500, 1000, 2000, 4000)
    assert "16 parameter sets at 500-4,000 time steps by f0" in band.describe()
    np.testing.assert_allclose(band.low, np.percentile(coarse, 2.5, axis=0), rtol=1e-12)
    # The analysis's grid as coarse as the rule allows keeps it for every f0 ...
    assert set(band_module.band_grids(model, f0[-2:], 0.05, 1000)) == {1000}
    # ... and so does a site whose central curve moves on the coarser grids.
    monkeypatch.setattr(band_module, "BAND_STEP_TOLERANCE", 0.0)
    assert set(band_module.band_grids(model, f0, 0.05, 4000)) == {4000}


def test_no_band_without_standard_errors(paper_model: Any) -> None:
    from stepframe.pipeline.amplification.band import parameter_band

    assert parameter_band(paper_model, {}, np.array([1.0]), 0.05, n_steps=200) is None


def test_band_samples_apply_only_to_the_monte_carlo_band() -> None:
    with pytest.raises(InputError, match="band_samples = 100 with band = 'delta'"):
        AmplificationOptions(band="delta", band_samples=100)
    assert AmplificationOptions(band_samples=100).band_samples_or_default == 100
    assert AmplificationOptions().band_samples_or_default == 512


def test_records_report_draws_the_band(records_amplification_html: Path) -> None:
    import pandas as pd

    numbers = _numbers(records_amplification_html)
    assert numbers["band"]["method"] == "monte-carlo"
    assert numbers["band"]["n_curves"] == RECORDS_BAND_CURVES
    # The grids of its curves, which the report names: the fixture's 1,000 steps for the
    # f0 above 3.6 Hz (four steps a period over the site's 35 s), 500 below.
    assert numbers["band"]["grid_steps"] == [500, 1000]
    assert f"{RECORDS_BAND_CURVES} parameter sets at 500-1,000 time steps by f0" in html.unescape(
        records_amplification_html.read_text()
    )
    table = pd.read_csv(data_folder_of(records_amplification_html) / "amplification.csv")
    assert (table["band_low"] < table["response_vs_fixed"]).all()
    assert (table["response_vs_fixed"] < table["band_high"]).all()


# -- figures ------------------------------------------------------------------------------------


def test_the_site_frequencies_are_on_the_figures_beyond_the_grid(rsn8883_site: Any) -> None:
    """RSN 8883's f_p (15.9 Hz) lies above the 0.1-10 Hz grid: the axes reach it, it is named on
    the scale above the axes, and no legend covers its label."""
    from stepframe.stochastic import plots

    model = rsn8883_site.model
    f_p = model.omega_p_rad_s / (2 * math.pi)
    assert f_p > 10.0
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    figure = plots.spectral_ratio_figure(model, site="RSN 8883")
    FigureCanvasAgg(figure).draw()
    ax = figure.axes[0]
    assert ax.get_xlim()[1] > f_p
    [scale] = ax.child_axes  # the scale above the axes
    [label] = [t for t in scale.get_xticklabels() if t.get_text().startswith("f_p")]
    assert label.get_text() == f"f_p {f_p:.3g} Hz"
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    legend = ax.get_legend().get_window_extent(renderer)
    assert not legend.overlaps(label.get_window_extent(renderer))


@pytest.mark.parametrize("f_s_hz", [3.15, 2.2])
def test_site_frequency_labels_do_not_overlap(f_s_hz: float) -> None:
    """f_r = 2.09 Hz with f_s = 3.15 Hz (the Beverly Hills records) or 2.2 Hz, over 0.06-16 Hz
    with the report's legend beside the axes: upright labels apart, or one label for both."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from stepframe.stochastic import plots
    from stepframe.stochastic.model import GroundMotionModel

    model = GroundMotionModel.from_hz(10.4, f_s_hz, 2.09, 0.175, 0.658, t_max_s=5.8,
                                      t_dur_s=21.0)  # fmt: skip
    f0 = np.geomspace(0.0626, 16.0, 40)
    figure = plots.response_amplification_figure(
        f0, 3 + 0 * f0, 2 + 0 * f0, model, site="Beverly Hills - Mulhol", xi0=0.05,
        band_hz=(0.11, 1.03), parameter_band=(2 + 0 * f0, 4 + 0 * f0, "95 % band, N = 256"),
    )  # fmt: skip
    FigureCanvasAgg(figure).draw()
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    [scale] = figure.axes[0].child_axes
    labels = [label.get_text() for label in scale.get_xticklabels()]
    boxes = [label.get_window_extent(renderer) for label in scale.get_xticklabels()]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
    if f_s_hz == 2.2:  # 5 % apart: one label
        assert labels == ["f_r 2.09, f_s 2.2 Hz", "f_p 10.4 Hz"]
    else:
        assert labels == ["f_r 2.09 Hz", "f_s 3.15 Hz", "f_p 10.4 Hz"]


def test_long_titles_are_wrapped_inside_the_figure(rsn8883_site: Any) -> None:
    from stepframe.pipeline.reports.document import fit_titles, texts_outside
    from stepframe.stochastic import plots

    name = "A site with a very long name, " * 4
    figure = plots.spectral_ratio_figure(rsn8883_site.model, site=name)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(figure)
    assert texts_outside(figure)  # as drawn, the title runs off both edges
    fit_titles(figure)
    assert texts_outside(figure) == []
    assert figure.axes[0].get_title().count("\n") >= 1


def test_the_legend_states_t_max_and_t_dur_as_the_table_does(rsn8883_site: Any) -> None:
    """The omega-path figure draws t_0 + t_dur in record time, but labels t_dur as the table
    does (the issue: a legend said 36.3 s where the table said 11.13 s)."""
    from stepframe.records import read
    from stepframe.stochastic import plots
    from stepframe.stochastic.features import record_features
    from stepframe.stochastic.fit import fit_model
    from stepframe.stochastic.spectra import evolutionary_spectrum

    path = Path(__file__).parents[2] / "data" / "peer_nga_west2" / "RSN8883_14383980_13849360.AT2"
    trace = read(str(path))[0]
    features = record_features(trace)
    model = fit_model(features).model
    figure = plots.omega_path_figure(evolutionary_spectrum(trace), features, model, name="x")
    legend = [t.get_text() for t in figure.axes[0].get_legend().get_texts()]
    assert f"t_0 + t_dur, t_dur = {model.t_dur_s:.3g} s" in legend
    assert f"t_0 + t_max, t_max = {model.t_max_s:.3g} s" in legend
    assert features.t0_s > 20  # the P pick: a label in record time would differ by it


def test_the_provenance_command_keeps_the_site_name(tmp_path: Path) -> None:
    from stepframe.pipeline.amplification.analysis import AmplificationReportOptions
    from stepframe.pipeline.amplification.report import make_amplification_report

    options = AmplificationReportOptions(
        fp_hz=7.43, fs_hz=3.12, fr_hz=1.11, xi_p=0.096, xi_r=0.655, t_max_s=5.0, t_dur_s=20.0,
        site_name="Paper's site", monte_carlo=0, n_steps=300, n_frequencies=5, grid_only=True,
    )  # fmt: skip
    out = make_amplification_report(str(tmp_path / "p.html"), options)
    provenance = json.loads((data_folder_of(out) / "provenance.json").read_text())
    assert "--site-name 'Paper'\"'\"'s site'" in provenance["command"]  # shell quoting
    assert "--grid-only" in provenance["command"]
    # the parameters on the page read as typed (jinja's tojson wrote \u0027 for the quote)
    page = html.unescape(out.read_text(encoding="utf-8"))
    assert '"site_name": "Paper\'s site"' in page and "\\u0027" not in page
