"""The engine at catalogue scale: the same outputs whatever runs the items (this process, a worker
pool, a Dask cluster), each record file read once by the catalogue stages, record hashes
remembered while a file is unchanged."""

from __future__ import annotations

import json
import os
import re
import shutil
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path
from typing import Any

import pandas as pd
import pytest

from stepframe.core import execution
from stepframe.pipeline.catalogue import file_hashes
from stepframe.pipeline.catalogue.example_files import write_example_files
from stepframe.pipeline.engine.runner import run_workflow
from stepframe.pipeline.stages import shipped_stages

from .conftest import write_workflow

SHIPPED = Path(__file__).parents[2] / "src" / "stepframe" / "workflows"

#: The selection workflow as shipped, on a folder, choosing 3 (12 components: 6 plausible).
SELECTION = """\
workspace = "{workspace}"

[records]
folder = "records"

[frame]
file = "frames/example-4.toml"

[selection]
n = 3
confirm = true

[outputs]
features = true
selection = true
"""
#: The same with the report, whose figures and simulations run on the workers too.
SELECTION_AND_REPORT = SELECTION + "selection_report = true\n"
#: The outputs compared byte for byte: the selection's tables and summary, and the report's
#: numbers and tables (its page names the workflow file, which differs between the runs: its
#: figures are compared instead).
COMPARED = (
    "features.parquet",
    "features.csv",
    "features.failures.csv",
    "selection/selection.csv",
    "selection/candidates.csv",
    "selection/confirmation.csv",
    "selection/failures.csv",
    "selection/selection.json",
    "selection/spectra.csv",
    "selection_report_files/numbers.json",
    "selection_report_files/correlations.csv",
    "selection_report_files/tiers.csv",
    "selection_report_files/moving_resonance.csv",
)


@pytest.fixture
def selection_scene(tmp_path: Path) -> Path:
    """Twelve example components as AT2 files, the Example 4 frame."""
    write_example_files(tmp_path / "records", count=12)
    shutil.copytree(SHIPPED / "frames", tmp_path / "frames")
    return tmp_path


def _outputs(folder: Path) -> dict[str, Any]:
    """The compared outputs' bytes, and the report's figures (PNG bytes, in page order)."""
    page = (folder / "outputs" / "selection_report.html").read_text(encoding="utf-8")
    figures = re.findall(r"data:image/png;base64,([A-Za-z0-9+/=]+)", page)
    return {name: (folder / "outputs" / name).read_bytes() for name in COMPARED} | {
        "figures": figures
    }


