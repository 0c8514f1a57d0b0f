"""catc as a unified-planning engine, on problems nobody here wrote (UP's own examples).

Every plan catc returns is checked by UP's own sequential plan validator; answers are checked
against what the examples record (they are all solvable, some carry their optimum), and the
shortest plans against a breadth-first search over UP's own sequential simulator. Unsolvable
problems are small hand-made ones whose answer is argued in their docstrings.
"""

from __future__ import annotations

import sys
from collections import deque
from fractions import Fraction

import pytest

up = pytest.importorskip("unified_planning")

from unified_planning.engines import PlanGenerationResultStatus as Status  # noqa: E402
from unified_planning.engines import ValidationResultStatus  # noqa: E402
from unified_planning.shortcuts import (  # noqa: E402
    And,
    BoolType,
    Equals,
    Fluent,
    InstantaneousAction,
    IntType,
    Not,
    Object,
    OneshotPlanner,
    PlanValidator,
    Problem,
    SequentialSimulator,
    UserType,
    get_environment,
)
from unified_planning.test.examples import get_example_problems  # noqa: E402

from catc.frontend.up_import import UpImportError, UpMissing, plan_to_up, up_to_instance  # noqa: E402
from catc.interfaces.up_engine import CatcEngine  # noqa: E402
from catc.queries.solve import solve  # noqa: E402
from catgrammar import codes  # noqa: E402

PER_PROBLEM = 30.0  # seconds; a problem that runs out counts as TIMEOUT (none does today)
TEMPORAL = ("CONTINUOUS_TIME", "DISCRETE_TIME")  # the "non-temporal": neither


@pytest.fixture(scope="module")
def catc_engine():
    env = get_environment()
    env.credits_stream = None
    if "catc" not in env.factory.engines:
        env.factory.add_engine("catc", "catc.interfaces.up_engine", "CatcEngine")
    return env


@pytest.fixture(scope="module")
def examples():
    return get_example_problems()


def _valid(problem, plan):
    with PlanValidator(name="sequential_plan_validator") as v:
        res = v.validate(problem, plan)
    return res


def _run_examples(examples):
    counts = {"solved": 0, "optimal": 0, "refused": 0, "timeout": 0, "failed": 0}
    failures = []
    for name, ex in examples.items():
        p = ex.problem
        with OneshotPlanner(name="catc") as planner:
            if not planner.supports(p.kind):
                with pytest.raises(UpImportError):  # refused by kind, with its reasons
                    up_to_instance(p)
                counts["refused"] += 1
                continue
            try:
                r = planner.solve(p, timeout=PER_PROBLEM)
            except Exception as exc:  # a crash is a failure, reported with the others
                failures.append(f"{name}: crashed: {exc!r}")
                continue
        if r.status is Status.TIMEOUT:
            counts["timeout"] += 1
            continue
        if r.status not in (Status.SOLVED_SATISFICING, Status.SOLVED_OPTIMALLY):
            failures.append(f"{name}: {r.status.name}, but the example records a valid plan")
            continue
        v = _valid(p, r.plan)
        if v.status is not ValidationResultStatus.VALID:
            failures.append(f"{name}: UP's validator rejects catc's plan {r.plan}: {v.reason}")
            continue
        counts["solved"] += 1
        failures += _optimum_agrees(name, ex, r, v)
        if r.status is Status.SOLVED_OPTIMALLY:
            counts["optimal"] += 1
    counts["failed"] = len(failures)
    return counts, failures


def _optimum_agrees(name, ex, r, v):
    """The value UP's validator computes for catc's plan against the example's optimum."""
    if ex.optimum is None or not v.metric_evaluations:
        return []
    (metric, value), *_ = v.metric_evaluations.items()
    value, optimum = Fraction(str(value)), Fraction(str(ex.optimum))
    maximise = metric.is_maximize() if hasattr(metric, "is_maximize") else False
    if r.status is Status.SOLVED_OPTIMALLY and value != optimum:
        return [f"{name}: catc claims optimal {value}, the example's optimum is {optimum}"]
    better = value > optimum if maximise else value < optimum
    if better:
        return [f"{name}: catc's plan scores {value}, better than the example's optimum {optimum}"]
    return []


