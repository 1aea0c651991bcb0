"""The chosen motions out: each chosen component at its scale factor, ready for an analysis.

``OUTDIR/motions/`` holds, for each chosen component in the chosen order (``NN`` its place):

- ``NN_<record>_<component>.AT2`` (the record's name without its folders): a PEER AT2 file in
  g (ten significant digits, DT in its shortest exact form), which ``stepframe`` and PEER's own
  tools read;
- ``NN_<record>_<component>.txt``: the same samples in g, one per line and nothing else, so that
  an OpenSees ``timeSeries Path -dt DT -filePath FILE -factor g`` or a spreadsheet reads it
  directly (its DT is in the manifest);
- ``manifest.csv``: one row per component (:data:`MANIFEST_COLUMNS`), the table a script
  loops over.

The scaled spectra of the set are ``OUTDIR/spectra.csv`` (:mod:`.chosen`). Values are the
recorded samples times the scale factor, divided by standard gravity (9.80665 m/s²).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import Path, PurePath
from typing import Any

import numpy as np

from stepframe.pipeline.selection.chosen import Motion
from stepframe.records.units import STANDARD_GRAVITY_M_S2

#: The manifest's columns: name → (unit, meaning).
MANIFEST_COLUMNS: dict[str, tuple[str, str]] = {
    "order": ("", "place in the chosen set (1 first)"),
    "at2_file": ("", "the PEER AT2 file, relative to the manifest"),
    "text_file": ("", "the one-column text file (samples only), relative to the manifest"),
    "record": ("", "the record the component belongs to"),
    "component": ("", "the component (channel) name"),
    "scale": ("", "scale factor applied to the recorded samples"),
    "dt_s": ("s", "sampling interval"),
    "npts": ("", "number of samples"),
    "units": ("", "units of the exported values (g: standard gravity 9.80665 m/s²)"),
    "pga_g": ("g", "peak absolute value of the exported (scaled) samples"),
    "source_file": ("", "the record file it was read from"),
}
MOTIONS_FOLDER = "motions"
MANIFEST_FILE = "manifest.csv"
#: Digits after the point in the exported values (ten significant digits).
DIGITS = 9


def _safe(text: str) -> str:
    """A file-name-safe version of ``text`` (letters, digits, ``-`` and ``.``)."""
    return re.sub(r"[^A-Za-z0-9.\-]+", "_", text).strip("_") or "record"


def scaled_g(motion: Motion) -> np.ndarray:
    """The exported samples: acceleration times the scale factor, in g."""
    return np.asarray(motion.acc_m_s2 * motion.scale / STANDARD_GRAVITY_M_S2)


def export_motions(motions: Sequence[Motion], folder: Path) -> dict[str, Path]:
    """Write the chosen motions into ``folder / "motions"``, replacing the folder whole
    (:func:`stepframe.core.io.staged_folder`: a reader sees the earlier motions or these, and
    none of an earlier run is left beside them: a re-run with fewer picks left the earlier
    run's 03_... to 10_... files beside a manifest of two).

    Parameters
    ----------
    motions
        The chosen components in the chosen order.
    folder
        The selection's output folder.

    Returns
    -------
    dict
        ``manifest`` → its path (the files are listed in it).
    """
    from stepframe.core.io import staged_folder

    target = folder / MOTIONS_FOLDER
    with staged_folder(target) as staging:
        _write_motions(motions, staging)
    return {"manifest": target / MANIFEST_FILE}


def _write_motions(motions: Sequence[Motion], target: Path) -> None:
    """The motions' AT2 and text files and the manifest, in ``target``."""
    import pandas as pd

    from stepframe.core.io import atomic_write, write_bytes
    from stepframe.pipeline.catalogue.example_files import at2_bytes

    rows: list[dict[str, Any]] = []
    for k, motion in enumerate(motions):
        # The record's own name, not its path: a record named by its file, given as
        # ../data/CICLC.v1, made 03_.._data_CICLC.v1_360.txt; the place NN keeps stems apart.
        stem = f"{k + 1:02d}_{_safe(PurePath(motion.record).name)}_{_safe(motion.component)}"
        values = scaled_g(motion)
        data = at2_bytes(
            values,
            motion.dt_s,
            motion.component,
            (motion.event or motion.record).replace(",", " "),
            motion.station.replace(",", " "),
            digits=DIGITS,
            dt_text=repr(float(motion.dt_s)),
        )
        write_bytes(target / f"{stem}.AT2", data)
        text = "".join(f"{v:.{DIGITS}E}\n" for v in values)
        write_bytes(target / f"{stem}.txt", text.encode("ascii"))
        rows.append(
            {
                "order": k + 1,
                "at2_file": f"{stem}.AT2",
                "text_file": f"{stem}.txt",
                "record": motion.record,
                "component": motion.component,
                "scale": motion.scale,
                "dt_s": motion.dt_s,
                "npts": int(values.size),
                "units": "g",
                "pga_g": float(np.max(np.abs(values))) if values.size else float("nan"),
                "source_file": motion.file,
            }
        )
    manifest = pd.DataFrame(rows, columns=list(MANIFEST_COLUMNS))
    with atomic_write(target / MANIFEST_FILE) as handle:
        manifest.to_csv(handle, index=False, float_format="%.10g")
