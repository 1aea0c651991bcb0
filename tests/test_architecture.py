"""The house rules of docs/architecture.md, checked on the source (static analysis, no imports).

- no import cycle anywhere under src/ (imports inside functions count; ``if TYPE_CHECKING:``
  blocks do not, since they never run);
- the workflow engine imports no science (records, stochastic, structure) and no job;
- the library areas never import the pipeline, the commands or the CLI, and stochastic and
  structure do not import each other;
- every function over 120 lines outside the numba kernels is listed, with its reason, in
  docs/architecture.md ("Functions over 120 lines").

Run as a script (``python tests/test_architecture.py``) it prints the import cycles and the long
functions.
"""

from __future__ import annotations

import ast
import re
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "src" / "stepframe"
MAX_FUNCTION_LINES = 120
AREAS = ("stepframe.records", "stepframe.stochastic", "stepframe.structure")
JOBS = tuple(
    f"stepframe.pipeline.{job}"
    for job in ("catalogue", "amplification", "selection", "dynamics", "reports", "stages", "demo")
)


def module_name(path: Path) -> str:
    """``src/stepframe/a/b.py`` → ``stepframe.a.b`` (``__init__`` → the package)."""
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def modules() -> dict[str, Path]:
    """Every module of the package by its dotted name."""
    return {module_name(path): path for path in sorted(PACKAGE.rglob("*.py"))}


def _is_type_checking(node: ast.If) -> bool:
    test = node.test
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _import_nodes(tree: ast.AST) -> Iterator[ast.Import | ast.ImportFrom]:
    """Import statements anywhere in the tree, except under ``if TYPE_CHECKING:``."""
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.If) and _is_type_checking(node):
            for other in node.orelse:
                yield from _import_nodes(other)
            continue
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            yield node
        yield from _import_nodes(node)


def imports_of(name: str, path: Path, known: set[str]) -> set[str]:
    """The package's modules that module ``name`` imports (resolved to modules, not names)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in _import_nodes(tree):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        else:
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - (node.level - 1)]
                base = ".".join([*anchor, base] if base else anchor)
            targets = [f"{base}.{alias.name}" for alias in node.names]
            targets = [t if t in known else base for t in targets]
        found.update(t for t in targets if t in known and t != name)
    return found


def import_graph() -> dict[str, set[str]]:
    """Module → the package modules it imports."""
    known = modules()
    names = set(known)
    return {name: imports_of(name, path, names) for name, path in known.items()}


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan), sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    cycles: list[list[str]] = []
    counter = 0

    def visit(node: str) -> None:
        nonlocal counter
        index[node] = low[node] = counter
        counter += 1
        stack.append(node)
        on_stack.add(node)
        for target in sorted(graph[node]):
            if target not in index:
                visit(target)
                low[node] = min(low[node], low[target])
            elif target in on_stack:
                low[node] = min(low[node], index[target])
        if low[node] == index[node]:
            component = []
            while True:
                member = stack.pop()
                on_stack.discard(member)
                component.append(member)
                if member == node:
                    break
            if len(component) > 1:
                cycles.append(sorted(component))

    for node in sorted(graph):
        if node not in index:
            visit(node)
    return sorted(cycles)


def _kernel_names(tree: ast.Module) -> set[str]:
    """Functions compiled by numba: decorated with ``njit``/``jit`` or wrapped ``njit(...)(f)``."""
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            for decorator in node.decorator_list:
                call = decorator.func if isinstance(decorator, ast.Call) else decorator
                if isinstance(call, (ast.Name, ast.Attribute)) and (
                    getattr(call, "id", None) in ("njit", "jit")
                    or getattr(call, "attr", None) in ("njit", "jit")
                ):
                    names.add(node.name)
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Call)
            and getattr(node.func.func, "id", None) in ("njit", "jit")
        ):
            names.update(arg.id for arg in node.args if isinstance(arg, ast.Name))
    return names


def long_functions(limit: int = MAX_FUNCTION_LINES) -> dict[str, int]:
    """``module:function`` → its length in lines, for functions longer than ``limit`` lines
    (the numba kernels left out)."""
    found = {}
    for name, path in modules().items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        kernels = _kernel_names(tree)
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                assert node.end_lineno is not None
                length = node.end_lineno - node.lineno + 1
                if length > limit and node.name not in kernels:
                    found[f"{name}:{node.name}"] = length
    return found


def documented_long_functions() -> set[str]:
    """The ``module:function`` names listed under "Functions over 120 lines" in
    docs/architecture.md."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = text.split("### Functions over 120 lines", 1)[1].split("\n#", 1)[0]
    return set(re.findall(r"`(stepframe\.[\w.]+:\w+)`", section))


def test_no_import_cycle() -> None:
    assert import_cycles(import_graph()) == []


def test_the_engine_imports_no_science_and_no_job() -> None:
    graph = import_graph()
    for module, targets in graph.items():
        if module.startswith("stepframe.pipeline.engine"):
            forbidden = [t for t in targets if t.startswith(AREAS + JOBS)]
            assert forbidden == [], f"{module} imports {forbidden}"


def test_the_areas_import_no_pipeline_and_not_each_other() -> None:
    graph = import_graph()
    above = ("stepframe.pipeline", "stepframe.commands", "stepframe.cli")
    for module, targets in graph.items():
        if module.startswith(AREAS):
            assert [t for t in targets if t.startswith(above)] == [], module
        if module.startswith("stepframe.stochastic"):
            assert [t for t in targets if t.startswith("stepframe.structure")] == [], module
        if module.startswith("stepframe.structure"):
            assert [t for t in targets if t.startswith("stepframe.stochastic")] == [], module


def test_long_functions_are_the_documented_ones() -> None:
    assert set(long_functions()) == documented_long_functions()


def test_the_analysis_sees_what_it_checks(tmp_path: Path) -> None:
    """The cycle finder and the kernel filter on small cases with a known answer."""
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert import_cycles({"a": {"b"}, "b": set()}) == []
    graph = import_graph()
    # a known edge inside a function body, and one under TYPE_CHECKING that must not count
    assert "stepframe.pipeline.stages" in graph["stepframe.commands.run"]
    assert "stepframe.pipeline.engine.workflow" not in graph["stepframe.pipeline.engine.stage"]
    kernels = _kernel_names(ast.parse((PACKAGE / "structure" / "_exact.py").read_text()))
    assert {"integrate", "integrate_batch"} <= kernels
    wrapped = "def f(x):\n    return x\n\ng = njit(cache=True)(f)\n\ndef h(x):\n    return x\n"
    assert _kernel_names(ast.parse(wrapped)) == {"f"}


if __name__ == "__main__":
    for cycle in import_cycles(import_graph()):
        print("cycle:", " -> ".join(cycle))
    for function, length in sorted(long_functions().items(), key=lambda item: -item[1]):
        print(f"{length:5d} lines  {function}")
