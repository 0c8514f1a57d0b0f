"""Relaxed reachability: a cheap, sound proof that no composition exists, at any horizon.

An abstract interpretation of the composition semantics (docs/semantics.md §4) in the spirit of
the relaxed planning graphs of numeric planners (Metric-FF, ENHSP's h^max): every resource
holds an over-approximation of the values it can ever take — an interval for a number (with
±∞), a set of possible values for a Boolean or a symbol, the elements it may and must hold for
a set — starting from the initial state and grown, morphism by morphism, until nothing
changes.  Deletes are kept only where they cannot hurt (an interval joins the old and the new
value; a set's may-hold elements only grow), and an interval that keeps growing is widened to
infinity (then cut by the resource's bounds), so the fixpoint is reached in a few rounds.

A morphism may fire only if each of its preconditions can hold in that over-approximation; a
goal can be reached only if each goal literal can hold in it.  When one cannot, *no* plan of
any length satisfies the constraints considered — the proof is sound for every horizon, for
the sequential and the parallel semantics alike (each parallel step is a sequence of single
relaxed applications, since every morphism of a step reads the same state).

The analysis speaks the labels of :mod:`catc.ir.labels` (``pre/m/i``, ``eff/m/i``,
``init/r``, ``goal/i``, ``bound/m/p``, ``bounds/r``, ``uses/m``): :func:`refute` takes the set
of labels to enforce, as :class:`catc.smt.labelled.LabelledModel` does, so the lifelong
queries use it to settle most unsat-core tests without a solver (``catc diagnose``) and
``catc solve`` uses it to answer an infeasible problem before encoding it.  A dropped initial
value leaves its resource free; a dropped effect may or may not happen; a dropped bound no
longer cuts.  The analysis is incomplete by design — it answers "refuted" or "don't know" —
and tests check every refutation against the SMT encoding (tests/test_relaxed.py).
"""

from __future__ import annotations

from collections.abc import Collection, Iterable, Iterator, Mapping
from fractions import Fraction
from math import ceil, floor
from typing import TypeAlias, assert_never

from catc import ir
from catc.ir import SortKind
from catc.semantics import transfer
from catgrammar import limits

# ---------------------------------------------------------------- extended numbers

#: A bound: a rational, or None for -∞ (as a lower bound) / +∞ (as an upper bound).
Bound: TypeAlias = Fraction | None
_INF = "inf"
_NINF = "-inf"
Ext: TypeAlias = Fraction | str  # a rational or ±∞, inside interval products


def _ext_lo(b: Bound) -> Ext:
    return _NINF if b is None else b


def _ext_hi(b: Bound) -> Ext:
    return _INF if b is None else b


def _key(x: Ext) -> tuple[int, Fraction]:
    if x == _NINF:
        return (-1, Fraction(0))
    if x == _INF:
        return (1, Fraction(0))
    assert isinstance(x, Fraction)
    return (0, x)


def _sign(x: Ext) -> int:
    if isinstance(x, Fraction):
        return (x > 0) - (x < 0)
    return 1 if x == _INF else -1


def _mul(a: Ext, b: Ext) -> Ext:
    """Products of interval endpoints: 0·∞ = 0 (∞ is never attained)."""
    if isinstance(a, Fraction) and isinstance(b, Fraction):
        return a * b
    s = _sign(a) * _sign(b)
    return Fraction(0) if s == 0 else (_INF if s > 0 else _NINF)


# ---------------------------------------------------------------- abstract values


class _Record:
    """Immutable value records, compared by kind and fields (no dataclasses: ``catc solve``'s
    fast route imports neither them nor click, tests/test_entry.py)."""

    __slots__ = ()
    _fields: tuple[str, ...] = ()

    def _key(self) -> tuple[object, ...]:
        return (type(self), *(getattr(self, f) for f in self._fields))

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Record) and self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def __repr__(self) -> str:
        return f"{type(self).__name__}({', '.join(f'{f}={getattr(self, f)!r}' for f in self._fields)})"


