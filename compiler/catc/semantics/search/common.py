"""What the parts of the forward search share: its answer (:class:`SearchResult`), the
exception for what it does not model, exact numbers, and linear forms over the resources."""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum
from fractions import Fraction
from typing import Any, Protocol

from catc import ir
from catc.ir import ArithOp
from catc.ir.fold import arith
from catc.semantics.bounds import linear
from catc.semantics.plan import Plan


class SearchStatus(str, Enum):
    PLAN = "plan"
    NONE = "none"  # no composition within the horizon (``final``: of any length)
    STOPPED = "stopped"  # the time ran out
    UNSUPPORTED = "unsupported"


class SearchResult:
    __slots__ = ("status", "plan", "final", "expanded", "reason", "length", "shortest", "first_plan")

    def __init__(
        self,
        status: SearchStatus,
        plan: Plan | None = None,
        *,
        final: bool = False,
        expanded: int = 0,
        reason: str = "",
        shortest: bool = True,
        first_plan: float | None = None,
    ) -> None:
        self.status, self.plan, self.final, self.expanded, self.reason = status, plan, final, expanded, reason
        self.length = None if plan is None else len(plan.steps)
        #: a plan is a shortest one (proven by A*); False: the greedy search's plan, no proof
        self.shortest = shortest
        #: seconds until the first plan was found (the greedy search's), None when none was
        self.first_plan = first_plan


class _Unsupported(Exception):
    pass


# ---------------------------------------------------------------- concrete terms
#
# Numbers are exact: a whole number is a Python int (much faster than a Fraction of
# denominator 1, and as exact), any other a Fraction; division always goes through Fraction.


def _num(v: Any) -> Any:
    """An int for a whole Fraction (not a bool), the value itself otherwise."""
    if isinstance(v, Fraction) and v.denominator == 1:
        return int(v.numerator)
    return v


def _arith(op: ArithOp, values: list[Any]) -> Any:
    if op is ArithOp.DIV:
        out = Fraction(values[0])
        for x in values[1:]:
            out /= x
        return _num(out)
    return _num(arith(op, [Fraction(v) for v in values]))


State = tuple[Any, ...]


class _TaskShape(Protocol):
    """What :func:`~catc.semantics.search.bounds.infer_bounds` reads of a ground task."""

    names: list[str]
    init: State
    kinds: list[str]


class _Bound(Protocol):
    """A lower bound on the steps to the goal (None: a dead end), as the counting bound."""

    def h(self, s: State) -> int | None: ...


Fn = Callable[[State], Any]

_FAR = 1 << 40  # "not reached" in h_add: larger than any sum of reached costs


def _linear(e: ir.Expr, index: dict[str, int]) -> tuple[dict[int, Fraction], Fraction] | None:
    """``e`` as Σ w·x + k over the task's numeric resources (by position), or None when it is
    not linear or reads a resource the task does not have (:func:`catc.semantics.bounds.linear`)."""
    form = linear(e)
    if form is None or any(n not in index for n in form[0]):
        return None
    return {index[n]: c for n, c in form[0].items()}, form[1]


def _minus(
    a: tuple[dict[int, Fraction], Fraction], b: tuple[dict[int, Fraction], Fraction]
) -> tuple[dict[int, Fraction], Fraction]:
    w = dict(a[0])
    for i, c in b[0].items():
        w[i] = w.get(i, Fraction(0)) - c
    return w, a[1] - b[1]


def _reads(e: ir.Expr) -> set[str]:
    out: set[str] = set()
    todo = [e]
    while todo:
        x = todo.pop()
        if isinstance(x, ir.ResourceRef):
            out.add(x.name)
        elif isinstance(x, (ir.Arith, ir.BoolOp)):
            todo.extend(x.args)
        elif isinstance(x, ir.Compare):
            todo += [x.left, x.right]
        elif isinstance(x, ir.Ite):
            todo += [x.cond, x.then, x.orelse]
    return out


def _constant(e: ir.Expr) -> bool | None:
    """The Boolean constant ``e`` folds to (UP's add-after-delete gives ``true ∨ …``), else None."""
    from catc.ir.fold import FoldError, fold_constant

    try:
        v = fold_constant(e)
    except FoldError:
        return None
    return v.value if isinstance(v, ir.Const) and isinstance(v.value, bool) else None
