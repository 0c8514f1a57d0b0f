"""The forward A* search (:mod:`catc.semantics.search`, ``catc solve --strategy search``):
shortest sequential compositions checked against the SMT search (an independent route) and
hand counts, unsolvability proven by exhausting the reachable states, and the fall back to the
SMT search where the forward search does not apply."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from unified_planning.io import PDDLReader
from unified_planning.shortcuts import LE, Equals, Fluent, InstantaneousAction, IntType, Plus, Problem, get_environment

from catc.bench import corpus
from catc.frontend.up_import import up_to_instance
from catc.queries.solve import SolveStatus, solve
from catc.semantics.relaxed import refute
from catc.semantics.search import SearchStatus, search

FERRY = Path(__file__).parent / "fixtures" / "pddl" / "ferry-untyped"
EXAMPLES = Path(__file__).parent.parent / "examples"


def _read(domain: Path, problem: Path):
    get_environment().credits_stream = None
    return PDDLReader().parse_problem(str(domain), str(problem))


def _ferry():
    return up_to_instance(_read(FERRY / "domain.pddl", FERRY / "problem.pddl"))[0]


def test_the_shortest_ferry_plan_is_as_long_as_the_smt_search_finds():
    inst = _ferry()
    r = search(inst, 20)
    smt = solve(inst, horizon=20, sequential=True)
    assert r.status is SearchStatus.PLAN and smt.status is SolveStatus.SAT and smt.plan is not None
    assert r.length == len(smt.plan.steps) == 7
    via = solve(inst, horizon=20, sequential=True, strategy="search")  # validated inside solve
    assert via.status is SolveStatus.SAT and via.plan is not None and len(via.plan.steps) == 7


def test_a_horizon_below_the_shortest_plan_is_none_but_not_final():
    r = search(_ferry(), 6)
    assert r.status is SearchStatus.NONE and not r.final
    smt = solve(_ferry(), horizon=6, sequential=True)
    assert smt.status is SolveStatus.UNSAT


def test_counters_shortest_plan_is_the_hand_count(tmp_path):
    """n counters from 0 that must end strictly increasing: c_i ≥ i, so Σ i = n(n-1)/2 = 6
    increments for n = 4, and 6 suffice."""
    wheel = corpus.wheel_dir()
    assert wheel is not None
    (tmp_path / "p.pddl").write_text(corpus.counters_problem(4))
    inst, _ = up_to_instance(_read(wheel / "counters" / "domain.pddl", tmp_path / "p.pddl"))
    r = search(inst, 50)
    assert r.status is SearchStatus.PLAN and r.length == 6


def _parity() -> Problem:
    """x ∈ [0, 20] starts at 0 and only grows by 2: x = 7 is never reached. The interval
    relaxation cannot tell from the start (7 lies within [0, 20]); the search sees x = 0, 2, 4,
    6, whose relaxations still reach 7, and proves x ≥ 8 a dead end (the interval only grows
    from above 7)."""
    x = Fluent("x", IntType(0, 20))
    step = InstantaneousAction("step")
    step.add_precondition(LE(x, 18))
    step.add_increase_effect(x, 2)
    p = Problem("parity")
    p.add_fluent(x, default_initial_value=0)
    p.add_action(step)
    p.add_goal(Equals(x, 7))
    return p


def test_unsolvable_proven_by_exhausting_the_reachable_states():
    inst, _ = up_to_instance(_parity())
    assert refute(inst) is None  # not the relaxation's proof
    r = search(inst, 200, greedy=False)  # A*: x = 0, 2, 4, 6 expanded, x ≥ 8 dead ends
    assert r.status is SearchStatus.NONE and r.final
    assert "(4)" in r.reason
    r = search(inst, 200)  # the greedy search prunes nothing: x = 0, 2, …, 20, all 11 states
    assert r.status is SearchStatus.NONE and r.final
    assert "(11)" in r.reason
    via = solve(inst, horizon=200, sequential=True, strategy="search")
    assert via.status is SolveStatus.UNSAT and via.final


def test_a_goal_met_at_first_is_the_empty_plan():
    p = _parity()
    p.clear_goals()
    p.add_goal(Equals(Plus(get_environment().expression_manager.Int(0), 0), 0))
    inst, _ = up_to_instance(p)
    r = search(inst, 5)
    assert r.status is SearchStatus.PLAN and r.length == 0


def test_parameters_fall_back_to_the_smt_search():
    """A .cat model whose morphisms have parameters: the forward search does not apply, and
    ``strategy="search"`` answers exactly as ``incremental``."""
    from catc.frontend.session import load_checked
    from catgrammar.diagnostics import Diagnostics

    path = EXAMPLES / "navigation" / "coarse.cat"
    inst = load_checked(path, None, Diagnostics())
    assert inst is not None and any(m.params for m in inst.morphisms.values())
    assert search(inst, 5).status is SearchStatus.UNSUPPORTED
    a = solve(inst, horizon=6, sequential=True, strategy="search")
    b = solve(inst, horizon=6, sequential=True)
    assert a.status is b.status
    assert (a.plan is None) == (b.plan is None)
    if a.plan is not None and b.plan is not None:
        assert len(a.plan.steps) == len(b.plan.steps)


def test_an_unbounded_tank_that_only_grows_past_the_goal_is_proven_unsolvable():
    """tank starts at 0 and grows by 3 or 4: tank = 1 never holds. tank is an unbounded real,
    so the states are infinitely many; the search sees tank = 0, whose relaxation still
    reaches 1, and the widened relaxation proves every tank ≥ 3 a dead end (it never falls)."""
    from unified_planning.shortcuts import RealType

    tank = Fluent("tank", RealType())
    p = Problem("tank")
    p.add_fluent(tank, default_initial_value=0)
    for amount in (3, 4):
        fill = InstantaneousAction(f"fill{amount}")
        fill.add_increase_effect(tank, amount)
        p.add_action(fill)
    p.add_goal(Equals(tank, 1))
    inst, _ = up_to_instance(p)
    assert refute(inst) is None
    r = search(inst, 200)
    assert r.status is SearchStatus.NONE and r.final


def _corpus_script():
    import importlib.util
    import sys

    spec = importlib.util.spec_from_file_location(
        "planning_corpus", EXAMPLES.parent / "benchmarks" / "planning_corpus.py"
    )
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("planning_corpus", mod)
    spec.loader.exec_module(mod)
    return mod


def test_the_greedy_plan_is_proven_shortest_by_a_star_or_replaced(tmp_path):
    """gripper with 4 balls: 11 actions at best (pick, pick, move, drop, drop, move back per
    pair, no last move back). The greedy search's plan, then A* below its length: the answer
    is 11 long and proven shortest, and A* alone agrees."""
    corpus_mod = _corpus_script()
    (tmp_path / "d.pddl").write_text(corpus_mod.GRIPPER)
    (tmp_path / "p.pddl").write_text(corpus_mod.gripper(4))
    inst, _ = up_to_instance(_read(tmp_path / "d.pddl", tmp_path / "p.pddl"))
    r = search(inst, 60)
    assert r.status is SearchStatus.PLAN and r.length == 11 and r.shortest
    assert search(inst, 60, greedy=False).length == 11
    greedy = search(inst, 60, prove=False)  # the greedy plan alone: no claim that it is shortest
    assert greedy.status is SearchStatus.PLAN and not greedy.shortest and greedy.length is not None
    assert greedy.length >= 11
    via = solve(inst, horizon=60, sequential=True, strategy="greedy")  # replayed by the validator
    assert via.status is SolveStatus.SAT and not via.shortest


def test_counters_greedy_plan_is_valid_and_no_shorter_than_the_hand_count(tmp_path):
    """counters-6 (15 increments at best, c_i ≥ i): the greedy plan, numeric h_add, validated
    inside solve; it can be no shorter than 15."""
    wheel = corpus.wheel_dir()
    assert wheel is not None
    (tmp_path / "p.pddl").write_text(corpus.counters_problem(6))
    inst, _ = up_to_instance(_read(wheel / "counters" / "domain.pddl", tmp_path / "p.pddl"))
    via = solve(inst, horizon=100, sequential=True, strategy="greedy")
    assert via.status is SolveStatus.SAT and via.plan is not None
    assert len(via.plan.steps) >= 15


def test_the_consumption_bound_runs_only_where_the_forward_search_does_not(monkeypatch):
    """On a ground task the forward search settles the answer, so issue 24's least-consumption
    bound (seconds on blocks-8, and no proof there) is not computed first; where the forward
    search does not apply (parameters) it still is, before the SMT search."""
    import catc.queries.solve as solve_mod

    calls: list[str] = []

    def counted(inst):
        calls.append(inst.problem.name)
        return None

    monkeypatch.setattr(solve_mod, "consumption_proof", counted)
    # its solver-free first step (issue 23): when a component set passes, the check is skipped
    passes = solve_mod._passes_abstraction

    def counted_passes(inst):
        calls.append(inst.problem.name)
        return passes(inst)

    monkeypatch.setattr(solve_mod, "_passes_abstraction", counted_passes)
    r = solve(_ferry(), horizon=20, sequential=True, strategy="search")
    assert r.status is SolveStatus.SAT and calls == []
    from catc.frontend.session import load_checked
    from catgrammar.diagnostics import Diagnostics

    inst = load_checked(EXAMPLES / "navigation" / "coarse.cat", None, Diagnostics())
    assert inst is not None
    solve(inst, horizon=6, sequential=True, strategy="search")
    assert calls and set(calls) == {inst.problem.name}


def test_a_greedy_search_past_its_share_gives_way_to_a_star(monkeypatch):
    """With room for one state only, the greedy phase stops at once and A* alone answers: the
    parity task is still proven unsolvable, by A*'s dead ends (x = 0, 2, 4, 6 expanded)."""
    import catc.semantics.search.algorithms as algorithms

    monkeypatch.setattr(algorithms, "GREEDY_STATES", 0)
    inst, _ = up_to_instance(_parity())
    r = search(inst, 200)
    assert r.status is SearchStatus.NONE and r.final and "(4)" in r.reason


