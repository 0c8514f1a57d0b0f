"""The conditions and effects of a ground task as functions: concrete (of a state tuple,
exact values) and relaxed (of a layer of the interval relaxation)."""

from __future__ import annotations

import itertools
import operator
from collections.abc import Callable
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import ArithOp, BoolOpKind, CmpOp, SortKind
from catc.semantics.search.common import Fn, _arith, _linear, _minus, _num, _Unsupported

_CMP: dict[CmpOp, Callable[[Any, Any], Any]] = {
    CmpOp.EQ: operator.eq,
    CmpOp.LT: operator.lt,
    CmpOp.LE: operator.le,
    CmpOp.GT: operator.gt,
    CmpOp.GE: operator.ge,
}


def _concrete(e: ir.Expr, index: dict[str, int]) -> Fn:
    """``e`` as a function of the state tuple (exact values: Fraction, bool, str)."""
    if isinstance(e, ir.Const):
        v = _num(e.value)
        return lambda s: v
    if isinstance(e, ir.ResourceRef):
        i = index[e.name]
        return lambda s: s[i]
    if isinstance(e, ir.Arith):
        fs = [_concrete(a, index) for a in e.args]
        op = e.op
        if op is ArithOp.ADD and len(fs) == 2:
            a, b = fs
            return lambda s: a(s) + b(s)
        if op is ArithOp.SUB and len(fs) == 2:
            a, b = fs
            return lambda s: a(s) - b(s)
        if op is ArithOp.MUL and len(fs) == 2:
            a, b = fs
            return lambda s: a(s) * b(s)
        return lambda s: _arith(op, [f(s) for f in fs])
    if isinstance(e, ir.Compare):
        a, b = _concrete(e.left, index), _concrete(e.right, index)
        cmp = _CMP[e.op]
        return lambda s: bool(cmp(a(s), b(s)))
    if isinstance(e, ir.BoolOp):
        fs = [_concrete(a, index) for a in e.args]
        if e.op is BoolOpKind.AND:
            return lambda s: all(f(s) for f in fs)
        if e.op is BoolOpKind.OR:
            return lambda s: any(f(s) for f in fs)
        if e.op is BoolOpKind.NOT:
            (f,) = fs
            return lambda s: not f(s)
        *init, last = fs
        return lambda s: (not all(f(s) for f in init)) or last(s)
    if isinstance(e, ir.Ite):
        c, t, o = _concrete(e.cond, index), _concrete(e.then, index), _concrete(e.orelse, index)
        return lambda s: t(s) if c(s) else o(s)
    raise _Unsupported(type(e).__name__)


# ---------------------------------------------------------------- relaxed terms
#
# A relaxed value: a number → (lo, hi), None for an infinite bound; a Boolean → (can be true,
# can be false); a symbol → a frozenset of the names it may hold.

Relaxed = tuple[Any, ...]


def _shift(x: tuple[Any, Any], c: Any) -> tuple[Any, Any]:
    return (None if x[0] is None else x[0] + c, None if x[1] is None else x[1] + c)


def _lo_add(a: Fraction | None, b: Fraction | None) -> Fraction | None:
    return None if a is None or b is None else a + b


def _mul(a: tuple[Any, Any], b: tuple[Any, Any]) -> tuple[Any, Any]:
    if None in a or None in b:
        if a == (0, 0) or b == (0, 0):
            return (0, 0)
        return (None, None)
    ps = [x * y for x in a for y in b]
    return (min(ps), max(ps))


def _div(a: tuple[Any, Any], b: tuple[Any, Any]) -> tuple[Any, Any]:
    lo, hi = b
    if lo is None or hi is None or lo <= 0 <= hi or None in a:
        return (None, None)
    return _mul(a, (Fraction(1) / hi, Fraction(1) / lo))


