"""The import graph of catc, catrt and catgrammar has no cycle (docs/architecture.md).

Arrows are read off the source with ``ast``: every ``import`` and ``from … import`` anywhere
in a module — at module level, inside functions (an import deferred for start-up time is
still an arrow), under ``if TYPE_CHECKING:`` (an annotation is still an arrow) and relative
ones.  ``from pkg import name`` is an arrow to ``pkg.name`` when that is a module, else to
``pkg`` (its ``__init__``); a module's parent packages, which Python runs first, are not
arrows of their own.  A cycle fails the test with the path that closes it."""

from __future__ import annotations

import ast
import functools
from pathlib import Path

from conftest import ROOT

PACKAGES = {"catc": ROOT / "compiler", "catrt": ROOT / "runtime", "catgrammar": ROOT}


def _modules() -> dict[str, Path]:
    paths = {}
    for package, base in PACKAGES.items():
        for path in (base / package).rglob("*.py"):
            parts = path.relative_to(base).with_suffix("").parts
            paths[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    return paths


def _arrows(name: str, path: Path, paths: dict[str, Path]) -> set[str]:
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name in paths}
        elif isinstance(node, ast.ImportFrom):
            module = node.module or ""
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                module = ".".join([*base, *([module] if module else [])])
            subs = {f"{module}.{a.name}" for a in node.names} & paths.keys()
            found |= subs or ({module} & paths.keys())
    return found - {name}


@functools.cache  # read by two tests: built once a process
def import_graph() -> dict[str, set[str]]:
    paths = _modules()
    return {name: _arrows(name, path, paths) for name, path in paths.items()}


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """A cycle of ``graph`` as a closed path (``[a, b, a]``), or None (a depth-first search
    for a back edge, iterative so the depth of the graph does not matter)."""
    state: dict[str, int] = {}  # 1: on the path, 2: done
    for root in sorted(graph):
        if root in state:
            continue
        path, stack = [root], [iter(sorted(graph[root]))]
        state[root] = 1
        while stack:
            dep = next(stack[-1], None)
            if dep is None:
                state[path.pop()] = 2
                stack.pop()
            elif state.get(dep) == 1:
                return [*path[path.index(dep) :], dep]
            elif dep not in state:
                state[dep] = 1
                path.append(dep)
                stack.append(iter(sorted(graph.get(dep, ()))))
    return None


def test_the_import_graph_has_no_cycle():
    graph = import_graph()
    assert len(graph) > 150 and "catc.frontend.workspace" in graph and "catrt.runtime" in graph
    cycle = find_cycle(graph)
    assert cycle is None, "an import cycle: " + " -> ".join(cycle)


def test_the_graph_sees_every_kind_of_import():
    """The reader finds what the cycle search relies on: deferred, TYPE_CHECKING, relative
    and package-level imports."""
    graph = import_graph()
    assert "catc.frontend.units" in graph["catc.frontend.check_domain"]  # inside a function and TYPE_CHECKING
    assert "catc.ir" in graph["catc.ir.labels"]  # from catc import ir: the package itself
    assert "catgrammar.parser" in graph["catgrammar"]  # under TYPE_CHECKING


def test_the_search_finds_a_cycle():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": set(), "c": {"a", "b"}}) is None
    assert find_cycle({"a": {"a"}}) == ["a", "a"]
