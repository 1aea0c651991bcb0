"""Size and streams: a 2 GB file, a FIFO, standard input and process substitution.

These run the command in a subprocess: a FIFO could block and a large file could take the test's
memory, so the bound is the child's (wait4 gives its peak memory) and a timeout guards the run.
"""

from __future__ import annotations

import gzip
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from stepframe.errors import InputError
from stepframe.records import read

AT2 = Path(__file__).parents[1] / "data" / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"
#: Guard against a hang only (not a timing assertion): a blocked command is killed after this.
GUARD_S = 60


#: Runs the command and reports the child's own peak memory on its last stderr line. VmHWM is
#: the peak of this program's address space (getrusage's ru_maxrss would also count the pages
#: the child shared with the forking test process before exec).
_CHILD = """
import sys
from pathlib import Path
from stepframe.cli import main
code = main(sys.argv[1:])
status = Path("/proc/self/status").read_text().splitlines()
peak_kib = next(int(x.split()[1]) for x in status if x.startswith("VmHWM:"))
print(f"peak_kib={peak_kib}", file=sys.stderr)
sys.exit(code)
"""


def _run(argv: list[str], **kwargs: object) -> tuple[int, str, str, float]:
    """Run ``stepframe ARGV``; (status, stdout, stderr, peak memory of the child [MiB])."""
    try:
        result = subprocess.run(
            [sys.executable, "-c", _CHILD, *argv],
            capture_output=True,
            text=True,
            timeout=GUARD_S,
            **kwargs,  # type: ignore[call-overload]
        )
    except subprocess.TimeoutExpired:
        pytest.fail(f"stepframe {' '.join(argv)} blocked for {GUARD_S} s")
    lines = result.stderr.splitlines(keepends=True)
    assert lines and lines[-1].startswith("peak_kib="), result.stderr
    peak_mib = int(lines[-1].split("=")[1]) / 1024.0
    return result.returncode, result.stdout, "".join(lines[:-1]), peak_mib


@pytest.fixture
def sparse_2gb(tmp_path: Path) -> Path:
    path = tmp_path / "huge.AT2"
    with path.open("wb") as handle:
        handle.write(AT2.read_bytes()[:2000])
        handle.truncate(2 * 1024**3)  # sparse: 2 GiB of size, a few kB on disk
    return path


@pytest.mark.parametrize("fmt", [None, "at2"])
def test_2gb_sparse_file_refused_with_bounded_memory(sparse_2gb: Path, fmt: str | None) -> None:
    argv = ["records", "info", *(["--format", fmt] if fmt else []), str(sparse_2gb)]
    status, out, err, peak_mib = _run(argv)
    assert status == 2 and out == ""
    assert err.count("\n") == 1 and "2147483648 bytes" in err and "at most" in err, err
    assert peak_mib < 100, peak_mib


def test_fifo_is_an_error_not_a_block(tmp_path: Path) -> None:
    fifo = tmp_path / "record.AT2"
    os.mkfifo(fifo)
    status, out, err, _ = _run(["records", "info", str(fifo)])
    assert status == 2 and out == "" and "FIFO with no writer" in err, err
    with pytest.raises(InputError, match="empty input"):
        read(fifo)


def test_catalog_skips_a_fifo_and_its_own_outputs(tmp_path: Path) -> None:
    folder = tmp_path / "records"
    folder.mkdir()
    shutil.copy(AT2, folder / AT2.name)
    os.mkfifo(folder / "pipe.AT2")
    (folder / "LICENSE.txt").write_text("licence text, not a record\n")
    for _ in range(2):  # the second run must not read the first run's outputs
        status, _, err, _ = _run(["records", "catalog", str(folder), "-o", str(folder / "cat.csv")])
        assert status == 0, err
        failures = (folder / "cat.failures.csv").read_text().splitlines()
        assert failures == ["item,stage,error_type,message"], failures
        assert len((folder / "cat.csv").read_text().splitlines()) == 2


def test_catalog_output_checked_before_work(tmp_path: Path) -> None:
    status, _, err, _ = _run(["records", "catalog", str(AT2.parent), "-o", "/nonexistent/x.csv"])
    assert status == 2 and "output folder does not exist" in err and "[1/" not in err, err


def _info_json(argv: list[str], **kwargs: object) -> str:
    status, out, err, _ = _run(argv, **kwargs)
    assert status == 0, err
    return out


def test_stdin_and_dev_stdin_read_like_the_file(tmp_path: Path) -> None:
    expected = _info_json(["records", "info", "--json", str(AT2)])
    with AT2.open("rb") as handle:
        from_dash = _info_json(["records", "info", "--json", "-"], stdin=handle)
    with AT2.open("rb") as handle:
        from_dev = _info_json(["records", "info", "--json", "/dev/stdin"], stdin=handle)
    # Same numbers; only the file name differs.
    strip = [line for line in expected.splitlines() if "file" not in line]
    assert [line for line in from_dash.splitlines() if "file" not in line] == strip
    assert [line for line in from_dev.splitlines() if "file" not in line] == strip


@pytest.mark.skipif(shutil.which("bash") is None, reason="process substitution needs bash")
def test_process_substitution_of_a_gzip(tmp_path: Path) -> None:
    packed = tmp_path / "rec.AT2.gz"
    packed.write_bytes(gzip.compress(AT2.read_bytes()))
    expected = _info_json(["records", "info", "--json", str(AT2)])
    command = f'"{sys.executable}" -m stepframe.cli records info --json <(zcat "{packed}")'
    result = subprocess.run(
        ["bash", "-c", command], capture_output=True, text=True, timeout=GUARD_S
    )
    assert result.returncode == 0, result.stderr
    strip = [line for line in expected.splitlines() if "file" not in line]
    assert [line for line in result.stdout.splitlines() if "file" not in line] == strip


def test_gzip_bomb_bounded(tmp_path: Path) -> None:
    bomb = tmp_path / "bomb.AT2.gz"
    with gzip.open(bomb, "wb", compresslevel=1) as handle:
        for _ in range(8):
            handle.write(b"0" * 1024**2)
    start = time.monotonic()
    with pytest.raises(InputError, match="decompresses to more than 1000000 bytes"):
        read(bomb, max_bytes=1_000_000)
    assert time.monotonic() - start < GUARD_S