class Interval(_Record):
    """The closed interval [lo, hi] of a number (None = unbounded on that side)."""

    __slots__ = ("lo", "hi")
    _fields = ("lo", "hi")

    def __init__(self, lo: Bound = None, hi: Bound = None) -> None:
        self.lo = lo
        self.hi = hi

    @property
    def empty(self) -> bool:
        return self.lo is not None and self.hi is not None and self.lo > self.hi

    def join(self, other: Interval) -> Interval:
        if self.empty:
            return other
        if other.empty:
            return self
        lo = None if self.lo is None or other.lo is None else min(self.lo, other.lo)
        hi = None if self.hi is None or other.hi is None else max(self.hi, other.hi)
        return Interval(lo, hi)

    def meet(self, lo: Bound, hi: Bound) -> Interval:
        new_lo = lo if self.lo is None else (self.lo if lo is None else max(self.lo, lo))
        new_hi = hi if self.hi is None else (self.hi if hi is None else min(self.hi, hi))
        return Interval(new_lo, new_hi)

    def integral(self) -> Interval:
        """Rounded inwards to the integers (an Int resource's values)."""
        return Interval(
            None if self.lo is None else Fraction(ceil(self.lo)), None if self.hi is None else Fraction(floor(self.hi))
        )

    def widen(self, newer: Interval) -> Interval:
        """Standard interval widening: a side that grew goes to infinity."""
        lo = None if newer.lo is None or (self.lo is not None and newer.lo < self.lo) else newer.lo
        hi = None if newer.hi is None or (self.hi is not None and newer.hi > self.hi) else newer.hi
        return Interval(lo, hi)

    @staticmethod
    def hull(points: Iterable[Ext]) -> Interval:
        pts = sorted(points, key=_key)
        lo, hi = pts[0], pts[-1]
        return Interval(lo if isinstance(lo, Fraction) else None, hi if isinstance(hi, Fraction) else None)


class Finite(_Record):
    """The possible values of a Boolean or a symbol; ``values`` None = any value."""

    __slots__ = ("values",)
    _fields = ("values",)

    def __init__(self, values: frozenset[object] | None) -> None:
        self.values = values

    def join(self, other: Finite) -> Finite:
        if self.values is None or other.values is None:
            return Finite(None)
        return Finite(self.values | other.values)


class SetValue(_Record):
    """A set: the elements it may hold (None = any) and those it surely holds."""

    __slots__ = ("may", "must")
    _fields = ("may", "must")

    def __init__(self, may: frozenset[object] | None, must: frozenset[object]) -> None:
        self.may = may
        self.must = must

    def join(self, other: SetValue) -> SetValue:
        may = None if self.may is None or other.may is None else self.may | other.may
        return SetValue(may, self.must & other.must)


Value: TypeAlias = Interval | Finite | SetValue
TRUTH = Finite(frozenset({True, False}))
TRUE, FALSE = Finite(frozenset({True})), Finite(frozenset({False}))


def top(sort: ir.Sort) -> Value:
    """Every value of ``sort``."""
    if sort.is_numeric:
        return Interval()
    if sort.kind is SortKind.BOOL:
        return TRUTH
    if sort.kind is SortKind.SET:
        return SetValue(None, frozenset())
    return Finite(None)


def _join(a: Value, b: Value) -> Value:
    return a.join(b)  # type: ignore[arg-type]  # one sort, one kind of value


def can_hold(v: Value) -> bool:
    return isinstance(v, Finite) and (v.values is None or True in v.values)


def can_fail(v: Value) -> bool:
    return isinstance(v, Finite) and (v.values is None or False in v.values)


# ---------------------------------------------------------------- evaluation


class _Eval:
    """Evaluates IR expressions over an abstract state and abstract parameters."""

    def __init__(self, state: Mapping[str, Value], params: Mapping[str, Value]) -> None:
        self.state = state
        self.params = params

    def __call__(self, e: ir.Expr) -> Value:
        match e:
            case ir.Const():
                return _const(e)
            case ir.ResourceRef():
                return self.state.get(e.name, top(e.sort))
            case ir.ParamRef():
                return self.params.get(e.name, top(e.sort))
            case ir.SetLit():
                return _set_of([self(x) for x in e.elements])
            case ir.Arith():
                return self.arith(e)
            case ir.Compare():
                return _compare(e.op, self(e.left), self(e.right))
            case ir.BoolOp():
                return self.boolop(e)
            case ir.Ite():
                c = self(e.cond)
                parts = ([self(e.then)] if can_hold(c) else []) + ([self(e.orelse)] if can_fail(c) else [])
                out = parts[0] if parts else top(e.sort)
                for p in parts[1:]:
                    out = _join(out, p)
                return out
            case ir.Member():
                return _member(self(e.element), self(e.set))
            case ir.Uses():
                return Interval(Fraction(0), None)
            case ir.TotalChurn() | ir.TotalCost() | ir.ParamValue():
                return top(e.sort)  # objective-only terms: anything of their sort
            case _:
                assert_never(e)

    def boolop(self, e: ir.BoolOp) -> Value:
        args = [self(a) for a in e.args]
        if e.op is ir.BoolOpKind.NOT:
            return _not(args[0])
        if e.op is ir.BoolOpKind.IMPLY:
            args = [_not(args[0]), *args[1:]]
            return _or(args)
        if e.op is ir.BoolOpKind.AND:
            return _not(_or([_not(a) for a in args]))
        return _or(args)

    def arith(self, e: ir.Arith) -> Value:
        args = [self(a) for a in e.args]
        if not all(isinstance(a, Interval) and not a.empty for a in args):
            return top(e.sort)
        ivs = [a for a in args if isinstance(a, Interval)]
        out = _arith(e.op, ivs)
        return out.integral() if e.sort.kind is SortKind.INT and e.op is not ir.ArithOp.DIV else out


