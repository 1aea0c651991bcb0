"""The workspace lock: one run at a time, released by the OS when the holder dies.

``fcntl.flock`` on ``<workspace>/lock``: the kernel drops the lock when the process exits for any
reason (SIGKILL included), so a killed run never leaves a stale lock to clear by hand. The holder
writes its pid into the file so that a second run can say who holds it. The lock file is the one
file not written through ``atomic_write``: it must stay the same inode for the lock to mean
anything, and its content is only informative.
"""

from __future__ import annotations

import contextlib
import fcntl
import os
from collections.abc import Iterator
from pathlib import Path

from stepframe.errors import InputError, StepframeError

LOCK_NAME = "lock"


class WorkspaceBusy(StepframeError):
    """Another process holds the workspace lock (exit status 3).

    Parameters
    ----------
    pid
        The holder's pid as written in the lock file (None if it could not be read).
    """

    def __init__(self, workspace: Path, pid: int | None) -> None:
        self.workspace = workspace
        self.pid = pid
        holder = f"pid {pid}" if pid is not None else "pid unknown"
        super().__init__(f"{workspace}: already running ({holder})")


def _holder(path: Path) -> int | None:
    try:
        return int(path.read_text().strip() or "x")
    except (OSError, ValueError):
        return None


@contextlib.contextmanager
def workspace_lock(workspace: Path, *, wait: bool = False) -> Iterator[Path]:
    """Hold the workspace's lock for the ``with`` block.

    Parameters
    ----------
    workspace
        The workspace folder (created if missing).
    wait
        Block until the lock is free instead of raising :class:`WorkspaceBusy`.

    Raises
    ------
    WorkspaceBusy
        Another run holds the lock and ``wait`` is False.
    InputError
        The workspace cannot be created or written.
    """
    path = workspace / LOCK_NAME
    try:
        workspace.mkdir(parents=True, exist_ok=True)
        descriptor = os.open(path, os.O_RDWR | os.O_CREAT, 0o666)
    except PermissionError:
        raise InputError(
            "workspace is not writable, expected a writable folder", workspace
        ) from None
    except OSError as error:
        raise InputError(
            f"cannot create the workspace ({error.strerror}), expected a writable folder",
            workspace,
        ) from None
    try:
        try:
            fcntl.flock(descriptor, fcntl.LOCK_EX | (0 if wait else fcntl.LOCK_NB))
        except BlockingIOError:
            raise WorkspaceBusy(workspace, _holder(path)) from None
        os.ftruncate(descriptor, 0)
        os.pwrite(descriptor, f"{os.getpid()}\n".encode(), 0)
        try:
            yield path
        finally:
            # Empty before unlocking: a pid in an unlocked file would name a finished run.
            os.ftruncate(descriptor, 0)
            fcntl.flock(descriptor, fcntl.LOCK_UN)
    finally:
        os.close(descriptor)
