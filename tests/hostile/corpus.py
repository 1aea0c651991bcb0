"""A seeded corpus of damaged accelerogram files, generated from tests/data at test time.

Each damage is one a real user or a real disk produces: a truncated download, flipped bits, a
header number edited by hand or by a broken converter (``inf``, ``nan``, ``1e308``, ``1e-300``,
``27.1.4``), a NaN, an infinity or an absurd value among the samples, CRLF line ends, an empty or
binary file, a corrupt gzip, a record of zeros, escape sequences or a spreadsheet formula in a
station name, odd file names. :func:`build` writes them into a folder and returns their paths and
the format each came from; the same seed gives the same corpus.
"""

from __future__ import annotations

import gzip
import random
import re
from dataclasses import dataclass
from pathlib import Path

DATA = Path(__file__).parents[1] / "data"

#: Source files (relative to tests/data) and their --format names.
SOURCES: tuple[tuple[str, str], ...] = (
    ("peer_nga_west2/RSN8883_14383980_13849090.AT2", "at2"),
    ("formats/cosmos/Cosmos12TimeSeriesTest.v1.gz", "cosmos"),
    ("formats/cosmos/us1000hyfh_akbmrp_AKBMR--n.1000hyfh.BNZ.--.acc.V2c.gz", "cosmos"),
    ("formats/dmg/CE58667.V2.gz", "dmg"),
    ("formats/dmg/CICLC.v1.gz", "dmg"),
    ("formats/esm/HI.ARS1..HNE.D.20190728.160908.C.ACC.ASC.gz", "esm"),
    ("formats/geonet/20180212_211557_WPWS_20.V2A.gz", "geonet"),
    ("formats/geonet/20161113_110300_HSES_20.V1A.gz", "geonet"),
    ("formats/knet/AOM0011801241951.EW.gz", "knet"),
    ("formats/miniseed/CE.68150.unprocessed_counts.mseed", "mseed"),
    ("formats/sac/seism.sac", "sac"),
    # Agency variants the project wrote itself (issue 27): ESM after processing lines, with
    # None fields; CDMG V2 of the 1980s, CRLF and DOS end-of-file characters.
    ("formats/variants/esm/TK.0001..HNE.agency.ASC", "esm"),
    ("formats/variants/dmg/CDMG1983.V2", "dmg"),
)

#: Replacements for a header number: unusable values that parse, and values that do not.
BAD_NUMBERS = (
    "nan",
    "inf",
    "-inf",
    "1e308",
    "1e400",
    "1e-300",
    "0",
    "-1",
    "99999999999",
    "27.1.4",
    ".",
    "",
    "-4.1.6",
    "0x10",
)

#: Replacements for one sample.
BAD_SAMPLES = ("nan", "inf", "-inf", "1e308", "1e30", "-1e300")

_NUMBER = re.compile(r"(?<![\w.])-?\d+(?:\.\d*)?(?:[eEdD][-+]?\d+)?(?![\w.])")


@dataclass(frozen=True)
class Damaged:
    """One damaged file: its path, the format its source is in, and the damage done."""

    path: Path
    format: str
    damage: str


def _source_bytes(relative: str) -> bytes:
    raw = (DATA / relative).read_bytes()
    return gzip.decompress(raw) if relative.endswith(".gz") else raw


def _is_text(data: bytes) -> bool:
    return b"\x00" not in data[:4096]


def _edit_number(text: str, rng: random.Random, first_lines: int, values: tuple[str, ...]) -> str:
    """Replace one number among the first ``first_lines`` lines (header) by a bad value."""
    lines = text.split("\n")
    limit = min(first_lines, len(lines))
    candidates = [(i, m.start(), m.end()) for i in range(limit) for m in _NUMBER.finditer(lines[i])]
    if not candidates:
        return text
    i, start, end = rng.choice(candidates)
    lines[i] = lines[i][:start] + rng.choice(values) + lines[i][end:]
    return "\n".join(lines)


def _edit_sample(text: str, rng: random.Random) -> str:
    """Replace one number in the second half of the file (data) by a non-finite or huge value."""
    lines = text.split("\n")
    half = len(lines) // 2
    for _ in range(50):
        i = rng.randrange(half, len(lines))
        found = list(_NUMBER.finditer(lines[i]))
        if found:
            m = rng.choice(found)
            value = rng.choice(BAD_SAMPLES).rjust(m.end() - m.start())
            lines[i] = lines[i][: m.start()] + value + lines[i][m.end() :]
            return "\n".join(lines)
    return text


def _zero_data(text: str) -> str:
    """Every number in the second half of the file set to zero (keeps the header)."""
    lines = text.split("\n")
    half = len(lines) // 3
    body = [_NUMBER.sub(lambda m: "0".rjust(len(m[0])), line) for line in lines[half:]]
    return "\n".join(lines[:half] + body)


def _station(text: str, rng: random.Random) -> str:
    """Put an escape sequence or a spreadsheet formula into the header's first words."""
    payload = rng.choice(
        ["\x1b[31mRED\x1b[0m", '=HYPERLINK("http://x","y")', "+1+1", "@SUM(A1)", "\x07bell\r"]
    )
    lines = text.split("\n")
    i = rng.randrange(0, min(6, len(lines)))
    lines[i] = payload + lines[i]
    return "\n".join(lines)