def _counters(tmp_path, n: int, max_int: int | None = None):
    import re

    wheel = corpus.wheel_dir()
    assert wheel is not None
    text = corpus.counters_problem(n)
    if max_int is not None:
        text = re.sub(r"\(=\s*\(max_int\)\s*[0-9.]+\)", f"(= (max_int) {max_int})", text)
    (tmp_path / "p.pddl").write_text(text)
    return up_to_instance(_read(wheel / "counters" / "domain.pddl", tmp_path / "p.pddl"))[0]


def test_counters_bounds_are_inferred_from_the_guards_of_every_change(tmp_path):
    """decrement needs value ≥ 1 and takes 1: value never falls below 0 (its initial value);
    increment needs value + 1 ≤ max_int and adds 1: value never exceeds max_int. PDDL declares
    neither (the import gives unbounded reals)."""
    from catc.semantics.search import _Task, infer_bounds

    inst = _counters(tmp_path, 4, max_int=9)
    assert all(r.lower is None and r.upper is None for r in inst.domain.resources.values())
    task = _Task(inst)
    bounds = dict(zip(task.names, infer_bounds(inst, task)))
    assert {bounds[f"value_c{i}"] for i in range(4)} == {(0, 9)}


def test_a_change_without_a_guard_gives_no_bound():
    """tank starts at 5, fill adds 3 unguarded, drain takes 2 when tank ≥ 2: no upper bound
    (fill has no guard), lower bound 0 (2 − 2, below the initial 5)."""
    from unified_planning.shortcuts import GE, RealType

    from catc.semantics.search import _Task, infer_bounds

    tank = Fluent("tank", RealType())
    p = Problem("tank")
    p.add_fluent(tank, default_initial_value=5)
    fill = InstantaneousAction("fill")
    fill.add_increase_effect(tank, 3)
    drain = InstantaneousAction("drain")
    drain.add_precondition(GE(tank, 2))
    drain.add_decrease_effect(tank, 2)
    p.add_action(fill)
    p.add_action(drain)
    p.add_goal(Equals(tank, 1))
    inst, _ = up_to_instance(p)
    task = _Task(inst)
    assert infer_bounds(inst, task) == [(0, None)]
    r = search(inst, 50)  # 5 − 2 − 2 = 1; no single step reaches 1 (8 or 3)
    assert r.status is SearchStatus.PLAN and r.length == 2 and r.shortest


