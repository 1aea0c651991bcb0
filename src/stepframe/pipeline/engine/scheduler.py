"""Where a run's work goes: this machine's process pool, a local Dask cluster, or a remote one.

``None`` (default): the batches go through :func:`stepframe.core.execution.map_items` to one
:class:`~stepframe.core.execution.WorkerPool` of ``jobs`` workers for the whole run (started by
the first batch worth it; ``jobs=1`` runs everything in this process). ``"dask-local"`` starts a
``dask.distributed.LocalCluster`` (loopback only, one thread per worker process, no dashboard);
``"tcp://HOST:PORT"`` connects to a running scheduler. Both hand ``map_items`` the client's
``concurrent.futures`` executor (``client.get_executor()``). Dask workers read records from their
paths: they must see the same filesystem as the machine that runs ``stepframe run``
(docs/scaling.md).
"""

from __future__ import annotations

import contextlib
from collections.abc import Iterator
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import Any

from stepframe.errors import InputError

DASK_INSTALL = "pip install 'stepframe[dask]'"


@dataclass(frozen=True)
class Execution:
    """The executor of a run: ``executor`` None means this process (``jobs`` 1)."""

    executor: Any
    jobs: int
    description: str


def _import_dask() -> Any:
    try:
        import dask.distributed as distributed
    except ImportError:
        raise InputError(
            f"Dask is not installed, expected the dask extra: {DASK_INSTALL}"
        ) from None
    return distributed


def check_scheduler(scheduler: str | None, jobs: int | None) -> None:
    """Check ``--scheduler`` and ``--jobs`` without starting anything.

    Raises
    ------
    InputError
        ``jobs`` below 1 (or, without it, a bad ``STEPFRAME_JOBS``), an unknown scheduler, or
        Dask missing (naming the install command).
    """
    from stepframe.core.execution import default_jobs

    if jobs is not None and jobs < 1:
        raise InputError(f"--jobs {jobs}, expected ≥ 1")
    if jobs is None:
        default_jobs()  # the variable is checked before anything is written
    if scheduler is None:
        return
    if scheduler != "dask-local" and not scheduler.startswith("tcp://"):
        raise InputError(f"--scheduler {scheduler}, expected dask-local or tcp://HOST:PORT")
    _import_dask()


@contextlib.contextmanager
def open_execution(
    scheduler: str | None, jobs: int | None, executor: Executor | None = None
) -> Iterator[Execution]:
    """The executor for a run, closed (cluster stopped) when the ``with`` block ends.

    A given ``executor`` (any ``concurrent.futures.Executor``) is used as it is and left open:
    its owner shuts it down.

    Raises
    ------
    InputError
        An unknown scheduler, Dask missing (naming ``pip install 'stepframe[dask]'``), or a
        scheduler address that does not answer.
    """
    from stepframe.core.execution import default_jobs, worker_pool

    if jobs is not None and jobs < 1:
        raise InputError(f"--jobs {jobs}, expected ≥ 1")
    if executor is not None:
        workers = jobs or default_jobs()
        yield Execution(executor, workers, f"{type(executor).__name__}, {workers} worker(s)")
        return
    if scheduler is None:
        workers = default_jobs() if jobs is None else jobs
        # One pool for the whole run, started by the first batch worth it: each batch used to
        # start its own (about a second of worker start-up per batch and stage).
        with worker_pool(workers) as pool:
            yield Execution(pool, workers, f"process pool, {workers} worker(s)")
        return
    if scheduler == "dask-local":
        distributed = _import_dask()
        workers = default_jobs() if jobs is None else jobs
        with (
            distributed.LocalCluster(
                n_workers=workers,
                threads_per_worker=1,
                processes=True,
                host="127.0.0.1",
                dashboard_address=None,
            ) as cluster,
            distributed.Client(cluster) as client,
        ):
            yield Execution(client.get_executor(), workers, f"dask-local, {workers} worker(s)")
        return
    if scheduler.startswith("tcp://"):
        distributed = _import_dask()
        try:
            client = distributed.Client(scheduler, timeout=10)
        except OSError as error:
            raise InputError(
                f"--scheduler {scheduler}: no Dask scheduler answers ({error}), expected a "
                "running scheduler at tcp://HOST:PORT"
            ) from None
        with client:
            workers = max(1, len(client.scheduler_info().get("workers", {})))
            yield Execution(client.get_executor(), workers, f"{scheduler}, {workers} worker(s)")
        return
    raise InputError(f"--scheduler {scheduler}, expected dask-local or tcp://HOST:PORT")