def test_every_example_is_solved_and_validated_or_refused_by_kind(catc_engine, examples):
    counts, failures = _run_examples(examples)
    assert failures == []
    non_temporal = [e for e in examples.values() if not any(f in e.problem.kind.features for f in TEMPORAL)]
    # the counts of docs/interop.md: 66 examples, 47 non-temporal; 41 solved (3 proven optimal), 25 refused
    assert len(examples) == 66 and len(non_temporal) == 47
    assert counts == {"solved": 41, "optimal": 3, "refused": 25, "timeout": 0, "failed": 0}


def test_optimal_costs_match_the_examples(catc_engine, examples):
    """UP records the optimum of four examples (action costs, oversubscription gains)."""
    for name in ("basic_with_costs", "locations_connected_cost_minimize", "basic_oversubscription"):
        ex = examples[name]
        with OneshotPlanner(name="catc") as planner:
            r = planner.solve(ex.problem, timeout=PER_PROBLEM)
        assert r.status is Status.SOLVED_OPTIMALLY, name
        (value,) = _valid(ex.problem, r.plan).metric_evaluations.values()
        assert Fraction(str(value)) == Fraction(str(ex.optimum)), name


def _bfs_length(problem, most_nodes=20_000):
    """The length of a shortest plan by breadth-first search over UP's own simulator (None
    when the search passes ``most_nodes`` states)."""
    with SequentialSimulator(problem=problem) as sim:
        start = sim.get_initial_state()
        if sim.is_goal(start):
            return 0
        seen, queue = {start}, deque([(start, 0)])
        while queue:
            state, depth = queue.popleft()
            for action, params in sim.get_applicable_actions(state):
                nxt = sim.apply(state, action, params)
                if nxt is None or nxt in seen:
                    continue
                if sim.is_goal(nxt):
                    return depth + 1
                seen.add(nxt)
                if len(seen) > most_nodes:
                    return None
                queue.append((nxt, depth + 1))
    return None


def test_catc_plans_are_as_short_as_breadth_first_search(examples):
    """catc deepens one step at a time with one action a step: its first plan is a shortest
    one. Checked against BFS where the state space is small enough to search."""
    compared = 0
    for name, ex in examples.items():
        p = ex.problem
        if p.quality_metrics or not CatcEngine.supports(p.kind):
            continue
        try:
            inst, report = up_to_instance(p)
        except UpImportError:
            continue
        shortest = _bfs_length(p)
        if shortest is None:
            continue
        r = solve(inst, horizon=200, sequential=True)
        assert r.plan is not None, name
        assert len(plan_to_up(r.plan, report, p).actions) == shortest, name
        compared += 1
    assert compared == 35  # every supported example without a metric: BFS exhausts each


# ---------------------------------------------------------------- unsolvable, by hand


def _mutex():
    """make_p and make_q each need neither p nor q: at most one of them ever holds, so the
    goal p ∧ q is unreachable; relaxed reachability (deletes ignored) cannot see it, but the
    problem has 4 states, all within the horizon: proven."""
    p, q = Fluent("p"), Fluent("q")
    a = InstantaneousAction("make_p")
    a.add_precondition(Not(p))
    a.add_precondition(Not(q))
    a.add_effect(p, True)
    b = InstantaneousAction("make_q")
    b.add_precondition(Not(p))
    b.add_precondition(Not(q))
    b.add_effect(q, True)
    pr = Problem("mutex")
    pr.add_fluent(p, default_initial_value=False)
    pr.add_fluent(q, default_initial_value=False)
    pr.add_actions([a, b])
    pr.add_goal(And(p, q))
    return pr


