"""core.execution.map_items: input order, failures recorded, any executor, equal results."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import pytest

from stepframe.core.execution import map_items
from stepframe.errors import InputError


def square_or_fail(value: int) -> int:
    """Module level, so a process pool can pickle it."""
    if value % 5 == 3:
        raise ValueError(f"{value} is unlucky")
    return value * value


ITEMS = list(range(23))
EXPECTED = [v * v for v in ITEMS if v % 5 != 3]


def test_serial_order_failures_and_indices() -> None:
    outcome = map_items(square_or_fail, ITEMS, jobs=1, stage="square", name_of=lambda v: f"#{v}")
    results, failures = outcome
    assert results == EXPECTED
    assert outcome.indices == [v for v in ITEMS if v % 5 != 3]
    assert [(f.item, f.stage, f.error_type) for f in failures] == [
        (f"#{v}", "square", "ValueError") for v in (3, 8, 13, 18)
    ]
    assert failures[0].message == "3 is unlucky"
    assert outcome.seconds >= 0


@pytest.mark.parametrize("chunk_size", [1, 4, 64])
def test_a_thread_pool_and_a_process_pool_give_the_serial_result(chunk_size: int) -> None:
    serial = map_items(square_or_fail, ITEMS, jobs=1)
    with ThreadPoolExecutor(max_workers=3) as pool:
        threaded = map_items(
            square_or_fail, ITEMS, executor=pool, chunk_size=chunk_size, worth_s=0.0
        )
    processes = map_items(square_or_fail, ITEMS, jobs=2, chunk_size=chunk_size, worth_s=0.0)
    for other in (threaded, processes):
        assert other.results == serial.results
        assert other.indices == serial.indices
        assert other.failures == serial.failures


def test_an_empty_batch_and_bad_arguments() -> None:
    assert map_items(square_or_fail, [], jobs=2).results == []
    with pytest.raises(InputError, match="jobs = 0"):
        map_items(square_or_fail, ITEMS, jobs=0)
    with pytest.raises(InputError, match="chunk_size = 0"):
        map_items(square_or_fail, ITEMS, chunk_size=0)


def test_progress_prints_one_summary_line_when_stderr_is_not_a_terminal(
    capsys: pytest.CaptureFixture[str],
) -> None:
    map_items(square_or_fail, ITEMS, jobs=1, progress="squares")
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("squares: 23 items, 4 failed, ")


def compile_notice_setting(_: int) -> str:
    import os

    return os.environ.get("STEPFRAME_COMPILE_NOTICE", "unset")


@pytest.mark.parametrize(("parent", "workers"), [("1", "worker"), ("0", "0")])
def test_pool_workers_announce_only_once_for_the_pool(
    monkeypatch: pytest.MonkeyPatch, parent: str, workers: str
) -> None:
    """Workers compiling at once printed notices that interleaved on one line: in a pool they
    speak in one complete line for all (tests/core/test_jit.py), and are silent when the
    parent is."""
    monkeypatch.setenv("STEPFRAME_COMPILE_NOTICE", parent)
    results, failures = map_items(
        compile_notice_setting, range(8), jobs=2, chunk_size=1, worth_s=0.0
    )
    assert results == [workers] * 8 and failures == []
    assert compile_notice_setting(0) == parent  # the parent still announces as before


def process_id(seconds: float) -> int:
    """Sleep ``seconds``, then say which process ran the item."""
    import os
    import time

    time.sleep(seconds)
    return os.getpid()


def test_a_small_batch_stays_in_this_process_and_a_large_one_goes_to_the_workers() -> None:
    """The first items are run here and timed: 40 items of nothing stay here (starting workers
    would cost more); 40 items of 50 ms each (about 2 s, over POOL_WORTH_S = 1 s) go to the
    workers after the two probe items."""
    import os

    small = map_items(process_id, [0.0] * 40, jobs=2)
    assert set(small.results) == {os.getpid()}
    large = map_items(process_id, [0.05] * 40, jobs=2)
    assert large.results[:2] == [os.getpid()] * 2
    assert os.getpid() not in large.results[2:]


def test_a_slow_first_item_does_not_start_the_workers_for_quick_ones() -> None:
    """The first item pays a process's first calls (imports, kernels loaded): 1.2 s, then ten
    items of nothing. Timed alone it would have sent the ten to workers (10 × 1.2 s); the second
    item, timed warm, keeps them here. With one item left after the first, nothing is started."""
    import os

    warm_up = map_items(process_id, [1.2] + [0.0] * 10, jobs=2)
    assert set(warm_up.results) == {os.getpid()}
    two = map_items(process_id, [1.2, 0.0], jobs=2)
    assert two.results == [os.getpid()] * 2


def sleep_group(group: list[float]) -> int:
    """Sleep each of the group's seconds; the process that ran it."""
    import os
    import time

    time.sleep(sum(group))
    return os.getpid()


