"""Saving figures: the one place a :class:`~matplotlib.figure.Figure` becomes a file.

The plot functions of the areas (``stepframe.<area>.plots``) return figures; the command line and
the reports save them here, through :func:`stepframe.core.io.atomic_write`, so a figure file is
either the old one or the new one, never half-written.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import TYPE_CHECKING

from stepframe.core.io import atomic_write
from stepframe.errors import InputError

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: File suffixes a figure can be saved as (the format follows the suffix).
FIGURE_SUFFIXES = (".png", ".pdf", ".svg")


def check_figure_path(path: str | PathLike[str], option: str = "--plot") -> Path:
    """``path`` as a Path if its suffix is a figure format and its folder exists."""
    target = Path(path)
    if target.suffix.lower() not in FIGURE_SUFFIXES:
        raise InputError(f"{option} {path}: suffix {target.suffix!r}, expected .png, .pdf or .svg")
    if not target.resolve().parent.is_dir():
        raise InputError("output folder does not exist, expected an existing folder", target)
    if target.is_dir():  # found here, not after the work when the rename fails
        raise InputError(f"{option} target is a directory, expected a file name", target)
    return target


def save_figure(figure: Figure, path: str | PathLike[str], *, dpi: int = 120) -> Path:
    """Write ``figure`` to ``path`` atomically; the format follows the suffix (png, pdf, svg).

    Parameters
    ----------
    figure
        The figure (built by a ``plots`` module).
    path
        The file to write; its folder must exist.
    dpi
        Resolution of raster formats [dots per inch].

    Returns
    -------
    Path
        ``path``.
    """
    target = check_figure_path(path)
    with atomic_write(target, "wb") as out:
        figure.savefig(out, format=target.suffix.lower().lstrip("."), dpi=dpi)
    return target


__all__ = ["FIGURE_SUFFIXES", "check_figure_path", "save_figure"]
