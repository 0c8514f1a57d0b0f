"""The SMT route's proofs that no composition of any length exists (issue 27), where the
reachable-state bound does not apply: a path visiting no state twice that no horizon has
(catc.queries.solve._Search._no_simple_path) and a sum of numbers that never grows
(catc.semantics.bounds.conserved_sums). Every answer is argued by hand in the test's
docstring; the statuses are asserted, never the time."""

from __future__ import annotations

from fractions import Fraction

from catc import ir
from catc.api import loads
from catc.queries.solve import SolveStatus, solve
from catc.semantics.bounds import conserved_sums, sum_refutation
from catc.semantics.horizon import state_bound
from catc.semantics.validate import initial_state, validate


def _token(goal: str) -> ir.Instance:
    """A token on a line of six places p1..p6, moved one place right or left: each move
    clears the place it leaves and sets the next, so exactly one place holds it in every
    reachable state (6 states), although 6 Booleans make 64 combinations."""
    moves = []
    for i in range(1, 6):
        moves.append(f"(:morphism r{i} :precondition p{i} :effect (and (assign p{i} false) (assign p{i + 1} true)))")
        moves.append(
            f"(:morphism l{i} :precondition p{i + 1} :effect (and (assign p{i + 1} false) (assign p{i} true)))"
        )
    text = f"""
(define (domain token) (:requirements :recomposition)
  (:resources {" ".join(f"(p{i} bool)" for i in range(1, 7))})
  {" ".join(moves)})
(define (problem t) (:domain token) (:init (= p1 true)) (:goal {goal}))
"""
    return loads({"token.cat": text}, "token.cat").instance


def test_a_goal_no_path_reaches_is_final_once_no_path_visits_no_state_twice():
    """p1 and p2 together: never (one token). Relaxed reachability cannot tell (each is
    reachable alone), the use limits are unlimited and the state bound counts 2⁶ = 64 > 31
    states for horizon 30, so before this the deepening ended UNSAT but not final. The
    token's states lie on a line of 6, so no path visits 9 distinct states (8 steps): the
    check after horizon 8 (the first of the schedule) has no such path, and the UNSAT is
    final — within 9 horizons (0..8), not 31."""
    inst = _token("(and p1 p2)")
    assert state_bound(inst, 31) is None
    r = solve(inst, horizon=30, sequential=True)
    assert r.status is SolveStatus.UNSAT and r.final
    assert r.horizons_tried == 9
    assert "visits no state twice" in (r.reason or "")


def test_the_same_line_still_finds_its_shortest_plan():
    """p6 from p1: five moves right, r1..r5, and no fewer (each moves the token one place)."""
    inst = _token("p6")
    r = solve(inst, horizon=30, sequential=True)
    assert r.status is SolveStatus.SAT and r.plan is not None
    assert [a.morphism for step in r.plan.steps for a in step] == ["r1", "r2", "r3", "r4", "r5"]
    assert validate(inst, r.plan, horizon=30, sequential=True).ok


FARMS = """
(define (domain farms) (:requirements :numeric :recomposition)
  (:resources (x0 real) (x1 real) (x2 real) (cost real))
  (:morphism slow01 :precondition (>= x0 1) :effect (and (decrease x0 1) (increase x1 1) (increase cost 1)))
  (:morphism slow10 :precondition (>= x1 1) :effect (and (decrease x1 1) (increase x0 1) (increase cost 1)))
  (:morphism slow12 :precondition (>= x1 1) :effect (and (decrease x1 1) (increase x2 1) (increase cost 1)))
  (:morphism slow21 :precondition (>= x2 1) :effect (and (decrease x2 1) (increase x1 1) (increase cost 1)))
  (:morphism fast01 :precondition (>= x0 4) :effect (and (decrease x0 4) (increase x1 2) (increase cost 1))))
(define (problem p) (:domain farms) (:init (= x0 WORKERS) (= x1 0) (= x2 0) (= cost 0))
  (:goal (and (>= x0 1) (>= x1 1) (>= x2 1))))
"""


def _farms(workers: int) -> ir.Instance:
    return loads({"farms.cat": FARMS.replace("WORKERS", str(workers))}, "farms.cat").instance


def test_farmland_short_of_workers_is_final_by_the_sum_that_never_grows():
    """IPC 2023 farmland's moves on three farms: a slow move keeps the workers' total, a fast
    one loses two of four, so x0 + x1 + x2 never grows (cost, only raised, is no member). The
    goal needs each farm ≥ 1, a total ≥ 3; two workers never make it. No state bound (x1 and
    x2 have no guarded upper bound, cost none at all): before this, UNSAT at every horizon,
    never final. Now final with nothing deepened."""
    inst = _farms(2)
    assert conserved_sums(inst, {n: v for n, v in initial_state(inst).items()}) == [
        (("x0", "x1", "x2"), Fraction(2), -1)
    ]
    r = solve(inst, horizon=20, sequential=True)
    assert r.status is SolveStatus.UNSAT and r.final
    assert r.horizons_tried == 0
    assert "never grows from its initial 2" in (r.reason or "")


def test_farmland_with_enough_workers_is_solved_as_before():
    """Three workers on x0: one slow move to x1, one more, then x1 → x2: 3 steps, and no
    fewer (x2 is two moves away, x1 needs its own worker). The sum refutes nothing here."""
    inst = _farms(3)
    assert sum_refutation(inst, initial_state(inst)) is None
    r = solve(inst, horizon=20, sequential=True)
    assert r.status is SolveStatus.SAT and r.plan is not None and len(r.plan) == 3
    assert validate(inst, r.plan, horizon=20, sequential=True).ok


def test_a_sum_with_an_assigned_member_or_a_raising_morphism_is_no_invariant():
    """An assignment of x2 (a reset to 5) can raise the total: no sum. A morphism adding a
    worker (x0 + 1) makes the total grow: no sum that never grows; it never shrinks either
    (fast01 loses two)."""
    reset = FARMS.replace(
        "(increase x2 1) (increase cost 1)))\n  (:morphism slow21",
        "(assign x2 5) (increase cost 1)))\n  (:morphism slow21",
    )
    inst = loads({"farms.cat": reset.replace("WORKERS", "2")}, "farms.cat").instance
    assert conserved_sums(inst, dict(initial_state(inst))) == []
    hire = FARMS.replace("(:morphism fast01", "(:morphism hire :effect (increase x0 1))\n  (:morphism fast01")
    inst = loads({"farms.cat": hire.replace("WORKERS", "2")}, "farms.cat").instance
    assert conserved_sums(inst, dict(initial_state(inst))) == []
