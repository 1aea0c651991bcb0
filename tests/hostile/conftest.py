"""Fixtures of the hostile-input suite: the damaged-file corpus and an in-process CLI runner."""

from __future__ import annotations

import contextlib
import importlib.util
import io
import json
import math
import signal
import sys
from dataclasses import dataclass
from pathlib import Path
from types import FrameType, ModuleType
from typing import Any

import pytest

from stepframe.cli import main

HERE = Path(__file__).parent
#: Seconds one command may take on one file before it counts as a hang.
TIME_LIMIT_S = 20


def _load(name: str) -> ModuleType:
    spec = importlib.util.spec_from_file_location(f"hostile_{name}", HERE / f"{name}.py")
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # dataclasses look their module up there
    spec.loader.exec_module(module)
    return module


corpus_module = _load("corpus")


@dataclass
class Run:
    """One in-process run of the ``stepframe`` command."""

    argv: list[str]
    status: int | None
    stdout: str
    stderr: str
    problem: str | None  # None: a clean run (exit 0 with finite output, or exit 2 one line)


class _Timeout(Exception):
    pass


def _alarm(signum: int, frame: FrameType | None) -> None:
    raise _Timeout


def _non_finite(value: Any) -> bool:
    if isinstance(value, float):
        return not math.isfinite(value)
    if isinstance(value, dict):
        return any(_non_finite(v) for v in value.values())
    if isinstance(value, list):
        return any(_non_finite(v) for v in value)
    return False


def run_cli(argv: list[str], time_limit_s: int = TIME_LIMIT_S) -> Run:
    """Run ``stepframe ARGV`` in this process and classify the outcome."""
    out, err = io.StringIO(), io.StringIO()
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(time_limit_s)
    status: int | None = None
    problem: str | None = None
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            status = main(argv)
    except _Timeout:
        problem = f"hang (> {time_limit_s} s)"
    except BaseException as exc:  # anything escaping main is a traceback for the user
        problem = f"traceback {type(exc).__name__}: {str(exc)[:200]}"
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
    stdout, stderr = out.getvalue(), err.getvalue()
    if problem is None:
        errors = [x for x in stderr.splitlines() if x.startswith("stepframe: error:")]
        if status == 2:
            if len(errors) != 1 or stdout:
                problem = f"exit 2 without exactly one error line: {stderr[:200]!r}"
        elif status == 0:
            try:
                data = json.loads(stdout)
            except ValueError:
                problem = f"exit 0 with output that is not JSON: {stdout[:200]!r}"
            else:
                if _non_finite(data) or "NaN" in stdout or "Infinity" in stdout:
                    problem = "exit 0 with non-finite output"
        else:
            problem = f"exit {status}: {stderr[:200]!r}"
    return Run(argv, status, stdout, stderr, problem)


@pytest.fixture(scope="session")
def corpus(tmp_path_factory: pytest.TempPathFactory) -> list[Any]:
    """The damaged files (seed 16), written once per session."""
    return list(corpus_module.build(tmp_path_factory.mktemp("corpus")))


@pytest.fixture(scope="session")
def frame_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The frame template (the paper's Example 4), as ``structure simulate`` takes it."""
    path = tmp_path_factory.mktemp("frame") / "frame.toml"
    run = run_cli(["structure", "frame-template"])
    path.write_text(run.stdout)
    return path


@pytest.fixture
def cli() -> Any:
    """The in-process runner :func:`run_cli` (exit status, output, and any problem)."""
    return run_cli
