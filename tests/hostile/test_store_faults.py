"""A store that cannot lie (issue 27): faults injected at every read and write path of the store.

Reads: every object of a workspace (result and failure segments of ``inventory`` and
``features``, their index files, each whole-set result's files: the site model, the
amplification curve, ``selection.csv``, ``selection.json``, the stored report) is truncated,
emptied, flipped, deleted or replaced by a folder. The next run names each damaged object in its
summary, moves it to ``store/quarantine/``, recomputes it and publishes outputs byte-identical to
an undamaged run's: exit 0, no traceback. Writes: disk full (``ENOSPC``) and a read-only file
system (``EROFS``) are injected at each kind of write (a segment, an index, a whole-set result's
file, an output, the run log; ``ENOSPC`` at the quarantine itself): one line, exit 1, the store
consistent (``store verify`` finds nothing), and the next run finishes with the same outputs.
"""

from __future__ import annotations

import errno
import os
import shutil
import subprocess
import sys
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest

from stepframe.cli import main
from stepframe.pipeline.catalogue.example_files import write_example_files
from stepframe.pipeline.engine.integrity import QUARANTINE
from stepframe.pipeline.engine.store import Store
from stepframe.pipeline.engine.upkeep import upkeep
from stepframe.pipeline.stages import shipped_stages

FRAMES = Path(__file__).resolve().parents[2] / "src" / "stepframe" / "workflows" / "frames"

WORKFLOW = """\
[records]
folder = "records"

[frame]
file = "frames/example-4.toml"

[selection]
n = 2
confirm = true

[site]
from = "parameters"
fp_hz = 7.43
fs_hz = 3.12
fr_hz = 1.11
xi_p = 0.096
xi_r = 0.655
t_max_s = 5.0
t_dur_s = 20.0

[amplification]
n_frequencies = 5
n_steps = 400

[outputs]
inventory = true
features = true
site = true
amplification = true
selection = true
selection_report = true
"""


def _tree(folder: Path) -> dict[str, bytes]:
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def _run(scene: Path, capsys: pytest.CaptureFixture[str], *extra: str) -> tuple[int, str, str]:
    capsys.readouterr()
    status = main(["run", str(scene / "wf.toml"), "--jobs", "1", *extra])
    out, err = capsys.readouterr()
    assert "Traceback" not in out + err
    return status, out, err