def _arith_relaxed(op: ArithOp, args: list[tuple[Any, Any]]) -> tuple[Any, Any]:
    if op is ArithOp.ADD:
        lo: Any = 0
        hi: Any = 0
        for a_lo, a_hi in args:
            lo, hi = _lo_add(lo, a_lo), _lo_add(hi, a_hi)
        return (lo, hi)
    if op is ArithOp.SUB:
        first = args[0]
        if len(args) == 1:
            return (None if first[1] is None else -first[1], None if first[0] is None else -first[0])
        rest = _arith_relaxed(ArithOp.ADD, args[1:])
        return (
            _lo_add(first[0], None if rest[1] is None else -rest[1]),
            _lo_add(first[1], None if rest[0] is None else -rest[0]),
        )
    if op is ArithOp.MUL:
        out = args[0]
        for a in args[1:]:
            out = _mul(out, a)
        return out
    if op is ArithOp.DIV:
        out = args[0]
        for a in args[1:]:
            out = _div(out, a)
        return out
    pick = min if op is ArithOp.MIN else max
    los, his = [a[0] for a in args], [a[1] for a in args]
    if op is ArithOp.MIN:
        lo = None if None in los else pick(los)
        hi = pick(h for h in his if h is not None) if any(h is not None for h in his) else None
    else:
        lo = pick(x for x in los if x is not None) if any(x is not None for x in los) else None
        hi = None if None in his else pick(his)
    return (lo, hi)


def _lt(a: Any, b: Any) -> bool:
    """a < b for a lower end ``a`` (None: -∞) and an upper end ``b`` (None: +∞)."""
    return a is None or b is None or a < b


def _le(a: Any, b: Any) -> bool:
    return a is None or b is None or a <= b


def _compare_relaxed(op: CmpOp, a: Any, b: Any, kind: str) -> tuple[bool, bool]:
    if kind == "bool":
        t = (a[0] and b[0]) or (a[1] and b[1])
        f = (a[0] and b[1]) or (a[1] and b[0])
        return (t, f)
    if kind == "symbol":
        return (bool(a & b), not (len(a) == 1 and a == b))
    if op is CmpOp.EQ:
        t = _le(a[0], b[1]) and _le(b[0], a[1])
        f = not (a[0] is not None and a[0] == a[1] == b[0] == b[1])
        return (t, f)
    if op in (CmpOp.GT, CmpOp.GE):
        a, b = b, a
        op = CmpOp.LT if op is CmpOp.GT else CmpOp.LE
    if op is CmpOp.LT:  # a < b can hold when a.lo < b.hi; fail when a.hi >= b.lo
        return (_lt(a[0], b[1]), _le(b[0], a[1]))
    return (_le(a[0], b[1]), _lt(b[0], a[1]))  # a <= b


def _kind(sort: ir.Sort) -> str:
    if sort.kind is SortKind.BOOL:
        return "bool"
    if sort.is_numeric:
        return "number"
    if sort.kind in (SortKind.SYMBOL, SortKind.ENUM):
        return "symbol"
    raise _Unsupported(f"a {sort.kind.value} value")


def _relaxed(e: ir.Expr, index: dict[str, int]) -> Callable[[Relaxed], Any]:
    if isinstance(e, ir.Const):
        k = _kind(e.sort)
        v: Any
        if k == "bool":
            v = (bool(e.value), not e.value)
        elif k == "number":
            v = (_num(e.value), _num(e.value))
        else:
            v = frozenset({e.value})
        return lambda r: v
    if isinstance(e, ir.ResourceRef):
        i = index[e.name]
        return lambda r: r[i]
    if isinstance(e, ir.Arith):
        fs = [_relaxed(a, index) for a in e.args]
        op = e.op
        if op in (ArithOp.ADD, ArithOp.SUB) and len(e.args) == 2 and isinstance(e.args[1], ir.Const):
            x, c = fs[0], _num(e.args[1].value)  # the common x ± c, without the general case's lists
            c = c if op is ArithOp.ADD else -c
            return lambda r: _shift(x(r), c)
        return lambda r: _arith_relaxed(op, [f(r) for f in fs])
    if isinstance(e, ir.Compare):
        a, b = _relaxed(e.left, index), _relaxed(e.right, index)
        cop, kind = e.op, _kind(e.left.sort)
        if kind == "number" and cop in (CmpOp.LE, CmpOp.GE):
            lo_side, hi_side = (a, b) if cop is CmpOp.LE else (b, a)  # lo_side <= hi_side

            def le(r: Relaxed) -> tuple[bool, bool]:
                x, y = lo_side(r), hi_side(r)
                return (_le(x[0], y[1]), _lt(y[0], x[1]))

            return le
        return lambda r: _compare_relaxed(cop, a(r), b(r), kind)
    if isinstance(e, ir.BoolOp):
        fs = [_relaxed(a, index) for a in e.args]
        if e.op is BoolOpKind.AND:

            def conj(r: Relaxed) -> tuple[bool, bool]:
                vs = [f(r) for f in fs]
                return (all(v[0] for v in vs), any(v[1] for v in vs))

            return conj
        if e.op is BoolOpKind.OR:

            def disj(r: Relaxed) -> tuple[bool, bool]:
                vs = [f(r) for f in fs]
                return (any(v[0] for v in vs), all(v[1] for v in vs))

            return disj
        if e.op is BoolOpKind.NOT:
            (f,) = fs
            return lambda r: f(r)[::-1]
        *init, last = fs

        def imply(r: Relaxed) -> tuple[bool, bool]:
            vs = [f(r) for f in init]
            premise = (all(v[0] for v in vs), any(v[1] for v in vs))
            c = last(r)
            return (premise[1] or c[0], premise[0] and c[1])

        return imply
    if isinstance(e, ir.Ite):
        c, t, o = _relaxed(e.cond, index), _relaxed(e.then, index), _relaxed(e.orelse, index)
        kind = _kind(e.sort)

        def ite(r: Relaxed) -> Any:
            can_t, can_f = c(r)
            if can_t and can_f:
                return _join(t(r), o(r), kind)
            return t(r) if can_t else o(r)

        return ite
    raise _Unsupported(type(e).__name__)


