"""Workers that imported nothing beforehand run a workflow's items: each task carries its stage's
compute function, so a spawn-started process pool and a Dask cluster's workers need no stage
table, and give the serial run's bytes."""

from __future__ import annotations

import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pytest

from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.stages import shipped_stages

from .conftest import FEATURES_WORKFLOW, write_workflow

OUTPUTS = ("features.parquet", "features.csv", "features.failures.csv")


def _serial(scene: Path) -> Path:
    serial = write_workflow(scene, 'workspace = "serial"\n' + FEATURES_WORKFLOW, "serial.toml")
    report = run_workflow(serial, shipped_stages(), jobs=1)
    assert report.exit_code == 0
    return scene / "serial" / "outputs"


@pytest.mark.slow
def test_a_spawn_started_pool_gives_the_serial_tables(scene: Path) -> None:
    expected = _serial(scene)
    spawned = write_workflow(scene, 'workspace = "spawn"\n' + FEATURES_WORKFLOW, "spawn.toml")
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=2, mp_context=context) as pool:
        report = run_workflow(spawned, shipped_stages(), executor=pool, jobs=2)
    assert report.execution == "ProcessPoolExecutor, 2 worker(s)"
    assert [s.computed for s in report.stages] == [4, 4]
    assert report.failures == []
    for name in OUTPUTS:
        assert (scene / "spawn" / "outputs" / name).read_bytes() == (expected / name).read_bytes()


@pytest.mark.slow
def test_dask_workers_started_empty_give_the_serial_tables(scene: Path) -> None:
    distributed = pytest.importorskip("dask.distributed")
    expected = _serial(scene)
    remote = write_workflow(scene, 'workspace = "dask"\n' + FEATURES_WORKFLOW, "dask.toml")
    with (
        distributed.LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
        ) as cluster,
        distributed.Client(cluster) as client,
    ):
        # the workers are new processes with nothing of stepframe imported before the run
        before = client.run(
            lambda: sorted(m for m in __import__("sys").modules if "stepframe" in m)
        )
        assert all(modules == [] for modules in before.values())
        report = run_workflow(remote, shipped_stages(), executor=client.get_executor(), jobs=2)
        after = client.run(lambda: "stepframe.pipeline.stages" in __import__("sys").modules)
    assert report.failures == []
    assert [s.computed for s in report.stages] == [4, 4]
    # no worker needed the composition root: the compute functions came with the tasks
    assert not any(after.values())
    for name in OUTPUTS:
        assert (scene / "dask" / "outputs" / name).read_bytes() == (expected / name).read_bytes()
