"""The one executor for batches: :func:`map_items`.

A batch maps one function over many items (record files, components, simulations). Items go to
workers in chunks (a few per task, so the hand-over cost stays small against the work); results
come back in input order whatever the worker count, so runs are reproducible. An item whose
function raises is recorded as a :class:`~stepframe.core.results.Failure` and the batch goes on.

Where the work runs is the caller's choice: ``jobs=1`` in this process; ``jobs=N`` a process pool
created once for the call (its workers die with this process, even on SIGKILL, on Linux); or any
``concurrent.futures.Executor`` the caller owns (a Dask client's ``get_executor()``, a thread
pool, a :class:`WorkerPool` shared by the batches of a run), which is used and left open.

Parallel work pays only when there is enough of it: before workers are started, :func:`map_items`
runs the first item in this process and times it, and runs the rest here too when they would take
less than starting the workers costs (:data:`POOL_WORTH_S`). The first item also pays this
process's first calls (imports, compiled kernels loaded from the cache), so when it says the
workers pay, a second item, timed on the warm process, decides (:data:`PROBE_ITEMS`); workers
forked after the probe inherit what it loaded. So ``jobs=2`` is never much slower than
``jobs=1`` on a small batch, and the probe items are work that needed doing. An executor whose
workers run (a started :class:`WorkerPool`, a Dask cluster) gets every batch, with no probe: the
main process stays free (its time is the serial part of a run).
"""

from __future__ import annotations

import contextlib
import math
import multiprocessing
import multiprocessing.context
import os
import sys
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Executor, Future, ProcessPoolExecutor
from dataclasses import dataclass
from typing import Any, Generic, ParamSpec, TypeVar

from stepframe.core.results import Failure
from stepframe.errors import InputError

Item = TypeVar("Item")
Result = TypeVar("Result")
Value = TypeVar("Value")
Params = ParamSpec("Params")

#: A batch whose remaining items would take less than this in this process [s] is run here
#: while the workers are not started: starting them costs about this much (fork, then what a
#: worker imports on its first item).
POOL_WORTH_S = 1.0

#: Items the probe runs in this process at most: the first pays the process's first calls, so a
#: second, timed warm, decides when the first alone would start the workers.
PROBE_ITEMS = 2


@dataclass(frozen=True)
class MapOutcome(Generic[Result]):
    """What :func:`map_items` returns.

    Attributes
    ----------
    results
        The results of the items that succeeded, in input order.
    failures
        One :class:`Failure` per item that raised, in input order.
    indices
        ``indices[k]`` is the input position of ``results[k]``.
    seconds
        Wall time of the batch [s].
    """

    results: list[Result]
    failures: list[Failure]
    indices: list[int]
    seconds: float

    def __iter__(self) -> Iterator[Any]:
        # Unpacks as ``results, failures = map_items(...)``.
        return iter((self.results, self.failures))


#: The environment variable that sets the number of worker processes a command starts when
#: ``--jobs`` is not given (a shared machine; a test suite whose own workers fill the CPUs).
JOBS_ENVIRONMENT = "STEPFRAME_JOBS"


def default_jobs() -> int:
    """Worker processes by default: :data:`JOBS_ENVIRONMENT` when set, else the CPUs this
    process may use.

    Raises
    ------
    InputError
        :data:`JOBS_ENVIRONMENT` is not a whole number in the range ``--jobs`` accepts.
    """
    text = os.environ.get(JOBS_ENVIRONMENT, "").strip()
    if text:
        from stepframe.core.options import JOBS

        jobs = int(text) if text.isdecimal() else 0
        if not JOBS.contains(jobs):
            raise InputError(
                f"{JOBS_ENVIRONMENT} = {text!r}, expected a number of worker processes "
                f"{JOBS.describe()} (or unset: all CPUs)"
            )
        return jobs
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def default_chunk_size(n_items: int, workers: int) -> int:
    """About four tasks per worker, at most 64 items a task."""
    return max(1, min(64, math.ceil(n_items / max(1, 4 * workers))))