def _redundant(exprs: list[ir.Expr], index: dict[str, int]) -> list[Callable[[Relaxed], tuple[bool, bool]]]:
    """Relaxed tests of the sums of two linear inequalities among the conjuncts ``exprs`` where
    a resource cancels out (as ENHSP's hrmax adds redundant constraints): x + y ≥ d and
    y − x ≥ d give 2·y ≥ 2·d, which the intervals of x and y, taken one conjunct at a time,
    do not see. Each sum is implied by the conjunction (non-strict, weaker than a strict sum),
    so testing it too keeps the relaxation an over-approximation: h^max stays admissible and
    consistent, and grows where the sum needs more layers."""
    forms: list[tuple[dict[int, Fraction], Fraction]] = []
    todo = list(exprs)
    while todo:
        e = todo.pop()
        if isinstance(e, ir.BoolOp) and e.op is BoolOpKind.AND:
            todo.extend(e.args)
            continue
        if not isinstance(e, ir.Compare) or e.op not in (CmpOp.LE, CmpOp.LT, CmpOp.GE, CmpOp.GT):
            continue
        if _kind(e.left.sort) != "number":
            continue
        left, right = _linear(e.left, index), _linear(e.right, index)
        if left is not None and right is not None:
            forms.append(_minus(right, left) if e.op in (CmpOp.LE, CmpOp.LT) else _minus(left, right))
    out = []
    for (wa, ka), (wb, kb) in itertools.combinations(forms, 2):
        w = dict(wa)
        for i, c in wb.items():
            w[i] = w.get(i, Fraction(0)) + c
        terms = [(i, _num(c)) for i, c in w.items() if c != 0]
        if terms and len(terms) < len(set(wa) | set(wb)):
            out.append(_linear_test(terms, _num(ka + kb)))
    return out


def _linear_test(terms: list[tuple[int, Any]], k: Any) -> Callable[[Relaxed], tuple[bool, bool]]:
    """Whether Σ c·x + k ≥ 0 can hold over intervals (and, not tracked, whether it can fail)."""

    def test(r: Relaxed) -> tuple[bool, bool]:
        hi = k
        for i, c in terms:
            end = r[i][1] if c > 0 else r[i][0]
            if end is None:
                return (True, True)
            hi += c * end
        return (hi >= 0, True)

    return test


def _join(a: Any, b: Any, kind: str) -> Any:
    if kind == "bool":
        return (a[0] or b[0], a[1] or b[1])
    if kind == "symbol":
        return a | b
    lo = None if a[0] is None or b[0] is None else min(a[0], b[0])
    hi = None if a[1] is None or b[1] is None else max(a[1], b[1])
    return (lo, hi)


def _point(v: Any, kind: str) -> Any:
    if kind == "bool":
        return (v, not v)
    if kind == "symbol":
        return frozenset({v})
    return (v, v)


# ---------------------------------------------------------------- the ground task
