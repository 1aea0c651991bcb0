"""Property: any bytes given to any reader give a Stream or a stepframe error, nothing else.

Each reader is called directly (not through :func:`stepframe.records.read`, whose last-resort net
turns an unforeseen exception into a one-line error), so an exception a reader did not foresee
fails here. Inputs are real files from tests/data edited at hypothesis-chosen places with
hypothesis-chosen text (numbers that parse but cannot be used, separators, cut lines), plus raw
bytes; each example runs under a time bound.
"""

from __future__ import annotations

import gzip
import signal
from pathlib import Path
from types import FrameType

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from stepframe.errors import StepframeError
from stepframe.records.formats import ReadOptions, registered_formats

DATA = Path(__file__).parents[1] / "data"
#: Readers warn about what they skip or doubt; that is part of a clean read here.
pytestmark = pytest.mark.filterwarnings("ignore")
SOURCES = {
    "at2": "peer_nga_west2/RSN8883_14383980_13849090.AT2",
    "cosmos": "formats/cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c.gz",
    "dmg": "formats/dmg/CE58667.V2.gz",
    "esm": "formats/esm/HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz",
    "geonet": "formats/geonet/20180212_211557_WPWS_20.V2A.gz",
    "knet": "formats/knet/AOM0011801241951.EW.gz",
    "mseed": "formats/miniseed/CE.68150.unprocessed_counts.mseed",
    "sac": "formats/sac/seism.sac",
}
TOKENS = [
    "nan", "inf", "-inf", "1e308", "1e400", "1e-300", "0", "-1", "99999999999", "27.1.4", ".",
    "", " ", "-", "\n", "\r\n", ",", "=", "0x1F", "1D+05", "\x00", "\xff", "-4.1.6", "9" * 40,
]  # fmt: skip
#: Seconds one example may take (a guard against hangs, far above a normal read).
LIMIT_S = 20
SETTINGS = settings(
    max_examples=25,
    deadline=None,
    derandomize=True,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
)


def _source(name: str) -> bytes:
    raw = (DATA / SOURCES[name]).read_bytes()
    data = gzip.decompress(raw) if SOURCES[name].endswith(".gz") else raw
    # A short prefix keeps each example cheap; the header (where damage matters most) is in it.
    return data[:60_000]


class _Hang(Exception):
    pass


def _alarm(signum: int, frame: FrameType | None) -> None:
    raise _Hang


def _check(name: str, content: bytes, tmp_path: Path) -> None:
    path = tmp_path / f"example.{name}"
    path.write_bytes(content)
    reader = registered_formats()[name if name != "knet" else "knet"]
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(LIMIT_S)
    try:
        stream = reader.read(path, ReadOptions(units="g", dt_s=0.01))
    except StepframeError:
        return
    except _Hang:
        pytest.fail(f"{name} reader took more than {LIMIT_S} s")
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    for trace in stream:
        assert trace.stats.delta > 0 and np.asarray(trace.data).ndim == 1


edits = st.lists(
    st.tuples(st.floats(0, 1), st.integers(0, 12), st.sampled_from(TOKENS)), min_size=1, max_size=4
)


def _apply(data: bytes, changes: list[tuple[float, int, str]], header_bias: bool) -> bytes:
    out = bytearray(data)
    for where, width, token in changes:
        # Most damage goes to the first 3 kB (the header), the rest anywhere.
        span = min(len(out), 3000) if header_bias else len(out)
        at = int(where * max(span - 1, 0))
        out[at : at + width] = token.encode("latin-1")
    return bytes(out)


@pytest.mark.parametrize("name", sorted(SOURCES))
@SETTINGS
@given(changes=edits, header_bias=st.booleans(), cut=st.floats(0.0, 1.0))
def test_edited_real_file(
    name: str, changes: list[tuple[float, int, str]], header_bias: bool, cut: float,
    tmp_path_factory: pytest.TempPathFactory,
) -> None:  # fmt: skip
    data = _apply(_source(name), changes, header_bias)
    if cut < 0.2:
        data = data[: int(len(data) * cut / 0.2)]
    _check(name, data, tmp_path_factory.mktemp(name))


@pytest.mark.parametrize("name", sorted({*SOURCES, "text", "fema"}))
@SETTINGS
@given(content=st.binary(max_size=3000))
def test_any_bytes(name: str, content: bytes, tmp_path_factory: pytest.TempPathFactory) -> None:
    _check(name, content, tmp_path_factory.mktemp(name))


def test_every_registered_format_is_covered() -> None:
    # A new format must join this suite (obspy's long tail is covered through read()'s net).
    ours = {n for n, f in registered_formats().items() if f.read.__module__.endswith(n)}
    assert ours <= {*SOURCES, "text", "fema"}, ours