#: In a worker of a :class:`WorkerPool`: the pool's shared flag, set by the first worker that
#: announces a compilation (:func:`claim_compile_notice`).
_compile_announced: Any = None


def _die_with_parent(parent_pid: int, announced: Any = None) -> None:
    """Process-pool initializer: end this worker when the process that started the batch dies,
    and let one worker of the pool announce a compilation (:mod:`stepframe.core.jit`).

    With a plain fork, Linux's parent-death signal (prctl PR_SET_PDEATHSIG) does it. A worker
    started from a fork server has the server as its parent, which outlives a SIGKILLed batch, so
    a daemon thread also polls the batch's process and ends the worker once it is gone.
    ``announced`` is the pool's shared flag (a ``multiprocessing.Value``).
    """
    # A worker forked before the kernels were loaded (a pool started by the records' hashing)
    # compiles them itself on a first run: one line for the whole pool, complete at once (notices
    # under way in several workers would interleave on one line); silenced as the parent is.
    global _compile_announced
    if os.environ.get("STEPFRAME_COMPILE_NOTICE", "1") != "0":
        os.environ["STEPFRAME_COMPILE_NOTICE"] = "worker"
    _compile_announced = announced
    if sys.platform.startswith("linux"):
        import ctypes
        import signal

        pr_set_pdeathsig = 1
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(pr_set_pdeathsig, signal.SIGTERM)
    if not _running(parent_pid):  # died between the fork and now
        os._exit(1)
    threading.Thread(target=_watch, args=(parent_pid,), daemon=True).start()


def claim_compile_notice() -> bool:
    """In a worker of a :class:`WorkerPool`: True for the first worker of the pool to ask (it
    announces the workers' compilation), False for the others and outside a pool."""
    flag = _compile_announced
    if flag is None:
        return False
    with flag.get_lock():
        first = not flag.value
        flag.value = 1
    return bool(first)


def _running(pid: int) -> bool:
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by someone else
        return True
    return True


def _watch(parent_pid: int) -> None:
    while _running(parent_pid):
        time.sleep(0.5)
    os._exit(1)


def _pool_context() -> multiprocessing.context.BaseContext:
    """A plain fork while it is safe, else a fork server (Linux, macOS), else spawn.

    A forked worker starts at once with this process's imports, which matters for short batches
    (docs/benchmarks.md, parallel efficiency). It is unsafe once this process has run numba's
    parallel loop: GNU OpenMP kills a child forked after its parent used its thread pool (the
    batch simulator does). Then workers come from a fork server, forked early from a clean
    state; a worker's parent is the server, and each worker watches this process (see
    :func:`_die_with_parent`), so the workers still die with it.
    """
    methods = multiprocessing.get_all_start_methods()
    if "fork" in methods and not _numba_threads_started():
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context("forkserver" if "forkserver" in methods else "spawn")


def _numba_threads_started() -> bool:
    """Whether this process has started numba's parallel thread pool (without importing numba)."""
    parallel = sys.modules.get("numba.np.ufunc.parallel")
    return bool(getattr(parallel, "_is_initialized", False))


class WorkerPool(Executor):
    """A process pool shared by the batches of a run, started on its first ``submit``.

    A run whose work is all cached, or small enough for :func:`map_items` to keep in this
    process, starts no worker. The start method is chosen at that first submit
    (:func:`_pool_context`: a plain fork while this process has not run numba's parallel loop),
    and a fork then gives the workers every module this process has imported, numba's compiled
    kernels included. The workers die with this process (:func:`_die_with_parent`).

    Parameters
    ----------
    workers
        Worker processes (≥ 1).
    """

    def __init__(self, workers: int) -> None:
        if workers < 1:
            raise InputError(f"jobs = {workers}, expected ≥ 1")
        self.workers = workers
        self._pool: ProcessPoolExecutor | None = None

    @property
    def started(self) -> bool:
        """Whether the worker processes have been started."""
        return self._pool is not None

    def submit(
        self, fn: Callable[Params, Value], /, *args: Params.args, **kwargs: Params.kwargs
    ) -> Future[Value]:
        """Submit to the pool, starting it first if needed."""
        if self._pool is None:
            context = _pool_context()
            self._pool = ProcessPoolExecutor(
                max_workers=self.workers,
                mp_context=context,
                initializer=_die_with_parent,
                initargs=(os.getpid(), context.Value("b", 0)),
            )
        return self._pool.submit(fn, *args, **kwargs)

    def shutdown(self, wait: bool = True, *, cancel_futures: bool = False) -> None:
        """Stop the workers (if started)."""
        if self._pool is not None:
            self._pool.shutdown(wait=wait, cancel_futures=cancel_futures)
            self._pool = None


