"""A report as data (sections of figures, tables and notes) and its self-contained HTML file.

The HTML needs no network: figures are inline PNG (``data:`` URIs), the style sheet and the small
table-sorting script are inline, and the page is fully readable with scripts off. Every number a
report shows is also written beside it: each table as CSV (with its column dictionary), the summary
and the provenance as JSON, in the folder ``<report stem>_files/``. Writing is all-or-nothing:
the page is rendered in memory, the folder is written under a temporary name and published by
:func:`stepframe.core.io.staged_folder`, and the HTML is renamed into place last by
:func:`stepframe.core.io.atomic_write`, so an error leaves no
partial report.
"""

from __future__ import annotations

import base64
import io
import json
import math
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import Executor
from dataclasses import dataclass, field, replace
from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING, Any

from stepframe.core.io import atomic_write, staged_folder
from stepframe.errors import InputError
from stepframe.pipeline.reports.provenance import Provenance

if TYPE_CHECKING:
    import pandas as pd
    from matplotlib.figure import Figure as MplFigure

#: Resolution of the inline PNG figures [dots per inch]: sharp on screen, ~50-120 kB each.
FIGURE_DPI = 110


@dataclass(frozen=True)
class Figure:
    """One figure: PNG bytes, alt text and a short "how to read this" paragraph.

    ``clipped`` lists the texts that reach past the PNG's edges (:func:`texts_outside`, after
    :func:`fit_titles`): empty for a figure that shows all its words; the page carries it on
    the image (``data-clipped``), where the browser test reads it.
    """

    key: str
    title: str
    png: bytes
    alt: str
    how_to_read: str
    clipped: tuple[str, ...] = ()

    @property
    def data_uri(self) -> str:
        """The PNG as a ``data:`` URI (inline, no file needed)."""
        return "data:image/png;base64," + base64.b64encode(self.png).decode("ascii")


@dataclass(frozen=True)
class Table:
    """One table: the data (written as ``<key>.csv``), its column dictionary and a caption."""

    key: str
    title: str
    frame: pd.DataFrame
    caption: str
    columns: Mapping[str, str] = field(default_factory=dict)
    sortable: bool = False
    on_page: bool = True  # False: too wide to read on the page; written as CSV only, and listed


@dataclass(frozen=True)
class Note:
    """A paragraph of text (a choice stated next to the numbers it changes, a warning)."""

    text: str
    kind: str = "note"


@dataclass(frozen=True)
class Section:
    """A titled group of figures, tables and notes."""

    title: str
    items: Sequence[Figure | Table | Note | FigureJob]
    intro: str = ""


@dataclass(frozen=True)
class Report:
    """A whole report: title, headline numbers, sections, provenance and the JSON of its numbers.

    Attributes
    ----------
    title, subtitle
        Heading of the page.
    summary
        ``(label, value text)`` pairs shown first.
    sections
        The body.
    provenance
        How the report was made.
    numbers
        JSON-ready dictionary of every headline number (written as ``numbers.json``).
    warnings
        What a reader must not miss (a design value beyond failure, say), shown above the
        summary.
    """

    title: str
    subtitle: str
    summary: Sequence[tuple[str, str]]
    sections: Sequence[Section]
    provenance: Provenance
    numbers: Mapping[str, Any] = field(default_factory=dict)
    warnings: Sequence[str] = ()

    def __post_init__(self) -> None:
        if any(isinstance(item, FigureJob) for s in self.sections for item in s.items):
            raise ValueError("a figure of the report is not drawn, expected draw_figures first")

    def tables(self) -> list[Table]:
        """Every table of the report (on the page or CSV only), in page order."""
        return [item for s in self.sections for item in s.items if isinstance(item, Table)]

    def page_tables(self) -> list[Table]:
        """The tables drawn on the page."""
        return [table for table in self.tables() if table.on_page]

    def figures(self) -> list[Figure]:
        """Every figure of the report, in page order."""
        return [item for s in self.sections for item in s.items if isinstance(item, Figure)]