def test_counters_7_is_proven_shortest_by_the_counting_bound(tmp_path):
    """7 counters from 0 ending strictly increasing: the values never fall below 0 (inferred),
    so c_i ≥ i at the end and each increment raises one counter by one: Σ i = 21 steps at
    least, and 21 suffice. h^max alone left A* unfinished after 60 s (~400,000 states); the
    counting bound is 21 at the initial state, so the greedy plan is proven at once."""
    inst = _counters(tmp_path, 7)
    r = search(inst, 200, deadline=__import__("time").monotonic() + 120)
    assert r.status is SearchStatus.PLAN and r.length == 21 and r.shortest


def test_counters_that_do_not_fit_below_max_int_are_proven_unsolvable(tmp_path):
    """5 strictly increasing values ≥ 0 need the last ≥ 4; max_int = 3 forbids it. The inferred
    bounds make the counting system infeasible at the initial state; with max_int = 4 the task
    stays solvable (0, 1, 2, 3, 4: 10 increments)."""
    inst = _counters(tmp_path, 5, max_int=3)
    r = search(inst, 200)
    assert r.status is SearchStatus.NONE and r.final and r.expanded == 0
    assert solve(inst, horizon=200, sequential=True, strategy="search").status is SolveStatus.UNSAT
    ok = _counters(tmp_path, 5, max_int=4)
    r = search(ok, 200)
    assert r.status is SearchStatus.PLAN and r.length == 10 and r.shortest