def _const(e: ir.Const) -> Value:
    v = e.value
    if isinstance(v, bool):
        return Finite(frozenset({v}))
    if isinstance(v, Fraction):
        return Interval(v, v)
    return Finite(frozenset({v}))


def _set_of(elements: list[Value]) -> SetValue:
    may: set[object] = set()
    must: set[object] = set()
    for x in elements:
        if not isinstance(x, Finite) or x.values is None:
            return SetValue(None, frozenset(must))
        may |= x.values
        if len(x.values) == 1:
            must |= x.values
    return SetValue(frozenset(may), frozenset(must))


def _not(v: Value) -> Value:
    if not isinstance(v, Finite) or v.values is None:
        return TRUTH
    return Finite(frozenset(not x for x in v.values))


def _or(args: list[Value]) -> Value:
    out: set[object] = set()
    if any(can_hold(a) for a in args):
        out.add(True)
    if all(can_fail(a) for a in args):
        out.add(False)
    return Finite(frozenset(out))


def _arith(op: ir.ArithOp, args: list[Interval]) -> Interval:
    if op is ir.ArithOp.ADD or (op is ir.ArithOp.SUB and len(args) > 1):
        first, rest = args[0], args[1:]
        if op is ir.ArithOp.SUB:
            rest = [Interval(None if a.hi is None else -a.hi, None if a.lo is None else -a.lo) for a in rest]
        lo: Bound = first.lo
        hi: Bound = first.hi
        for a in rest:
            lo = None if lo is None or a.lo is None else lo + a.lo
            hi = None if hi is None or a.hi is None else hi + a.hi
        return Interval(lo, hi)
    if op is ir.ArithOp.SUB:  # negation
        a = args[0]
        return Interval(None if a.hi is None else -a.hi, None if a.lo is None else -a.lo)
    if op is ir.ArithOp.MUL:
        out = args[0]
        for a in args[1:]:
            out = _times(out, a)
        return out
    if op is ir.ArithOp.DIV:
        num, den = args
        if (den.lo is None or den.lo <= 0) and (den.hi is None or den.hi >= 0):
            return Interval()  # the divisor may be 0 (or approach it)
        inverse = Interval.hull([_inv(den.lo), _inv(den.hi)])
        return _times(num, inverse)
    pick = min if op is ir.ArithOp.MIN else max
    los, his = [a.lo for a in args], [a.hi for a in args]
    lo_ext = pick((_ext_lo(x) for x in los), key=_key)
    hi_ext = pick((_ext_hi(x) for x in his), key=_key)
    return Interval(lo_ext if isinstance(lo_ext, Fraction) else None, hi_ext if isinstance(hi_ext, Fraction) else None)


def _inv(b: Bound) -> Ext:
    return Fraction(0) if b is None else 1 / b


def _times(a: Interval, b: Interval) -> Interval:
    return Interval.hull(_mul(x, y) for x in (_ext_lo(a.lo), _ext_hi(a.hi)) for y in (_ext_lo(b.lo), _ext_hi(b.hi)))


def _compare(op: ir.CmpOp, a: Value, b: Value) -> Value:
    if isinstance(a, Interval) and isinstance(b, Interval):
        return _compare_numbers(op, a, b)
    if op is not ir.CmpOp.EQ or not isinstance(a, Finite) or not isinstance(b, Finite):
        return TRUTH
    if a.values is None or b.values is None:
        return TRUTH
    out: set[object] = set()
    if a.values & b.values:
        out.add(True)
    if not (len(a.values) == 1 and a.values == b.values):
        out.add(False)
    return Finite(frozenset(out))


def _le(x: Ext, y: Ext, strict: bool) -> bool:
    """x ≤ y (x < y when strict) for extended numbers, where an infinite end is never attained."""
    if x == _NINF or y == _INF:
        return True
    if x == _INF or y == _NINF:
        return False
    assert isinstance(x, Fraction) and isinstance(y, Fraction)
    return x < y if strict else x <= y


