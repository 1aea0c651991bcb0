"""The HTML every report is: valid HTML5, alt text, table headers, self-contained; written all or
nothing."""

from __future__ import annotations

import hashlib
import io
import re
from pathlib import Path
from typing import Any

import html5lib
import numpy as np
import pandas as pd
import pytest

from stepframe.core.io import file_sha256
from stepframe.errors import InputError
from stepframe.pipeline.reports import collect_provenance
from stepframe.pipeline.reports.document import (
    Note,
    Report,
    Section,
    Table,
    data_folder_of,
    format_value,
    write_report,
)

REPORTS = ["amplification_html", "records_amplification_html", "selection_html"]


@pytest.mark.parametrize("fixture", REPORTS)
def test_report_is_valid_html5(fixture: str, request: pytest.FixtureRequest) -> None:
    html: Path = request.getfixturevalue(fixture)
    parser = html5lib.HTMLParser(strict=True)
    parser.parse(html.read_text(encoding="utf-8"))  # strict: raises on the first parse error
    assert parser.errors == []


@pytest.mark.parametrize("fixture", REPORTS)
def test_figures_have_alt_text_and_tables_headers(
    fixture: str, request: pytest.FixtureRequest
) -> None:
    html: Path = request.getfixturevalue(fixture)
    document = html5lib.parse(html.read_text(encoding="utf-8"), namespaceHTMLElements=False)
    images = list(document.iter("img"))
    assert images
    for image in images:
        assert len(image.get("alt", "")) > 40  # a sentence, not a file name
        assert image.get("src", "").startswith("data:image/png;base64,")
    for table in document.iter("table"):
        headers = table.findall("./thead/tr/th")
        assert headers and all(th.get("scope") == "col" for th in headers)
        for row in table.findall("./tbody/tr"):
            assert len(row.findall("td")) == len(headers)


@pytest.mark.parametrize("fixture", REPORTS)
def test_report_needs_no_network(fixture: str, request: pytest.FixtureRequest) -> None:
    text = Path(request.getfixturevalue(fixture)).read_text(encoding="utf-8")
    # no external resource of any kind: no http(s) or protocol-relative URL in src/href
    assert not re.search(r"""(src|href)\s*=\s*["'](https?:)?//""", text)
    assert "<link" not in text
    assert re.search(r"<script[^>]*\ssrc=", text) is None


@pytest.mark.parametrize("fixture", REPORTS)
def test_every_table_is_written_beside_the_report(
    fixture: str, request: pytest.FixtureRequest
) -> None:
    html: Path = request.getfixturevalue(fixture)
    folder = data_folder_of(html)
    text = html.read_text(encoding="utf-8")
    for key in re.findall(r'id="tab-([a-z_0-9]+)"', text):
        table = pd.read_csv(folder / f"{key}.csv")
        assert len(table.columns) >= 2
        assert (folder / f"{key}.columns.json").is_file()
    assert (folder / "numbers.json").is_file()
    assert (folder / "provenance.json").is_file()


def _tiny_report() -> Report:
    table = Table("t", "A table", pd.DataFrame({"x": [1.0, 2.5], "name": ["a<b", "c&d"]}), "cap")
    return Report(
        "Title <&>",
        "subtitle",
        [("label", "value")],
        [Section("S", [table, Note("a note")])],
        collect_provenance("test"),
        {"x": 1.0},
    )


def test_text_is_escaped(tmp_path: Path) -> None:
    out = write_report(_tiny_report(), tmp_path / "r.html")
    text = out.read_text(encoding="utf-8")
    assert "<title>Title &lt;&amp;&gt;</title>" in text
    assert "a&lt;b" in text and "c&amp;d" in text


