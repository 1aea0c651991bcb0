"""The probe of a run's item stage: while the workers are to be started, the first two tasks run
alone in this process (the first pays its imports and compiled kernels, the second is timed on
the warm process: stepframe.core.execution.PROBE_ITEMS), so the workers do not wait for a whole
group of them; with workers running, there is no probe and no group is cut smaller."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pytest

from stepframe.pipeline.catalogue.example_files import write_example_files
from stepframe.pipeline.engine import runner
from stepframe.pipeline.engine.chain import Work, groups
from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.stages import shipped_stages

from .conftest import FEATURES_WORKFLOW, write_workflow


def _group_sizes(
    monkeypatch: pytest.MonkeyPatch, scene: Path, name: str, **options: Any
) -> tuple[list[int], bytes]:
    """Items per group handed to the executor by the first item stage, and the features table."""
    seen: list[list[int]] = []
    original = runner.iter_items

    def recording(function: Any, items: Any, **kwargs: Any) -> Any:
        seen.append([len(group[1]) for group in items])
        return original(function, items, **kwargs)

    monkeypatch.setattr(runner, "iter_items", recording)
    workflow = write_workflow(scene, f'workspace = "{name}"\n' + FEATURES_WORKFLOW, f"{name}.toml")
    report = run_workflow(workflow, shipped_stages(), **options)
    assert report.exit_code == 0 and report.failures == []
    return seen[0], (scene / name / "outputs" / "features.parquet").read_bytes()


def test_the_first_two_tasks_run_alone_only_while_workers_are_to_start(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    write_example_files(tmp_path / "records", count=10)
    serial, expected = _group_sizes(monkeypatch, tmp_path, "serial", jobs=1)
    assert serial == [3, 3, 3, 1]  # a quarter of the 10 tasks a group, no probe
    pooled, table = _group_sizes(monkeypatch, tmp_path, "pool", jobs=2)
    assert pooled == [1, 1, 2, 2, 2, 2]  # an eighth (two workers), after the two alone
    assert table == expected
    with ThreadPoolExecutor(2) as running:
        given, table = _group_sizes(monkeypatch, tmp_path, "threads", executor=running, jobs=2)
    assert given == [2, 2, 2, 2, 2] and table == expected


def test_groups_cut_the_probe_tasks_off_and_keep_the_order() -> None:
    table = shipped_stages()
    stage = next(table[name] for name in table.names if table[name].kind == "item")
    tasks = [f"task{k}" for k in range(20)]
    cut = groups(stage, tasks, (), workers=2, most=1000, single=2)  # type: ignore[arg-type]
    assert [len(g[1]) for g in cut] == [1, 1, 3, 3, 3, 3, 3, 3]
    assert [t for g in cut for t in g[1]] == tasks
    whole = groups(stage, tasks, (), workers=2, most=1000)  # type: ignore[arg-type]
    assert [len(g[1]) for g in whole] == [3] * 6 + [2]
    assert all(g[0] == Work.of(stage) for g in cut)