def test_the_probe_is_timed_per_unit_of_grouped_items() -> None:
    """Groups carrying several items (a run's groups of tasks): a one-item probe group of 20 ms
    is set against the units still to come, not the groups. Two more groups of 30 items of
    20 ms (1.2 s, over POOL_WORTH_S) go to the workers; timed per group (2 × 20 ms) they would
    have stayed here."""
    import os

    work = [[0.02], [0.02], [0.02] * 30, [0.02] * 30]
    outcome = map_items(sleep_group, work, jobs=2, chunk_size=1, units_of=len)
    assert outcome.results[:2] == [os.getpid()] * 2
    assert os.getpid() not in outcome.results[2:]


def test_probe_items_only_while_workers_are_to_start() -> None:
    """What a caller that groups its work keeps small: the probe's items, none in this process's
    own run (jobs 1) or with workers already running."""
    from concurrent.futures import ThreadPoolExecutor

    from stepframe.core.execution import PROBE_ITEMS, WorkerPool, probe_items

    assert PROBE_ITEMS == 2
    assert probe_items(None, 1) == 0
    assert probe_items(None, 2) == 2
    with WorkerPool(2) as pool:
        assert probe_items(pool, 2) == 2
        pool.submit(int).result()
        assert probe_items(pool, 2) == 0
    with ThreadPoolExecutor(2) as threads:  # an executor whose workers run
        assert probe_items(threads, 2) == 0


def test_a_shared_worker_pool_starts_on_first_use_and_serves_many_batches() -> None:
    import os

    from stepframe.core.execution import WorkerPool

    with WorkerPool(2) as pool:
        assert not pool.started
        map_items(square_or_fail, ITEMS, executor=pool)  # small: kept in this process
        assert not pool.started
        first = map_items(process_id, [0.0] * 6, executor=pool, worth_s=0.0)
        assert pool.started
        second = map_items(process_id, [0.0] * 6, executor=pool, worth_s=0.0)
    assert not pool.started
    workers = set(first.results) | set(second.results)
    assert os.getpid() not in workers
    assert len(workers) <= 2  # both batches ran on the same two processes


def sum_group_or_fail(group: list[int]) -> list[int]:
    """A group's items squared, -1 for a negative item; a group holding 13 fails whole."""
    if 13 in group:
        raise ValueError("thirteen")
    return [-1 if item < 0 else item * item for item in group]


def test_progress_counts_the_units_of_grouped_items(capsys: pytest.CaptureFixture[str]) -> None:
    groups = [[1, 2, 3], [4, -5], [13, 6, 7, 8], [9]]
    map_items(
        sum_group_or_fail, groups, jobs=1, progress="groups",
        units_of=len, failures_in=lambda squares: squares.count(-1),
    )  # fmt: skip
    err = capsys.readouterr().err.strip().splitlines()
    # 10 items; failed: the -5 inside a group, and the four of the group that raised
    assert len(err) == 1 and err[0].startswith("groups: 10 items, 5 failed, "), err


def input_error(value: int) -> int:
    raise InputError(f"value {value}, expected another", "records/a.AT2", 3)


def test_call_each_results_in_order_on_the_workers_and_a_failure_raised() -> None:
    """call_each: independent calls of one step, their results in order; on a started pool (no
    probe) none in this process; a call that raised fails the step with its message, an
    InputError as an InputError."""
    import functools
    import os

    from stepframe.core.execution import WorkerPool, call_each

    calls = [functools.partial(square_or_fail, v) for v in (2, 4, 7)]
    assert call_each(calls) == [4, 16, 49]
    with WorkerPool(2) as pool:
        pool.submit(int).result()  # started, as by a run's first batch
        pids = call_each([functools.partial(process_id, 0.0)] * 4, jobs=2, executor=pool)
        assert os.getpid() not in pids
        assert call_each(calls, jobs=2, executor=pool) == [4, 16, 49]
        with pytest.raises(InputError, match=r"^records/a\.AT2:3: value 1, expected another$"):
            call_each([functools.partial(input_error, 1)], jobs=2, executor=pool)
        unlucky = [functools.partial(square_or_fail, v) for v in (1, 3, 8)]
        with pytest.raises(RuntimeError, match=r"^square: ValueError: 3 is unlucky$"):
            call_each(unlucky, jobs=2, executor=pool, stage="square")