def worker_pool(jobs: int | None) -> contextlib.AbstractContextManager[WorkerPool | None]:
    """A :class:`WorkerPool` of ``jobs`` workers (default: the CPUs available) for the batches of
    one run or command, shut down when the ``with`` block ends; None for ``jobs=1`` (all in
    this process)."""
    workers = default_jobs() if jobs is None else jobs
    if workers == 1:
        return contextlib.nullcontext(None)
    return WorkerPool(workers)


def _run_chunk(
    function: Callable[[Any], Any],
    chunk: Sequence[tuple[int, Any]],
    stage: str,
    name_of: Callable[[Any], str],
) -> list[tuple[int, bool, Any]]:
    """Run ``function`` on each (index, item); (index, True, result) or (index, False, Failure)."""
    out: list[tuple[int, bool, Any]] = []
    for index, item in chunk:
        try:
            out.append((index, True, function(item)))
        except Exception as error:  # a batch never stops for one bad item
            out.append((index, False, Failure.from_exception(name_of(item), stage, error)))
    return out


class _Progress:
    """Count, rate and ETA on stderr (tqdm on a terminal; one summary line otherwise)."""

    def __init__(self, total: int, label: str, enabled: bool) -> None:
        self.total = total
        self.label = label
        self.enabled = enabled and total > 0
        self.start = time.perf_counter()
        self.failed = 0
        self.bar: Any = None
        if self.enabled and sys.stderr.isatty():
            from tqdm import tqdm

            self.bar = tqdm(total=total, desc=label, unit="item", file=sys.stderr, leave=False)

    def update(self, done: int, failed: int) -> None:
        self.failed += failed
        if self.bar is not None:
            self.bar.update(done)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()
        if self.enabled:
            seconds = time.perf_counter() - self.start
            rate = self.total / seconds if seconds > 0 else float("inf")
            print(
                f"{self.label}: {self.total} items, {self.failed} failed, "
                f"{seconds:.1f} s ({rate:.1f} items/s)",
                file=sys.stderr,
            )