def _undrawn_tick_labels(figure: MplFigure) -> set[int]:
    """Ids of the tick labels matplotlib keeps but does not draw (ticks outside the view)."""
    hidden: set[int] = set()
    axes = [ax for parent in figure.axes for ax in (parent, *parent.child_axes)]
    for ax in axes:
        for axis in (ax.xaxis, ax.yaxis):
            low, high = sorted(axis.get_view_interval())
            span = (high - low) * 1e-9
            for tick in (*axis.get_major_ticks(), *axis.get_minor_ticks()):
                if not low - span <= tick.get_loc() <= high + span:
                    hidden.update((id(tick.label1), id(tick.label2)))
    return hidden


def _place_texts(figure: MplFigure) -> None:
    """Lay the figure out as a draw would (the layout engine places the texts at draw time)
    without painting a pixel: the texts' extents are those of the PNG that savefig paints
    after. Painting here too made a third of a report's figure time (a heat map painted three
    times: docs/benchmarks.md, issue 29 item 2)."""
    figure.draw_without_rendering()


def texts_outside(figure: MplFigure, *, laid_out: bool = False) -> list[str]:
    """The drawn texts of a figure (titles, labels, tick labels, legends) that reach past its
    edges: clipped in the PNG. Empty for a figure that shows all its words.

    ``laid_out``: the figure was laid out since its last change (:func:`fit_titles` says so),
    so its texts' extents are read as they are instead of laying it out again (a layout is a
    draw without the pixels: a quarter of a report's figure time)."""
    from matplotlib.text import Text

    if not laid_out:
        _place_texts(figure)
    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    width, height = figure.bbox.width, figure.bbox.height
    hidden = _undrawn_tick_labels(figure)
    out = []
    for text in figure.findobj(Text):
        if id(text) in hidden or not text.get_visible() or not text.get_text().strip():
            continue
        box = text.get_window_extent(renderer)
        if box.x0 < -0.5 or box.y0 < -0.5 or box.x1 > width + 0.5 or box.y1 > height + 0.5:
            out.append(text.get_text())
    return out


#: Characters per line below which a title is not wrapped further.
MIN_TITLE_CHARACTERS = 24


def wrap_titles(figure: MplFigure) -> bool:
    """Wrap each axes title that reaches past the figure's edges in its current layout onto
    more lines (a long site or file name would otherwise be cut at both edges of the PNG). A
    title is centred over its axes, which need not be centred in the figure: the room is twice
    the distance from the title's centre to the nearer edge.

    Returns True when a title changed (the layout is then stale)."""
    import textwrap

    renderer = figure.canvas.get_renderer()  # type: ignore[attr-defined]
    width = figure.bbox.width
    wrapped = False
    for ax in figure.axes:
        title = ax.title
        text = title.get_text()
        box = title.get_window_extent(renderer)
        if not text or (box.x0 >= 0 and box.x1 <= width):
            continue
        centre = (box.x0 + box.x1) / 2
        room = 2 * min(centre, width - centre) * 0.95
        longest = max(len(line) for line in text.split("\n"))
        fits = max(MIN_TITLE_CHARACTERS, int(longest * room / box.width))
        new = "\n".join(textwrap.wrap(text.replace("\n", " "), fits))
        if new != text:
            title.set_text(new)
            wrapped = True
    return wrapped


#: Layouts :func:`fit_titles` and :func:`figure_from_matplotlib` make at most (a title wrapped
#: once seldom needs a second wrap: each narrows it to the room its layout gave).
MAX_TITLE_LAYOUTS = 4


def fit_titles(figure: MplFigure) -> bool:
    """Lay the figure out and :func:`wrap_titles` until no title changes.

    Returns True when the figure's layout is current (its last layout wrapped nothing), False
    when the last wrapping changed a title after it."""
    for _ in range(MAX_TITLE_LAYOUTS):
        _place_texts(figure)
        if not wrap_titles(figure):
            return True
    return False


