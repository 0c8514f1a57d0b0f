"""What the architecture promises (docs/architecture.md): one registry serves every
interface, the backends are interchangeable, and nothing a long-lived process uses keeps
global state — several threads parse, check and solve at once and get the answers they get
alone."""

from __future__ import annotations

import ast
import json
import re
import threading
import tomllib
from pathlib import Path

import pytest
from conftest import ROOT, run_catc

from catc.api import load
from catc.interfaces import cli
from catc.queries import registry
from catc.queries.base import ExitCode, Status
from catc.queries.solve import SolveStatus, solve
from catc.smt.backend import BACKENDS, BackendError, open_backend
from catc.targets import registry as target_registry

EXAMPLES = ROOT / "examples"


def cases():
    for expect in sorted(EXAMPLES.glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            yield expect.parent / case["file"], case


CASES = list(cases())


# ---------------------------------------------------------------- one registry


@pytest.mark.parametrize("name", registry.names())
def test_every_query_reaches_every_interface(name):
    query = registry.get(name)
    assert query.name == name and query.schema == f"catc.{name}/1"
    # the command line: a command of that name with the query's options
    command = cli.main.get_command(None, name)
    flags = {f for p in command.params for f in getattr(p, "opts", ())}
    assert {f for o in query.options for f in o.flags if f.startswith("-")} <= flags
    # the API: a method of that name
    model = load(EXAMPLES / "detection/person.cat")
    assert callable(getattr(model, name)) and name in dir(model)
    # documented
    assert f"catc {name}" in (ROOT / "docs/cli.md").read_text()
    # each status carries its exit code
    module = vars(__import__(query.run.__module__, fromlist=["_"]))
    statuses = {c for c in module.values() if isinstance(c, type) and issubclass(c, Status) and c is not Status}
    assert statuses and all(isinstance(s.exit_code, ExitCode) for cls in statuses for s in cls)


def test_adding_a_query_is_one_module_and_one_line(tmp_path, monkeypatch):
    """A query written outside catc, registered by one line, is a command, an API method and
    a JSON document at once."""
    (tmp_path / "count_query.py").write_text(
        """
from dataclasses import dataclass, field
from catc.queries.base import ExitCode, Query, Result, Status, json_option

class CountStatus(Status):
    COUNTED = "counted", ExitCode.OK

@dataclass
class Counted(Result):
    query = "count"
    status: CountStatus
    morphisms: int
    timings: dict = field(default_factory=dict)

def count(inst, *, horizon=None, sequential=False):
    return Counted(CountStatus.COUNTED, len(inst.morphisms))

QUERY = Query(
    "count",
    summary="Count the morphisms.",
    description="Exit 0.",
    options=(json_option("catc.count/1"),),
    run=count,
    to_json=lambda inst, r: {"schema": "catc.count/1", "morphisms": r.morphisms},
    render=lambda console, inst, r, options: console.print(f"{r.morphisms} morphisms"),
)
"""
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(registry.QUERIES, "count", "count_query")
    person = str(EXAMPLES / "detection/person.cat")
    res = run_catc("count", person, "--json")
    assert res.exit_code == 0 and json.loads(res.stdout) == {"schema": "catc.count/1", "morphisms": 3}
    assert run_catc("count", person, via_click=True).stdout.strip() == "3 morphisms"
    model = load(person)
    assert model.to_json(model.count()) == {"schema": "catc.count/1", "morphisms": 3}


@pytest.mark.parametrize("name", target_registry.names())
def test_every_target_reaches_every_interface(name):
    target = target_registry.get(name)
    assert target.name == name
    # the command line: the command its words name, with the target's options
    if target.command:
        group = cli.main.get_command(None, target.command[0])
        command = group if len(target.command) == 1 else group.get_command(None, target.command[1])
        flags = {f for p in command.params for f in getattr(p, "opts", ())}
        assert {f for o in target.options for f in o.flags if f.startswith("-")} <= flags
        assert f"## `catc {' '.join(target.command)}`" in (ROOT / "docs/cli-reference.md").read_text()
    # the API: model.export(name), its JSON document named by the target's schema
    model = load(EXAMPLES / "detection/person.cat")
    options = {"grid": {"ram-req": "1/2"}} if name == "pddl" else {}
    assert model.export_json(name, model.export(name, **options))["schema"] == target.schema
    # the language server: a catc.export.<name> command
    pytest.importorskip("pygls")
    from catc.interfaces.lsp import build_server

    assert f"catc.export.{name}" in build_server().protocol.fm.commands


def test_the_ground_target_answers_the_api_and_the_language_server():
    """model.ground() solves, replays and grounds person.cat: its manifest names the plan's
    three morphisms (examples/detection/expect.toml: mount-rgb-camera among them)."""
    from catc.interfaces.lsp import run_target_on_file

    model = load(EXAMPLES / "detection/person.cat")
    grounding = model.ground()
    doc = model.export_json("ground", grounding)
    assert doc["schema"] == "catc.ground/1" and set(doc["artifacts"]) >= {"compose.yaml", "bt.xml"}
    assert "mount-rgb-camera" in {a["morphism"] for step in doc["plan"]["steps"] for a in step}
    uri = (EXAMPLES / "detection/person.cat").resolve().as_uri()
    assert run_target_on_file("ground", uri)["plan"] == doc["plan"]
    refused = run_target_on_file("pddl", uri)  # a real θ without a grid step: an input error
    assert refused["schema"] == "catc.error/1" and "grid step" in refused["diagnostics"][0]["message"]


def test_adding_a_target_is_one_module_and_one_line(tmp_path, monkeypatch):
    """A target written outside catc, registered by one line, is a command, an API method, a
    language-server command and a section of the generated command reference at once."""
    (tmp_path / "names_target.py").write_text(
        """
from pathlib import Path
from catc.queries.base import Kind, Option, Use
from catc.targets.base import Target, load_options

def names(inst, *, upper=False):
    words = sorted(inst.morphisms)
    return [w.upper() for w in words] if upper else words

def write(inst, words, options):
    path = Path(options["output"]) / "names.txt"
    path.write_text("".join(w + "\\n" for w in words))
    return [f"wrote {path}"]

TARGET = Target(
    "names",
    summary="List the morphisms, one a line.",
    description="A test target.",
    options=(
        Option("output", ("-o", "--output"), Kind.OUTPUT_FOLDER, "Folder for names.txt.", use=Use.OUTPUT),
        Option("upper", ("--upper",), Kind.FLAG, "In capitals."),
        *load_options("Use this view."),
    ),
    run=names,
    to_json=lambda inst, words: {"schema": "catc.export-names/1", "names": words},
    render=lambda inst, words: "".join(w + "\\n" for w in words),
    write=write,
)
"""
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setitem(target_registry.TARGETS, "names", "names_target")
    person = EXAMPLES / "detection/person.cat"
    # person.cat's morphisms, read off its domain's source by a regex (the three of
    # test_adding_a_query_is_one_module_and_one_line)
    expected = sorted(re.findall(r"\(:morphism ([\w-]+)", (EXAMPLES / "detection/domain.cat").read_text()))
    assert len(expected) == 3
    res = run_catc("export", "names", str(person), "--upper")
    assert res.exit_code == 0 and res.stdout.split() == [w.upper() for w in expected]
    res = run_catc("export", "names", str(person), "-o", str(tmp_path))
    assert res.exit_code == 0 and (tmp_path / "names.txt").read_text().split() == expected
    model = load(person)
    assert model.export_json("names", model.export("names")) == {"schema": "catc.export-names/1", "names": expected}
    from catc.interfaces.docgen import cli_reference
    from catc.interfaces.lsp import run_target_on_file

    assert run_target_on_file("names", person.resolve().as_uri(), {"upper": True})["names"] == [
        w.upper() for w in expected
    ]
    reference = cli_reference()
    assert "## `catc export names`" in reference and "--upper" in reference


def _import_graph(package: str) -> dict[str, set[str]]:
    """Module → the modules of ``package`` it imports, read off the source (function-level
    imports too: an import deferred for start-up time is still an arrow)."""
    base = ROOT / "compiler"
    paths = {}
    for path in (base / package.replace(".", "/")).rglob("*.py"):
        parts = path.relative_to(base).with_suffix("").parts
        paths[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    graph: dict[str, set[str]] = {}
    for name, path in paths.items():
        found = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom) and node.module and not node.level:
                found |= {m for m in (node.module, *(f"{node.module}.{a.name}" for a in node.names)) if m in paths}
            elif isinstance(node, ast.Import):
                found |= {a.name for a in node.names if a.name in paths}
        graph[name] = found - {name}
    return graph


@pytest.mark.parametrize("package", ["catc.targets", "catc.interfaces.cli", "catc.interfaces.lsp"])
def test_no_import_cycle_among_the_targets_and_the_interfaces(package):
    """pddl ⇄ pddlplus and lsp ⇄ lsp_tools were cycles; none is left (a depth-first search
    for a back edge)."""
    graph = _import_graph(package)
    state: dict[str, int] = {}  # 1: on the path, 2: done

    def visit(name: str, path: list[str]) -> None:
        state[name] = 1
        for dep in sorted(graph[name]):
            assert state.get(dep) != 1, " -> ".join([*path[path.index(dep) :], dep])
            if dep not in state:
                visit(dep, [*path, dep])
        state[name] = 2

    for name in sorted(graph):
        if name not in state:
            visit(name, [name])


# ---------------------------------------------------------------- interchangeable backends


@pytest.mark.parametrize("backend", sorted(BACKENDS))
@pytest.mark.parametrize("path, case", CASES, ids=lambda x: x.name if isinstance(x, Path) else x.get("problem", ""))
def test_the_example_table_on_every_backend(backend, path, case):
    """Every example's expected outcome (examples/*/expect.toml, derived by hand) holds on
    every backend; every SAT answer is replayed by the independent validator inside solve."""
    model = load(path, problem_name=case.get("problem"))
    result = solve(model.instance, backend=backend)
    assert result.status.value == case["status"]
    if result.status is SolveStatus.UNSAT:
        assert result.final == case.get("final_unsat", False)
        return
    used = result.plan.components
    assert set(case.get("uses", [])) <= used and not set(case.get("not_uses", [])) & used
    if "steps" in case:
        assert len(result.plan) == case["steps"]


def test_solve_on_cvc5_from_the_command_line():
    res = run_catc("solve", str(EXAMPLES / "detection/person.cat"), "--backend", "cvc5", "--json")
    doc = json.loads(res.stdout)
    assert res.exit_code == 0 and doc["status"] == "sat" and doc["backend"] == "cvc5"
    assert "backend" not in json.loads(run_catc("solve", str(EXAMPLES / "detection/person.cat"), "--json").stdout)


def test_a_backend_refuses_what_it_cannot_do():
    with pytest.raises(BackendError, match="no optimize support"):
        open_backend("cvc5", optimize=True)
    with pytest.raises(BackendError, match="unknown backend"):
        open_backend("yices")


def test_only_the_backends_import_a_solver():
    for path in (ROOT / "compiler").rglob("*.py"):
        imports = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Import):
                imports |= {a.name.split(".")[0] for a in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                imports.add(node.module.split(".")[0])
        solvers = imports & {"z3", "cvc5"}
        assert not solvers or path.name in ("z3backend.py", "cvc5backend.py"), (path, solvers)


# ---------------------------------------------------------------- no hidden global state


def _answers(paths_and_cases):
    out = []
    for path, case in paths_and_cases:
        model = load(path, problem_name=case.get("problem"))
        doc = model.to_json(model.solve())
        doc.pop("timings")
        out.append(doc)
    return out


def test_threads_parse_check_and_solve_at_once_with_the_answers_they_get_alone():
    work = [c for c in CASES if "search-and-rescue" not in str(c[0])]  # the small ones, several times
    alone = _answers(work)
    together: dict[int, list] = {}
    errors: list[BaseException] = []

    def run(i: int) -> None:
        try:
            together[i] = _answers(work)
        except BaseException as exc:
            errors.append(exc)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors, errors
    assert all(together[i] == alone for i in range(4))


def test_no_function_is_longer_than_80_lines():
    long = []
    for root in (ROOT / "compiler" / "catc", ROOT / "catgrammar", ROOT / "runtime" / "catrt"):
        for path in root.rglob("*.py"):
            if path.name == "_lalr.py":  # generated tables
                continue
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and node.end_lineno - node.lineno >= 80:
                    long.append(f"{path.relative_to(ROOT)}:{node.lineno} {node.name}")
    assert not long, long


def test_division_by_zero_in_a_constant_is_a_located_error(tmp_path):
    """`catc check` on (:init (= x (/ 1 (- 1 1)))) used to exit 70 (the checker's folder had
    no guard); it is E0310 at the expression."""
    (tmp_path / "d.cat").write_text("(define (domain d) (:requirements :numeric) (:resources (x real)))\n")
    (tmp_path / "p.cat").write_text(
        "(define (problem p) (:domain d)\n  (:init (= x (/ 1 (- 1 1))))\n  (:goal (>= x 0)))\n"
    )
    res = run_catc("check", str(tmp_path / "d.cat"), str(tmp_path / "p.cat"))
    assert res.exit_code == 1 and re.search(r"p\.cat:2:15: error\[E0310\]: division by zero", res.stdout)


def test_the_architecture_picture_is_drawn_from_the_current_code():
    import subprocess
    import sys

    res = subprocess.run([sys.executable, "docs/img/architecture.py", "--check"], cwd=ROOT)
    assert res.returncode == 0, "run: python docs/img/architecture.py"