def _compare_numbers(op: ir.CmpOp, a: Interval, b: Interval) -> Value:
    if a.empty or b.empty:
        return Finite(frozenset())
    if op in (ir.CmpOp.GT, ir.CmpOp.GE):
        a, b = b, a
        op = ir.CmpOp.LT if op is ir.CmpOp.GT else ir.CmpOp.LE
    out: set[object] = set()
    if op is ir.CmpOp.EQ:
        if _le(_ext_lo(a.lo), _ext_hi(b.hi), False) and _le(_ext_lo(b.lo), _ext_hi(a.hi), False):
            out.add(True)
        if not (a.lo is not None and a.lo == a.hi == b.lo == b.hi):
            out.add(False)
        return Finite(frozenset(out))
    strict = op is ir.CmpOp.LT
    if _le(_ext_lo(a.lo), _ext_hi(b.hi), strict):  # some a below some b
        out.add(True)
    if _le(_ext_lo(b.lo), _ext_hi(a.hi), not strict):  # some a at or above (above) some b
        out.add(False)
    return Finite(frozenset(out))


def _member(element: Value, s: Value) -> Value:
    if not isinstance(s, SetValue) or not isinstance(element, Finite) or element.values is None:
        return TRUTH
    out: set[object] = set()
    if s.may is None or element.values & s.may:
        out.add(True)
    if not (len(element.values) == 1 and element.values <= s.must):
        out.add(False)
    return Finite(frozenset(out))


# ---------------------------------------------------------------- the fixpoint


class Refutation(_Record):
    """Why no composition exists: a sentence, the label of the construct that cannot hold,
    and the analysis that proved it (``by``, as the answer names it)."""

    __slots__ = ("reason", "label", "by")
    _fields = ("reason", "label", "by")

    def __init__(self, reason: str, label: str | None = None, by: str = "relaxed reachability") -> None:
        self.reason = reason
        self.label = label
        self.by = by


#: After this many changes of one interval, its growing sides are widened to infinity.
WIDEN_AFTER = 3


class RelaxedAnalysis:
    """The relaxed reachability fixpoint of one instance under a set of enforced labels.

    ``components`` (a composition, as ``catc diagnose --relative-to``): only these morphisms
    may fire, and each must fire."""

    def __init__(self, inst: ir.Instance, enforced: Collection[str], components: Collection[str] | None = None) -> None:
        self.inst = inst
        self.on = enforced
        self.components = None if components is None else frozenset(components)
        self.fired: dict[str, None] = {}  # morphisms that may fire, in the order they first may
        self.state: dict[str, Value] = {}
        self._changes: dict[str, int] = {}
        self.refutation: Refutation | None = self._run()

    # -- the initial state and the bounds
    def _bounds(self, r: ir.Resource) -> tuple[Bound, Bound]:
        if r.bounds_label not in self.on:
            return None, None
        return r.lower, r.upper

    def _cut(self, r: ir.Resource, v: Value) -> Value:
        if isinstance(v, Interval):
            lo, hi = self._bounds(r)
            v = v.meet(lo, hi)
            return v.integral() if r.sort.kind is SortKind.INT else v
        return v

    def _initial(self) -> Refutation | None:
        for r in self.inst.resources.values():
            init = self.inst.problem.init.get(r.name)
            v = _Eval({}, {})(init.value) if init is not None and init.label in self.on else top(r.sort)
            v = self._cut(r, v)
            if isinstance(v, Interval) and v.empty:
                why = "its initial value is outside its bounds" if init is not None else "its bounds are empty"
                return Refutation(f"resource '{r.name}': {why}", r.bounds_label)
            self.state[r.name] = v
        return None

    # -- morphisms
    def _params(self, m: ir.Morphism) -> dict[str, Value] | None:
        out: dict[str, Value] = {}
        for p in m.params:
            v = top(p.sort)
            bounded = p.fixed or m.uses != 0  # a switched-off morphism's θ has no constraints
            if isinstance(v, Interval) and bounded and m.bound_label(p.name) in self.on:
                v = v.meet(p.lower, p.upper)
                v = v.integral() if p.sort.kind is SortKind.INT else v
                if v.empty:
                    return None  # no value for θ: the morphism cannot fire
            out[p.name] = v
        return out

    def _may_fire(self, m: ir.Morphism) -> dict[str, Value] | None:
        """θ's values when every enforced precondition of ``m`` can hold (else None)."""
        if self.components is not None and m.name not in self.components:
            return None
        if m.uses == 0 and m.uses_label in self.on:
            return None
        params = self._params(m)
        if params is None:
            return None
        ev = _Eval(self.state, params)
        for lit in m.pre:
            if lit.label in self.on and not can_hold(ev(lit.expr)):
                return None
        return params

    def _post(self, m: ir.Morphism, params: Mapping[str, Value]) -> dict[str, Value]:
        """The values ``m``'s effects may give each resource it writes, as the successor-state
        axioms combine them: increments summed, then an assignment overriding them.  A dropped
        effect may or may not happen."""
        ev = _Eval(self.state, params)
        writes = [(e, ev(e.value), e.label in self.on) for e in m.effects]
        out = transfer.post(VALUES, writes, self.state.__getitem__)
        return {name: self._cut(self.inst.resources[name], v) for name, v in out.items()}

    def _update(self, name: str, new: Value) -> bool:
        old = self.state[name]
        joined = _join(old, new)
        if joined == old:
            return False
        n = self._changes[name] = self._changes.get(name, 0) + 1
        if isinstance(joined, Interval) and isinstance(old, Interval) and n > WIDEN_AFTER:
            r = self.inst.resources[name]
            cut = self._cut(r, old.widen(joined))
            assert isinstance(cut, Interval)
            joined = cut
        self.state[name] = joined
        return True

    def _run(self) -> Refutation | None:
        stop = self._initial()
        if stop is not None:
            return stop
        changed = True
        while changed:
            limits.check_time("relaxed reachability")
            changed = False
            for m in self.inst.morphisms.values():
                params = self._may_fire(m)
                if params is None:
                    continue
                if m.name not in self.fired:
                    self.fired[m.name] = None
                    changed = True
                for name, value in self._post(m, params).items():
                    changed |= self._update(name, value)
        return self._verdict()

    def _verdict(self) -> Refutation | None:
        ev = _Eval(self.state, {})
        for lit in self.inst.problem.goal:
            if lit.label in self.on and not can_hold(ev(lit.expr)):
                return Refutation("the goal can never hold", lit.label)
        for name in sorted(self.components or ()):
            if name in self.inst.morphisms and name not in self.fired:
                return Refutation(f"morphism '{name}' of the composition can never fire", None)
        return None


