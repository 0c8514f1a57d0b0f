"""docs/architecture.md, "Where new things go": a query, a backend, a target, a lint, a kind
of event change and a standard-library domain are each one file plus one registry line.

For each registry, the modules of its package that define the registered thing (read off
the source: a module-level ``QUERY = ...``, ``TARGET``, ``LINT``, ``CHANGE``, a subclass of
``Backend``; a ``NAME.cat`` file) are exactly the modules the registry lists — so a module
added without its line fails here, and so does a line without its module.  Adding a lint
and a change kind from outside the package, by one line each, shows the line is all it takes.
"""

from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest
from conftest import ROOT, run_catc

from catc.frontend.lints import registry as lints
from catc.queries import registry as queries
from catc.smt.backend import BACKENDS
from catc.targets import registry as targets
from catgrammar import codes

CATC = ROOT / "compiler" / "catc"


def _module_name(path: Path, base: Path) -> str:
    return ".".join(path.relative_to(base).with_suffix("").parts)


def defining(folder: Path, base: Path, name: str) -> set[str]:
    """The modules directly in ``folder`` (a subpackage: its ``__init__``) that assign ``name``
    at module level."""
    found = set()
    for path in sorted([*folder.glob("*.py"), *folder.glob("*/__init__.py")]):
        tree = ast.parse(path.read_text(), str(path))
        for node in tree.body:
            targets_ = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", None)]
            if any(isinstance(t, ast.Name) and t.id == name for t in targets_):
                found.add(_module_name(path.parent if path.name == "__init__.py" else path, base))
    return found


def subclassing(folder: Path, base: Path, cls: str) -> set[str]:
    """The modules directly in ``folder`` that define a subclass of ``cls``."""
    found = set()
    for path in sorted(folder.glob("*.py")):
        for node in ast.parse(path.read_text(), str(path)).body:
            if isinstance(node, ast.ClassDef) and any(isinstance(b, ast.Name) and b.id == cls for b in node.bases):
                found.add(_module_name(path, base))
    return found


# (what, the package's folder, the modules defining one, the modules the registry lists)
REGISTRIES = {
    "query": (CATC / "queries", lambda: defining(CATC / "queries", ROOT / "compiler", "QUERY"), queries.QUERIES),
    "target": (CATC / "targets", lambda: defining(CATC / "targets", ROOT / "compiler", "TARGET"), targets.TARGETS),
    "backend": (
        CATC / "smt",
        # the SMT-LIB2 writer is a Backend that decides nothing: the smt2 target's, not a solver by name
        lambda: subclassing(CATC / "smt", ROOT / "compiler", "Backend") - {"catc.smt.smtlib"},
        {name: spec.partition(":")[0] for name, spec in BACKENDS.items()},
    ),
    "lint": (
        CATC / "frontend" / "lints",
        lambda: defining(CATC / "frontend" / "lints", ROOT / "compiler", "LINT"),
        lints.LINTS,
    ),
}


@pytest.mark.parametrize("what", sorted(REGISTRIES))
def test_the_registry_lists_exactly_the_modules_of_its_package(what):
    folder, found, registry = REGISTRIES[what]
    modules = found()
    assert modules, f"no {what} module found in {folder}"
    listed = set(registry.values())
    assert modules - listed == set(), f"a {what} module without its registry line"
    assert listed - modules == set(), f"a {what} registry line without its module"


def test_the_event_change_kinds_registry_lists_exactly_its_modules_and_the_schema_fields():
    from catrt.changes import registry as changes
    from catrt.events import APPROVAL_KEYS, schema

    folder = ROOT / "runtime" / "catrt" / "changes"
    assert defining(folder, ROOT / "runtime", "CHANGE") == set(changes.CHANGES.values())
    for field, module in changes.CHANGES.items():  # each line names a field its module reads
        assert field in changes.get(field).fields, (field, module)
    for module in set(changes.CHANGES.values()):
        fields = __import__(module, fromlist=["CHANGE"]).CHANGE.fields
        assert all(changes.CHANGES[f] == module for f in fields), module
    # the published schema has a property for each field; the others are an event's own (its
    # version, id and time) and the approvals
    meta = {"v", "id", "at"}
    assert set(schema()["properties"]) - meta - set(APPROVAL_KEYS) == set(changes.CHANGES)


def test_the_standard_library_registry_lists_exactly_its_files():
    import stdlib_domains

    folder = ROOT / "stdlib_domains"
    assert {p.stem for p in folder.glob("*.cat")} == set(stdlib_domains.DOMAINS)
    for name in stdlib_domains.DOMAINS:  # each file defines the domain it is named after, and only that
        text = (folder / f"{name}.cat").read_text()
        assert re.findall(r"\(define\s+\(domain\s+([^\s)]+)", text) == [name]


def test_each_lint_is_registered_under_its_codes_name():
    for name in lints.names():
        lint = lints.get(name)
        assert codes.CODES[lint.code].name == name and lint.code.startswith("W01")


def test_a_module_without_its_line_is_found(tmp_path):
    """The check above can fail: a module defining ``LINT`` beside the registered ones."""
    package = tmp_path / "pkg"
    package.mkdir()
    (package / "registered.py").write_text("LINT = 1\n")
    (package / "forgotten.py").write_text("from x import y\n\nLINT: int = 2\n")
    (package / "helper.py").write_text("def LINT_like():\n    LINT = 3\n")
    assert defining(package, tmp_path, "LINT") - {"pkg.registered"} == {"pkg.forgotten"}


# ---------------------------------------------------------------- one module and one line


def test_adding_a_lint_is_one_module_and_one_line(tmp_path, monkeypatch):
    (tmp_path / "many_morphisms.py").write_text(
        """
from catc.frontend.lints.base import Lint, Scope
from catgrammar import codes

def run(inst, diags, is_user):
    if len(inst.morphisms) > 2:
        diags.report(codes.UNWRITABLE_GOAL, f"{len(inst.morphisms)} morphisms", inst.problem.span)

LINT = Lint(codes.UNWRITABLE_GOAL, Scope.INSTANCE, run)
"""
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    person = str(ROOT / "examples/detection/person.cat")
    assert "3 morphisms" not in run_catc("check", person).output
    monkeypatch.setitem(lints.LINTS, "many-morphisms", "many_morphisms")
    assert "W0104" in run_catc("check", person).output and "3 morphisms" in run_catc("check", person).output


def test_adding_a_change_kind_is_one_module_and_one_line(tmp_path, monkeypatch):
    """A kind of change registered from outside the package applies with the others (the
    event is made directly: its field is not in the published schema)."""
    from catc.api import load
    from catrt.apply import apply_change
    from catrt.changes import registry as changes
    from catrt.events import Event
    from catrt.model import initial_model

    (tmp_path / "double_horizon.py").write_text(
        """
from catrt.changes.base import Change

def apply(state, inst, sources, body, origins):
    origins["horizon"] = "double"
    return state.with_problem(horizon=2 * inst.problem.horizon)

CHANGE = Change(("double",), apply)
"""
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(changes.CHANGES, "double", "double_horizon")
    path = ROOT / "examples/detection/person.cat"
    model = load(path)
    state = initial_model(model.instance, path.read_text(), str(path))
    new, origins = apply_change(state, model.instance, {}, Event("e", {"horizon": 3, "double": True}, "test"))
    assert origins == {"horizon": "double"}  # the registry's order: horizon first, then the new kind
    assert new.problem.horizon == 2 * model.instance.problem.horizon != state.problem.horizon
