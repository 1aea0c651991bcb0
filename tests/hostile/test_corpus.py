"""The damaged-file corpus through the four commands that read a record.

Every damaged file (tests/hostile/corpus.py, seed 16, built from tests/data at test time) goes
through ``records info``, ``records spectrum``, ``stochastic fit`` and ``structure simulate``
(sniffed), and through ``records info`` and ``records spectrum`` again with the source's
``--format``. Each run must be clean: exit 2 with exactly one ``stepframe: error:`` line, or exit
0 with JSON holding only finite numbers; no traceback, no hang (a SIGALRM guard), no MemoryError.
The counts are printed (``-s``) and recorded in docs/reliability.md.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

RECORD = Path(__file__).parents[1] / "data" / "peer_nga_west2" / "RSN8883_14383980_13849090.AT2"

COMMANDS: dict[str, list[str]] = {
    "records info": ["records", "info"],
    "records spectrum": ["records", "spectrum", "--periods-s", "0.1,0.5,1,3"],
    "stochastic fit": ["stochastic", "fit"],
    "structure simulate": ["structure", "simulate", "--tail-s", "2", "--frame", "{frame}"],
}
#: Commands also run with the source's --format (the others read through the same read()).
WITH_FORMAT = ("records info", "records spectrum")

pytestmark = [pytest.mark.slow, pytest.mark.filterwarnings("ignore")]


@pytest.mark.parametrize("command", list(COMMANDS))
def test_corpus_has_no_traceback_hang_or_silent_nonfinite(
    command: str, corpus: list[Any], frame_file: Path, cli: Callable[..., Any]
) -> None:
    base = [a.format(frame=frame_file) for a in COMMANDS[command]]
    # Warm up once without the guard: numba compiles on the first simulation, and an alarm
    # interrupting a compile would make it start over on the next file.
    assert cli([*base, "--json", str(RECORD)], time_limit_s=600).problem is None
    formats: list[str | None] = [None, "given"] if command in WITH_FORMAT else [None]
    outcomes: Counter[str] = Counter()
    problems = []
    for damaged in corpus:
        for fmt in formats:
            option = ["--format", damaged.format] if fmt else []
            run = cli([*base, "--json", *option, "--", str(damaged.path)])
            outcomes[f"exit {run.status}" if run.problem is None else "problem"] += 1
            if run.problem is not None:
                problems.append((damaged.damage, damaged.path.name, fmt, run.problem))
    print(f"\n{command}: {len(corpus)} files, {sum(outcomes.values())} runs, {dict(outcomes)}")
    assert len(corpus) >= 250
    assert problems == []