def test_the_counting_lp_is_solved_exactly():
    """min c1 + c2 subject to c1 + 2·c2 ≥ 3, 3·c1 + c2 ≥ 4 (c ≥ 0): the vertices (0, 4), (1, 1),
    (3, 0) give 4, 2, 3, so 2; read from the dual max 3·y1 + 4·y2 under y1 + 3·y2 ≤ 1,
    2·y1 + y2 ≤ 1. With c1 + c2 ≥ 1 and −c1 − c2 ≥ 0 there is no c: the dual is unbounded."""
    from fractions import Fraction as F

    from catc.semantics.search import _max_dual

    assert _max_dual([[F(1), F(3)], [F(2), F(1)]], [F(3), F(4)], 100) == 2
    assert _max_dual([[F(1), F(-1)], [F(1), F(-1)]], [F(1), F(0)], 100) is None


def test_a_warm_started_dual_answers_as_a_fresh_one():
    """The kept basis of one objective is a feasible start for the next: the same maxima as
    from the slack basis. The region y1 + 3·y2 ≤ 1, 2·y1 + y2 ≤ 1, y ≥ 0 has the vertices
    (0, 0), (0, 1/3), (2/5, 1/5), (1/2, 0): 4·y1 + 3·y2 takes 0, 1, 11/5, 2 there, so 11/5."""
    from fractions import Fraction as F

    from catc.semantics.search import _Dual, _max_dual

    a = [[F(1), F(3)], [F(2), F(1)]]
    dual = _Dual(a, 2)
    assert dual.solve([F(3), F(4)], 100) == 2
    assert dual.solve([F(4), F(3)], 100) == _max_dual(a, [F(4), F(3)], 100) == F(11, 5)
    assert dual.solve([F(0), F(0)], 100) == 0