@pytest.mark.slow
def test_outputs_are_identical_in_this_process_on_a_pool_and_on_dask(
    selection_scene: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """--jobs 1, --jobs 2 and a Dask cluster give the same bytes, the selection's whole-set
    parts made on the workers too (the bootstrap intervals of the tiers and the confirmation,
    the report's figures and moving-resonance runs). Without this monkeypatch the batches of
    this small catalogue would all stay in this process (POOL_WORTH_S): 0 sends every batch to
    the workers."""
    pytest.importorskip("dask.distributed")
    monkeypatch.setattr(execution, "POOL_WORTH_S", 0.0)
    monkeypatch.chdir(selection_scene)
    runs = {}
    for name, kwargs in (
        ("serial", {"jobs": 1}),
        ("pool", {"jobs": 2}),
        ("dask", {"scheduler": "dask-local", "jobs": 2}),
    ):
        text = SELECTION_AND_REPORT.format(workspace=name)
        workflow = write_workflow(selection_scene, text, f"{name}.toml")
        report = run_workflow(workflow, shipped_stages(), **kwargs)
        assert report.exit_code == 0, report.describe()
        runs[name] = report
    assert runs["pool"].execution == "process pool, 2 worker(s)"
    assert runs["dask"].execution == "dask-local, 2 worker(s)"
    serial = _outputs(selection_scene / "serial")
    assert _outputs(selection_scene / "pool") == serial
    assert _outputs(selection_scene / "dask") == serial
    # what the workers made is there: 8 figures (3 of moving resonance), the intervals
    assert len(serial["figures"]) == 8
    numbers = json.loads(serial["selection_report_files/numbers.json"])
    assert len(numbers["moving_resonance"]) == 3
    assert json.loads(serial["selection/selection.json"])["correlations"]
    selection = pd.read_csv(selection_scene / "serial" / "outputs" / "selection" / "selection.csv")
    assert len(selection) == 3
    confirmation = pd.read_csv(
        selection_scene / "serial" / "outputs" / "selection" / "confirmation.csv"
    )
    assert (confirmation["case"] == "equal-psa-t1").sum() >= 3  # every candidate simulated


def test_each_record_file_is_read_once_per_run(
    selection_scene: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The inventory reads a file; the features of its components follow in the same call, and
    the selection's responses at the end of the call's group, from the records it read; the
    selection itself reads only the chosen records and their controls again, for the
    confirmation at their scale. A run with nothing new reads nothing, and one new file is
    read once."""
    import stepframe.records
    import stepframe.records.io

    reads: Counter[str] = Counter()
    read = stepframe.records.read

    def counting(path: Any, **options: Any) -> Any:
        reads[Path(path).name] += 1
        return read(path, **options)

    monkeypatch.setattr(stepframe.records, "read", counting)
    # the stages read through records.io.read_measured, which calls its module's read
    monkeypatch.setattr(stepframe.records.io, "read", counting)
    workflow = write_workflow(selection_scene, SELECTION.format(workspace="work"))
    report = run_workflow(workflow, shipped_stages(), jobs=1)
    assert report.exit_code == 0
    outputs = selection_scene / "work" / "outputs" / "selection"
    confirmation = pd.read_csv(outputs / "confirmation.csv")
    chosen_scale = confirmation.loc[confirmation["case"] == "chosen-scale", "file"]
    at_scale = Counter(Path(f).name for f in chosen_scale)
    files = sorted(p.name for p in (selection_scene / "records").iterdir())
    assert len(files) == 12 and len(at_scale) == 6  # 3 chosen and 3 controls
    assert dict(reads) == {f: 1 + at_scale[f] for f in files}
    counts = {s.name: (s.computed, s.cached) for s in report.stages}
    # the features and responses were computed with the inventory, in the same calls
    assert counts == {
        "inventory": (12, 0),
        "features": (12, 0),
        "responses": (12, 0),
        "selection": (1, 0),
    }
    reads.clear()
    again = run_workflow(workflow, shipped_stages(), jobs=1)
    assert [s.computed for s in again.stages] == [0, 0, 0, 0] and not reads
    # One new file: its own pass, and the selection again (its chosen records read again).
    write_example_files(selection_scene / "new", count=13)
    new = sorted({p.name for p in (selection_scene / "new").iterdir()} - set(files))[0]
    shutil.move(selection_scene / "new" / new, selection_scene / "records" / new)
    reads.clear()
    added = run_workflow(workflow, shipped_stages(), jobs=1)
    assert [s.computed for s in added.stages] == [1, 1, 1, 1]
    confirmation = pd.read_csv(outputs / "confirmation.csv")
    chosen_scale = confirmation.loc[confirmation["case"] == "chosen-scale", "file"]
    at_scale = Counter(Path(f).name for f in chosen_scale)
    assert dict(reads) == {f: (f == new) + at_scale[f] for f in {new, *at_scale}}


def test_record_hashes_are_remembered_while_a_file_is_unchanged(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    files = write_example_files(tmp_path / "records", count=3)
    cache = tmp_path / "hashes.parquet"
    hashed: list[str] = []
    sha = file_hashes.file_sha256

    def counting(path: Any) -> str:
        hashed.append(Path(path).name)
        return sha(path)

    monkeypatch.setattr(file_hashes, "file_sha256", counting)
    # Files just written are "racy" (changed less than RACY_S ago): hashed, never remembered.
    monkeypatch.setattr(file_hashes, "RACY_S", 3600.0)
    file_hashes.file_hashes(files, cache, update=True)
    file_hashes.file_hashes(files, cache, update=True)
    assert sorted(hashed) == sorted(2 * [p.name for p in files])
    # Older than RACY_S: remembered.
    monkeypatch.setattr(file_hashes, "RACY_S", 0.0)
    hashed.clear()
    first = file_hashes.file_hashes(files, cache, update=True)
    assert first == [sha(p) for p in files] and len(hashed) == 3
    hashed.clear()
    assert file_hashes.file_hashes(files, cache, update=True) == first
    assert hashed == []  # all three from the cache
    # The same size, the modification time set back: the status-change time still tells.
    stat = files[1].stat()
    data = bytearray(files[1].read_bytes())
    data[-2] = ord("7") if data[-2] != ord("7") else ord("8")
    files[1].write_bytes(bytes(data))
    os.utime(files[1], ns=(stat.st_atime_ns, stat.st_mtime_ns))
    assert files[1].stat().st_size == stat.st_size
    changed = file_hashes.file_hashes(files, cache, update=True)
    assert hashed == [files[1].name]
    assert changed[1] == sha(files[1]) != first[1] and changed[0] == first[0]
    # A damaged cache costs a re-hash, never a wrong hash.
    cache.write_bytes(b"not parquet")
    hashed.clear()
    assert file_hashes.file_hashes(files, cache) == [sha(p) for p in files]
    assert len(hashed) == 3


def test_record_hashes_computed_on_the_workers_are_the_files_sha256(tmp_path: Path) -> None:
    # A first run hashes the files on the run's workers (pool or cluster), not in its own
    # process; the hashes are hashlib's, in the files' order, and a file that cannot be read
    # fails as it does in this process: the same OSError, naming the file.
    import hashlib

    files = write_example_files(tmp_path / "records", count=7)
    expected = [hashlib.sha256(p.read_bytes()).hexdigest() for p in files]
    folder = tmp_path / "records"
    with execution.WorkerPool(2) as pool:
        assert pool.submit(os.getpid).result() != os.getpid()  # started: every file goes there
        assert file_hashes.file_hashes(files, executor=pool) == expected
        with pytest.raises(IsADirectoryError) as on_workers:
            file_hashes.file_hashes([*files, folder], executor=pool)
    with pytest.raises(IsADirectoryError) as here:
        file_hashes.file_hashes([*files, folder], threads=2)
    assert on_workers.value.filename == here.value.filename == str(folder)
    assert on_workers.value.errno == here.value.errno

    class Counting(ThreadPoolExecutor):  # an executor whose workers run: no probe here
        submitted = 0

        def submit(self, *args: Any, **kwargs: Any) -> Any:
            Counting.submitted += 1
            return super().submit(*args, **kwargs)

    with Counting(2) as counting:
        assert file_hashes.file_hashes(files, executor=counting) == expected
    assert Counting.submitted >= 2  # in chunks, on its workers
