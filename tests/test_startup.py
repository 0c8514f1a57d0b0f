"""What the ``catc`` executable imports for a plain command (start-up is part of every answer's
time: docs/benchmarks.md), and the click-free ``catc check`` route printing what click's does.

The module lists are read from ``sys.modules`` of a fresh process that ran the command through
:func:`catc.interfaces.entry.main`, as the installed ``catc`` script does.  An allowed module
is named by its package (a split of ``ir/nodes.py`` adds modules under ``catc.ir.`` and
stays allowed); what a command must never load is named one by one."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from conftest import ROOT, run_catc

from catc.interfaces.check_command import parse_check

#: Packages and modules of catc a plain solve may load (a name, or a package ending in ".").
SOLVE_ALLOWED = (
    "catc",
    "catc.interfaces",
    "catc.interfaces.entry",
    "catc.interfaces.command",
    "catc.interfaces.guard",
    "catc.queries",
    "catc.queries.base",
    "catc.queries.registry",
    "catc.queries.solve",
    "catc.frontend.",
    "catc.ir.",
    "catc.semantics.",
    "catc.smt.",
    "catc.present",
    "catc.present.composition",
    "catc.present.console",
    "catc.present.values",
    "catgrammar.",
    "catc.frontend",
    "catc.ir",
    "catc.semantics",
    "catc.smt",
    "catgrammar",
)

#: What no plain query loads: the other front ends, the exporters, the editor and plotting
#: tools, the optional solvers, and libraries only those need.
NEVER = (
    "click",
    "rich",
    "pint",
    "lark",
    "pygments",
    "matplotlib",
    "numpy",
    "hypothesis",
    "dataclasses",
    "inspect",
    "cvc5",
    "unified_planning",
    "catc.targets",
    "catc.bench",
    "catc.interfaces.cli",
    "catc.interfaces.lsp",
    "catc.interfaces.lsp_tools",
    "catc.interfaces.export_cli",
    "catc.interfaces.docgen",
    "catc.present.diagram",
    "catc.present.plot",
    "catc.frontend.formatter",
    "catc.interfaces.layout",
    "catc.frontend.up_import",
    "catc.smt.cvc5backend",
    "catgrammar.lexer",
    "catgrammar.build_parser",
)

#: ``catc check`` answers without a solver.
CHECK_NEVER = (*NEVER, "z3", "catc.smt.z3backend", "catc.smt.encoder", "catc.queries.solve", "catc.present")


def loaded(*args: str) -> tuple[int, list[str]]:
    """The exit code of ``catc ARGS`` and every module loaded by its end."""
    probe = (
        "import sys\n"
        "from catc.interfaces.entry import main\n"
        "try:\n"
        f"    main({list(args)!r})\n"
        "except SystemExit as exc:\n"
        "    code = exc.code\n"
        "print(code, *sorted(sys.modules), file=sys.stderr)\n"
    )
    proc = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=120)
    code, *names = proc.stderr.split()
    return int(code), names


def within(name: str, entries: tuple[str, ...]) -> bool:
    return any(name == e or (e.endswith(".") and name.startswith(e)) for e in entries)


def never(names: list[str], entries: tuple[str, ...]) -> list[str]:
    return [n for n in names if any(n == e or n.startswith(e + ".") for e in entries)]


@pytest.mark.parametrize("extra", [["--json"], []], ids=["json", "text"])
def test_a_plain_solve_loads_only_what_solving_needs(extra):
    code, names = loaded("solve", "examples/detection/person.cat", *extra)
    assert code == 0
    own = [n for n in names if n.split(".")[0] in ("catc", "catgrammar")]
    assert [n for n in own if not within(n, SOLVE_ALLOWED)] == []
    assert never(names, NEVER) == []
    assert "z3" in names  # the probe sees what it should: the solver was loaded


def test_a_plain_check_loads_no_solver_and_no_click():
    code, names = loaded("check", "examples/detection/person.cat")
    assert code == 0
    assert never(names, CHECK_NEVER) == []
    assert "catc.frontend.check" in names and "catc.interfaces.check_command" in names


def test_the_deny_list_catches_what_the_click_route_loads():
    """The probe can fail: ``--path`` is left to click, which is then loaded."""
    code, names = loaded("check", "examples/detection/person.cat", "--path", "examples")
    assert code == 0
    assert {"click", "catc.interfaces.cli"} <= set(never(names, CHECK_NEVER))


# ------------------------------------------------------------------ catc check without click

CHECKS = [
    ["examples/detection/person.cat"],
    ["examples"],
    ["examples", "-q"],
    ["tests/fixtures/invalid"],
    ["tests/fixtures/invalid", "--format", "json"],
    ["tests/fixtures/invalid", "--format=github", "--strict"],
    ["examples/navigation", "--strict", "--quiet", "--format", "text"],
    ["missing.cat"],
    ["missing.cat", "examples/detection/person.cat", "--format", "json"],
]


@pytest.mark.parametrize("args", CHECKS, ids=" ".join)
def test_both_routes_of_check_print_the_same(args):
    assert parse_check(args) is not None
    args = [str(ROOT / a) if not a.startswith("-") and a not in ("json", "text") else a for a in args]
    fast, slow = run_catc("check", *args), run_catc("check", *args, via_click=True)
    assert (fast.exit_code, fast.stdout, fast.stderr) == (slow.exit_code, slow.stdout, slow.stderr)
    assert fast.exit_code in (0, 1, 2)
    if "json" in args:
        json.loads(fast.stdout)


@pytest.mark.parametrize(
    "args",
    [
        [],
        ["--strict"],
        [""],
        ["p.cat", "--help"],
        ["p.cat", "-h"],
        ["p.cat", "--path", "lib"],
        ["p.cat", "--limit", "tokens=10"],
        ["p.cat", "--memory", "100"],
        ["p.cat", "--format"],
        ["p.cat", "--format", "xml"],
        ["p.cat", "--format=Text"],
        ["p.cat", "--"],
        ["p.cat", "-"],
        ["p.cat", "-qx"],
        ["p.cat", "--strict=1"],
    ],
    ids=lambda a: " ".join(a) or "(none)",
)
def test_other_check_command_lines_are_left_to_click(args):
    assert parse_check(args) is None


# ------------------------------------------------------------------ catc validate without click


def test_both_routes_of_validate_answer_alike(tmp_path):
    """A plain ``catc validate PROBLEM PLAN_FILE`` is read without click, and answers as
    click's route does, for a valid plan and for one the validator rejects."""
    person = str(ROOT / "examples/detection/person.cat")
    solved = run_catc("solve", person, "--json")
    assert solved.exit_code == 0
    good = tmp_path / "good.json"
    good.write_text(solved.stdout)
    doc = json.loads(solved.stdout)
    doc["steps"] = list(reversed(doc["steps"]))  # the same components in the wrong order
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(doc))
    for plan, codes in ((good, {0}), (bad, {1})):
        for extra in ([], ["--json"]):
            fast, slow = (run_catc("validate", person, str(plan), *extra, via_click=v) for v in (False, True))
            assert (fast.exit_code, fast.stdout, fast.stderr) == (slow.exit_code, slow.stdout, slow.stderr)
            assert fast.exit_code in codes
    _, names = loaded("validate", "examples/detection/person.cat", str(good))
    assert never(names, (*NEVER, "z3", "catc.smt.z3backend")) == []  # no click, no dataclasses, no solver