def test_farmland_is_proven_shortest_and_short_of_workers_unsolvable(tmp_path):
    """farmland's actions on a line of 5 farms, all workers on f0 (the corpus script's
    generator, whose docstring argues the counts): with 5 workers the 4 + 3 + 2 + 1 = 10
    move-slow steps are the shortest plan; with 4 there is none (the total never grows)."""
    mod = _corpus_script()
    (tmp_path / "d.pddl").write_text(mod.FARMLAND)
    for workers, expect in ((5, 10), (4, None)):
        (tmp_path / "p.pddl").write_text(mod.farmland(5, workers))
        inst, _ = up_to_instance(_read(tmp_path / "d.pddl", tmp_path / "p.pddl"))
        r = search(inst, 200)
        if expect is None:
            assert r.status is SearchStatus.NONE and r.final
        else:
            assert r.status is SearchStatus.PLAN and r.length == expect and r.shortest
            via = solve(inst, horizon=200, sequential=True, strategy="search")  # validated inside
            assert via.status is SolveStatus.SAT and via.plan is not None and len(via.plan.steps) == 10


def test_the_plan_neighbourhood_shortens_the_greedy_gripper_plan(tmp_path):
    """gripper-12: h_add's greedy plan carries one ball a trip (47 actions, 63 for 16 balls);
    two a trip is 6 per pair less the last move back: 35. The search of the plan's
    neighbourhood finds trips of two; the plan is replayed by the validator."""
    from catc.semantics.validate import validate

    corpus_mod = _corpus_script()
    (tmp_path / "d.pddl").write_text(corpus_mod.GRIPPER)
    (tmp_path / "p.pddl").write_text(corpus_mod.gripper(12))
    inst, _ = up_to_instance(_read(tmp_path / "d.pddl", tmp_path / "p.pddl"))
    r = search(inst, 200, prove=False)
    assert r.status is SearchStatus.PLAN and r.plan is not None and not r.shortest
    assert r.length == 35
    assert validate(inst, r.plan, sequential=True).ok


def test_sums_of_conditions_strengthen_h_max_on_sailing(tmp_path):
    """UP's sailing, persons 3q and 3q − 6 away (the corpus script's generator argues 2q + 2
    by hand). save_person needs x + y ≥ d and y − x ≥ d: taken one at a time the intervals
    meet them after ~2/3 of the 2q moves; their sum 2·y ≥ 2·d needs y to grow by 1.5 per move
    for all of them. With the sum tested, h^max at the start is 2q layers of moves and one of
    both saves together (h^max lets them share a layer): 2q + 1, one below the optimum."""
    from catc.semantics.search import _Task

    mod = _corpus_script()
    (tmp_path / "p.pddl").write_text(mod.sailing_far(7))
    inst, _ = up_to_instance(_read(corpus.wheel_dir() / "sailing" / "domain.pddl", tmp_path / "p.pddl"))
    task = _Task(inst)
    assert task.hmax(task.init, 100) == 2 * 7 + 1
    r = search(inst, 200)
    assert r.status is SearchStatus.PLAN and r.length == 16 and r.shortest


def test_the_goal_achiever_bound_is_the_optimum_on_sailing(tmp_path):
    """The same sailing task: saving p1 changes nothing saving p0 reads (the boat's x and y),
    so it is a step besides the 2q layers of moves before p0's save and the save itself: the
    bound at the start is 2q + 2, the hand count, and A* below the greedy plan's length ends at
    the start."""
    from catc.semantics.search import _Task

    mod = _corpus_script()
    (tmp_path / "p.pddl").write_text(mod.sailing_far(19))
    inst, _ = up_to_instance(_read(corpus.wheel_dir() / "sailing" / "domain.pddl", tmp_path / "p.pddl"))
    task = _Task(inst)
    assert task.h(task.init, 100) == 2 * 19 + 2
    r = search(inst, 200)
    assert r.status is SearchStatus.PLAN and r.length == 40 and r.shortest


