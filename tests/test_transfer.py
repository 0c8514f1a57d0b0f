"""The transfer function shared by the abstract analyses (catc.semantics.transfer): increments
summed, then an assignment overriding them; a dropped effect joined with the value it would
change.  Expected values are worked out by hand, over a toy domain of possible numbers and over
the analyses' own intervals and may/must sets (issue 23)."""

from __future__ import annotations

from fractions import Fraction

from catc import ir
from catc.semantics import transfer
from catc.semantics.relaxed import VALUES, Finite, Interval, SetValue, Value

F = Fraction
K = ir.EffectKind
_DUMMY = ir.Const(F(0), ir.REAL)  # the transfer function reads an effect's kind and resource only


def _eff(kind: ir.EffectKind, resource: str) -> ir.Effect:
    return ir.Effect(kind, resource, _DUMMY, f"eff/m/{resource}")


class _Numbers:
    """Possible values of numbers, as finite sets: exact, and unlike intervals nothing merges."""

    def join(self, a: frozenset[Fraction], b: frozenset[Fraction]) -> frozenset[Fraction]:
        return a | b

    def change(self, kind: ir.EffectKind, old: frozenset[Fraction], amount: frozenset[Fraction]) -> frozenset[Fraction]:
        sign = 1 if kind is K.INCREASE else -1
        return frozenset(o + sign * a for o in old for a in amount)


NUMBERS = _Numbers()


def _num(*xs: int) -> frozenset[Fraction]:
    return frozenset(F(x) for x in xs)


def _post_numbers(state: dict[str, frozenset[Fraction]], *writes: tuple[K, str, frozenset[Fraction], bool]):
    return transfer.post(NUMBERS, [(_eff(k, r), v, sure) for k, r, v, sure in writes], state.__getitem__)


# ---------------------------------------------------------------- the rule, over possible numbers


def test_increments_are_summed():
    # x = 1; +2, +3, −1 in one step: 1 + 2 + 3 − 1 = 5
    state = {"x": _num(1), "y": _num(7)}
    out = _post_numbers(
        state, (K.INCREASE, "x", _num(2), True), (K.INCREASE, "x", _num(3), True), (K.DECREASE, "x", _num(1), True)
    )
    assert out == {"x": _num(5)}  # y is not written: not in the answer


def test_an_assignment_overrides_increments_whatever_their_order():
    # the assignment's value is the new value, before or after the increments in the list
    state = {"x": _num(1)}
    assert _post_numbers(state, (K.INCREASE, "x", _num(2), True), (K.ASSIGN, "x", _num(10), True)) == {"x": _num(10)}
    assert _post_numbers(state, (K.ASSIGN, "x", _num(10), True), (K.INCREASE, "x", _num(2), True)) == {"x": _num(10)}


def test_assignments_read_the_old_state_not_each_other():
    # y := 4 and an increment of x: each resource on its own; the old values are not changed
    state = {"x": _num(1), "y": _num(0)}
    out = _post_numbers(state, (K.ASSIGN, "y", _num(4), True), (K.INCREASE, "x", _num(2, 3), True))
    assert out == {"y": _num(4), "x": _num(3, 4)}
    assert state == {"x": _num(1), "y": _num(0)}


def test_a_dropped_effect_may_or_may_not_happen():
    state = {"x": _num(1)}
    # +2 surely, +3 maybe: 1 + 2 = 3, or 3 + 3 = 6
    out = _post_numbers(state, (K.INCREASE, "x", _num(2), True), (K.INCREASE, "x", _num(3), False))
    assert out == {"x": _num(3, 6)}
    # a dropped assignment: the new value, or the value it would have replaced
    assert _post_numbers(state, (K.ASSIGN, "x", _num(10), False)) == {"x": _num(1, 10)}


# ---------------------------------------------------------------- the analyses' domain: intervals


def _post(state: dict[str, Value], *writes: tuple[K, str, Value, bool]) -> dict[str, Value]:
    return transfer.post(VALUES, [(_eff(k, r), v, sure) for k, r, v, sure in writes], state.__getitem__)


def test_intervals():
    state: dict[str, Value] = {"x": Interval(F(0), F(5))}
    # [0, 5] + [1, 2] − [0, 1] = [0 + 1 − 1, 5 + 2 − 0] = [0, 7]
    out = _post(state, (K.INCREASE, "x", Interval(F(1), F(2)), True), (K.DECREASE, "x", Interval(F(0), F(1)), True))
    assert out == {"x": Interval(F(0), F(7))}
    # an increment then an assignment of [4, 4]: [4, 4]
    out = _post(state, (K.INCREASE, "x", Interval(F(1), F(2)), True), (K.ASSIGN, "x", Interval(F(4), F(4)), True))
    assert out == {"x": Interval(F(4), F(4))}
    # a dropped increment of [1, 2]: [0, 5] joined with [1, 7] = [0, 7]
    assert _post(state, (K.INCREASE, "x", Interval(F(1), F(2)), False)) == {"x": Interval(F(0), F(7))}
    # an unbounded amount: unbounded above only
    assert _post(state, (K.INCREASE, "x", Interval(F(1), None), True)) == {"x": Interval(F(1), None)}


# ---------------------------------------------------------------- may/must sets and possible values


def test_sets():
    state: dict[str, Value] = {"s": SetValue(frozenset({"a"}), frozenset({"a"}))}
    a, b = Finite(frozenset({"a"})), Finite(frozenset({"b"}))
    # {a} + b − a: may hold a (the removal is of the old must) and b; surely holds b only
    out = _post(state, (K.ADD, "s", b, True), (K.REMOVE, "s", a, True))
    assert out == {"s": SetValue(frozenset({"a", "b"}), frozenset({"b"}))}
    # adding one of b, c: may hold both, surely neither
    out = _post(state, (K.ADD, "s", Finite(frozenset({"b", "c"})), True))
    assert out == {"s": SetValue(frozenset({"a", "b", "c"}), frozenset({"a"}))}
    # a dropped add of b: may hold b, surely holds a only
    assert _post(state, (K.ADD, "s", b, False)) == {"s": SetValue(frozenset({"a", "b"}), frozenset({"a"}))}
    # removing an unknown element: nothing is sure any more
    assert _post(state, (K.REMOVE, "s", Finite(None), True)) == {"s": SetValue(frozenset({"a"}), frozenset())}


def test_possible_values_of_a_boolean_under_a_dropped_assignment():
    state: dict[str, Value] = {"p": Finite(frozenset({False}))}
    assert _post(state, (K.ASSIGN, "p", Finite(frozenset({True})), True)) == {"p": Finite(frozenset({True}))}
    assert _post(state, (K.ASSIGN, "p", Finite(frozenset({True})), False)) == {"p": Finite(frozenset({True, False}))}
