"""The ranges every reachable state keeps on numbers (catc.semantics.bounds.numeric_ranges),
the one derivation the forward search, the state bound and the churn search share: each
expected range argued by hand in the test's docstring."""

from __future__ import annotations

from catc import ir
from catc.api import loads
from catc.semantics.bounds import numeric_ranges, ranges
from catc.semantics.validate import initial_state

TANK = """
(define (domain tank) (:requirements :numeric :recomposition)
  (:resources (level real) (cap real) (spent real) (mode real))
  (:morphism fill :precondition (<= (+ level 3) cap) :effect (and (increase level 3) (increase spent 1)))
  (:morphism drain :precondition (> level 1) :effect (decrease level 2))
  (:morphism reset :effect (assign mode 7)))
(define (problem p) (:domain tank) (:init (= level 4) (= cap 10) (= spent 0) (= mode 2)) (:goal (= level 5)))
"""


def _inst(text: str) -> ir.Instance:
    return loads({"tank.cat": text}, "tank.cat").instance


def test_guards_changes_and_initial_values_bound_each_number():
    """level starts at 4; fill adds 3 where level + 3 ≤ cap, cap never written (static 10):
    level ≤ 7 before, ≤ 10 after; drain takes 2 where level > 1 (read as ≥ 1): ≥ −1 after.
    So level ∈ [−1, 10]. cap: never written, [10, 10]. spent: only raised by an unguarded
    increase: ≥ 0, no upper bound. mode: assigned 7 only: [2, 7]."""
    inst = _inst(TANK)
    got = ranges(inst, initial_state(inst))
    assert got == {"level": (-1, 10), "cap": (10, 10), "spent": (0, None), "mode": (2, 7)}


def test_a_non_constant_change_or_an_unguarded_decrease_gives_no_bound():
    """drain by ``spent`` (not a constant): level has no range at all. drain without its
    guard: no lower bound (level may fall forever), the upper one stays (10)."""
    by_spent = _inst(TANK.replace("(decrease level 2)", "(decrease level spent)"))
    assert ranges(by_spent, initial_state(by_spent))["level"] == (None, None)
    unguarded = _inst(TANK.replace(":precondition (> level 1) ", ""))
    assert ranges(unguarded, initial_state(unguarded))["level"] == (None, 10)


def test_a_resource_left_out_of_the_numbers_is_no_constant_to_the_guards():
    """Without cap among the numbers (as for a number with no initial value), fill's guard
    reads two unknowns: no upper bound on level; the lower one (drain's) stays."""
    inst = _inst(TANK)
    init = initial_state(inst)
    got = numeric_ranges(inst, {"level": init["level"], "spent": init["spent"]})
    assert got == {"level": (-1, None), "spent": (0, None)}
