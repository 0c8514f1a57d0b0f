"""`catc export pddl`, checked by tools we did not write.

* every example exports (real θ on a grid) and the files parse with PyPI ``pddl-plus-parser``
  package and with unified-planning's ``PDDLReader``;
* ENHSP (the ``up-enhsp`` jar) solves them; its plan, read back through the ground action
  names, is accepted by catc's independent validator with sequential semantics;
* agreement: ENHSP and ``catc solve --sequential`` give the same SAT/UNSAT answer on every
  example, except the one whose only solution needs a fresh (reserve) value, which the export
  report announces;
* refusals (a real θ without grid step or bounds) exit 2 with a clear message; the report
  lists holes, soft constraints, views, reserve values, the grid and parallel-step semantics.

The parser/planner tests skip, naming what to install, when the ``baselines`` extra or Java
is missing.
"""

from __future__ import annotations

import sys
import tomllib
from fractions import Fraction
from pathlib import Path

import pytest
from click.testing import CliRunner
from conftest import run_catc

from catc.frontend.workspace import load_instance
from catc.interfaces.cli import main
from catc.ir.views import apply_view
from catc.queries.solve import SolveStatus, solve
from catc.semantics.horizon import default_horizon
from catc.semantics.validate import validate
from catc.targets.pddl import RESERVED, ExportError, export_pddl
from catgrammar.diagnostics import Diagnostics

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = ROOT / "examples"

#: Grid steps for the real θ of the examples (by parameter name).  1.93 puts navigation's
#: witness 9.65 m = 5 × 1.93 on the grid.
GRID = {
    "ram-req": Fraction(1, 2),
    "m": Fraction(1, 4),
    "d": Fraction("1.93"),
    "mem": Fraction(1, 2),
    "distance": Fraction(25),
}

#: Cases where ENHSP's answer differs from catc's for a reason the export report names.
EXPECTED_DIFFERENCE = {
    "semantics/reserve.cat:fresh-topic": "reserve values",  # the only topic is a fresh value
}


#: Examples whose ENHSP/catc comparison takes tens of seconds on a loaded machine: run in the
#: slow group (.ci/run), not the default suite.
SLOW_FOLDERS = {"search-and-rescue", "navigation"}


