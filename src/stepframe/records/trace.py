"""Building the record type: an ``obspy.Trace`` in m/s² with ``stats.stepframe`` metadata.

Every reader ends here, so every record has the same metadata keys whatever its format
(DESIGN.md, Types users see). ``stats.stepframe.processing`` starts with the steps a format's own
definition requires (for example NIED's mean removal) and grows as processing steps succeed.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike

from stepframe.errors import InputError

if TYPE_CHECKING:
    from obspy import Trace, UTCDateTime

#: Keys every record's ``stats.stepframe`` carries (``None`` where the format has no value).
#: ``incomplete`` is None for a complete record; a record read short (``allow_short``) carries
#: what is missing there (``"3849 of 28600 samples"``, ``"1 of 3 components"``), so every
#: output made from it can say so.
METADATA_KEYS = (
    "source_file",
    "format",
    "units_in",
    "event",
    "rsn",
    "magnitude",
    "repi_km",
    "rrup_km",
    "rjb_km",
    "vs30_m_s",
    "incomplete",
    "processing",
)


def make_trace(
    data_m_s2: ArrayLike,
    dt_s: float,
    *,
    station: str = "",
    channel: str = "",
    network: str = "",
    location: str = "",
    starttime: UTCDateTime | str | float | None = None,
    **metadata: object,
) -> Trace:
    """Make a record (``obspy.Trace``) from acceleration samples in m/s².

    Parameters
    ----------
    data_m_s2
        Acceleration samples [m/s²], uniformly spaced.
    dt_s
        Sampling interval [s], kept at full precision.
    station, channel, network, location
        SEED-style identifiers (free text for formats that have no SEED codes).
    starttime
        Time of the first sample (``obspy.UTCDateTime`` or anything it accepts); epoch 0 if None.
    **metadata
        Values for ``stats.stepframe`` (keys of :data:`METADATA_KEYS`; others are kept too).

    Returns
    -------
    obspy.Trace
        ``stats.stepframe`` is an ``obspy.core.util.AttribDict`` with every key of
        :data:`METADATA_KEYS`; ``processing`` is a list of ``{"step": name, **parameters}``.
    """
    from obspy import Trace, UTCDateTime
    from obspy.core.util import AttribDict

    data = np.asarray(data_m_s2, dtype=np.float64)
    if data.ndim != 1 or data.size == 0:
        raise InputError(
            f"record has {data.size} samples in shape {data.shape}, expected a 1-D series"
        )
    if not (np.isfinite(dt_s) and dt_s > 0):
        raise InputError(f"sampling interval dt = {dt_s} s, expected a positive number")
    info = dict.fromkeys(METADATA_KEYS)
    info["processing"] = []
    info.update(metadata)
    trace = Trace(data=np.ascontiguousarray(data))
    trace.stats.delta = float(dt_s)
    trace.stats.network = network
    trace.stats.station = station
    trace.stats.location = location
    trace.stats.channel = channel
    trace.stats.starttime = UTCDateTime(0) if starttime is None else UTCDateTime(starttime)
    trace.stats.stepframe = AttribDict(info)
    return trace
