"""catc's grounder (:mod:`catc.frontend.up_ground`) and the import and engine bugs of issue 27:
untyped IPC encodings that crashed UP 1.3's grounder, grounding within the time given, undefined
initial values refused only where a ground action reads them (naming the fluent), and
``OneshotPlanner(name="catc").solve()`` answering with a status, never an exception.

Fixtures under tests/fixtures/pddl/ were written for these tests; their expected answers are
argued by hand in the comments."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from conftest import run_catc
from unified_planning.engines import PlanGenerationResultStatus as Status
from unified_planning.io import PDDLReader
from unified_planning.plans import ActionInstance
from unified_planning.shortcuts import OneshotPlanner, get_environment

from catc.bench import corpus
from catc.frontend import up_ground
from catc.frontend.up_import import UpImportError, UpImportStopped, up_to_instance
from catc.interfaces import up_engine
from catc.queries.solve import SolveResult, SolveStatus, solve

PDDL = Path(__file__).parent / "fixtures" / "pddl"
FERRY = PDDL / "ferry-untyped"
UNDEF = PDDL / "undefined-unread"


def _pddl(ai) -> str:
    return f"({ai.action.name} {' '.join(map(str, ai.actual_parameters))})"


def _read(domain: Path, problem: Path):
    get_environment().credits_stream = None
    return PDDLReader().parse_problem(str(domain), str(problem))


@pytest.fixture(scope="module")
def catc_engine():
    env = get_environment()
    env.credits_stream = None
    up_engine.register(env)
    return env


def test_untyped_ferry_imports_where_ups_grounder_removed_an_object_twice(tmp_path):
    """sail(?from ?to) needs (place ?from) (place ?to) (not-eq ?from ?to): a car fails two
    static preconditions of one parameter, which made UP 1.3's ``_purge_items_list`` call
    ``list.remove`` twice (exit 70). By hand, the ground actions are: sail l0→l1, l1→l0 (2),
    board and debark of 2 cars at 2 places (8): 10."""
    r = run_catc("import", "pddl", str(FERRY / "domain.pddl"), str(FERRY / "problem.pddl"), "-o", str(tmp_path))
    assert r.exit_code == 0, r.stderr
    assert "10 morphisms" in r.stdout
    _, report = up_to_instance(_read(FERRY / "domain.pddl", FERRY / "problem.pddl"))
    assert sorted(str(a) for a in report.actions.values()) == sorted(
        [f"sail({a}, {b})" for a, b in (("l0", "l1"), ("l1", "l0"))]
        + [f"{verb}({c}, {loc})" for verb in ("board", "debark") for c in ("c0", "c1") for loc in ("l0", "l1")]
    )


def test_untyped_ferry_shortest_plan_is_the_hand_count_and_ups_validator_accepts_it():
    """Two cars from l0 to l1 with a one-car ferry: board, sail, debark, sail back, board,
    sail, debark — 7 actions; 6 cannot do (each car needs its board, debark and a crossing
    with it, and the ferry must come back between the two crossings)."""
    problem = _read(FERRY / "domain.pddl", FERRY / "problem.pddl")
    inst, report = up_to_instance(problem)
    r = solve(inst, horizon=10, sequential=True)
    assert r.status is SolveStatus.SAT and r.plan is not None
    steps = [_pddl(report.actions[a.morphism]) for s in r.plan.steps for a in s]
    assert len(steps) == 7
    assert corpus.up_validates(problem, steps)


def test_the_grounder_tests_static_preconditions_before_instantiating():
    """drive(?t ?a ?b) of the fuel-trucks fixture: (usable ?t) holds of t1 only and (road ?a ?b)
    of (p,q), (q,r): 1 × 2 = 2 tuples, of 2 × 3 × 3 = 18 in the product."""
    problem = _read(UNDEF / "domain.pddl", UNDEF / "problem.pddl")
    g = up_ground.ground(problem)
    assert g.candidates == 2 and g.actions == 2
    assert sorted(str(a.name) for a in g.problem.actions) == ["drive_t1_p_q", "drive_t1_q_r"]


def test_an_undefined_value_that_no_ground_action_reads_is_not_refused(tmp_path):
    """fuel(t2) is undefined, but t2 is not usable, so no ground action reads it: the import
    goes on (refused by catc before), and the plan drives t1 p→q→r (2 actions)."""
    r = run_catc("import", "pddl", str(UNDEF / "domain.pddl"), str(UNDEF / "problem.pddl"), "-o", str(tmp_path))
    assert r.exit_code == 0, r.stderr
    inst, _ = up_to_instance(_read(UNDEF / "domain.pddl", UNDEF / "problem.pddl"))
    res = solve(inst, horizon=4, sequential=True)
    assert res.status is SolveStatus.SAT and res.plan is not None and len(res.plan.steps) == 2


def test_an_undefined_value_a_ground_action_reads_is_refused_naming_the_fluent(tmp_path):
    """With t2 usable, drive(t2, p, q) reads fuel(t2), which has no value: E1201 names it, in
    the message and in import-report.md."""
    problem = UNDEF / "problem-read.pddl"
    r = run_catc("import", "pddl", str(UNDEF / "domain.pddl"), str(problem), "-o", str(tmp_path))
    assert r.exit_code == 2
    assert "error[E1201]" in r.stderr and "fuel(t2)" in r.stderr
    assert "fuel(t2) has no initial value" in (tmp_path / "import-report.md").read_text()
    with pytest.raises(UpImportError) as info:
        up_to_instance(_read(UNDEF / "domain.pddl", problem))
    assert any("fuel(t2)" in why for _, why in info.value.report.refused)


def test_grounding_stops_when_the_time_given_has_passed():
    with pytest.raises(UpImportStopped):
        up_to_instance(_read(FERRY / "domain.pddl", FERRY / "problem.pddl"), timeout=0)


def test_the_engine_solves_the_untyped_ferry(catc_engine):
    problem = _read(FERRY / "domain.pddl", FERRY / "problem.pddl")
    with OneshotPlanner(name="catc") as planner:
        res = planner.solve(problem)
    assert res.status is Status.SOLVED_SATISFICING
    assert len(res.plan.actions) == 7


def test_grounding_out_of_time_is_timeout(catc_engine, monkeypatch):
    def stopped(problem, **kw):
        raise UpImportStopped("the time ran out while grounding")

    monkeypatch.setattr(up_engine, "up_to_instance", stopped)
    with OneshotPlanner(name="catc") as planner:
        res = planner.solve(_read(FERRY / "domain.pddl", FERRY / "problem.pddl"), timeout=5)
    assert res.status is Status.TIMEOUT


def test_no_exception_escapes_solve(catc_engine, monkeypatch):
    def broken(problem, **kw):
        raise ValueError("list.remove(x): x not in list")

    monkeypatch.setattr(up_engine, "up_to_instance", broken)
    with OneshotPlanner(name="catc") as planner:
        res = planner.solve(_read(FERRY / "domain.pddl", FERRY / "problem.pddl"))
    assert res.status is Status.INTERNAL_ERROR
    assert any("list.remove" in m.message for m in res.log_messages)


@pytest.mark.parametrize("reason", ["canceled", "timeout", "interrupted"])
def test_every_stop_by_the_clock_is_timeout(reason):
    """Z3 calls its own timer "canceled"; catc's queries say "timeout": both are TIMEOUT, not
    UNSOLVABLE_INCOMPLETELY."""
    problem = _read(FERRY / "domain.pddl", FERRY / "problem.pddl")
    run = up_engine._Run(up_engine.CatcEngine(), problem, None)
    run.inst, run.report = up_to_instance(problem)
    res = run._no_plan(SolveResult(SolveStatus.UNKNOWN, 5, reason=reason))
    assert res.status is Status.TIMEOUT


def test_an_undecided_answer_that_is_not_the_clock_stays_incomplete():
    problem = _read(FERRY / "domain.pddl", FERRY / "problem.pddl")
    run = up_engine._Run(up_engine.CatcEngine(), problem, None)
    run.inst, run.report = up_to_instance(problem)
    res = run._no_plan(SolveResult(SolveStatus.UNKNOWN, 5, reason="(incomplete quantifiers)"))
    assert res.status is Status.UNSOLVABLE_INCOMPLETELY


@pytest.mark.parametrize("folder", ["counters", "depot", "miconic", "sailing", "tpp_metric", "safe_road"])
def test_the_same_ground_actions_as_ups_grounder(folder):
    """Where UP 1.3's grounder does not crash, catc's grounder keeps exactly its ground actions
    (UP's grounder is the oracle: it instantiates every tuple and simplifies each)."""
    from unified_planning.engines import CompilationKind
    from unified_planning.engines.compilers import Grounder, QuantifiersRemover

    wheel = corpus.wheel_dir()
    assert wheel is not None
    problem = _read(wheel / folder / "domain.pddl", wheel / folder / "problem.pddl")
    lifted = problem
    ours = up_ground.ground(lifted)
    base = lifted
    k = lifted.kind
    if k.has_existential_conditions() or k.has_universal_conditions() or k.has_forall_effects():
        base = QuantifiersRemover()._compile(lifted, CompilationKind.QUANTIFIERS_REMOVING).problem
    theirs = Grounder()._compile(base, CompilationKind.GROUNDING)
    names = sorted(str(ours.back(ActionInstance(a))) for a in ours.problem.actions)
    expected = sorted(str(theirs.map_back_action_instance(ActionInstance(a))) for a in theirs.problem.actions)
    assert names == expected


def test_import_pddl_stops_grounding_at_its_timeout(tmp_path):
    """A timeout of a nanosecond has passed by the grounder's first look at the clock (which
    follows the PDDL reading): exit 3, E1109, nothing written but the folder."""
    r = run_catc(
        "import",
        "pddl",
        str(FERRY / "domain.pddl"),
        str(FERRY / "problem.pddl"),
        "-o",
        str(tmp_path),
        "--timeout",
        "1e-9",
    )
    assert r.exit_code == 3
    assert "error[E1109]" in r.stderr and "grounding" in r.stderr
    assert not (tmp_path / "domain.cat").exists()