def _islands():
    """No road leads to l3: unreachable at any length, which relaxed reachability proves."""
    loc = UserType("Loc")
    at = Fluent("at", BoolType(), l=loc)
    road = Fluent("road", BoolType(), a=loc, b=loc)
    mv = InstantaneousAction("move", a=loc, b=loc)
    x, y = mv.parameters
    mv.add_precondition(at(x))
    mv.add_precondition(road(x, y))
    mv.add_effect(at(x), False)
    mv.add_effect(at(y), True)
    pr = Problem("islands")
    pr.add_fluent(at, default_initial_value=False)
    pr.add_fluent(road, default_initial_value=False)
    l1, l2, l3 = (Object(f"l{i}", loc) for i in (1, 2, 3))
    pr.add_objects([l1, l2, l3])
    pr.add_action(mv)
    pr.set_initial_value(at(l1), True)
    pr.set_initial_value(road(l1, l2), True)
    pr.set_initial_value(road(l2, l1), True)
    pr.add_goal(at(l3))
    return pr


def _parity(down: bool = True):
    """x starts at 0 and grows or falls by 2: x = 3 never holds, but x is unbounded and can go
    either way, so no state is a provable dead end and there are infinitely many: catc can only
    say that no plan exists within its horizon. With ``down=False`` x only grows, and every
    x ≥ 4 is a dead end (the widened relaxation of the forward search proves it)."""
    x = Fluent("x", IntType())
    a = InstantaneousAction("add2")
    a.add_effect(x, x + 2)
    pr = Problem("parity")
    pr.add_fluent(x, default_initial_value=0)
    pr.add_action(a)
    if down:
        b = InstantaneousAction("sub2")
        b.add_effect(x, x - 2)
        pr.add_action(b)
    pr.add_goal(Equals(x, 3))
    return pr


def _solve(problem, **params):
    with OneshotPlanner(name="catc", params=params) as planner:
        return planner.solve(problem, timeout=PER_PROBLEM)


def _log(result):
    return "\n".join(m.message for m in result.log_messages)


def test_unsolvable_proven_by_a_finite_state_space_with_its_diagnosis(catc_engine):
    r = _solve(_mutex(), max_horizon=6)
    assert r.status is Status.UNSOLVABLE_PROVEN and r.plan is None
    log = _log(r)
    assert "at most 4 states" in log
    assert "catc diagnose" in log and "goal 1: p" in log and "goal 2: q" in log and "make_p" in log


def test_unsolvable_proven_by_relaxed_reachability_with_its_diagnosis(catc_engine):
    r = _solve(_islands())
    assert r.status is Status.UNSOLVABLE_PROVEN
    log = _log(r)
    assert "relaxed reachability" in log and "goal 1: at(l3)" in log


def test_unsolvable_within_the_horizon_only_is_not_called_proven(catc_engine):
    r = _solve(_parity(), max_horizon=6)
    assert r.status is Status.UNSOLVABLE_INCOMPLETELY
    assert "no plan of at most 6 actions" in _log(r)


def test_unsolvable_proven_where_the_state_space_is_infinite_but_the_dead_ends_are_proven(catc_engine):
    """x only grows by 2 from 0: the forward search sees x = 0 and 2, whose relaxations still
    reach 3, and proves every x ≥ 4 a dead end — no plan of any length."""
    r = _solve(_parity(down=False), max_horizon=6)
    assert r.status is Status.UNSOLVABLE_PROVEN
    assert "every reachable state" in _log(r)


def test_the_default_horizon_is_the_state_count_of_a_finite_problem(catc_engine):
    """x ∈ [0, 20] moves by ±2 from 0 and the goal is x = 7: 21 values, so some shortest plan
    (if any) has at most 20 actions, and the engine searches exactly that far by default (not
    200): "no plan within 20 actions" is then a proof for every length."""
    x = Fluent("x", IntType(0, 20))
    pr = Problem("bounded-parity")
    pr.add_fluent(x, default_initial_value=0)
    for name, d in (("up2", 2), ("down2", -2)):
        a = InstantaneousAction(name)
        a.add_effect(x, x + d)
        pr.add_action(a)
    pr.add_goal(Equals(x, 7))
    r = _solve(pr)
    assert r.status is Status.UNSOLVABLE_PROVEN
    log = _log(r)
    assert "no plan within 20 actions" in log and "at most 21 states" in log
    r = _solve(pr, max_horizon=30)  # given: searched as given
    assert r.status is Status.UNSOLVABLE_PROVEN and "no plan within 30 actions" in _log(r)