def map_items(
    function: Callable[[Item], Result],
    items: Sequence[Item],
    *,
    jobs: int | None = None,
    executor: Executor | None = None,
    chunk_size: int | None = None,
    stage: str = "",
    name_of: Callable[[Item], str] = str,
    progress: bool | str = False,
    worth_s: float | None = None,
    units_of: Callable[[Item], int] | None = None,
    failures_in: Callable[[Result], int] | None = None,
    settled_failures: int = 0,
) -> MapOutcome[Result]:
    """Apply ``function`` to every item, in parallel, recording failures instead of stopping.

    With workers to start, the first one or two items run in this process and are timed (per
    unit, ``units_of``); the others run here too when they would take less than ``worth_s``,
    else on the workers (see the module docstring).

    Parameters
    ----------
    function
        Called as ``function(item)``. With a process pool or a remote executor it and the items
        must be picklable (a module-level function, plain data or paths: records are read on the
        worker from their path).
    items
        The work.
    jobs
        Worker processes when no ``executor`` is given (default: the CPUs available; 1 runs in
        this process).
    executor
        Any ``concurrent.futures.Executor`` (a Dask client's ``get_executor()``, a
        :class:`WorkerPool`); used as given and not shut down.
    chunk_size
        Items per task (default :func:`default_chunk_size`).
    stage
        The stage name written in each failure.
    name_of
        Names an item in its failure (default ``str``).
    progress
        False: silent. True or a label: a bar with count, rate and ETA on stderr when it is a
        terminal, and one summary line at the end either way.
    worth_s
        Least work [s] worth starting the workers for (default :data:`POOL_WORTH_S`; none for an
        executor whose workers run); 0 hands every item to them, with no probe.
    units_of, failures_in
        What the progress counts when an item holds several (a group of a stage's items): the
        units in an item (default 1), and the failed units inside a successful result (default
        none); a failed item counts all its units as failed.
    settled_failures
        Items the caller settled as failures before the map (files left out as copies of
        another): the progress line counts them among its items and its failed, so that it
        counts what the caller's failure table holds.

    Returns
    -------
    MapOutcome
        ``results`` (input order, successes only), ``failures``, ``indices``, ``seconds``;
        unpacks as ``results, failures``.

    Raises
    ------
    InputError
        ``jobs`` or ``chunk_size`` below 1.
    """
    start = time.perf_counter()
    collected = sorted(
        iter_items(
            function,
            items,
            jobs=jobs,
            executor=executor,
            chunk_size=chunk_size,
            stage=stage,
            name_of=name_of,
            progress=progress,
            worth_s=worth_s,
            units_of=units_of,
            failures_in=failures_in,
            settled_failures=settled_failures,
        ),
        key=lambda entry: entry[0],
    )
    results = [value for _, ok, value in collected if ok]
    indices = [index for index, ok, _ in collected if ok]
    failures = [value for _, ok, value in collected if not ok]
    return MapOutcome(results, failures, indices, time.perf_counter() - start)


def iter_items(
    function: Callable[[Item], Result],
    items: Sequence[Item],
    *,
    jobs: int | None = None,
    executor: Executor | None = None,
    chunk_size: int | None = None,
    stage: str = "",
    name_of: Callable[[Item], str] = str,
    progress: bool | str = False,
    worth_s: float | None = None,
    units_of: Callable[[Item], int] | None = None,
    failures_in: Callable[[Result], int] | None = None,
    settled_failures: int = 0,
) -> Iterator[tuple[int, bool, Any]]:
    """:func:`map_items` as its items finish: ``(index, True, result)`` or ``(index, False,
    Failure)`` in the order they complete, not the input order.

    For a caller that keeps what finished as it goes (a run stores a segment every
    ``batch_items`` items) while the workers carry on with the rest: every chunk is handed to
    the executor at once, so no worker waits for the slowest chunk of a batch or for this
    process to store it. The same parameters, probe and rules as :func:`map_items`; closing the
    iterator early cancels the chunks not started.
    """
    workers = default_jobs() if jobs is None else jobs
    if workers < 1:
        raise InputError(f"jobs = {jobs}, expected ≥ 1")
    if chunk_size is not None and chunk_size < 1:
        raise InputError(f"chunk_size = {chunk_size}, expected ≥ 1")
    indexed = list(enumerate(items))
    label = progress if isinstance(progress, str) else (stage or "items")
    units = [1 if units_of is None else units_of(item) for item in items]
    bar = _Progress(sum(units) + settled_failures, label, bool(progress))
    bar.update(settled_failures, settled_failures)

    def counted(part: list[tuple[int, bool, Any]]) -> list[tuple[int, bool, Any]]:
        failed = 0
        for index, ok, value in part:
            if not ok:
                failed += units[index]
            elif failures_in is not None:
                failed += failures_in(value)
        bar.update(sum(units[index] for index, _, _ in part), failed)
        return part

    try:
        rest = indexed
        parallel = (executor is not None or workers > 1) and len(indexed) > 1
        threshold_s = _worth_s(executor) if worth_s is None else worth_s
        if parallel and threshold_s > 0:
            # The probe: items here, timed per unit; the rest go to workers only if that pays.
            # The first item also pays this process's first calls (imports, compiled kernels
            # loaded), which workers forked after it inherit: when even that estimate says the
            # workers pay, a second item, on the warm process, decides.
            for _ in range(PROBE_ITEMS):
                probe_start = time.perf_counter()
                yield from counted(_run_chunk(function, rest[:1], stage, name_of))
                per_unit_s = (time.perf_counter() - probe_start) / max(1, units[rest[0][0]])
                rest = rest[1:]
                parallel = per_unit_s * sum(units[index] for index, _ in rest) >= threshold_s
                if not parallel or len(rest) <= 1:
                    break
        size = chunk_size or default_chunk_size(len(rest), workers)
        chunks = [rest[i : i + size] for i in range(0, len(rest), size)]
        if not parallel or (executor is None and len(chunks) <= 1):
            for chunk in chunks:
                yield from counted(_run_chunk(function, chunk, stage, name_of))
        elif executor is not None:
            for part in _completed(executor, function, chunks, stage, name_of):
                yield from counted(part)
        else:
            with WorkerPool(min(workers, len(chunks))) as pool:
                for part in _completed(pool, function, chunks, stage, name_of):
                    yield from counted(part)
    finally:
        bar.close()