def figure_from_matplotlib(
    figure: MplFigure, *, key: str, title: str, alt: str, how_to_read: str
) -> Figure:
    """Render a matplotlib figure to PNG bytes (titles wrapped to fit: :func:`wrap_titles`; texts
    still past its edges listed: :func:`texts_outside`) and close it.

    The PNG is painted first and its layout read after: the figure is painted again only when
    a title had to be wrapped (laying a figure out before painting it cost a second draw, about
    40 % of a report's figure time; docs/benchmarks.md, "Report figures painted once")."""
    from matplotlib.backend_bases import FigureCanvasBase

    if type(figure.canvas) is FigureCanvasBase:  # a Figure made without pyplot: draw with Agg
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(figure)
    # At the PNG's own resolution, the layout the texts are read from is the one painted.
    figure.set_dpi(FIGURE_DPI)
    png = _painted(figure)
    for _ in range(MAX_TITLE_LAYOUTS):
        if not wrap_titles(figure):
            break
        png = _painted(figure)  # a title changed: paint its new layout
    clipped = tuple(texts_outside(figure, laid_out=True))
    figure.clear()
    return Figure(key, title, png, alt, how_to_read, clipped)


def _painted(figure: MplFigure) -> bytes:
    """The figure painted as PNG at :data:`FIGURE_DPI` (its texts then placed as painted)."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=FIGURE_DPI)
    return buffer.getvalue()


@dataclass(frozen=True)
class FigureJob:
    """A figure still to draw: ``make()`` gives the matplotlib figure, which
    :func:`figure_from_matplotlib` renders with the other fields. A section holds it until
    :func:`draw_figures` draws every figure of a report at once (in the workers): ``make`` is
    picklable (``functools.partial`` of a module-level function on plain data)."""

    make: Callable[[], MplFigure]
    key: str
    title: str
    alt: str
    how_to_read: str

    def __call__(self) -> Figure:
        """The figure drawn and rendered to PNG."""
        return figure_from_matplotlib(
            self.make(),
            key=self.key,
            title=self.title,
            alt=self.alt,
            how_to_read=self.how_to_read,
        )


def draw_figures(
    sections: Sequence[Section],
    more: Sequence[Callable[[], Any]] = (),
    *,
    jobs: int | None = 1,
    executor: Executor | None = None,
) -> tuple[list[Section], list[Any]]:
    """Every :class:`FigureJob` of ``sections`` drawn, and the calls ``more`` (other parts of
    the report that cost as much, such as simulations drawn with their figure) made, in one
    batch of :func:`stepframe.core.execution.call_each`: the figures are independent, so they
    go to the workers (a figure is drawn in whole by one process: the same PNG bytes whatever
    draws it).

    Parameters
    ----------
    sections
        The report's sections, their figures still :class:`FigureJob` items.
    more
        Picklable zero-argument calls made in the same batch.
    jobs, executor
        Where (:func:`stepframe.core.execution.map_items`; default this process).

    Returns
    -------
    tuple
        The sections with their figures drawn, and the results of ``more`` in order.
    """
    from stepframe.core.execution import call_each

    pending = [item for s in sections for item in s.items if isinstance(item, FigureJob)]
    calls: list[Callable[[], Any]] = [*pending, *more]
    done: list[Any] = call_each(calls, jobs=jobs, executor=executor, stage="report")
    figures = dict(zip(map(id, pending), done, strict=False))
    drawn = [replace(s, items=[figures.get(id(item), item) for item in s.items]) for s in sections]
    return drawn, done[len(pending) :]


def format_value(value: Any) -> str:
    """A table cell as text: 4 significant digits for floats, empty for missing values."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, float) or (hasattr(value, "dtype") and value.dtype.kind == "f"):
        number = float(value)
        if math.isnan(number):
            return ""
        if math.isinf(number):
            return "∞" if number > 0 else "-∞"
        return f"{number:.4g}"
    return str(value)


