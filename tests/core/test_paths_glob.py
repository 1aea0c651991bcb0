"""A records glob matches a path inside the folder as the recursive definition says: ``**`` is
any folders or none, every other part one folder or name (the fast form for a single leading
``**``, the listing's case, against the definition written out here)."""

from __future__ import annotations

import fnmatch
import itertools

import pytest

from stepframe.core.paths import _glob_parts, _matches


def _defined(parts: tuple[str, ...], pattern: tuple[str, ...]) -> bool:
    """The definition: ``**`` takes any number of leading parts, a name part exactly one."""
    if not pattern:
        return not parts
    if pattern[0] == "**":
        return any(_defined(parts[k:], pattern[1:]) for k in range(len(parts) + 1))
    return (
        bool(parts)
        and fnmatch.fnmatchcase(parts[0], pattern[0])
        and _defined(parts[1:], pattern[1:])
    )


PATHS = [
    ("a.AT2",),
    ("a.at2",),
    ("sub", "a.AT2"),
    ("sub", "deep", "a.AT2"),
    ("sub", "a.txt"),
    ("x", "sub", "a.AT2"),
    ("sub",),
    (),
]
PATTERNS = ["*", "*.AT2", "sub/*.AT2", "sub/*/*.AT2", "s*/*", "**/deep/*", "sub/**/*.AT2", "?.AT2"]


@pytest.mark.parametrize(("pattern", "recursive"), list(itertools.product(PATTERNS, (True, False))))
def test_glob_matches_as_defined(pattern: str, recursive: bool) -> None:
    glob = _glob_parts(pattern, recursive)
    for parts in PATHS:
        assert _matches(parts, glob) == _defined(parts, glob), (pattern, recursive, parts)


def test_recursive_glob_examples() -> None:
    glob = _glob_parts("*.AT2", recursive=True)
    assert _matches(("sub", "deep", "a.AT2"), glob)
    assert not _matches(("sub", "a.at2"), glob)  # case matters
    glob = _glob_parts("sub/*.AT2", recursive=True)
    assert _matches(("x", "sub", "a.AT2"), glob)
    assert not _matches(("sub", "deep", "a.AT2"), glob)
    assert not _matches(("a.AT2",), glob)
