"""∃-step parallel steps (catc.smt.encoder, ``solve(exists_step=True)``) against a naive
sequential search, on the random ground domains of test_solve_property.

The sound direction, as the issue asks: every ∃-step composition linearises to a sequential
one that this file's own simulator replays (preconditions, the counter's bounds, the use
limits, the goal); and the least ∃-step horizon is at most the shortest sequential length
(a sequential composition is an ∃-step one of one activation per step), so an ∃-step UNSAT
at horizon h means no sequential composition within h steps.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, given, settings
from test_solve_property import COUNTER_MAX, domains, to_cat

from catc.frontend.workspace import load_instance
from catc.queries.solve import SolveStatus, linearised, solve
from catc.semantics.plan import Activation, Plan
from catgrammar.diagnostics import Diagnostics

HORIZON = 3


def _apply(morphs, state, i):
    """The state after morphism ``i`` fires sequentially, or None when it cannot."""
    bools, c, used = state
    m = morphs[i]
    if m.uses is not None and used[i] >= m.uses:
        return None
    if not all(lit.holds(bools, c) for lit in m.pre):
        return None
    new_b = list(bools)
    c = m.apply(new_b, c)
    if not 0 <= c <= COUNTER_MAX:
        return None
    return tuple(new_b), c, tuple(u + (k == i) for k, u in enumerate(used))


def _shortest_sequential(morphs, init_bools, init_c, goal, most):
    """The least number of sequential steps reaching the goal, up to ``most``, else None."""
    frontier = {(init_bools, init_c, tuple(0 for _ in morphs))}
    seen = set(frontier)
    for depth in range(most + 1):
        if any(all(lit.holds(b, c) for lit in goal) for b, c, _ in frontier):
            return depth
        nxt = set()
        for s in frontier:
            for i in range(len(morphs)):
                n = _apply(morphs, s, i)
                if n is not None and n not in seen:
                    seen.add(n)
                    nxt.add(n)
        frontier = nxt
    return None


def _replays(morphs, init_bools, init_c, goal, plan) -> bool:
    state = (init_bools, init_c, tuple(0 for _ in morphs))
    for step in plan.steps:
        if len(step) != 1:
            return False
        state = _apply(morphs, state, int(step[0].morphism[1:]))
        if state is None:
            return False
    bools, c, _ = state
    return all(lit.holds(bools, c) for lit in goal)


def test_a_step_linearises_in_the_order_it_fires():
    plan = Plan([(Activation("a"), Activation("b")), (Activation("c"),)])
    assert [s[0].morphism for s in linearised(plan).steps] == ["a", "b", "c"]
    assert all(len(s) == 1 for s in linearised(plan).steps)


@settings(
    max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "60")),
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(domain=domains())
def test_exists_step_plans_replay_and_are_never_longer_in_steps(tmp_path, domain):
    _nb, morphs, init_bools, init_c, goal, _ = domain
    path = tmp_path / "random.cat"
    path.write_text(to_cat(*domain))
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, [d.message for d in diags]
    r = solve(inst, horizon=HORIZON, sequential=True, exists_step=True, presolve=False, prune=False)
    seq = _shortest_sequential(morphs, init_bools, init_c, goal, HORIZON)
    if r.status is SolveStatus.UNSAT:
        assert seq is None  # no sequential composition within the horizon either
        return
    assert r.status is SolveStatus.SAT and r.plan is not None
    assert not r.shortest
    assert _replays(morphs, init_bools, init_c, goal, r.plan)
    steps = r.horizons_tried - 1  # the deepening stopped at the least ∃-step horizon
    if seq is not None:
        assert steps <= seq


def _load(tmp_path, text: str):
    path = tmp_path / "m.cat"
    path.write_text(text)
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, [d.message for d in diags]
    return inst


def test_a_chain_of_enablers_is_one_exists_step(tmp_path):
    """m0 makes b0, m1 needs b0 and makes b1, m2 needs b1 and makes b2 (declared in that
    order): sequentially and with ∀-steps (m1 reads what m0 writes: they interfere) the goal
    b2 takes 3 steps; one ∃-step fires all three in order."""
    inst = _load(
        tmp_path,
        "(define (domain chain) (:resources (b0 bool) (b1 bool) (b2 bool))"
        " (:morphism m0 :effect (assign b0 true))"
        " (:morphism m1 :precondition b0 :effect (assign b1 true))"
        " (:morphism m2 :precondition b1 :effect (assign b2 true)))"
        " (define (problem p) (:domain chain) (:init) (:goal b2) (:horizon 5))",
    )
    assert len(solve(inst, sequential=True, presolve=False).plan) == 3
    assert len(solve(inst, sequential=False, presolve=False).plan) == 3
    r = solve(inst, sequential=True, exists_step=True, presolve=False)
    assert r.status is SolveStatus.SAT and r.horizons_tried == 2  # horizons 0 and 1
    assert [s[0].morphism for s in r.plan.steps] == ["m0", "m1", "m2"]


def test_a_later_morphism_reads_what_an_earlier_one_of_its_step_left(tmp_path):
    """m0 needs p and clears it (making q); m1 needs p (making r). In the fixed order m0, m1 no
    step holds both (m1 would read p after m0 cleared it), so the ∃-step horizon is 2 — m1 in
    step 1, m0 in step 2 — as the sequential length. Read on the step's first state instead,
    one step would hold both and its linearisation m0, m1 would not run."""
    inst = _load(
        tmp_path,
        "(define (domain clash) (:resources (p bool) (q bool) (r bool))"
        " (:morphism m0 :precondition p :effect (and (assign p false) (assign q true)))"
        " (:morphism m1 :precondition p :effect (assign r true)))"
        " (define (problem c) (:domain clash) (:init p) (:goal (and q r)) (:horizon 4))",
    )
    r = solve(inst, sequential=True, exists_step=True, presolve=False)
    assert r.status is SolveStatus.SAT and r.horizons_tried == 3  # horizons 0, 1 and 2
    assert [s[0].morphism for s in r.plan.steps] == ["m1", "m0"]


def test_the_command_line_flag_answers_as_the_default_with_a_plan_the_validator_accepts(tmp_path):
    """``catc solve --exists-step`` (the solve query's registry option, so the CLI, the API
    and docs/cli-reference get it together): on the detection example the same status as the
    default (SAT; UNSAT on the navigation example's coarse map, final both ways), its plan
    marked not proven shortest and replayed by the independent validator (the command says
    so), and the API's plan (model.query) the same and valid for catc.semantics.validate. Without
    --sequential: ∃-step compositions are sequential ones."""
    import json

    from conftest import ROOT, run_catc

    from catc.api import load
    from catc.semantics.validate import validate

    det = ROOT / "examples" / "detection"
    args = (str(det / "domain.cat"), str(det / "person.cat"), "--no-presolve")
    default = run_catc("solve", *args, "--json")
    exists = run_catc("solve", *args, "--json", "--exists-step")
    assert default.exit_code == exists.exit_code == 0, exists.output
    a, b = json.loads(default.stdout), json.loads(exists.stdout)
    assert a["status"] == b["status"] == "sat"
    assert b["sequential"] is True and b["shortest"] is False
    assert all(len(step) == 1 for step in b["steps"])
    model = load(det / "domain.cat", det / "person.cat")
    r = model.query("solve", exists_step=True, presolve=False)  # the API, through the same registry
    assert r.status is SolveStatus.SAT and not r.shortest and r.plan is not None
    assert [a.morphism for step in r.plan.steps for a in step] == [a["morphism"] for step in b["steps"] for a in step]
    assert validate(model.instance, r.plan, horizon=len(r.plan), sequential=True).ok
    text = run_catc("solve", *args, "--exists-step")
    assert "validated by independent replay" in text.stdout and "not proven shortest" in text.stdout
    coarse = ROOT / "examples" / "navigation" / "coarse.cat"
    for extra in ((), ("--exists-step",)):
        res = run_catc("solve", str(coarse), "--no-presolve", *extra)
        assert res.exit_code == 1 and "this is final" in res.stdout, res.output
