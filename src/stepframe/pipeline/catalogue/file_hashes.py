"""The sha256 of each record file, hashed once: later runs reuse it while the file is unchanged.

The store keys everything by the content of the record files
(:func:`stepframe.core.io.file_sha256`), which means reading every byte of every
file at every run: 4-5 GB for a catalogue the size of NGA-West2, several seconds even from the
page cache. A file whose identity is unchanged since it was hashed (device, inode, size,
modification and status-change times in nanoseconds, as ``git`` and ``make`` judge a file) keeps
its hash: writing to a file, replacing it, or setting its times all change its status-change
time, which no user call can set back. A file changed within :data:`RACY_S` of being hashed is
not remembered (the clock's granularity could hide a second change), so it is hashed again next
time. The remembered hashes are one Parquet table in the workspace (:data:`CACHE_NAME`), written
atomically; a missing or unreadable one costs a re-hash, never a wrong key.

The files not remembered are hashed by the run's workers when it has them (a process pool, a Dask
cluster): on a first run of a large catalogue the hashing is a job per file, and in the main
process it was a third of the run's serial part (4.7 GB at about 200 MB/s of one core is 23 s
of CPU at 43,000 components), which no number of workers would shorten.
"""

from __future__ import annotations

import os
import time
from collections.abc import Sequence
from concurrent.futures import Executor, ThreadPoolExecutor
from pathlib import Path

from stepframe.core.io import atomic_write, file_sha256
from stepframe.core.paths import absolute_name

#: The workspace file that remembers the hashes.
CACHE_NAME = "record-hashes.parquet"
#: A file modified less than this before it was hashed is hashed again next run [s].
RACY_S = 2.0
_IDENTITY = ("device", "inode", "size", "mtime_ns", "ctime_ns")

Identity = tuple[int, int, int, int, int]


def _identity(stat: os.stat_result) -> Identity:
    return (stat.st_dev, stat.st_ino, stat.st_size, stat.st_mtime_ns, stat.st_ctime_ns)


def _read_cache(path: Path) -> dict[str, tuple[Identity, str]]:
    import pandas as pd

    try:
        table = pd.read_parquet(path)
        columns = [table[name].to_numpy().tolist() for name in ("path", *_IDENTITY, "sha256")]
    except Exception:  # missing, damaged or of another layout: everything is hashed again
        return {}
    return {
        str(name): (tuple(int(v) for v in identity), str(sha))  # type: ignore[misc]
        for name, *identity, sha in zip(*columns, strict=True)
    }


def file_hashes(
    paths: Sequence[Path],
    cache: Path | None = None,
    *,
    update: bool = False,
    threads: int = 1,
    executor: Executor | None = None,
) -> list[str]:
    """The sha256 (hex) of each file, from ``cache`` where the file is unchanged.

    Parameters
    ----------
    paths
        The files.
    cache
        The cache file (None: hash everything).
    update
        Write the cache for ``paths`` (only the files given are kept; nothing is written when
        nothing changed). A dry run reads it and writes nothing.
    threads
        Threads hashing the files not in the cache (sha256 releases the GIL on large blocks),
        when no ``executor`` is given.
    executor
        The run's executor (a :class:`~stepframe.core.execution.WorkerPool`, a Dask client's):
        the files not in the cache are hashed on its workers, a chunk of files per task
        (:func:`~stepframe.core.execution.map_items`: kept in this process when too few to pay).

    Returns
    -------
    list of str
        One hash per path, in order.
    """
    hashes = readable_hashes(paths, cache, update=update, threads=threads, executor=executor)
    for sha in hashes:
        if isinstance(sha, OSError):
            raise sha
    return [str(sha) for sha in hashes]


def readable_hashes(
    paths: Sequence[Path],
    cache: Path | None = None,
    *,
    update: bool = False,
    threads: int = 1,
    executor: Executor | None = None,
) -> list[str | OSError]:
    """:func:`file_hashes`, with the error of each file that could not be read (no permission,
    gone since it was listed) in its place instead of raised: one such file of an inbox is a
    failed item of the run, not the end of the run. Such a file is never remembered."""
    known = _read_cache(cache) if cache is not None else {}
    names = [absolute_name(path) for path in paths]
    identities: list[Identity | None] = []
    hashes: list[str | OSError | None] = []
    for name, path in zip(names, paths, strict=True):
        try:
            identity: Identity | None = _identity(os.stat(path))
        except OSError as error:  # gone since the folder was listed
            identities.append(None)
            hashes.append(error)
            continue
        identities.append(identity)
        entry = known.get(name)
        hashes.append(entry[1] if entry is not None and entry[0] == identity else None)
    missing = [i for i, sha in enumerate(hashes) if sha is None]
    started_ns = time.time_ns()
    # by absolute name: a cluster's workers do not run in this process's folder
    fresh = _hashed([Path(names[i]) for i in missing], threads, executor)
    for i, sha in zip(missing, fresh, strict=True):
        hashes[i] = sha
    result = [sha for sha in hashes if sha is not None]
    if update and cache is not None and (missing or len(known) != len(names)):
        readable = [i for i, sha in enumerate(result) if isinstance(sha, str)]
        _write_cache(
            cache,
            [names[i] for i in readable],
            [identity for i in readable if (identity := identities[i]) is not None],
            [str(result[i]) for i in readable],
            started_ns - int(RACY_S * 1e9),
        )
    return result


def _hashed(paths: list[Path], threads: int, executor: Executor | None) -> list[str | OSError]:
    """The sha256 of each file, on the executor's workers or in threads of this process; a
    file that could not be read gives its OSError (the same error wherever it was hashed)."""
    if executor is None:
        with ThreadPoolExecutor(max_workers=max(1, threads)) as pool:
            return list(pool.map(_sha256_or_oserror, paths))
    from stepframe.core.execution import map_items

    outcome = map_items(_sha256_or_error, paths, executor=executor, stage="inventory")
    if outcome.failures:  # not an OSError (those come back as values): a worker failed
        first = outcome.failures[0]
        raise RuntimeError(f"hashing {first.item}: {first.error_type}: {first.message}")
    hashes: list[str | OSError] = []
    for path, sha in zip(paths, outcome.results, strict=True):
        hashes.append(OSError(sha[0], sha[1], str(path)) if isinstance(sha, tuple) else sha)
    return hashes


def _sha256_or_oserror(path: Path) -> str | OSError:
    try:
        return file_sha256(path)
    except OSError as error:
        return error


def _sha256_or_error(path: Path) -> str | tuple[int, str]:
    """Worker's job: the file's sha256, or its read error's (errno, message), raised again as
    an OSError in the run's process (a remote worker's exception would arrive re-typed)."""
    try:
        return file_sha256(path)
    except OSError as error:
        return (error.errno or 0, error.strerror or str(error))


def _write_cache(
    cache: Path, names: list[str], identities: list[Identity], hashes: list[str], before_ns: int
) -> None:
    import pandas as pd

    keep = [i for i, identity in enumerate(identities) if max(identity[3], identity[4]) < before_ns]
    table = pd.DataFrame(
        {
            "path": [names[i] for i in keep],
            **{column: [identities[i][k] for i in keep] for k, column in enumerate(_IDENTITY)},
            "sha256": [hashes[i] for i in keep],
        }
    )
    cache.parent.mkdir(parents=True, exist_ok=True)
    with atomic_write(cache, "wb") as out:
        table.to_parquet(out, index=False, engine="pyarrow")