def damages(data: bytes, rng: random.Random) -> list[tuple[str, bytes]]:
    """Damaged versions of one file's bytes, each named by its damage."""
    out: list[tuple[str, bytes]] = []
    for fraction in (0.01, 0.3, 0.77, 0.999):
        cut = max(1, int(len(data) * fraction) + rng.randrange(-3, 4))
        out.append((f"truncated{fraction}", data[:cut]))
    for n in (1, 8, 64):
        flipped = bytearray(data)
        for _ in range(n):
            k = rng.randrange(len(flipped))
            flipped[k] ^= 1 << rng.randrange(8)
        out.append((f"flipped{n}", bytes(flipped)))
    head = bytearray(data)
    for _ in range(4):
        k = rng.randrange(min(len(head), 2048))
        head[k] = rng.randrange(256)
    out.append(("header_bytes", bytes(head)))
    if _is_text(data):
        text = data.decode("latin-1")
        for k in range(12):
            out.append(
                (f"header_number{k}", _edit_number(text, rng, 40, BAD_NUMBERS).encode("latin-1"))
            )
        for k in range(3):
            out.append((f"sample{k}", _edit_sample(text, rng).encode("latin-1")))
        out.append(("crlf", text.replace("\n", "\r\n").encode("latin-1")))
        out.append(("zeros", _zero_data(text).encode("latin-1")))
        out.append(("station", _station(text, rng).encode("latin-1")))
        out.append(("gzip_cut", gzip.compress(data)[: len(data) // 20 + 30]))
    return out


def build(folder: Path, seed: int = 16) -> list[Damaged]:
    """Write the corpus into ``folder`` and return its files (deterministic for a seed)."""
    rng = random.Random(seed)
    folder.mkdir(parents=True, exist_ok=True)
    corpus: list[Damaged] = []
    for relative, fmt in SOURCES:
        data = _source_bytes(relative)
        stem = Path(relative).name.removesuffix(".gz")
        for damage, content in damages(data, rng):
            path = folder / f"{damage}__{stem}"
            path.write_bytes(content)
            corpus.append(Damaged(path, fmt, damage))
    # Files that are damaged whatever their source.
    extra: list[tuple[str, bytes, str]] = [
        ("empty.AT2", b"", "at2"),
        ("blank.txt", b"\n\n   \n", "text"),
        ("random.bin", bytes(rng.randrange(256) for _ in range(5000)), "mseed"),
        ("nul.AT2", b"\x00" * 3000, "at2"),
        ("utf16.txt", "0.1\n0.2\n0.3\n".encode("utf-16"), "text"),
        ("one_value.txt", b"0.5\n", "text"),
        ("nan_time.txt", b"0 0.1\n0.01 0.2\nnan 0.3\n0.03 0.1\n0.5 0.2\n", "text"),
        ("gap_time.txt", b"0 0.1\n0.01 0.2\n0.02 0.3\n0.5 0.1\n0.51 0.2\n", "text"),
        ("huge.txt", b"0 1e308\n0.01 -1e308\n0.02 1e308\n", "text"),
        ("tiny_dt.txt", b"0 0.1\n1e-300 0.2\n2e-300 0.3\n", "text"),
        ("zeros.txt", b"0 0\n0.01 0\n0.02 0\n0.03 0\n", "text"),
        ("not_gzip.gz", b"\x1f\x8b" + b"garbage" * 100, "at2"),
        ("name with spaces ü.AT2", _source_bytes(SOURCES[0][0])[:3000], "at2"),
        ("-dash.AT2", _source_bytes(SOURCES[0][0])[:2000], "at2"),
    ]
    for name, content, fmt in extra:
        path = folder / name
        path.write_bytes(content)
        corpus.append(Damaged(path, fmt, name))
    directory = folder / "directory.AT2"
    directory.mkdir(exist_ok=True)
    corpus.append(Damaged(directory, "at2", "directory"))
    corpus.append(Damaged(folder / "missing.AT2", "at2", "missing"))
    return corpus


def write_long_at2(path: Path, npts: int) -> Path:
    """An AT2 file of ``npts`` samples at dt = 5 ms: the real 16,396-sample record of
    :data:`SOURCES` repeated, five values a line as PEER writes them (15.2 bytes a sample)."""
    lines = (DATA / SOURCES[0][0]).read_text().splitlines()
    values = " ".join(lines[4:]).split()
    block = [f"{float(v):15.7E}" for v in values[: len(values) - len(values) % 5]]
    body = "\n".join("".join(block[i : i + 5]) for i in range(0, len(block), 5)) + "\n"
    with path.open("w") as handle:
        handle.write("\n".join(lines[:3]) + "\n")
        handle.write(f"NPTS= {npts:>10d}, DT=   0.005 SEC\n")
        written = 0
        while written + len(block) <= npts:
            handle.write(body)
            written += len(block)
        rest = block[: npts - written]
        for i in range(0, len(rest), 5):
            handle.write("".join(rest[i : i + 5]) + "\n")
    return path


#: A child process (``python -c MEASURE_CHILD ARGV...``) that runs a stepframe command under
#: tracemalloc and prints on its last stderr line the exit status, the peak of every Python and
#: numpy allocation and each estimate asked of ``check_memory`` (need, what); the command in the
#: environment variable WARM (JSON), when given, runs first, outside the measure (imports, the
#: kernels' loading). Used by tests/hostile/test_memory_budget.py and bench/bench_command_memory.py.
MEASURE_CHILD = """\
import json, os, sys, tracemalloc
from stepframe.core import memory
asked = []
original = memory.check_memory
def spy(need, what, advice="", **kw):
    asked.append((need, what))
    return original(need, what, advice, **kw)
memory.check_memory = spy
import stepframe.pipeline.selection.memory as selection
selection.check_memory = spy  # bound at its import; the others import it when they check
from stepframe.cli import main
if os.environ.get("WARM"):
    main(json.loads(os.environ["WARM"]))
    asked.clear()
tracemalloc.start()
status = main(sys.argv[1:])
peak = tracemalloc.get_traced_memory()[1]
print(json.dumps({"status": status, "peak": peak, "asked": asked}), file=sys.stderr)
"""