def test_time_out_before_any_answer(catc_engine):
    with OneshotPlanner(name="catc") as planner:
        r = planner.solve(_parity(), timeout=0)
    assert r.status is Status.TIMEOUT and r.plan is None


# ---------------------------------------------------------------- UP's semantics, by hand


def test_add_after_delete_and_conflicting_assignments():
    """``flip`` sets p to false and to true (UP: true wins); ``set`` assigns x := 2, and also
    x := 1 when c holds (UP: the action is then inapplicable). c holds at first and ``clear``
    makes it false, so the shortest plan is clear, set (and flip, for p): 3 actions."""
    p, c, x = Fluent("p"), Fluent("c"), Fluent("x", IntType(0, 5))
    flip = InstantaneousAction("flip")
    flip.add_effect(p, False)
    flip.add_effect(p, True)
    clear = InstantaneousAction("clear")
    clear.add_effect(c, False)
    set_ = InstantaneousAction("set")
    set_.add_effect(x, 2)
    set_.add_effect(x, 1, condition=c)
    pr = Problem("semantics")
    for f, v in ((p, False), (c, True), (x, 0)):
        pr.add_fluent(f, default_initial_value=v)
    pr.add_actions([flip, clear, set_])
    pr.add_goal(And(p, Equals(x, 2)))
    inst, report = up_to_instance(pr)
    r = solve(inst, horizon=10, sequential=True)
    plan = plan_to_up(r.plan, report, pr)
    assert len(plan.actions) == 3
    assert [a.action.name for a in plan.actions].index("clear") < [a.action.name for a in plan.actions].index("set")
    assert _valid(pr, plan).status is ValidationResultStatus.VALID


def test_refused_by_kind_lists_every_reason(examples):
    with pytest.raises(UpImportError) as err:
        up_to_instance(examples["matchcellar"].problem)
    assert err.value.code == codes.IMPORT_UNSUPPORTED == "E1201"
    assert "CONTINUOUS_TIME" in [what for what, _ in err.value.report.refused]
    with pytest.raises(UpImportError) as err:
        up_to_instance(examples["basic_undef_bool"].problem)
    assert "initial state is complete" in err.value.report.text()


def test_without_unified_planning_the_extra_is_named(monkeypatch, examples):
    problem = examples["basic"].problem
    monkeypatch.setitem(sys.modules, "unified_planning", None)
    with pytest.raises(UpMissing) as err:
        up_to_instance(problem)
    assert err.value.code == codes.IMPORT_NEEDS_EXTRA == "E1202" and "catc-lang[up]" in str(err.value)


def test_conflicting_assignments_make_the_action_inapplicable(examples):
    """``set`` assigns x := 2, and x := 1 when c holds: UP's simulator rejects the action when
    both fire, so x = 1 is unreachable (without the guard, an if-term would give x = 1 in one
    step). BFS over UP's simulator agrees that there is no plan."""
    c, x = Fluent("c"), Fluent("x", IntType(0, 5))
    set_ = InstantaneousAction("set")
    set_.add_effect(x, 1, condition=c)  # first: an if-term chain would try it first
    set_.add_effect(x, 2)
    pr = Problem("conflict")
    pr.add_fluent(c, default_initial_value=True)
    pr.add_fluent(x, default_initial_value=0)
    pr.add_action(set_)
    pr.add_goal(Equals(x, 1))
    inst, _ = up_to_instance(pr)
    assert solve(inst, horizon=4, sequential=True).plan is None
    assert _bfs_length(pr) is None


def test_anytime_planner_improves_to_the_optimum(catc_engine, examples):
    """AnytimePlanner(name="catc"): the first plan (intermediate), then the optimum."""
    from unified_planning.shortcuts import AnytimePlanner

    ex = examples["locations_connected_cost_minimize"]
    with AnytimePlanner(name="catc") as planner:
        results = list(planner.get_solutions(ex.problem, timeout=PER_PROBLEM))
    assert [r.status for r in results] == [Status.INTERMEDIATE, Status.SOLVED_OPTIMALLY]
    (value,) = _valid(ex.problem, results[-1].plan).metric_evaluations.values()
    assert Fraction(str(value)) == Fraction(str(ex.optimum))


