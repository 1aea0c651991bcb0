"""Each report opened in headless Chromium, offline, from a file:// URL.

Checks: no console errors, no failed requests (networking is off: anything fetched from the
network would fail), every figure decoded and drawn with a non-zero size, every table present
with its header, and a full-page screenshot saved (docs/reports.md says where and how to view it).
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


@pytest.mark.parametrize("which", ["amplification", "records_amplification", "selection"])
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
