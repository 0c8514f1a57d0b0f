"""The reachable-state bound (catc.semantics.horizon.state_bound) in the SMT route and the
unified-planning engine (issue 27): numbers imported from PDDL are unbounded reals, but the
preconditions guarding their changes bound them, and constant changes keep them on a lattice,
so a task of a few counters has a finite state count that stops the deepening.

Every expected count and answer is argued by hand in the test's docstring."""

from __future__ import annotations

import itertools
from fractions import Fraction

import pytest

pytest.importorskip("unified_planning")

from unified_planning.engines import PlanGenerationResultStatus as Status
from unified_planning.shortcuts import (
    GE,
    LE,
    Equals,
    Fluent,
    InstantaneousAction,
    Object,
    OneshotPlanner,
    Plus,
    Problem,
    RealType,
    UserType,
    get_environment,
)

from catc.frontend.up_import import up_to_instance
from catc.queries.solve import SolveStatus, solve
from catc.semantics.horizon import state_bound


def _line(goal: Fraction | int, step: int = 1, guarded: bool = True) -> Problem:
    """x (an unbounded real) starts at 0; ``up`` adds ``step`` while x ≤ 20 − step, ``down``
    takes ``step`` while x ≥ step. Unguarded (``guarded=False``), ``up`` may always fire."""
    x = Fluent("x", RealType())
    p = Problem("line")
    p.add_fluent(x, default_initial_value=0)
    up = InstantaneousAction("up")
    if guarded:
        up.add_precondition(LE(x, 20 - step))
    up.add_increase_effect(x, step)
    down = InstantaneousAction("down")
    down.add_precondition(GE(x, step))
    down.add_decrease_effect(x, step)
    p.add_actions([up, down])
    p.add_goal(Equals(x, goal))
    return p


def _counters(n: int, max_int: int) -> Problem:
    """IPC 2023's counters, written by hand: n counters from 0, ``increment`` adds 1 when
    value + 1 ≤ max_int, ``decrement`` takes 1 when value ≥ 1; the goal orders the values
    strictly (c0 + 1 ≤ c1, c1 + 1 ≤ c2, ...)."""
    counter = UserType("counter")
    value = Fluent("value", RealType(), c=counter)
    most = Fluent("max_int", RealType())
    p = Problem("counters")
    cs = [Object(f"c{i}", counter) for i in range(n)]
    p.add_objects(cs)
    p.add_fluent(value, default_initial_value=0)
    p.add_fluent(most, default_initial_value=max_int)
    inc = InstantaneousAction("increment", c=counter)
    inc.add_precondition(LE(Plus(value(inc.parameter("c")), 1), most))
    inc.add_increase_effect(value(inc.parameter("c")), 1)
    dec = InstantaneousAction("decrement", c=counter)
    dec.add_precondition(GE(value(dec.parameter("c")), 1))
    dec.add_decrease_effect(value(dec.parameter("c")), 1)
    p.add_actions([inc, dec])
    for a, b in itertools.pairwise(cs):
        p.add_goal(LE(Plus(value(a), 1), value(b)))
    return p


def _inst(problem: Problem):
    get_environment().credits_stream = None
    return up_to_instance(problem)[0]


def test_the_guards_and_the_lattice_count_the_states():
    """Steps of 1 guarded to [0, 20]: the 21 integers 0..20. Steps of 2 from 0: the 11 even
    ones. An unguarded ``up``: x grows without bound, no count. counters(3, max_int=1): each
    of the three values within [0, 1], 2·2·2 = 8 (max_int is static: one value)."""
    assert all(r.lower is None and r.upper is None for r in _inst(_line(7)).resources.values())
    assert state_bound(_inst(_line(7)), 1000) == 21
    assert state_bound(_inst(_line(7, step=2)), 1000) == 11
    assert state_bound(_inst(_line(7, guarded=False)), 1000) is None
    assert state_bound(_inst(_counters(3, 1)), 1000) == 8
    assert state_bound(_inst(_line(7)), 20) is None  # more than asked for: no bound


@pytest.mark.parametrize("sequential", [True, False])
def test_the_deepening_stops_at_the_state_bound_with_a_final_unsat(sequential):
    """x = 21/2 is no integer: no plan. The line has 21 states, so the SMT route deepens to 20
    steps only (horizons 0..20: 21 checks, not 41) and the UNSAT is final (today: not final,
    every horizon up to 40 tried)."""
    inst = _inst(_line(Fraction(21, 2)))
    r = solve(inst, horizon=40, sequential=sequential, strategy="incremental")
    assert r.status is SolveStatus.UNSAT and r.final
    assert r.horizons_tried == 21
    assert "at most 21 states" in (r.reason or "")


def test_a_plan_as_long_as_the_state_bound_allows_is_still_found():
    """x = 20 needs 20 ups (each adds 1; downs only go back), exactly N − 1 for the 21 states:
    the last horizon the deepening tries."""
    r = solve(_inst(_line(20)), horizon=40, sequential=True, strategy="incremental")
    assert r.status is SolveStatus.SAT and r.plan is not None and len(r.plan) == 20


def test_counters_with_max_int_too_small_are_proven_unsolvable_by_the_smt_route():
    """Three strictly increasing values ≥ 0 need the last ≥ 2; max_int = 1 keeps every value
    ≤ 1: no plan of any length, final. With max_int = 2, 0 < 1 < 2 takes 1 + 2 = 3 increments
    (the shortest: c1 must rise once and c2 twice)."""
    for sequential in (True, False):
        r = solve(_inst(_counters(3, 1)), horizon=40, sequential=sequential, strategy="incremental", presolve=False)
        assert r.status is SolveStatus.UNSAT and r.final
    r = solve(_inst(_counters(3, 2)), horizon=40, sequential=True, strategy="incremental")
    assert r.status is SolveStatus.SAT and r.plan is not None and len(r.plan) == 3


def test_the_engine_searches_no_further_than_the_inferred_state_count():
    """The line of 21 states through the engine, x = 21/2: its default horizon is 20 (not
    200), and "no plan within 20 actions" is a proof for every length."""
    env = get_environment()
    if "catc" not in env.factory.engines:
        env.factory.add_engine("catc", "catc.interfaces.up_engine", "CatcEngine")
    with OneshotPlanner(name="catc") as planner:
        r = planner.solve(_line(Fraction(21, 2)), timeout=60)
    assert r.status is Status.UNSOLVABLE_PROVEN
    log = "\n".join(m.message for m in r.log_messages)
    assert "at most 21 states" in log and "no plan within 20 actions" in log
