"""Each report opened in headless Chromium, offline, from a file:// URL.

Checks: no console errors, no failed requests (networking is off: anything fetched from the
network would fail), every figure decoded and drawn with a non-zero size and no text cut at its
edges (each image states the texts that reach past them), every table present with its header,
and a full-page screenshot saved (docs/reports.md says where and how to view it).
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from stepframe.pipeline.reports.document import data_folder_of


def _expected_tables(html: Path) -> list[Any]:
    import html5lib

    document = html5lib.parse(html.read_text(encoding="utf-8"), namespaceHTMLElements=False)
    return list(document.iter("table"))


@pytest.mark.parametrize(
    "which", ["amplification", "records_amplification", "selection", "arrivals"]
)
def test_report_renders_offline_in_chromium(
    which: str,
    request: pytest.FixtureRequest,
    browser: str,
    screenshot_dir: Path,
    check_page: Callable[..., Any],
) -> None:
    html: Path = request.getfixturevalue(f"{which}_html")
    shot = screenshot_dir / f"{which}_report.png"
    seen = check_page(html, shot, browser=browser)
    assert seen.console_errors == []
    assert seen.failed_requests == []
    n_figures = html.read_text(encoding="utf-8").count("<figure ")
    assert n_figures >= 2
    assert len(seen.figures) == n_figures
    for figure in seen.figures:
        assert figure["complete"], figure["alt"]
        assert min(figure["natural"]) > 100, figure["alt"]  # the PNG decoded
        assert min(figure["box"]) > 100, figure["alt"]  # and was laid out with a size
        assert figure["clipped"] == "", figure["alt"]  # no text cut at the PNG's edges
    tables = _expected_tables(html)
    assert len(seen.tables) == len(tables) >= 3
    assert all(t["headers"] >= 2 for t in seen.tables)
    # the screenshot is a PNG of the whole page, not of the first screen only
    data = shot.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    width = int.from_bytes(data[16:20], "big")
    height = int.from_bytes(data[20:24], "big")
    assert (width, height) == seen.size_px
    assert height > 2000
    assert data_folder_of(html).is_dir()


def test_the_check_sees_network_use_and_errors(
    tmp_path: Path, browser: str, check_page: Callable[..., Any]
) -> None:
    # a page that needs the network and logs an error: the check must report both
    page = tmp_path / "bad.html"
    page.write_text(
        '<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>bad</title>'
        '<link rel="stylesheet" href="https://cdn.example.com/style.css"></head><body>'
        '<figure><img src="https://cdn.example.com/figure.png" alt="remote figure"></figure>'
        "<script>console.error('broken');</script></body></html>",
        encoding="utf-8",
    )
    seen = check_page(page, tmp_path / "bad.png", browser=browser)
    assert len(seen.failed_requests) >= 2
    assert any("broken" in message for message in seen.console_errors)
    assert seen.figures and seen.figures[0]["natural"] == [0, 0]


def test_the_check_sees_a_text_cut_at_the_edge(
    tmp_path: Path, browser: str, check_page: Callable[..., Any]
) -> None:
    """A long title is wrapped to fit; an axis label too long for its figure is cut, and the
    page says so on the image, where the browser reads it."""
    from matplotlib.figure import Figure as MplFigure

    from stepframe.pipeline.reports.document import (
        Report,
        Section,
        figure_from_matplotlib,
        write_report,
    )
    from stepframe.pipeline.reports.provenance import collect_provenance

    def figure(title: str, xlabel: str) -> Any:
        drawn = MplFigure(figsize=(4, 3), layout="constrained")
        ax = drawn.add_subplot()
        ax.plot([0, 1], [0, 1])
        ax.set_title(title)
        ax.set_xlabel(xlabel)
        return figure_from_matplotlib(drawn, key=xlabel[:4], title="t", alt=xlabel[:4],
                                      how_to_read="-")  # fmt: skip

    long = "a text far too long for a figure of this width, cut at both edges " * 2
    wrapped, cut = figure(long, "f [Hz]"), figure("short", long)
    assert wrapped.clipped == () and cut.clipped == (long,)
    report = Report("cut", "", [], [Section("s", [wrapped, cut])], collect_provenance("pytest"))
    page = write_report(report, tmp_path / "cut.html")
    seen = check_page(page, tmp_path / "cut.png", browser=browser)
    assert [f["clipped"] for f in seen.figures] == ["", long]
