"""``records.plots.response_spectra_figure``: the title names the record and its components."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from stepframe.pipeline.catalogue.record_spectra import record_spectra
from stepframe.records import read
from stepframe.records.plots import response_spectra_figure, spectra_title

PEER = Path(__file__).parents[1] / "data" / "peer_nga_west2"
NAMES = ("RSN8883_14383980_13849360.AT2", "RSN8883_14383980_13849090.AT2")


def test_title_names_each_file_with_its_component(tmp_path: Path) -> None:
    traces = [read(PEER / name)[0] for name in NAMES]
    data = record_spectra(traces, damping=0.02)
    psa = {c["component"]: c["psa_g"] for c in data["components"]}
    figure = response_spectra_figure(
        data["period_s"], psa, damping=0.02, combined_g={"RotD50": data["rotd50_g"]}, record=NAMES
    )
    (axes,) = figure.axes
    lines = axes.get_title().splitlines()
    assert lines == [f"{NAMES[0]} [360]", f"{NAMES[1]} [90]", lines[2]]
    assert "damping 2 %" in lines[2]
    legend = axes.get_legend()
    assert legend is not None
    assert [t.get_text() for t in legend.get_texts()] == ["360", "90", "RotD50"]
    np.testing.assert_allclose(np.asarray(axes.get_lines()[0].get_ydata(), dtype=float), psa["360"])
    figure.savefig(tmp_path / "psa.png")


def test_title_with_one_name_or_none() -> None:
    figure = response_spectra_figure([0.1, 1.0], {"360": [0.5, 0.1]}, damping=0.05, record=NAMES[0])
    assert figure.axes[0].get_title().splitlines()[0] == f"{NAMES[0]} [360]"
    assert spectra_title(None, ["HNE", "HNN"], 0.05).splitlines() == [
        "components HNE, HNN",
        "pseudo-spectral acceleration, damping 5 %",
    ]
    assert spectra_title([NAMES[0], NAMES[0]], ["HNE", "HNN"], 0.05).startswith(
        f"{NAMES[0]} [HNE, HNN]\n"
    )
    with pytest.raises(ValueError, match="3 record names for 2 components"):
        spectra_title(["a", "b", "c"], ["HNE", "HNN"], 0.05)


def test_a_vertical_named_like_peer_s_h_up_leaves_the_two_horizontals_for_rotd() -> None:
    # With a third component named H-UP (PEER's vertical), RotD50 is still the two horizontals'
    # (the catalogue's spectra once read H-UP as horizontal, found three, and drew no RotD).
    traces = [read(PEER / name)[0] for name in NAMES]
    vertical = traces[0].copy()
    vertical.stats.channel = "H-UP"
    both = record_spectra(traces, damping=0.05)
    three = record_spectra([*traces, vertical], damping=0.05)
    assert three["h1"] == "360" and three["h2"] == "90"
    np.testing.assert_array_equal(three["rotd50_g"], both["rotd50_g"])
