"""Dask: a LocalCluster on loopback (2 workers) gives the same tables as the serial run."""

from __future__ import annotations

import sys
from pathlib import Path

import pandas as pd
import pytest

from stepframe.cli import main
from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.stages import shipped_stages

from .conftest import FEATURES_WORKFLOW, write_workflow


@pytest.mark.slow
def test_local_cluster_tables_equal_the_serial_run(
    scene: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    distributed = pytest.importorskip("dask.distributed")
    serial = write_workflow(scene, 'workspace = "serial"\n' + FEATURES_WORKFLOW, "serial.toml")
    remote = write_workflow(scene, 'workspace = "dask"\n' + FEATURES_WORKFLOW, "dask.toml")
    serial_report = run_workflow(serial, shipped_stages(), jobs=1)
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1", dashboard_address=None
    ) as cluster:
        assert cluster.scheduler_address.startswith("tcp://127.0.0.1:")
        # the workflow named relative to a folder the workers are not in: they get absolute paths
        monkeypatch.chdir(scene)
        dask_report = run_workflow(
            remote.name, shipped_stages(), scheduler=cluster.scheduler_address
        )
    assert dask_report.execution.startswith(cluster.scheduler_address)
    assert [s.computed for s in dask_report.stages] == [s.computed for s in serial_report.stages]
    for name in ("features.parquet", "features.csv", "features.failures.csv"):
        assert (scene / "dask" / "outputs" / name).read_bytes() == (
            scene / "serial" / "outputs" / name
        ).read_bytes()
    table = pd.read_parquet(scene / "dask" / "outputs" / "features.parquet")
    assert len(table) == 4


@pytest.mark.slow
def test_dask_local_scheduler(scene: Path) -> None:
    pytest.importorskip("dask.distributed")
    report = run_workflow(scene / "wf.toml", shipped_stages(), scheduler="dask-local", jobs=2)
    assert report.exit_code == 0
    assert report.execution == "dask-local, 2 worker(s)"
    assert [s.computed for s in report.stages] == [4, 4]


def test_missing_dask_extra_is_one_line_naming_the_install(
    scene: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setitem(sys.modules, "dask.distributed", None)  # import fails as if absent
    assert main(["run", str(scene / "wf.toml"), "--scheduler", "dask-local"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        "stepframe: error: Dask is not installed, expected the dask extra: "
        "pip install 'stepframe[dask]'"
    ]
    assert not (scene / "stepframe-work").exists()


def test_unknown_scheduler(scene: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["run", str(scene / "wf.toml"), "--scheduler", "slurm"]) == 2
    assert "expected dask-local or tcp://HOST:PORT" in capsys.readouterr().err
