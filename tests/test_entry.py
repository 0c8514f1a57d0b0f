"""The ``catc`` executable's click-free route for plain query command lines
(catc.interfaces.entry): it reads arguments exactly as click does or leaves them to click, and the
command then behaves the same whichever route it took."""

from __future__ import annotations

import json
import subprocess
import sys
import tomllib

import click
import pytest
from conftest import ROOT, run_catc
from hypothesis import given, settings
from hypothesis import strategies as st

from catc.interfaces import cli, command
from catc.interfaces.entry import parse_query
from catc.queries import registry
from catc.queries.base import Kind

EXAMPLES = ROOT / "examples"
SOLVE = registry.get("solve")


def click_params(args: list[str], name: str = "solve") -> dict | None:
    """What click passes to the query command for ``args`` (None: click rejects them), with
    --minimize/--maximize folded into the query's ``objectives`` option as the command does."""
    query = registry.get(name)
    try:
        with cli.query_command(query).make_context(name, list(args)) as ctx:
            params = dict(ctx.params)
            raw = cli.raw_values(query, params, ctx)
    except (click.ClickException, click.exceptions.Exit):
        return None
    return {"paths": params["paths"], **raw}


def parse_solve(args: list[str]) -> dict | None:
    return parse_query(SOLVE, args)


@pytest.mark.parametrize("name", registry.names())
def test_defaults_are_clicks(name):
    query = registry.get(name)
    if any(o.kind is Kind.PLAN_FILE for o in query.options):
        assert parse_query(query, ["p.cat"]) is None  # no plan file: click's usage error
        for args in (["p.cat", "plan.json"], ["d.cat", "p.cat", "plan.json"]):
            assert parse_query(query, args) == click_params(args, name) is not None
        assert parse_query(query, ["p.cat", "tests"]) is None  # a folder: click's error
        return
    assert parse_query(query, ["p.cat"]) == click_params(["p.cat"], name)


PLAIN = [
    ["p.cat"],
    ["d.cat", "p.cat"],
    ["p.cat", "--json"],
    ["--json", "d.cat", "p.cat", "--sequential", "--no-prune"],
    ["-k", "3", "p.cat"],
    ["-k3", "p.cat"],
    ["--horizon=12", "p.cat", "--horizon", "4"],  # the last one counts, as in click
    ["p.cat", "--timeout", "2.5", "--strategy", "single"],
    ["p.cat", "--timeout=10", "--view", "sim", "--problem", "detect-person"],
    ["p.cat", "--horizon", "007"],
    [""],  # an empty path: click passes it on (and the command reports it unreadable)
]


@pytest.mark.parametrize("args", PLAIN, ids=" ".join)
def test_plain_command_lines_are_read_as_click_reads_them(args):
    params = parse_solve(args)
    assert params is not None
    assert params == click_params(args)


LEFT_TO_CLICK = [
    [],
    ["a.cat", "b.cat", "c.cat"],  # click's usage error, from the command
    ["--help"],
    ["-h", "p.cat"],
    ["p.cat", "--path", "lib"],
    ["p.cat", "--diagram", "out.svg"],
    ["--", "p.cat"],
    ["-", "p.cat"],
    ["p.cat", "-k", "-1"],
    ["p.cat", "-k"],
    ["p.cat", "-k=3"],
    ["p.cat", "--horizon="],
    ["p.cat", "--horizon", "3.0"],
    ["p.cat", "--horizon", "٣"],
    ["p.cat", "--horizon", " 3"],
    ["p.cat", "--timeout", "0"],
    ["p.cat", "--timeout", "nan"],
    ["p.cat", "--timeout", "1e3"],
    ["p.cat", "--timeout", "-1"],
    ["p.cat", "--timeout", ".5"],
    ["p.cat", "--timeout", "5."],
    ["p.cat", "--view", "--json"],
    ["p.cat", "--view", ""],
    ["p.cat", "--view"],
    ["p.cat", "--strategy", "Single"],
    ["p.cat", "--json=1"],
    ["p.cat", "--jso"],
    ["p.cat", "-x"],
    ["p.cat", "--version"],
]


@pytest.mark.parametrize("args", LEFT_TO_CLICK, ids=lambda a: " ".join(a) or "(none)")
def test_other_command_lines_are_left_to_click(args):
    assert parse_solve(args) is None


FLAGS = {flag for name in registry.names() for o in registry.get(name).options for flag in o.flags if flag[0] == "-"}
WORDS = sorted({*FLAGS, "--help", "-h", "--", "-", "-x", "--jso", "--version"}) + [
    "p.cat",
    "d.cat",
    "",
    "0",
    "3",
    "-1",
    "07",
    "2.5",
    "0.0",
    "nan",
    "inf",
    "1e3",
    ".5",
    "x",
    "sim",
    "single",
    "incremental",
    "Single",
    "-k3",
    "-k=3",
    "--horizon=2",
    "--horizon=",
    "--json=1",
    "--timeout=0.5",
    "--view=",
    "--strategy=single",
    "lib",
    "out.svg",
    "٣",
    " 3",
    "none",
    "a,b",
    "budget=2",
    "budget=x",
    "stability",
    "objective",
    "cat",
    "init/",
]