# ------------------------------------------------------------------ a model kept checked between runs

#: What a query whose checked model is kept (catc.frontend.model_cache) does not load: the
#: tokenizer, the parser and the checker.
HIT_NEVER = (
    "catgrammar.parser",
    "catgrammar._lalr",
    "catgrammar.tokens",
    "catgrammar.ast",
    "catc.frontend.workspace",
    "catc.frontend.check",
    "catc.frontend.typecheck",
    "catc.frontend.lints",
)


@pytest.mark.parametrize(
    "words",
    [["solve", "detection/person.cat"], ["optimize", "navigation/farthest.cat"]],
    ids=["solve", "optimize"],
)
def test_a_query_on_a_kept_model_loads_no_parser(words, tmp_path, monkeypatch):
    import os
    import shutil
    import time

    folder = words[1].split("/")[0]
    shutil.copytree(ROOT / "examples" / folder, tmp_path / folder)
    old = time.time() - 3600  # settled: a file changed in the last seconds is not kept
    for p in [*(tmp_path / folder).iterdir(), tmp_path / folder]:
        os.utime(p, (old, old))
    monkeypatch.setenv("CATC_CACHE", str(tmp_path / "cache"))
    args = [words[0], str(tmp_path / words[1]), "--json"]
    code, first = loaded(*args)  # a miss: parsed and checked, then kept
    assert code == 0 and "catgrammar.parser" in first
    code, names = loaded(*args)
    assert code == 0 and never(names, HIT_NEVER) == []
    if words[0] == "solve":
        own = [n for n in names if n.split(".")[0] in ("catc", "catgrammar")]
        assert [n for n in own if not within(n, SOLVE_ALLOWED)] == []
    assert "z3" in names