@pytest.fixture(scope="module")
def pristine(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A scene run once: records (6 example components and an unreadable file), the frame, the
    workflow and its workspace."""
    scene = tmp_path_factory.mktemp("pristine")
    write_example_files(scene / "records", count=6)
    (scene / "records" / "garbage.txt").write_text("not a record\n")
    shutil.copytree(FRAMES, scene / "frames")
    (scene / "wf.toml").write_text(WORKFLOW)
    assert main(["run", str(scene / "wf.toml"), "--jobs", "1"]) == 0
    return scene


@pytest.fixture
def scene(pristine: Path, tmp_path: Path) -> Iterator[Path]:
    """A copy of the pristine scene (its store holds every result) and its outputs."""
    copy = tmp_path / "scene"
    shutil.copytree(pristine, copy)
    yield copy


def _objects(work: Path) -> list[Path]:
    """Every stored object a fault is injected into: segments, index files, result files."""
    store = work / "store"
    found = sorted(store.glob("inventory/*-*.parquet")) + sorted(store.glob("features/*.parquet"))
    found += [store / stage / "index.json" for stage in ("inventory", "features")]
    for stage, name in (
        ("site", "site_model.json"),
        ("amplification", "amplification.nc"),
        ("selection", "selection.csv"),
        ("selection", "selection.json"),
        ("selection_report", "selection_report.html"),
    ):
        found += sorted(store.glob(f"{stage}/sets/*/{name}"))
    return found


def _truncate(path: Path) -> None:
    path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])


def _empty(path: Path) -> None:
    path.write_bytes(b"")


def _flip(path: Path) -> None:
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0x01
    path.write_bytes(bytes(data))


def _folder(path: Path) -> None:
    path.unlink()
    path.mkdir()


FAULTS: dict[str, Callable[[Path], None]] = {
    "truncate": _truncate,
    "empty": _empty,
    "flip": _flip,
    "delete": Path.unlink,
    "folder": _folder,
}


@pytest.mark.parametrize("fault", list(FAULTS))
def test_every_damaged_object_is_quarantined_named_and_recomputed(
    scene: Path, fault: str, capsys: pytest.CaptureFixture[str]
) -> None:
    work = scene / "stepframe-work"
    expected = _tree(work / "outputs")
    objects = _objects(work)
    assert len(objects) == 10  # 3 segments (one of failures), 2 indexes, 5 result files
    if fault == "delete":  # a deleted index cannot name deleted segments (its own test below)
        objects = [path for path in objects if path.name != "index.json"]
    for path in objects:
        FAULTS[fault](path)
    status, out, err = _run(scene, capsys)
    assert status == 0, err
    assert _tree(work / "outputs") == expected
    named = [line for line in out.splitlines() if line.startswith("store: ")]
    for path in objects:
        relative = path.relative_to(work / "store").as_posix()
        if path.parent.parent.name == "sets":  # a result's file: its folder is quarantined
            relative = path.parent.relative_to(work / "store").as_posix()
        assert any(line.startswith(f"store: {relative}: ") for line in named), relative
    moved = list((work / "store" / QUARANTINE).rglob("*")) if fault != "delete" else []
    if fault != "delete":
        assert moved
    # the store is sound again, and a second run computes nothing
    assert upkeep(work, shipped_stages(), "verify").events == []
    status, out, _ = _run(scene, capsys)
    assert status == 0 and "store: " not in out
    assert _tree(work / "outputs") == expected


def test_a_stage_folder_replaced_by_a_file(scene: Path, capsys: pytest.CaptureFixture[str]) -> None:
    work = scene / "stepframe-work"
    expected = _tree(work / "outputs")
    shutil.rmtree(work / "store" / "features")
    (work / "store" / "features").write_text("not a folder\n")
    status, out, _ = _run(scene, capsys)
    assert status == 0 and "store: features: not a folder: moved to quarantine/features/" in out
    assert _tree(work / "outputs") == expected


def test_a_dry_run_reports_damage_and_moves_nothing(
    scene: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    work = scene / "stepframe-work"
    segment = next((work / "store" / "features").glob("seg-*.parquet"))
    _flip(segment)
    before = segment.read_bytes()
    status, out, _ = _run(scene, capsys, "--dry-run")
    assert status == 0
    assert f"store: features/{segment.name}: checksum mismatch: would be quarantined" in out
    assert segment.read_bytes() == before and not (work / "store" / QUARANTINE).exists()


def test_a_segment_a_killed_run_did_not_index_is_adopted(
    scene: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """Killed between writing a segment and its index: the segment's name carries its checksum,
    so it is verified and kept (nothing recomputed); a damaged one is quarantined."""
    work = scene / "stepframe-work"
    index = work / "store" / "features" / "index.json"
    index.unlink()
    status, out, _ = _run(scene, capsys)
    assert status == 0
    assert "store: features/index.json: missing: rebuilt from the segments" in out
    assert "features                    6         0       6" in out
    index.unlink()
    _flip(next((work / "store" / "features").glob("seg-*.parquet")))
    status, out, _ = _run(scene, capsys)
    assert status == 0 and "checksum mismatch: moved to quarantine/features/" in out
    assert "features                    6         6       0" in out


def test_a_damaged_published_copy_is_not_an_output(
    scene: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """A copy that reaches the outputs short (a file system that lost a write) is caught by the
    store's checksums: the output is reported missing, exit 1."""
    import stepframe.core.io as core_io

    write = core_io.write_bytes

    def short(path: str | os.PathLike[str], data: bytes) -> Path:
        return write(path, data[:-10] if str(path).endswith("selection.json") else data)

    monkeypatch.setattr(core_io, "write_bytes", short)
    status, out, _ = _run(scene, capsys)
    assert status == 1
    assert "output selection NOT produced: " in out and "expected a copy of the stored" in out


# -- writes --------------------------------------------------------------------------------------

ERRORS = {errno.ENOSPC: "No space left on device", errno.EROFS: "Read-only file system"}


def _failing_fsync(monkeypatch: pytest.MonkeyPatch, target: str, code: int) -> list[str]:
    """Make the fsync of any temporary whose name contains ``target`` fail with ``code``: the
    write that atomic_write is finishing fails, as on a full disk. Returns the names hit."""
    real = os.fsync
    hit: list[str] = []

    def fsync(descriptor: int) -> None:
        name = os.readlink(f"/proc/self/fd/{descriptor}")
        if target in Path(name).name:
            hit.append(name)
            raise OSError(code, ERRORS[code], name)
        real(descriptor)

    monkeypatch.setattr(os, "fsync", fsync)
    return hit


#: (what, the temporary's name contains, the stage to force so that it is written again)
WRITES = [
    ("result segment", "seg-", "features"),
    ("failure segment", "fail-", "inventory"),
    ("index", "index.json", "features"),
    ("whole-set result file", "selection.csv", "selection"),
    ("output table", "features.parquet", "features"),
    ("output copy", "amplification.nc", "amplification"),
    ("run log", "runs.jsonl", "site"),
]


@pytest.mark.parametrize(("what", "target", "stage"), WRITES, ids=[w[0] for w in WRITES])
@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EROFS])
def test_a_failed_write_is_one_line_exit_1_and_the_next_run_resumes(
    scene: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
    what: str,
    target: str,
    stage: str,
    code: int,
) -> None:
    work = scene / "stepframe-work"
    expected = _tree(work / "outputs")
    shutil.rmtree(work / "outputs")
    with monkeypatch.context() as patch:
        hit = _failing_fsync(patch, target, code)
        status, out, err = _run(scene, capsys, "--force", stage, "--json")  # no progress lines
    assert hit, f"no {what} was written"
    assert status == 1 and out == ""
    [line] = err.strip().splitlines()
    assert line.startswith("stepframe: error: ") and line.endswith(
        f"cannot write ({ERRORS[code]}); the store is unchanged, the next run resumes"
    )
    assert not list(work.rglob("*.tmp"))
    assert upkeep(work, shipped_stages(), "verify").events == []
    status, _, err = _run(scene, capsys)
    assert status == 0, err
    assert _tree(work / "outputs") == expected


