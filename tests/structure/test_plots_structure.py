"""``structure.plots.response_figure``: the ground-motion panel and a legend that hides no line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from stepframe.pipeline.dynamics.response import simulate_record
from stepframe.records import read
from stepframe.records.units import STANDARD_GRAVITY_M_S2
from stepframe.structure.frame import PortalFrame
from stepframe.structure.frame_file import FRAME_TEMPLATE, read_frame_file
from stepframe.structure.plots import response_figure

RECORD = "peer_nga_west2/RSN8883_14383980_13849360.AT2"


@pytest.fixture(scope="module")
def frame(tmp_path_factory: pytest.TempPathFactory) -> PortalFrame:
    path = tmp_path_factory.mktemp("frame") / "FRAME.toml"
    path.write_text(FRAME_TEMPLATE, encoding="utf-8")
    return read_frame_file(path)


def _x_star_line(figure: Figure, frame: PortalFrame) -> Line2D:
    (axes,) = [ax for ax in figure.axes if ax.get_ylabel() == "x [m]"]
    (line,) = [ln for ln in axes.get_lines() if str(ln.get_label()).startswith("±x*")]
    assert np.asarray(line.get_ydata(), dtype=float)[0] == pytest.approx(frame.x_star_m)
    return line


@pytest.mark.parametrize("scale", [6.0, 12.0])  # steps and returns; overturns
def test_ground_panel_is_the_scaled_record_in_g_and_the_legend_hides_no_line(
    frame: PortalFrame, data_dir: Path, tmp_path: Path, scale: float
) -> None:
    trace = read(data_dir / RECORD)[0]
    response = simulate_record(frame, trace, scale=scale, tail_s=5.0)
    figure = response_figure(
        response.result, frame, title="test", ground_acc_m_s2=trace.data, scale=scale
    )
    ground, response_axes = figure.axes
    assert ground.get_ylabel() == "ground acc. [g]"
    assert ground.get_shared_x_axes().joined(ground, response_axes)
    line = ground.get_lines()[0]
    time_s = np.asarray(line.get_xdata(), dtype=float)
    acc_g = np.asarray(line.get_ydata(), dtype=float)
    np.testing.assert_allclose(acc_g, scale * trace.data / STANDARD_GRAVITY_M_S2, rtol=1e-12)
    np.testing.assert_allclose(time_s, np.arange(trace.stats.npts) * trace.stats.delta)
    assert np.max(np.abs(acc_g)) == pytest.approx(response.summary["pga_m_s2"] / 9.80665)

    figure.draw_without_rendering()
    legends = figure.legends + [lg for ax in figure.axes if (lg := ax.get_legend()) is not None]
    assert len(legends) == 1
    legend_box = legends[0].get_window_extent()
    labels = [text.get_text() for text in legends[0].get_texts()]
    assert any(label.startswith("±x*") for label in labels)
    assert any(label.startswith("ground acceleration") for label in labels)
    # The +x* line spans the axes' width at y = x*: no point of it lies under the legend.
    x_star = _x_star_line(figure, frame)
    left, right = response_axes.get_xlim()
    points = np.column_stack([np.linspace(left, right, 200), np.full(200, frame.x_star_m)])
    display = response_axes.transData.transform(points)
    assert response_axes.get_ylim()[1] > frame.x_star_m  # the line is drawn inside the axes
    assert not np.any(
        (display[:, 0] >= legend_box.x0)
        & (display[:, 0] <= legend_box.x1)
        & (display[:, 1] >= legend_box.y0)
        & (display[:, 1] <= legend_box.y1)
    ), x_star.get_label()
    for ax in figure.axes:  # below the axes: it overlaps none of the panels
        assert not legend_box.overlaps(ax.get_window_extent())
    if response.summary["overturned"]:
        assert any(label.startswith("overturned at") for label in labels)
    figure.savefig(tmp_path / "response.png")


def test_without_the_ground_motion_one_panel_and_the_legend_outside(
    frame: PortalFrame, data_dir: Path
) -> None:
    trace = read(data_dir / RECORD)[0]
    response = simulate_record(frame, trace, scale=6.0, tail_s=5.0)
    figure = response_figure(response.result, frame, title="RSN8883 × 6")
    (axes,) = figure.axes
    assert axes.get_title() == "RSN8883 × 6"
    figure.draw_without_rendering()
    (legend,) = figure.legends
    assert not legend.get_window_extent().overlaps(axes.get_window_extent())


def test_ida_figure_draws_overturned_runs_in_a_column_of_their_own() -> None:
    """The overturned runs' peak is the cap (5.77 m for Example 4), ten times the standing
    peaks: they go to an "overturned" column just beyond the widest standing peak, and the axis
    ends there, so the curves keep the width of the figure."""
    from stepframe.structure.dynamics_plots import ida_figure
    from stepframe.structure.ida import ItemIda

    items = [
        ItemIda(intensity=[0.1, 0.2, 0.3], overturned=[False, False, True],
                peak_abs_x_m=[0.05, 0.4, 5.77]),
        ItemIda(intensity=[0.1, 0.2], overturned=[False, True], peak_abs_x_m=[0.6, 5.77]),
    ]  # fmt: skip
    figure = ida_figure(items)
    (axes,) = figure.axes
    crosses = [line for line in axes.get_lines() if line.get_marker() == "x"]
    columns = {float(x) for line in crosses for x in line.get_xdata()}
    assert len(columns) == 1 and columns.pop() == pytest.approx(1.15 * 0.6)
    assert axes.get_xlim()[1] == pytest.approx(1.23 * 0.6)
    assert axes.get_xticklabels()[-1].get_text() == "overturned"
    # the standing runs are where they were
    standing = [line for line in axes.get_lines() if line.get_marker() == "o"]
    assert [list(line.get_xdata()) for line in standing] == [[0.05, 0.4], [0.6]]
