"""The embedded example catalogue (100 FEMA P695 components) as PEER AT2 files.

A workflow with ``[records] example = "fema-p695"`` reads these files like any folder, so the
example goes through the same inventory (content hashes) as user data. Values are written in g
with nine significant digits (``%.8E``), exactly as the source files hold them, so reading a file
back gives the embedded record bit for bit. Benchmarks and tests use the same writer.
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np

from stepframe.core.io import write_bytes


def at2_bytes(
    values_g: np.ndarray,
    dt_s: float,
    title: str,
    event: str,
    station: str,
    *,
    digits: int = 8,
    dt_text: str | None = None,
) -> bytes:
    """One component as the bytes of a PEER AT2 file (new header style, five values a line).

    ``digits`` after the point of each value (8: the example's source text); ``dt_text`` the
    DT as written (default four decimals, as the example's source files; the export of chosen
    motions writes Python's shortest round-trip form).
    """
    dt_word = f"{dt_s:.4f}" if dt_text is None else dt_text
    lines = [
        "PEER NGA STRONG MOTION DATABASE RECORD",
        f"{event}, {station}, {title}",
        "ACCELERATION TIME SERIES IN UNITS OF G",
        f"NPTS= {values_g.size:7d}, DT= {dt_word} SEC",
    ]
    # One %-format over all the values (a C loop; Python's float formatting, as f"{v: .8E}"):
    # formatting value by value was most of writing the example catalogue (1.7 s of the demo).
    word = f"% .{digits}E"
    full, rest = divmod(values_g.size, 5)
    layout = ["  ".join([word] * 5)] * full + (["  ".join([word] * rest)] if rest else [])
    if layout:
        lines.append("\n".join(layout) % tuple(values_g.tolist()))
    return ("\n".join(lines) + "\n").encode("ascii")


def example_name(row: dict[str, Any]) -> str:
    """The AT2 file name of an example component (:func:`stepframe.records.examples.file_name`,
    the one name it has everywhere)."""
    from stepframe.records.examples import file_name

    return file_name(row)


def example_metadata(folder: Path) -> Any:
    """The example catalogue's metadata table with ``file`` = the component's AT2 file in
    ``folder`` (magnitude, distances, Vs30, ... for the selection filters)."""
    from stepframe.records.examples import event_labels, metadata

    table = metadata()
    rows: list[dict[str, Any]] = table.to_dict(orient="records")  # type: ignore[assignment]
    table = table.assign(
        file=[str(folder / example_name(row)) for row in rows],
        event=event_labels(table),
    )
    return table


def example_files(scale: float = 1.0) -> Iterator[tuple[str, bytes]]:
    """(file name, AT2 bytes) of each example component, in catalogue order.

    Parameters
    ----------
    scale
        Multiplies every value (1: the records as they are). Other scales give distinct files
        of the same cost, for benchmarks of large synthetic catalogues.
    """
    from stepframe.records.examples import fema_p695
    from stepframe.records.units import STANDARD_GRAVITY_M_S2

    stream, table = fema_p695()
    rows: list[dict[str, Any]] = table.to_dict(orient="records")  # type: ignore[assignment]
    for trace, row in zip(stream, rows, strict=True):
        values_g = np.asarray(trace.data) / STANDARD_GRAVITY_M_S2 * scale
        # the stored values are exact decimals: rounding to 9 digits gives the source's text
        name = example_name(row)
        title = str(row["component_name"]).rsplit("/", 1)[-1]
        yield (
            name,
            at2_bytes(values_g, float(row["dt_s"]), title, str(row["event"]), str(row["station"])),
        )


def write_example_files(
    folder: Path, *, count: int | None = None, scale: float = 1.0, suffix: str = ""
) -> list[Path]:
    """Write the example components (the first ``count``) as AT2 files into ``folder``.

    Files that exist with the same bytes are left alone (their mtime too).

    Parameters
    ----------
    folder
        Created if missing.
    count
        How many (default all 100).
    scale
        As :func:`example_files`.
    suffix
        Added to each file's stem (distinct names for replicated catalogues).
    """
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for number, (name, data) in enumerate(example_files(scale)):
        if count is not None and number >= count:
            break
        stem, dot, extension = name.rpartition(".")
        target = folder / f"{stem}{suffix}{dot}{extension}"
        if not (target.is_file() and target.read_bytes() == data):
            write_bytes(target, data)
        written.append(target)
    return written