@settings(max_examples=600, deadline=None)
@given(st.sampled_from(registry.names()), st.lists(st.sampled_from(WORDS), max_size=7))
def test_whatever_is_read_here_click_reads_the_same(name, args):
    params = parse_query(registry.get(name), args)
    if params is not None:
        assert params == click_params(args, name)


# ---------------------------------------------------------------- the same command either way


def solve_cases():
    for expect in sorted(EXAMPLES.glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            args = [str(expect.parent / case["file"])] + (["--problem", case["problem"]] if "problem" in case else [])
            yield pytest.param(args, id=f"{expect.parent.name}/{case['file']}:{case.get('problem', '')}")


def without_timings(text: str) -> str:
    return "\n".join(line for line in text.splitlines() if not line.startswith("time: "))


@pytest.mark.parametrize("args", list(solve_cases()))
def test_both_routes_answer_every_example_alike(args):
    assert parse_solve(args) is not None and parse_solve(args + ["--json"]) is not None
    fast, slow = run_catc("solve", *args), run_catc("solve", *args, via_click=True)
    assert fast.exit_code == slow.exit_code and fast.exit_code in (0, 1)
    assert without_timings(fast.stdout) == without_timings(slow.stdout) and fast.stderr == slow.stderr
    fast, slow = run_catc("solve", *args, "--json"), run_catc("solve", *args, "--json", via_click=True)
    docs = [json.loads(r.stdout) for r in (fast, slow)]
    for doc in docs:
        doc.pop("timings")
    assert fast.exit_code == slow.exit_code and docs[0] == docs[1]


@pytest.mark.parametrize(
    "args",
    [
        ["missing.cat"],
        ["missing.cat", "--json"],
        [str(ROOT / "tests/fixtures/invalid/names.cat")],
        [str(EXAMPLES / "detection/person.cat"), "--view", "no-such-view"],
        [str(EXAMPLES / "detection/person.cat"), "--problem", "no-such-problem", "--json"],
        [str(EXAMPLES / "navigation/precise.cat"), "--sequential", "-k", "0"],
    ],
    ids=" ".join,
)
def test_both_routes_report_bad_input_alike(args):
    assert parse_solve(args) is not None
    fast, slow = run_catc("solve", *args), run_catc("solve", *args, via_click=True)
    assert (fast.exit_code, without_timings(fast.stdout), fast.stderr) == (
        slow.exit_code,
        without_timings(slow.stdout),
        slow.stderr,
    )


def test_interrupt_and_internal_errors_are_reported_as_click_does(monkeypatch):
    person = str(EXAMPLES / "detection/person.cat")

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    def broken(*args, **kwargs):
        raise ValueError("a bug")

    monkeypatch.setattr(command, "run_query", interrupted)
    for via_click in (False, True):
        res = run_catc("solve", person, via_click=via_click)
        assert res.exit_code == 130 and res.stderr == "catc: interrupted\n"  # not "Aborted!", exit 1 (UNSAT's)
    monkeypatch.setattr(command, "run_query", broken)
    for via_click in (False, True):
        res = run_catc("solve", person, via_click=via_click)
        assert res.exit_code == 70
        assert res.stderr == "catc: internal error: ValueError: a bug (set CATC_DEBUG=1 for details)\n"


@pytest.mark.parametrize(
    ("query", "example", "status"),
    [
        ("solve", "detection/person.cat", "sat"),
        ("optimize", "gpu-allocation/max-confidence.cat", "opt"),
        ("relax", "lifelong/budget-cut.cat", "relaxed"),
        ("recompose", "lifelong/cheaper-camera.cat", "opt"),
        ("pareto", "pareto-design/design.cat", "front"),
    ],
)
def test_a_plain_solve_or_optimize_imports_neither_click_nor_dataclasses(query, example, status):
    """Nor pint: the examples' units are all in the generated index (catc.frontend.units)."""
    probe = (
        "import sys\n"
        "from catc.interfaces.entry import main\n"
        "try:\n"
        f"    main(['{query}', 'examples/{example}', '--json'])\n"
        "except SystemExit as exc:\n"
        "    code = exc.code\n"
        "heavy = sorted(m for m in sys.modules\n"
        "               if m.split('.')[0] in ('click', 'dataclasses', 'inspect', 'rich', 'pint'))\n"
        "print(code, heavy, file=sys.stderr)\n"
    )
    proc = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert json.loads(proc.stdout)["status"] == status
    assert proc.stderr.strip() == "0 []"