def test_quarantine_on_a_full_disk(
    scene: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Moving a damaged object aside fails too: one line, exit 1, and the next run does it."""
    work = scene / "stepframe-work"
    expected = _tree(work / "outputs")
    _flip(next((work / "store" / "features").glob("seg-*.parquet")))
    real = os.replace

    def replace(source: str | os.PathLike[str], target: str | os.PathLike[str]) -> None:
        # the folder, not the name: this test's own folder is named after the quarantine too
        if f"{os.sep}{QUARANTINE}{os.sep}" in str(target):
            raise OSError(errno.ENOSPC, ERRORS[errno.ENOSPC], str(target))
        real(source, target)

    with monkeypatch.context() as patch:
        patch.setattr(os, "replace", replace)
        status, _, err = _run(scene, capsys)
    assert status == 1 and "No space left on device" in err
    status, out, _ = _run(scene, capsys)
    assert status == 0 and "moved to quarantine/features/" in out
    assert _tree(work / "outputs") == expected


def test_a_read_only_store_is_refused_before_any_work(scene: Path, read_only_bind: None) -> None:
    """Root ignores permission bits: the store's stage folder is a read-only bind mount."""
    folder = scene / "stepframe-work" / "store" / "features"
    command = f"{sys.executable} -m stepframe.cli run {scene / 'wf.toml'} --jobs 1"
    run = subprocess.run(
        ["unshare", "-m", "sh", "-c", f"mount --bind -o ro {folder} {folder} && {command}"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 2, run.stderr
    assert run.stdout == "" and run.stderr.strip().splitlines() == [
        f"stepframe: error: {folder}: is not writable, expected a writable folder"
    ]


def test_store_verify_removes_unreachable_objects(
    scene: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    work = scene / "stepframe-work"
    status, _, _ = _run(scene, capsys, "--force", "features")  # every key again, later
    assert status == 0
    assert len(list((work / "store" / "features").glob("seg-*.parquet"))) == 2
    stray = work / "store" / "site" / "sets" / ("0" * 64)
    stray.mkdir()
    capsys.readouterr()
    assert main(["store", "verify", str(work)]) == 0
    out = capsys.readouterr().out
    assert "every object matches its checksum" in out
    assert len(list((work / "store" / "features").glob("seg-*.parquet"))) == 1
    assert not stray.exists()
    store = Store(work / "store")
    assert store.verify()["features"]["removed"] == []
    _flip(next((work / "store" / "features").glob("seg-*.parquet")))
    capsys.readouterr()
    assert main(["store", "verify", str(scene / "wf.toml")]) == 1
    out = capsys.readouterr().out
    assert "damaged: features/seg-" in out
    # verify recomputes nothing: it leaves that to the next run (it said "; recomputed")
    assert "; the next run that needs it recomputes it" in out and "; recomputed" not in out
    # a path that does not exist is named so, not "no store/ in it"
    assert main(["store", "verify", str(scene / "no-such-folder")]) == 2
    assert "no such file or folder, expected a workspace" in capsys.readouterr().err