def _sort_key(value: Any) -> str:
    """The ``data-sort`` attribute: numbers as numbers so the script sorts 10 after 9."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        return str(value)
    return "" if math.isnan(number) else repr(number)


def _environment() -> Any:
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.PackageLoader("stepframe.pipeline.reports", "templates"),
        autoescape=jinja2.select_autoescape(["html", "j2"]),
        undefined=jinja2.StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    env.filters["cell"] = format_value
    env.filters["sortkey"] = _sort_key
    env.tests["instanceof_figure"] = lambda item: isinstance(item, Figure)
    env.tests["instanceof_table"] = lambda item: isinstance(item, Table)
    return env


def render(report: Report, data_folder: str) -> str:
    """The report's HTML (self-contained) as a string."""
    env = _environment()
    template = env.get_template("report.html.j2")
    rows = {
        table.key: [list(row) for row in table.frame.itertuples(index=False, name=None)]
        for table in report.tables()
    }
    provenance = _jsonable(report.provenance.to_dict())
    return str(
        template.render(
            report=report,
            rows=rows,
            data_folder=data_folder,
            provenance=provenance,
            # escaped as text by the template: "paper's site", not jinja's tojson "\u0027"
            parameters_json=json.dumps(
                provenance["parameters"], indent=2, sort_keys=True, ensure_ascii=False
            ),
        )
    )


def data_folder_of(out_html: Path) -> Path:
    """Where the CSV/JSON of a report's numbers go: ``<stem>_files`` beside the HTML."""
    return out_html.with_name(out_html.stem + "_files")


def _write_folder(report: Report, folder: Path) -> None:
    for table in report.tables():
        table.frame.to_csv(folder / f"{table.key}.csv", index=False)
        dictionary = [
            {"column": name, "meaning": table.columns.get(str(name), "")}
            for name in table.frame.columns
        ]
        (folder / f"{table.key}.columns.json").write_text(
            json.dumps(dictionary, indent=2, ensure_ascii=False), encoding="utf-8"
        )
    (folder / "numbers.json").write_text(
        json.dumps(_jsonable(report.numbers), indent=2, ensure_ascii=False, allow_nan=False),
        encoding="utf-8",
    )
    (folder / "provenance.json").write_text(
        json.dumps(_jsonable(report.provenance.to_dict()), indent=2, ensure_ascii=False),
        encoding="utf-8",
    )


def _jsonable(value: Any) -> Any:
    from stepframe.core.jsonable import to_jsonable

    return to_jsonable(value)


def check_report_target(out_html: str | PathLike[str]) -> Path:
    """The report's HTML file, checked before any work: not a folder, in an existing folder
    (an amplification report found a missing folder after all its curves, 7-8 s).

    Raises
    ------
    InputError
        The output folder does not exist, or the target is a folder.
    """
    target = Path(out_html)
    if target.is_dir():
        raise InputError("is a directory, expected an HTML file name", target)
    if not target.parent.is_dir():
        raise InputError("output folder does not exist, expected an existing folder", target)
    return target


def write_report(report: Report, out_html: str | PathLike[str]) -> Path:
    """Write ``report`` as one HTML file plus ``<stem>_files/`` with its numbers; all or nothing.

    Parameters
    ----------
    report
        The assembled report.
    out_html
        The HTML file to (re)write; its folder must exist.

    Returns
    -------
    pathlib.Path
        The HTML file.

    Raises
    ------
    InputError
        The output folder does not exist, or the target is a folder.
    """
    target = check_report_target(out_html)
    folder = data_folder_of(target)
    html = render(report, folder.name)  # in memory first: a template error writes nothing
    # The HTML is renamed into place last, after its data folder: a reader never finds an HTML
    # page whose numbers are not beside it. Any error leaves the previous report as it was.
    with atomic_write(target) as out, staged_folder(folder) as staging:
        _write_folder(report, staging)
        out.write(html)
    return target


def report_summary(out_html: str | PathLike[str]) -> tuple[dict[str, Any], str]:
    """What was written: ``{"report", "data_folder", "size_bytes"}`` and a line of text."""
    out = Path(out_html)
    folder = data_folder_of(out)
    size = out.stat().st_size
    data = {"report": str(out), "data_folder": str(folder), "size_bytes": size}
    return data, f"report: {out} ({size / 1e3:.0f} kB); its numbers: {folder}/"