def _line_task(teleport: bool):
    """A robot on 0..6 (right, left), goal: visited 2, visited 5 and a photo; visit_k needs
    the robot at k, the photo nothing. With ``teleport`` one more morphism, after the photo,
    marks both places visited at once (shared achievers: not independent)."""
    from unified_planning.shortcuts import GE, BoolType, Minus

    pos = Fluent("pos", IntType(0, 6))
    p = Problem("line")
    p.add_fluent(pos, default_initial_value=0)
    flags = {n: Fluent(n, BoolType()) for n in ("visited2", "visited5", "photo")}
    for f in flags.values():
        p.add_fluent(f, default_initial_value=False)
        p.add_goal(f)
    right = InstantaneousAction("right")
    right.add_precondition(LE(pos, 5))
    right.add_increase_effect(pos, 1)
    left = InstantaneousAction("left")
    left.add_precondition(GE(pos, 1))
    left.add_effect(pos, Minus(pos, 1))
    photo = InstantaneousAction("shoot")
    photo.add_effect(flags["photo"], True)
    p.add_actions([right, left, photo])
    for k in (2, 5):
        visit = InstantaneousAction(f"visit{k}")
        visit.add_precondition(Equals(pos, k))
        visit.add_effect(flags[f"visited{k}"], True)
        p.add_action(visit)
    if teleport:
        jump = InstantaneousAction("teleport")
        jump.add_precondition(flags["photo"])
        jump.add_effect(flags["visited2"], True)
        jump.add_effect(flags["visited5"], True)
        p.add_action(jump)
    return up_to_instance(p)[0]


@pytest.mark.parametrize("teleport", [False, True])
def test_the_goal_achiever_bound_never_exceeds_the_true_distance(teleport):
    """Every reachable state of a small task, its heuristic value against its true distance to
    the goal (breadth first backwards over the explicit state graph, an independent count):
    never above it (admissible). Without the teleport the start's bound is the optimum, 5
    moves right plus three marks (8, by hand); with it the optimum is 2 (photo, teleport) and
    the visits' achievers are shared, so no independence may be claimed."""
    from catc.semantics.search import _Task

    task = _Task(_line_task(teleport))
    succ: dict = {}
    todo, seen = [task.init], {task.init}
    while todo:
        s = todo.pop()
        succ[s] = [t for _, t in task.successors(s)]
        for t in succ[s]:
            if t not in seen:
                seen.add(t)
                todo.append(t)
    dist = {s: 0 for s in seen if task.is_goal(s)}
    layer = list(dist)
    while layer:
        nxt = []
        for s in seen:
            if s not in dist and any(t in dist and dist[t] == dist[layer[0]] for t in succ[s]):
                nxt.append(s)
        for s in nxt:
            dist[s] = dist[layer[0]] + 1
        layer = nxt
    assert len(dist) == len(seen)  # every state can reach the goal
    for s in seen:
        h = task.h(s, 100)
        assert h is not None and h <= dist[s], (s, h, dist[s])
    assert dist[task.init] == (2 if teleport else 8)
    if not teleport:
        assert task.h(task.init, 100) == 8


def test_hydropower_is_answered_shortest_where_the_greedy_order_misleads(tmp_path):
    """IPC 2023 hydropower's actions on the corpus script's demand curve (price 1 at t0, 2 in
    between, 10 at the last of 6 hours; its generator argues 2·units + T − 1 = 9 by hand):
    h_add prefers selling at any hour, so the greedy search wanders; A*, taking turns with it,
    answers with the shortest plan, replayed by the validator."""
    mod = _corpus_script()
    (tmp_path / "d.pddl").write_text(mod.HYDROPOWER)
    (tmp_path / "p.pddl").write_text(mod.hydropower(6, 2))
    inst, _ = up_to_instance(_read(tmp_path / "d.pddl", tmp_path / "p.pddl"))
    from catc.semantics.search import _Atoms, _inline_statics, _Task

    folded = _inline_statics(inst)  # UP leaves pump's price as (* 1.05 1): folded, a constant change
    task = _Task(folded)
    assert _Atoms(task, folded).varying == []
    r = search(inst, 200)
    assert r.status is SearchStatus.PLAN and r.length == 9 and r.shortest
    via = solve(inst, horizon=200, sequential=True, strategy="search")  # validated inside
    assert via.status is SolveStatus.SAT and via.plan is not None and len(via.plan.steps) == 9