class _Values:
    """The domain of :class:`Interval`, :class:`Finite` and :class:`SetValue` for the
    transfer function (:mod:`catc.semantics.transfer`)."""

    def join(self, a: Value, b: Value) -> Value:
        return _join(a, b)

    def change(self, kind: ir.EffectKind, old: Value, amount: Value) -> Value:
        return _effect(kind, old, amount)


#: The abstract values as a transfer-function domain (shared with :mod:`catc.smt.counting`).
VALUES = _Values()


def _effect(kind: ir.EffectKind, old: Value, value: Value) -> Value:
    """``old`` after one increase, decrease, add or remove by ``value``."""
    if kind is ir.EffectKind.ASSIGN:
        return value
    if kind in (ir.EffectKind.INCREASE, ir.EffectKind.DECREASE):
        if not isinstance(old, Interval) or not isinstance(value, Interval) or value.empty:
            return Interval()
        op = ir.ArithOp.ADD if kind is ir.EffectKind.INCREASE else ir.ArithOp.SUB
        return _arith(op, [old, value])
    if not isinstance(old, SetValue):
        return SetValue(None, frozenset())
    elems = value.values if isinstance(value, Finite) else None
    if kind is ir.EffectKind.ADD:
        may = None if old.may is None or elems is None else old.may | elems
        sure = elems if elems is not None and len(elems) == 1 else frozenset()
        return SetValue(may, old.must | sure)
    return SetValue(old.may, frozenset() if elems is None else old.must - elems)


def refute(
    inst: ir.Instance, enforced: Collection[str] | None = None, components: Collection[str] | None = None
) -> Refutation | None:
    """A reason no composition of any length satisfies the ``enforced`` labels (default: all
    of them), or None when the relaxation cannot tell."""
    return RelaxedAnalysis(inst, _Everything() if enforced is None else enforced, components).refutation


class _Everything(Collection[str]):
    """Every label (without listing them: the labels' index is for presenting answers)."""

    def __contains__(self, label: object) -> bool:
        return True

    def __iter__(self) -> Iterator[str]:  # pragma: no cover - never iterated
        raise TypeError("every label: not enumerable")

    def __len__(self) -> int:  # pragma: no cover - never measured
        raise TypeError("every label: not countable")