def _py_blocks(page):
    import re
    from pathlib import Path

    text = (Path(__file__).resolve().parents[1] / "docs" / page).read_text(encoding="utf-8")
    return re.findall(r"```py\n(.*?)```", text, re.S)


def test_the_examples_in_the_docs_run(catc_engine, examples, capsys):
    """docs/api.md's and docs/interop.md's unified-planning examples, on UP's ``basic``."""
    problem = examples["basic"].problem
    (api,) = _py_blocks("api.md")
    scope = {"problem": problem}
    exec(compile(api, "docs/api.md", "exec"), scope)
    assert _valid(problem, scope["up_plan"]).status is ValidationResultStatus.VALID
    (interop,) = _py_blocks("interop.md")
    scope = {"problem": problem}
    exec(compile(interop, "docs/interop.md", "exec"), scope)
    assert scope["result"].status is Status.SOLVED_SATISFICING
    assert "SOLVED_SATISFICING" in capsys.readouterr().out


def test_register_is_the_one_liner(catc_engine):
    from catc.interfaces.up_engine import register

    register()  # a second registration is harmless
    assert get_environment().factory.engines.count("catc") == 1


def test_a_grounded_problem_past_the_limits_is_refused(catc_engine, examples):
    """robot_loader grounds to 6 morphisms; with a morphisms limit of 5 it is refused (E1105)."""
    from catgrammar import limits

    problem = examples["robot_loader"].problem
    inst, _ = up_to_instance(problem)
    assert len(inst.morphisms) == 6
    with limits.using(limits.Limits(morphisms=5)):
        with pytest.raises(limits.LimitExceeded) as err:
            up_to_instance(problem)
        assert err.value.code == codes.TOO_MANY_MORPHISMS
        r = _solve(problem)
    assert r.status is Status.UNSUPPORTED_PROBLEM and "morphisms limit" in _log(r)


def test_forced_past_the_kind_check_the_answer_is_unsupported_with_the_report(catc_engine, examples):
    with OneshotPlanner(name="catc") as planner:
        planner.skip_checks = True  # UP would otherwise refuse before calling catc
        r = planner.solve(examples["matchcellar"].problem)
    assert r.status is Status.UNSUPPORTED_PROBLEM and r.plan is None
    assert "E1201" in _log(r) and "CONTINUOUS_TIME" in _log(r)


def test_an_up_ini_registers_the_engine(tmp_path, examples):
    """docs/interop.md's up.ini, read by UP's own factory (in a fresh environment)."""
    from unified_planning.environment import Environment

    ini = tmp_path / "up.ini"
    ini.write_text("[engine catc]\nmodule_name = catc.interfaces.up_engine\nclass_name = CatcEngine\n")
    env = Environment()
    env.credits_stream = None
    env.factory.configure_from_file(str(ini))
    assert "catc" in env.factory.engines
    engine = env.factory.engine("catc")
    assert engine.__name__ == "CatcEngine" and engine.supports(examples["basic"].problem.kind)


def test_every_refusal_of_an_example_says_why(examples):
    from catc.frontend.up_import import refusals

    for name, ex in examples.items():
        if CatcEngine.supports(ex.problem.kind):
            assert refusals(ex.problem.kind) == [], name
            continue
        reasons = refusals(ex.problem.kind)
        assert reasons, name
        assert all(why != "not expressible in catc" for _, why in reasons), (name, reasons)


def _steps_problem(invariant_ok_initially=True):
    """x ∈ [0, 10] from 0 (or 3) by steps of 1 and 3 to x = 6, never through x = 3: by hand,
    3+3 passes 3 and no 3 steps sum to 6, so a shortest plan is 1, 3, 1, 1 (4 actions)."""
    x = Fluent("x", IntType(0, 10))
    pr = Problem("steps")
    pr.add_fluent(x, default_initial_value=0 if invariant_ok_initially else 3)
    for n in (1, 3):
        a = InstantaneousAction(f"inc{n}")
        a.add_effect(x, x + n)
        pr.add_action(a)
    pr.add_state_invariant(Not(Equals(x, 3)))
    pr.add_goal(Equals(x, 6))
    return pr