def test_a_failed_write_leaves_nothing(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    import stepframe.pipeline.reports.document as document

    def broken(report: Report, folder: Path) -> None:
        (folder / "half.csv").write_text("x\n1\n")
        raise OSError("disk full")

    monkeypatch.setattr(document, "_write_folder", broken)
    with pytest.raises(OSError, match="disk full"):
        write_report(_tiny_report(), tmp_path / "r.html")
    assert list(tmp_path.iterdir()) == []


def test_a_failed_rewrite_keeps_the_previous_report(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    import stepframe.pipeline.reports.document as document

    out = write_report(_tiny_report(), tmp_path / "r.html")
    before = {p.name: p.read_bytes() for p in [out, *data_folder_of(out).iterdir()]}

    def broken_atomic_write(path: Path, mode: str = "w") -> None:
        raise OSError("no space left")

    monkeypatch.setattr(document, "atomic_write", broken_atomic_write)
    with pytest.raises(OSError, match="no space"):
        write_report(_tiny_report(), out)
    after = {p.name: p.read_bytes() for p in [out, *data_folder_of(out).iterdir()]}
    assert after == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.html", "r_files"]


def test_output_folder_must_exist(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="output folder does not exist"):
        write_report(_tiny_report(), tmp_path / "missing" / "r.html")


def test_format_value() -> None:
    assert format_value(3.14159265) == "3.142"
    assert format_value(float("nan")) == ""
    assert format_value(True) == "yes"
    assert format_value(12) == "12"
    assert format_value(float("inf")) == "∞"


def test_provenance_hashes_inputs(tmp_path: Path) -> None:
    (tmp_path / "a.txt").write_bytes(b"stepframe\n")
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "b.bin").write_bytes(bytes(range(256)))
    provenance = collect_provenance(["stepframe", "report"], inputs=[tmp_path], parameters={"k": 1})
    names = [Path(name).name for name, _ in provenance.inputs]
    assert names == ["a.txt", "b.bin"]
    assert provenance.inputs[0][1] == hashlib.sha256(b"stepframe\n").hexdigest()
    assert provenance.inputs[1][1] == file_sha256(tmp_path / "sub" / "b.bin")
    assert provenance.command == "stepframe report"
    assert provenance.versions["stepframe"] and provenance.versions["numpy"]
    assert provenance.cpu_count >= 1
    assert provenance.to_dict()["parameters"] == {"k": 1}


def _figure_with_long_title(title_words: int) -> Any:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure as MplFigure

    figure = MplFigure(figsize=(6.0, 3.0), layout="constrained")
    FigureCanvasAgg(figure)
    left, right = figure.subplots(1, 2)
    left.plot([0.0, 1.0], [0.0, 2.0])
    right.set_title(" ".join(["station"] * title_words))
    right.set_ylabel("acceleration [m/s²]")
    figure.text(1.02, 0.5, "past the right edge")
    return figure


@pytest.mark.parametrize("title_words", [3, 16])
def test_the_layout_fit_titles_leaves_is_the_one_texts_outside_would_make(
    title_words: int,
) -> None:
    """figure_from_matplotlib reads the clipped texts from fit_titles' last layout instead of
    laying the figure out again: the same texts as a fresh layout, a clipped one included."""
    from stepframe.pipeline.reports.document import fit_titles, texts_outside

    figure = _figure_with_long_title(title_words)
    right = figure.axes[1]
    laid_out = fit_titles(figure)
    assert laid_out
    reused = texts_outside(figure, laid_out=laid_out)
    assert reused == ["past the right edge"]
    assert texts_outside(figure) == reused
    assert ("\n" in right.get_title()) == (title_words > 3)  # the long title was wrapped


@pytest.mark.parametrize("title_words", [3, 16])
def test_a_figure_painted_first_is_the_one_laid_out_first(title_words: int) -> None:
    """figure_from_matplotlib paints the PNG and reads the texts from that painting (painting
    again only after wrapping a title): the clipped texts and the picture of laying the figure
    out at the PNG's resolution, fitting its titles, then painting it. (The pixels agree to
    anti-aliasing: a layout made from a painted one moves the axes by a thousandth of a
    pixel.)"""
    from PIL import Image

    from stepframe.pipeline.reports.document import (
        FIGURE_DPI,
        figure_from_matplotlib,
        fit_titles,
        texts_outside,
    )

    drawn = figure_from_matplotlib(
        _figure_with_long_title(title_words), key="k", title="t", alt="a", how_to_read="h"
    )
    expected = _figure_with_long_title(title_words)
    expected.set_dpi(FIGURE_DPI)
    assert fit_titles(expected)
    clipped = texts_outside(expected, laid_out=True)
    assert ("\n" in expected.axes[1].get_title()) == (title_words > 3)
    buffer = io.BytesIO()
    expected.savefig(buffer, format="png", dpi=FIGURE_DPI)
    assert drawn.clipped == tuple(clipped) == ("past the right edge",)
    pixels = [
        np.asarray(Image.open(io.BytesIO(png)).convert("L"), dtype=float)
        for png in (drawn.png, buffer.getvalue())
    ]
    assert pixels[0].shape == pixels[1].shape == (330, 660)  # 6 × 3 in at FIGURE_DPI
    assert np.abs(pixels[0] - pixels[1]).mean() < 0.5  # an unwrapped title differs by ~10


def test_a_report_made_by_a_workflow_says_where_its_records_are(arrivals_html: Path) -> None:
    """A workflow's report lists no input files (the run's tables do): it says the workflow
    names them, not that the report was computed from parameters alone."""
    page = arrivals_html.read_text(encoding="utf-8")
    assert "computed from parameters alone" not in page
    assert "the records are those the workflow below names" in page
    assert "<h3>Workflow wf.toml</h3>" in page
    html5lib.HTMLParser(strict=True).parse(page)  # still valid HTML5


def test_a_workflow_report_names_the_command_that_makes_it(tmp_path: Path) -> None:
    # A shipped workflow is run by its name: the page said "stepframe run
    # site-amplification.toml", a file the user does not have; a workflow file by its name.
    from stepframe.pipeline.engine.shipped import SHIPPED_DIR
    from stepframe.pipeline.reports.provenance import workflow_provenance

    shipped = workflow_provenance(SHIPPED_DIR / "site-amplification.toml", {})
    assert shipped.command == "stepframe run site-amplification"
    own = tmp_path / "my-site.toml"
    own.write_text((SHIPPED_DIR / "site-amplification.toml").read_text())
    assert workflow_provenance(own, {}).command == "stepframe run my-site.toml"
