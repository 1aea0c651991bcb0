"""Seams of the command line found on first contact (issue 15)."""

from __future__ import annotations

import subprocess
import sys


def test_broken_pipe_exits_quietly() -> None:
    """`stepframe demo --json | head -0`: the reader is gone before the first write."""
    process = subprocess.Popen(
        [sys.executable, "-c", "from stepframe.cli import main; import sys; sys.exit(main())",
         "demo", "--json"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )  # fmt: skip
    assert process.stdout is not None and process.stderr is not None
    process.stdout.close()  # no reader: every write raises BrokenPipeError
    stderr = process.stderr.read().decode()
    assert process.wait(timeout=120) == 141
    assert "Traceback" not in stderr and "BrokenPipe" not in stderr, stderr