def cases(mark_slow: bool = False):
    for expect in sorted(EXAMPLES.glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            marks = [pytest.mark.slow] if mark_slow and expect.parent.name in SLOW_FOLDERS else []
            yield pytest.param(
                expect.parent, case, id=f"{expect.parent.name}/{case['file']}:{case.get('problem', '')}", marks=marks
            )


def instance(folder: Path, case: dict):
    diags = Diagnostics()
    _, inst = load_instance(None, str(folder / case["file"]), diags, problem_name=case.get("problem"))
    assert inst is not None, [d.message for d in diags]
    return apply_view(inst, None)


def _pddl_missing() -> str | None:
    try:
        import pddl_plus_parser  # noqa: F401
        import unified_planning  # noqa: F401
    except ImportError as exc:
        return f"{exc.name} is not installed: pip install 'catc-lang[baselines]'"
    return None


def _enhsp_missing() -> str | None:
    from catc.targets.enhsp import available

    return available()


#: A coarser grid for the parser tests (unified-planning's reader takes ~14 s on 500 actions).
PARSE_GRID = {
    "ram-req": Fraction(1, 2),
    "m": Fraction(1, 2),
    "d": Fraction(25),
    "mem": Fraction(1),
    "distance": Fraction(50),
}

needs_parsers = pytest.mark.skipif(_pddl_missing() is not None, reason=str(_pddl_missing()))
needs_enhsp = pytest.mark.skipif(_enhsp_missing() is not None, reason=str(_enhsp_missing()))


def _write(ex, tmp_path: Path) -> tuple[Path, Path]:
    dom, prob = tmp_path / "domain.pddl", tmp_path / "problem.pddl"
    dom.write_text(ex.domain)
    prob.write_text(ex.problem)
    return dom, prob


# ---------------------------------------------------------------- parsing


@needs_parsers
@pytest.mark.parametrize("folder, case", list(cases()))
def test_export_parses_with_pddl_plus_parser_and_unified_planning(folder, case, tmp_path):
    from pddl_plus_parser.lisp_parsers import DomainParser, ProblemParser
    from unified_planning.io import PDDLReader

    ex = export_pddl(instance(folder, case), grid=PARSE_GRID)
    dom, prob = _write(ex, tmp_path)
    d = DomainParser(dom).parse_domain()
    p = ProblemParser(prob, d).parse_problem()
    assert len(d.actions) == len(ex.actions)
    assert p.domain.name == d.name
    up = PDDLReader().parse_problem(str(dom), str(prob))
    assert len(up.actions) == len(ex.actions)
    for name in ex.actions:  # names ENHSP accepts
        assert name.startswith("a-") and name not in RESERVED


# ---------------------------------------------------------------- ENHSP


@needs_enhsp
@pytest.mark.parametrize("folder, case", list(cases(mark_slow=True)))
def test_enhsp_agrees_with_catc_and_its_plans_validate(folder, case, tmp_path, request):
    from catc.targets.enhsp import run_enhsp

    inst = instance(folder, case)
    ex = export_pddl(inst, grid=GRID)
    dom, prob = _write(ex, tmp_path)
    res = run_enhsp(dom, prob, timeout=120)
    assert res.status in ("sat", "unsat"), res.output[-2000:]
    key = request.node.callspec.id
    if res.status == "sat":
        plan = ex.plan_from_actions(res.actions)
        report = validate(inst, plan, horizon=len(plan), sequential=True)
        assert report.ok, [str(v) for v in report.violations]
        # catc finds a sequential composition too (at ENHSP's length if the default horizon,
        # which counts parallel steps, is too short)
        catc = solve(inst, sequential=True)
        if catc.status is not SolveStatus.SAT:
            assert len(plan) > default_horizon(inst)
            assert solve(inst, horizon=len(plan), sequential=True).status is SolveStatus.SAT
    else:
        catc = solve(inst, sequential=True)
        if key in EXPECTED_DIFFERENCE:
            assert catc.status is SolveStatus.SAT
            assert any(c == EXPECTED_DIFFERENCE[key] for c, _ in ex.report.items)
        else:
            assert catc.status is SolveStatus.UNSAT


# ---------------------------------------------------------------- CLI, refusals, report


def test_cli_writes_files_and_report(tmp_path):
    r = CliRunner().invoke(
        main,
        [
            "export",
            "pddl",
            str(EXAMPLES / "detection/person.cat"),
            "-o",
            str(tmp_path),
            "--grid",
            "camera-driver.ram-req=0.5",
            "--no-check",
        ],
    )
    assert r.exit_code == 0, r.output
    for f in ("domain.pddl", "problem.pddl", "report.md", "actions.json"):
        assert (tmp_path / f).is_file()
    report = (tmp_path / "report.md").read_text()
    assert "camera-driver.ram-req" in report and "step 0.5" in report
    assert "sequential" in report and "reserve" in report
    assert "a-camera-driver-image-raw-0p5" in (tmp_path / "domain.pddl").read_text()


def test_real_parameter_without_grid_is_refused(tmp_path):
    r = CliRunner().invoke(main, ["export", "pddl", str(EXAMPLES / "detection/person.cat"), "-o", str(tmp_path)])
    assert r.exit_code == 2
    assert "--grid camera-driver.ram-req=STEP" in r.output


def test_real_parameter_without_bounds_is_refused(tmp_path):
    src = tmp_path / "p.cat"
    src.write_text("""(define (domain d) (:requirements :numeric :free-parameters)
  (:resources (x real))
  (:morphism go :parameters ((v real :bounds (0 *))) :effect (increase x v)))
(define (problem p) (:domain d) (:init (= x 0)) (:goal (>= x 1)))
""")
    r = CliRunner().invoke(main, ["export", "pddl", str(src), "-o", str(tmp_path / "out"), "--grid", "v=1"])
    assert r.exit_code == 2
    assert "no finite bounds" in r.output
    with pytest.raises(ExportError):
        export_pddl(instance(tmp_path, {"file": "p.cat"}), grid={"v": Fraction(1)})


def test_bad_grid_spec_is_a_usage_error(tmp_path):
    r = CliRunner().invoke(
        main, ["export", "pddl", str(EXAMPLES / "detection/person.cat"), "-o", str(tmp_path), "--grid", "oops"]
    )
    assert r.exit_code == 2 and "PARAM=STEP" in r.output


def test_report_lists_holes_softs_views_and_maximize():
    holes = export_pddl(instance(EXAMPLES / "holes", {"file": "talk.cat"}))
    assert any(c == "holes" for c, _ in holes.report.items)
    soft = export_pddl(instance(EXAMPLES / "semantics", {"file": "soft.cat", "problem": "fastest"}), grid=GRID)
    assert any(c == "soft constraints" for c, _ in soft.report.items) or any(
        c == "objective" for c, _ in soft.report.items
    )
    view = export_pddl(instance(EXAMPLES / "semantics", {"file": "view.cat", "problem": "shop-software"}))
    assert any(c == "views" for c, _ in view.report.items)
    far = export_pddl(instance(EXAMPLES / "navigation", {"file": "farthest.cat"}), grid=GRID)
    assert "maximize" not in far.problem
    assert any(c == "objective" and "maximisation" in t for c, t in far.report.items)


def test_horizon_bounds_the_number_of_actions():
    inst = instance(EXAMPLES / "semantics", {"file": "parallel.cat", "problem": "both-sensors"})
    ex = export_pddl(inst, horizon=1)
    assert "(< (catc-steps) 1)" in ex.domain and "(= (catc-steps) 0)" in ex.problem


def test_missing_baselines_name_what_to_install(monkeypatch, tmp_path):
    from catc.targets import enhsp
    from catc.targets.pddl_target import MissingParser, check_pddl

    monkeypatch.setattr(enhsp.shutil, "which", lambda _: None)
    with pytest.raises(enhsp.BaselineMissing, match="Java 17"):
        enhsp.run_enhsp(tmp_path / "d.pddl", tmp_path / "p.pddl")
    monkeypatch.setitem(sys.modules, "up_enhsp", None)
    with pytest.raises(enhsp.BaselineMissing, match=r"catc-lang\[baselines\]"):
        enhsp.enhsp_jar()
    monkeypatch.setitem(sys.modules, "pddl_plus_parser.lisp_parsers", None)
    with pytest.raises(MissingParser, match=r"pip install 'catc-lang\[baselines\]'"):
        check_pddl(tmp_path / "d.pddl", tmp_path / "p.pddl")
    monkeypatch.delitem(sys.modules, "pddl_plus_parser.lisp_parsers")
    monkeypatch.setitem(sys.modules, "unified_planning.io", None)
    _write(export_pddl(instance(EXAMPLES / "detection", {"file": "person.cat"}), grid=GRID), tmp_path)
    with pytest.raises(MissingParser, match=r"pip install 'catc-lang\[baselines\]'"):
        check_pddl(tmp_path / "domain.pddl", tmp_path / "problem.pddl", strict=True)
    # on the command line: a located error naming the extra, exit 2
    monkeypatch.setitem(sys.modules, "pddl_plus_parser.lisp_parsers", None)
    res = run_catc("export", "pddl", str(EXAMPLES / "lifelong/budget-cut.cat"), "-o", str(tmp_path / "out"))
    assert res.exit_code == 2 and "error[E0706]" in res.stderr and "catc-lang[baselines]" in res.stderr


def _action_block(domain: str, name: str) -> str:
    start = domain.index(f"(:action {name}\n")
    end = domain.find("(:action ", start + 1)
    return domain[start : end if end != -1 else len(domain)]


def test_maximising_a_resource_that_only_decreases_is_minimising_what_is_taken(tmp_path):
    """Event II maximises range-to-base, which only `return-to-range` changes, by
    (decrease range-to-base d), d ∈ [0, 500]: each ground action costs its d, every other
    action costs nothing, and minimising the total cost maximises the final distance."""
    inst = instance(EXAMPLES / "search-and-rescue", {"file": "event2-out-of-range.cat"})
    ex = export_pddl(inst, grid={"d": Fraction(1), "mem": Fraction(1, 2), "ram-req": Fraction(1, 4)})
    assert "(:metric minimize (total-cost))" in ex.problem and "(= (total-cost) 0)" in ex.problem
    assert "(increase (total-cost) 4)" in _action_block(ex.domain, "a-return-to-range-4")
    assert "total-cost" not in _action_block(ex.domain, "a-report")
    assert any(c == "objective" and "range-to-base only decreases" in t for c, t in ex.report.items)


def test_maximising_a_resource_that_may_rise_is_not_exported(tmp_path):
    text = (EXAMPLES / "search-and-rescue" / "domain.cat").read_text()
    # let return-to-range move by a signed amount: d ∈ [-5, 500] may raise range-to-base
    assert "(d real :unit m :bounds (0 500))" in text
    (tmp_path / "domain.cat").write_text(
        text.replace("(d real :unit m :bounds (0 500))", "(d real :unit m :bounds (-5 500))")
    )
    (tmp_path / "p.cat").write_text((EXAMPLES / "search-and-rescue" / "event2-out-of-range.cat").read_text())
    diags = Diagnostics()
    _, inst = load_instance(None, str(tmp_path / "p.cat"), diags)
    assert inst is not None, [d.message for d in diags]
    ex = export_pddl(apply_view(inst, None), grid={"d": Fraction(1), "mem": Fraction(1, 2), "ram-req": Fraction(1, 4)})
    assert "(:metric" not in ex.problem and "total-cost" not in ex.domain
    assert any(c == "objective" and "maximisation is not exported" in t for c, t in ex.report.items)


def test_enhsp_output_of_a_missing_file_is_an_error_not_unsat():
    """ENHSP prints "Unsolvable Problem" even after failing to read its input (seen with a
    relative path); that must not be taken for a proof of unsolvability."""
    from catc.targets.enhsp import parse_output

    text = (
        "Domain parsed\nSEVERE: null\njava.io.FileNotFoundException: p.pddl (No such file or directory)\n"
        "Problem Detected as Unsolvable by AIBR during preprocessing\nUnsolvable Problem\n"
    )
    assert parse_output(text).status == "error"
    assert (
        parse_output("Problem Detected as Unsolvable by AIBR during preprocessing\nUnsolvable Problem\n").status
        == "unsat"
    )


@needs_enhsp
def test_run_accepts_relative_paths(tmp_path, monkeypatch):
    from catc.targets.enhsp import run_enhsp

    ex = export_pddl(instance(EXAMPLES / "detection", {"file": "person.cat"}), grid=GRID)
    (tmp_path / "d.pddl").write_text(ex.domain)
    (tmp_path / "p.pddl").write_text(ex.problem)
    monkeypatch.chdir(tmp_path)
    assert run_enhsp("d.pddl", "p.pddl").status == "sat"


def test_a_constant_cost_expression_is_folded_into_the_total_cost(tmp_path):
    """(:cost (+ 1 2)) is the constant 3: each activation increases total-cost by 3
    (it crashed the metric check once, exit 70)."""
    (tmp_path / "c.cat").write_text("""(define (domain c)
  (:requirements :numeric :optimization)
  (:resources (done bool))
  (:morphism work :uses 1 :cost (+ 1 2) :effect (assign done true)))
(define (problem p) (:domain c) (:init (= done false)) (:goal done) (:metric minimize (total-cost)))
""")
    res = run_catc("export", "pddl", str(tmp_path / "c.cat"), "-o", str(tmp_path / "out"), "--no-check")
    assert res.exit_code == 0, res.output
    assert "(increase (total-cost) 3)" in _action_block((tmp_path / "out" / "domain.pddl").read_text(), "a-work")


@needs_parsers
def test_the_export_is_checked_without_the_pypi_pddl_package(tmp_path, monkeypatch):
    """PyPI pddl pins lark<1.2 (catc needs lark>=1.2): the default check must not need it."""
    monkeypatch.setitem(sys.modules, "pddl", None)  # as if not installed
    person = str(EXAMPLES / "detection/person.cat")
    res = run_catc("export", "pddl", person, "-o", str(tmp_path), "--grid", "ram-req=1/2")
    assert res.exit_code == 0, res.output
    # detection: 6 ground actions (camera, driver on the 1 topic × 4 ram-req values 0.5, 1, 1.5, 2, detector)
    assert "parsed by pddl-plus-parser (6 actions): ok" in res.stdout
    assert "PDDLReader" not in res.stdout  # the strict reader only when asked (slow on large groundings)
    res = run_catc("export", "pddl", person, "-o", str(tmp_path), "--grid", "ram-req=1/2", "--strict-check")
    assert res.exit_code == 0, res.output
    assert "parsed by pddl-plus-parser (6 actions): ok" in res.stdout
    assert "parsed by unified-planning's PDDLReader (6 actions): ok" in res.stdout


@needs_parsers
def test_a_malformed_export_is_rejected_by_the_strict_parser(tmp_path):
    from catc.targets.pddl_target import check_pddl

    ex = export_pddl(instance(EXAMPLES / "detection", {"file": "person.cat"}), grid=GRID)
    dom, prob = _write(ex, tmp_path)
    dom.write_text(ex.domain.replace("(increase", "(increse", 1).replace("(decrease", "(decrese", 1))
    assert check_pddl(dom, prob)  # the lax default parser reads it
    with pytest.raises(Exception):  # noqa: B017 - the parser's own error type
        check_pddl(dom, prob, strict=True)


TOGGLE = """(define (domain toggle)
  (:resources (a bool) (b bool) (c bool))
  (:morphism flip :precondition (not c) :effect (and (assign b (not b)) (assign c true)))
  (:morphism copy :effect (assign a (and b c))))
(define (problem toggle-p)
  (:domain toggle)
  (:init INIT)
  (:goal GOAL))
"""


@pytest.mark.parametrize(
    ("init", "goal", "answer"),
    [
        # flip turns b from false to true and c true (once: it needs c false); copy then sets a
        ("(not b)", "(and a b c)", "sat"),
        # b starts true: flip makes it false and c true, so b and c are never both true and a
        # (b and c when copy runs) never becomes true
        ("b", "(and a (not b))", "unsat"),
    ],
)
def test_a_state_dependent_bool_assignment_is_a_pair_of_conditional_effects(tmp_path, init, goal, answer):
    """(assign b (not b)) is exported as (when (not (b)) (b)) (when (not (not (b))) (not (b))):
    both read the state before the action, as catc's effects do; ENHSP agrees with catc (and
    with the hand count above)."""
    from catc.api import loads

    text = TOGGLE.replace("INIT", init).replace("GOAL", goal)
    model = loads({f"{tmp_path}/t.cat": text}, f"{tmp_path}/t.cat")
    ex = export_pddl(model.instance)
    flip = _action_block(ex.domain, "a-flip")
    assert "(when (not (b)) (b))" in flip and "(when (not (not (b))) (not (b)))" in flip
    assert ":conditional-effects" in ex.domain and not [t for c, t in ex.report.items if c == "components"]
    assert model.solve(horizon=4, sequential=True).status.value == answer
    if _enhsp_missing() is None:
        from catc.targets.enhsp import run_enhsp

        dom, prob = _write(ex, tmp_path)
        assert run_enhsp(dom, prob, timeout=60).status == answer
