"""docs/cli.md's table of option ranges is generated from the options' one declaration.

Every dataclass of the package with fields declared by ``core.options.option(..., valid=...)``
(the command line's, the workflow's and the library's options alike) gives one row per field:
its flag, the values it accepts (``core.options.accepted``, the words of the error message) and
its help. The test fails when docs/cli.md's table differs from the generated one; run as a
script (``python tests/test_option_ranges.py``) it prints the table to paste.
"""

from __future__ import annotations

import dataclasses
import importlib
import inspect
import pkgutil
from pathlib import Path

import stepframe
from stepframe.core.options import Range, accepted

DOC = Path(__file__).resolve().parents[1] / "docs" / "cli.md"
HEADING = "## Ranges of the options"
INTRO = (
    "Every numeric option is checked against its range at parse time, on the command line "
    "(`--flag value, expected ...`) and in a workflow file (`file:line: [table] key = value, "
    "expected ...`) alike (the key is the workflow's and the library's name); the library's "
    "dataclasses run the same check. Generated from the "
    "declarations by `python tests/test_option_ranges.py`."
)


def declared_ranges() -> list[tuple[str, str, str, str, str]]:
    """(declaring class, flag, key, accepted values, help) of every field with a range, in
    module and declaration order (a field inherited by another class is listed once, at its
    class)."""
    rows: list[tuple[str, str, str, str, str]] = []
    for info in pkgutil.walk_packages(stepframe.__path__, "stepframe."):
        module = importlib.import_module(info.name)
        for cls in vars(module).values():
            if not (
                isinstance(cls, type)
                and dataclasses.is_dataclass(cls)
                and cls.__module__ == module.__name__
            ):
                continue
            own = inspect.get_annotations(cls)
            for f in dataclasses.fields(cls):
                valid = f.metadata.get("valid")
                if not isinstance(valid, Range) or f.name not in own:
                    continue
                flag = f.metadata.get("flag") or "--" + f.name.replace("_", "-")
                help = (f.metadata.get("help") or "").replace("%(default)s", str(f.default))
                place = f"{cls.__module__.removeprefix('stepframe.')}.{cls.__qualname__}"
                rows.append((place, flag, f.name, accepted(f.metadata.get("kind"), valid), help))
    return rows


def table() -> str:
    """The section of docs/cli.md: heading, introduction and the table."""
    lines = [
        HEADING,
        "",
        INTRO,
        "",
        "| flag | key | accepted | meaning | declared on |",
        "|---|---|---|---|---|",
    ]
    for place, flag, key, values, help in declared_ranges():
        cells = (f"`{flag}`", f"`{key}`", values, help, f"`{place}`")
        lines.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(lines) + "\n"


def test_docs_table_is_generated_from_the_declarations() -> None:
    text = DOC.read_text()
    assert HEADING in text, f"{DOC} has no section {HEADING!r}: paste `python {__file__}`"
    section = text[text.index(HEADING) :]
    following = section.find("\n## ", len(HEADING))
    section = section if following < 0 else section[: following + 1]
    assert section.rstrip("\n") == table().rstrip("\n")


def test_the_table_holds_the_issue_28_ranges() -> None:
    """Spot checks against the values the options refuse (tests/hostile/test_hostile_ii.py)."""
    rows = {flag: values for _, flag, _, values, _ in declared_ranges()}
    assert rows["--window-s"] == "in [0.01, 600]"
    assert rows["--n-steps"] == "in [100, 1000000]"
    assert rows["--seed"] == "in [0, 18446744073709551615]"
    assert rows["--memory-mb"] == "in [64, 1e+09]"
    assert rows["--max-file-mb"] == "in (0, 65536]"


if __name__ == "__main__":
    print(table(), end="")