def _call(call: Callable[[], Result]) -> Result:
    return call()


def call_each(
    calls: Sequence[Callable[[], Result]],
    *,
    jobs: int | None = 1,
    executor: Executor | None = None,
    stage: str = "",
) -> list[Result]:
    """The result of each zero-argument call, in order: the independent parts of one whole-set
    step (a report's figures, a confirmation's bootstrap intervals) spread over the workers as
    one :func:`map_items` batch, so they follow its rules (kept in this process when too small
    to pay; on a run's started workers, none in this process).

    Parameters
    ----------
    calls
        Picklable zero-argument callables (``functools.partial`` of module-level functions, or
        instances of module-level classes) for a process pool or a remote executor.
    jobs, executor
        As :func:`map_items` (default: this process).
    stage
        Named in the error of a call that raised.

    Returns
    -------
    list
        ``calls[k]()`` for each k.

    Raises
    ------
    InputError
        A call raised an :class:`InputError` (its message), as it would have in this process;
        the step fails as a whole.
    RuntimeError
        A call raised anything else (its type and message).
    """
    outcome = map_items(
        _call, calls, jobs=jobs, executor=executor, chunk_size=1, stage=stage, name_of=_call_name
    )
    if outcome.failures:
        first = outcome.failures[0]
        if first.error_type == "InputError":
            raise InputError(first.message)
        raise RuntimeError(f"{stage}: {first.error_type}: {first.message}")
    return outcome.results


def _call_name(call: Callable[[], Any]) -> str:
    return getattr(getattr(call, "func", call), "__name__", type(call).__name__)


def probe_items(executor: Executor | None, jobs: int | None) -> int:
    """How many leading items :func:`map_items` may run in this process as its probe with this
    ``executor`` and ``jobs`` (:data:`PROBE_ITEMS` while workers are yet to start, else 0): a
    caller that groups its work keeps them small, since the workers wait for them."""
    workers = default_jobs() if jobs is None else jobs
    if executor is None and workers <= 1:
        return 0
    return PROBE_ITEMS if _worth_s(executor) > 0 else 0


def _worth_s(executor: Executor | None) -> float:
    """Least work [s] worth handing to ``executor`` (None: a pool to start); 0 when its workers
    run."""
    if executor is None or not getattr(executor, "started", True):
        return POOL_WORTH_S
    return 0.0


def _completed(
    executor: Executor,
    function: Callable[[Any], Any],
    chunks: list[list[tuple[int, Any]]],
    stage: str,
    name_of: Callable[[Any], str],
) -> Iterator[list[tuple[int, bool, Any]]]:
    """Each chunk's outcomes as it completes; every chunk submitted at once (the executor
    queues them), the ones not started cancelled when the caller stops early or fails."""
    from concurrent.futures import as_completed

    futures: list[Future[list[tuple[int, bool, Any]]]] = [
        executor.submit(_run_chunk, function, chunk, stage, name_of) for chunk in chunks
    ]
    try:
        for future in as_completed(futures):
            yield future.result()
    finally:
        for future in futures:
            future.cancel()