def test_state_invariants_are_regressed_into_preconditions(catc_engine):
    pr = _steps_problem()
    r = _solve(pr)
    assert r.status is Status.SOLVED_SATISFICING and len(r.plan.actions) == 4 == _bfs_length(pr)
    assert _valid(pr, r.plan).status is ValidationResultStatus.VALID


def test_an_invariant_false_at_first_leaves_no_plan(catc_engine):
    r = _solve(_steps_problem(invariant_ok_initially=False))
    assert r.status is Status.UNSOLVABLE_PROVEN
    assert "state invariant 1 is false in the initial state" in _log(r)


def test_the_declared_guarantees():
    from unified_planning.engines.mixins.anytime_planner import AnytimeGuarantee
    from unified_planning.engines.mixins.oneshot_planner import OptimalityGuarantee

    assert CatcEngine.satisfies(OptimalityGuarantee.SATISFICING)
    assert not CatcEngine.satisfies(OptimalityGuarantee.SOLVED_OPTIMALLY)  # bounded by its horizon
    assert CatcEngine.ensures(AnytimeGuarantee.INCREASING_QUALITY)
    kind = CatcEngine.supported_kind()
    assert "CONTINUOUS_TIME" not in kind.features and "ACTIONS_COST" in kind.features


def test_a_horizon_past_the_limit_is_a_usage_error():
    with pytest.raises(ValueError, match="horizon limit"):
        CatcEngine(max_horizon=1001)


def test_action_costs_that_read_changing_fluents(catc_engine):
    """``buy`` costs the current price and raises it by 1 (from 1); ``bulk`` gets 3 at once for
    7. By hand: three buys cost 1 + 2 + 3 = 6 < 7, so the optimum is 6 with 3 actions — longer
    than the shortest plan (bulk). UP evaluates each cost in the state before its action."""
    from unified_planning.model.metrics import MinimizeActionCosts

    have, price = Fluent("have", IntType(0, 10)), Fluent("price", IntType(0, 10))
    buy, bulk = InstantaneousAction("buy"), InstantaneousAction("bulk")
    buy.add_effect(have, have + 1)
    buy.add_effect(price, price + 1)
    bulk.add_effect(have, have + 3)
    pr = Problem("prices")
    pr.add_fluent(have, default_initial_value=0)
    pr.add_fluent(price, default_initial_value=1)
    pr.add_actions([buy, bulk])
    pr.add_goal(have >= 3)
    pr.add_quality_metric(MinimizeActionCosts({buy: price(), bulk: 7}))
    assert "FLUENTS_IN_ACTIONS_COST" in pr.kind.features
    r = _solve(pr)
    assert r.status in (Status.SOLVED_SATISFICING, Status.SOLVED_OPTIMALLY)
    check = _valid(pr, r.plan)
    assert check.status is ValidationResultStatus.VALID
    assert [a.action.name for a in r.plan.actions] == ["buy"] * 3
    assert Fraction(str(next(iter(check.metric_evaluations.values())))) == 6


def _maximise_x(upper):
    from unified_planning.model.metrics import MaximizeExpressionOnFinalState

    x = Fluent("x", IntType(0, upper))
    inc = InstantaneousAction("inc")
    inc.add_effect(x, x + 1)
    pr = Problem("most")
    pr.add_fluent(x, default_initial_value=0)
    pr.add_action(inc)
    pr.add_quality_metric(MaximizeExpressionOnFinalState(x()))
    return pr


