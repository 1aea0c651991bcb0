"""``stochastic.plots.fit_figure``: named t0/t_max lines, a spectrum panel sized to its energy."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from matplotlib.collections import QuadMesh
from matplotlib.figure import Figure

from stepframe.pipeline.catalogue import fitted as stage
from stepframe.records import read
from stepframe.stochastic.plots import TWO_PI, energy_band_hz, fit_figure

RECORD = "peer_nga_west2/RSN8883_14383980_13849360.AT2"


@pytest.fixture(scope="module")
def drawn(
    tmp_path_factory: pytest.TempPathFactory,
) -> tuple[Figure, stage.FittedRecord, xr.DataArray]:
    trace = read(Path(__file__).parents[1] / "data" / RECORD)[0]
    (record,) = stage.fit_records([trace], stage.FitOptions())
    spectrum = stage.record_spectrum(trace, record)
    figure = fit_figure(trace, spectrum, record.features, record.fitted)
    figure.savefig(tmp_path_factory.mktemp("fit") / "fit.png")  # draws it whole
    return figure, record, spectrum


def test_title_names_the_file_and_the_channel(
    drawn: tuple[Figure, stage.FittedRecord, xr.DataArray],
) -> None:
    figure, _, _ = drawn
    title = figure.axes[0].get_title()
    assert "RSN8883_14383980_13849360.AT2" in title and "[360]" in title


def test_t0_and_t_max_lines_have_legend_entries_at_their_times(
    drawn: tuple[Figure, stage.FittedRecord, xr.DataArray],
) -> None:
    figure, record, _ = drawn
    features = record.features
    assert features.t0_source == "p-pick"  # this record's P onset is picked
    legend = figure.axes[0].get_legend()
    assert legend is not None
    texts = [t.get_text() for t in legend.get_texts()]
    assert any(text.startswith("P onset") for text in texts)
    assert any(text.startswith("t_max") for text in texts)
    lines = {str(ln.get_label()): ln for ln in figure.axes[0].get_lines()}
    (p_line,) = [ln for label, ln in lines.items() if label.startswith("P onset")]
    (t_line,) = [ln for label, ln in lines.items() if label.startswith("t_max")]
    assert p_line.get_label() in texts and t_line.get_label() in texts
    assert np.allclose(p_line.get_xdata(), features.t0_s)
    assert np.allclose(t_line.get_xdata(), features.t0_s + features.t_max_s)


def test_spectrum_panel_spans_the_energy_band_and_f_p(
    drawn: tuple[Figure, stage.FittedRecord, xr.DataArray],
) -> None:
    figure, record, spectrum = drawn
    (panel,) = [ax for ax in figure.axes if ax.get_ylabel() == "frequency [Hz]"]
    bottom, top = panel.get_ylim()
    f_p = record.fitted.model.omega_p_rad_s / TWO_PI
    frequency = spectrum["omega"].values / TWO_PI
    assert bottom == 0.0
    assert top >= f_p and top >= energy_band_hz(spectrum)
    energy = spectrum.transpose("time", "omega").values.sum(axis=0)
    assert energy[frequency > top].sum() <= 0.01 * energy.sum()  # ≥ 99 % of it shown
    assert top <= 0.5 * frequency.max()  # not the whole grid, most of it empty
    # the fitted path is drawn whole: its highest value, f_p, is inside
    (fit_line,) = [
        ln for ln in panel.get_lines() if str(ln.get_label()).startswith("ω_g/2π fitted")
    ]
    assert np.nanmax(np.asarray(fit_line.get_ydata(), dtype=float)) <= top
    (mesh,) = [c for c in panel.collections if isinstance(c, QuadMesh)]
    assert mesh.get_clim() == (-40.0, 0.0)
    assert float(np.max(np.asarray(mesh.get_array()))) == pytest.approx(
        0.0
    )  # dB relative to the peak


def test_energy_band_is_where_99_percent_of_the_energy_lies() -> None:
    omega = TWO_PI * np.arange(0.0, 50.0, 0.5)
    power = np.zeros((3, omega.size))
    power[:, omega / TWO_PI == 2.0] = 98.0
    power[:, omega / TWO_PI == 10.0] = 1.5
    power[:, omega / TWO_PI == 40.0] = 0.5
    spectrum = xr.DataArray(power, coords={"time": [0.0, 1.0, 2.0], "omega": omega})
    assert energy_band_hz(spectrum) == pytest.approx(10.0)
    assert energy_band_hz(spectrum.transpose("omega", "time")) == pytest.approx(10.0)
    assert energy_band_hz(spectrum, share=0.5) == pytest.approx(2.0)
    assert energy_band_hz(spectrum * 0.0) == pytest.approx(omega[-1] / TWO_PI)
