"""Kill test of a parallel batch: SIGKILL the parent of a ``map_items`` pool mid-run.

The batch runs in a child Python process with two workers; each item records its worker's pid and
sleeps. Once both workers are busy, the child is killed with SIGKILL (no cleanup can run). No
worker may outlive it: the pool's initializer asks the kernel to signal each worker when its
parent dies (prctl PR_SET_PDEATHSIG, Linux).
"""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="prctl is Linux")

#: Seconds allowed for each phase (a guard against a hang, not a timing assertion).
GUARD_S = 60.0

_BATCH = textwrap.dedent(
    """
    import os, sys, time
    from pathlib import Path
    from stepframe.core.execution import map_items

    FOLDER = Path(sys.argv[1])

    def work(item):
        (FOLDER / f"{os.getpid()}.pid").write_text(str(item))
        time.sleep(120)  # long enough to be killed mid-item
        return item

    if __name__ == "__main__":
        # worth_s=0: every item to the workers (no first item timed here: this one sleeps)
        map_items(work, list(range(8)), jobs=2, chunk_size=1, worth_s=0)
    """
)


def _alive(pid: int) -> bool:
    """True while ``pid`` runs (a zombie awaiting its reaper counts as gone)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (FileNotFoundError, ProcessLookupError):
        return False
    return state != "Z"


def _wait_for(condition: object, what: str) -> None:
    deadline = time.monotonic() + GUARD_S
    while not condition():  # type: ignore[operator]
        if time.monotonic() > deadline:
            pytest.fail(f"{what} not within {GUARD_S} s")
        time.sleep(0.05)


def test_sigkill_of_parent_leaves_no_worker(tmp_path: Path) -> None:
    script = tmp_path / "batch.py"
    script.write_text(_BATCH)
    pids = tmp_path / "pids"
    pids.mkdir()
    parent = subprocess.Popen([sys.executable, str(script), str(pids)])
    try:
        _wait_for(lambda: len(list(pids.glob("*.pid"))) >= 2, "two busy workers")
        workers = [int(p.stem) for p in pids.glob("*.pid")]
        assert all(_alive(pid) for pid in workers) and parent.pid not in workers
        os.kill(parent.pid, signal.SIGKILL)
        parent.wait(timeout=GUARD_S)
        _wait_for(lambda: not any(_alive(pid) for pid in workers), "workers gone")
    finally:
        if parent.poll() is None:
            parent.kill()
        for pid_file in pids.glob("*.pid"):  # never leave a sleeper behind, even on failure
            with contextlib.suppress(ProcessLookupError):
                os.kill(int(pid_file.stem), signal.SIGKILL)