def test_a_final_value_metric_is_optimal_only_when_proven(catc_engine):
    """Maximise x (+1 per action, no goal). x ≤ 5: 6 states, so optimising over 5 actions
    covers every plan — proven optimal, 5. x ≤ 1000: the state space is past max_horizon + 1,
    so catc optimises over opt_horizon = 20 actions and claims nothing more: 20, satisficing."""
    r = _solve(_maximise_x(5))
    assert r.status is Status.SOLVED_OPTIMALLY
    assert next(iter(_valid(_maximise_x(5), r.plan).metric_evaluations.values())) == 5
    r = _solve(_maximise_x(1000))
    assert r.status is Status.SOLVED_SATISFICING and len(r.plan.actions) == 20
    assert "optimal among plans of at most 20 actions" in _log(r)


def test_the_benchmark_script_prints_the_documented_counts(catc_engine, capsys):
    """benchmarks/up_examples.py, the command behind docs/interop.md's table."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "benchmarks" / "up_examples.py"
    spec = importlib.util.spec_from_file_location("up_examples", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    assert module.main(["--markdown"]) == 0
    out = capsys.readouterr().out
    assert out.rstrip().endswith("solved 41, refused 25, timeout 0, failed 0 (of 66)")
    assert "| counter_to_50 | no | SOLVED_SATISFICING |" in out
    doc = (path.parents[1] / "docs" / "interop.md").read_text(encoding="utf-8")
    assert "solved 41, refused 25, timeout 0, failed 0 (of 66)" in doc


def test_planning_prints_no_credits_banner(catc_engine):
    """UP prints an engine's credits, in colour, on every planner it makes, unless the user
    turned its credits stream off; catc's engine prints none (issue 29)."""
    import io

    from unified_planning.shortcuts import Fluent, InstantaneousAction, OneshotPlanner, Problem

    env = catc_engine
    saved = env.credits_stream
    env.credits_stream = stream = io.StringIO()
    try:
        x = Fluent("x")
        a = InstantaneousAction("a")
        a.add_effect(x, True)
        problem = Problem("p")
        problem.add_fluent(x, default_initial_value=False)
        problem.add_action(a)
        problem.add_goal(x)
        with OneshotPlanner(name="catc") as planner:
            assert planner.solve(problem).plan is not None
    finally:
        env.credits_stream = saved
    assert stream.getvalue() == ""


def test_an_unsolvable_answer_carries_a_certificate_both_solvers_check(catc_engine):
    import json

    from catc.queries.certify import CertifyStatus, certify, cvc5_command, z3_command

    if z3_command() is None or cvc5_command() is None:
        pytest.skip("needs the z3 binary and cvc5")
    problem = _islands()
    r = _solve(problem)
    assert r.status is Status.UNSOLVABLE_PROVEN
    prefix = "catc certificate (check with catc.queries.certify.certify): "
    line = next(m.message for m in r.log_messages if m.message.startswith(prefix))
    doc = json.loads(line[len(prefix) :])
    assert doc["method"] == "invariant"
    inst, _ = up_to_instance(problem)
    assert certify(inst, doc).status is CertifyStatus.CERTIFIED


def test_a_plan_not_proven_shortest_is_never_optimal_for_plan_length(catc_engine, monkeypatch):
    """With a plan-length metric the engine answers SOLVED_OPTIMALLY only for a plan proven
    shortest. The forward search is made to stop before A* settles anything (its greedy plan
    alone, as when the time runs out): the same plan is then SOLVED_SATISFICING, and the log
    says it is not proven shortest."""
    from unified_planning.model.metrics import MinimizeSequentialPlanLength

    import catc.semantics.search as search_mod

    real = search_mod.search
    monkeypatch.setattr(
        search_mod, "search", lambda inst, k, **kw: real(inst, k, deadline=kw.get("deadline"), prove=False)
    )
    pr = _steps_problem()
    pr.add_quality_metric(MinimizeSequentialPlanLength())
    r = _solve(pr)
    assert r.status is Status.SOLVED_SATISFICING
    assert _valid(pr, r.plan).status is ValidationResultStatus.VALID
    assert "not proven shortest" in _log(r)
    monkeypatch.setattr(search_mod, "search", real)
    r = _solve(pr)  # proven: 4 actions, the breadth-first count
    assert r.status is Status.SOLVED_OPTIMALLY and len(r.plan.actions) == 4 == _bfs_length(pr)
