"""Expression typing: AST expressions → typed IR expressions, with located diagnostics.

One :class:`ExprChecker` per scope (a morphism, a problem's goal, ...).  Every method
returns ``None`` after reporting when its input is ill-typed, so callers keep going and a
run reports all errors.  The sort rules are in ``docs/semantics.md`` §Sorts.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from enum import Enum
from fractions import Fraction

from catc import ir
from catc.ir import BOOL, INT, REAL, Sort, SortKind
from catc.ir.fold import ConstantTooLarge, bounded_arith
from catgrammar import ast, codes
from catgrammar.diagnostics import Diagnostics, Fix, Note, Suggestion
from catgrammar.span import Span
from catgrammar.symbols import (
    EFFECT_OPERATORS,
    EXPRESSION_OPERATORS,
    OBJECTIVE_OPERATORS,
    Operator,
    Requirement,
)


class Context(str, Enum):
    CONDITION = "condition"  # preconditions, goals, soft constraints
    TERM = "term"  # right-hand sides of effects
    OBJECTIVE = "objective"  # metric terms
    COST = "cost"  # a morphism's :cost (θ and constants only)
    CONSTANT = "constant"  # init values (no resources, no θ)


_OPS = {op.value: op for op in Operator}
_EFFECT_HEADS = {op.value for op in EFFECT_OPERATORS} - {"and"}
_OBJECTIVE_HEADS = {op.value for op in OBJECTIVE_OPERATORS}
_ARITH = {
    "+": ir.ArithOp.ADD,
    "-": ir.ArithOp.SUB,
    "*": ir.ArithOp.MUL,
    "/": ir.ArithOp.DIV,
    "min": ir.ArithOp.MIN,
    "max": ir.ArithOp.MAX,
}
_CMP = {"=": ir.CmpOp.EQ, "<": ir.CmpOp.LT, "<=": ir.CmpOp.LE, ">": ir.CmpOp.GT, ">=": ir.CmpOp.GE}
_BOOL = {"and": ir.BoolOpKind.AND, "or": ir.BoolOpKind.OR, "not": ir.BoolOpKind.NOT, "imply": ir.BoolOpKind.IMPLY}


class Scope:
    """What names mean where an expression is checked."""

    __slots__ = ("sorts", "constants", "resources", "params", "morphisms")

    def __init__(
        self,
        sorts: Mapping[str, Sort],
        constants: Mapping[str, ir.Constant],
        resources: Mapping[str, ir.Resource],
        params: Mapping[str, ir.Param],
        morphisms: Mapping[str, ir.Morphism] | None = None,  # objectives only
    ) -> None:
        self.sorts = sorts
        self.constants = constants
        self.resources = resources
        self.params = params
        self.morphisms = morphisms

    def parent_of(self, name: str) -> str | None:
        sort = self.sorts.get(name)
        return sort.parent if sort else None


def root_of(sort: Sort, sorts: Mapping[str, Sort]) -> str:
    name = sort.name
    seen = set()
    while name in sorts and name not in seen:
        parent = sorts[name].parent
        if not parent:
            break
        seen.add(name)
        name = parent
    return name


def is_subsort(sub: Sort, sup: Sort, sorts: Mapping[str, Sort]) -> bool:
    if sub.kind is SortKind.ENUM or sup.kind is SortKind.ENUM:
        return sub.name == sup.name
    name: str | None = sub.name
    seen = set()
    while name is not None and name not in seen:
        if name == sup.name:
            return True
        seen.add(name)
        name = sorts[name].parent if name in sorts else None
    return False


def compatible(a: Sort, b: Sort, sorts: Mapping[str, Sort]) -> bool:
    """May values of these sorts be compared with ``=``?"""
    if a.is_numeric and b.is_numeric:
        return True
    if a.kind is SortKind.BOOL or b.kind is SortKind.BOOL:
        return a.kind is b.kind
    if a.is_symbolic and b.is_symbolic:
        if a.kind is SortKind.ENUM or b.kind is SortKind.ENUM:
            return a.name == b.name
        return root_of(a, sorts) == root_of(b, sorts)
    if a.kind is SortKind.SET and b.kind is SortKind.SET:
        return compatible(a.element, b.element, sorts)  # type: ignore[arg-type]
    return False


def assignable(target: Sort, value: Sort, sorts: Mapping[str, Sort]) -> bool:
    """May a value of sort ``value`` be stored where ``target`` is expected?"""
    if target.kind is SortKind.REAL:
        return value.is_numeric
    if target.kind is SortKind.INT:
        return value.kind is SortKind.INT
    if target.kind is SortKind.BOOL:
        return value.kind is SortKind.BOOL
    if target.kind is SortKind.SET:
        return value.kind is SortKind.SET and assignable(target.element, value.element, sorts)  # type: ignore[arg-type]
    if target.is_symbolic:
        return value.is_symbolic and is_subsort(value, target, sorts)
    return False


def describe(sort: Sort) -> str:
    """The sort as a noun phrase with its article: 'an int', 'a set of 'module''."""
    if sort.kind is SortKind.SYMBOL:
        return f"a symbol of sort '{sort.name}'"
    if sort.kind is SortKind.ENUM:
        return f"a value of enumeration '{sort.name}'"
    if sort.kind is SortKind.SET:
        return f"a set of '{sort.element}'"
    return {"bool": "a bool", "int": "an int", "real": "a real"}[sort.kind.value]


def numeric_join(args: list[ir.Expr]) -> Sort:
    return INT if all(a.sort.kind is SortKind.INT for a in args) else REAL


def const_number(value: Fraction, span: Span | None = None) -> ir.Const:
    return ir.Const(value, INT if value.denominator == 1 else REAL, span)


class ExprChecker:
    def __init__(
        self,
        scope: Scope,
        diags: Diagnostics,
        require: Callable[[Requirement, Span | None, str], None],
    ):
        self.scope = scope
        self.diags = diags
        self.require = require
        # every constant arithmetic node made so far, by id, with its value (kept here, so no
        # id is reused): each value is computed once from its arguments', and bounded
        self._values: dict[int, tuple[ir.Arith, Fraction]] = {}

    # ------------------------------------------------------------ entry points
    def condition(self, node: ast.Expr, ctx: Context = Context.CONDITION) -> ir.Expr | None:
        expr = self.term(node, ctx)
        if expr is not None and expr.sort.kind is not SortKind.BOOL:
            self.diags.report(
                codes.TYPE_MISMATCH, f"expected a condition (bool), found {describe(expr.sort)}", node.span
            )
            return None
        return expr

    def numeric(self, node: ast.Expr, ctx: Context) -> ir.Expr | None:
        expr = self.term(node, ctx)
        if expr is not None and not expr.sort.is_numeric:
            self.diags.report(codes.TYPE_MISMATCH, f"expected a number, found {describe(expr.sort)}", node.span)
            return None
        return expr

    def term(self, node: ast.Expr, ctx: Context, expected: Sort | None = None) -> ir.Expr | None:
        if isinstance(node, ast.Num):
            return const_number(node.value, node.span)
        if isinstance(node, ast.BoolLit):
            return ir.Const(node.value, BOOL, node.span)
        if isinstance(node, ast.Ref):
            return self._ref(node, ctx)
        if isinstance(node, ast.SetLit):
            return self._set_literal(node, ctx, expected)
        return self._call(node, ctx, expected)

    # ------------------------------------------------------------ names
    def _ref(self, node: ast.Ref, ctx: Context) -> ir.Expr | None:
        name = node.name
        sc = self.scope
        if name in sc.params:
            p = sc.params[name]
            return ir.ParamRef(name, p.sort, node.span)
        if name in sc.resources:
            if ctx in (Context.COST, Context.CONSTANT):
                where = "a morphism's :cost" if ctx is Context.COST else "an initial value"
                self.diags.report(
                    codes.TYPE_MISMATCH,
                    f"resource '{name}' cannot appear in {where}; only constants and parameters can",
                    node.span,
                )
                return None
            r = sc.resources[name]
            return ir.ResourceRef(name, r.sort, node.span)
        if name in sc.constants:
            c = sc.constants[name]
            return ir.Const(name, c.sort, node.span)
        candidates = list(sc.params) + list(sc.resources) + list(sc.constants)
        suggestion = Suggestion(name, candidates, node.span)
        hint, fixes = suggestion.hint, suggestion.fixes
        if sc.morphisms is not None and name in sc.morphisms:
            hint = f"; '{name}' is a morphism: use (uses {name}) to count its activations"
            # the fix only where (uses ...) is allowed: an objective
            fixes = (
                (Fix(f"Replace with '(uses {name})'", node.span, f"(uses {name})"),) if ctx is Context.OBJECTIVE else ()
            )
        self.diags.report(codes.UNKNOWN_NAME, f"unknown name '{name}'{hint}", node.span, fixes=fixes)
        return None

    def _set_literal(self, node: ast.SetLit, ctx: Context, expected: Sort | None) -> ir.Expr | None:
        self.require(Requirement.SETS, node.span, "a set literal")
        elems: list[ir.Expr] = []
        ok = True
        want = expected.element if expected is not None and expected.kind is SortKind.SET else None
        for el in node.elements:
            e = self.term(el, ctx)
            if e is None:
                ok = False
                continue
            if not e.sort.is_symbolic:
                self.diags.report(
                    codes.TYPE_MISMATCH, f"set elements must be symbols, found {describe(e.sort)}", el.span
                )
                ok = False
                continue
            elems.append(e)
        if not ok:
            return None
        if want is not None:
            for e, el in zip(elems, node.elements):
                if not assignable(want, e.sort, self.scope.sorts):
                    self.diags.report(
                        codes.TYPE_MISMATCH,
                        f"{describe(e.sort)} cannot be an element of a set of '{want}'",
                        el.span,
                    )
                    ok = False
            return ir.SetLit(tuple(elems), ir.set_of(want), node.span) if ok else None
        if not elems:
            self.diags.report(codes.TYPE_MISMATCH, "cannot tell the element sort of the empty set {} here", node.span)
            return None
        first = elems[0].sort
        for e, el in zip(elems[1:], node.elements[1:]):
            if not compatible(first, e.sort, self.scope.sorts):
                self.diags.report(
                    codes.TYPE_MISMATCH, f"set literal mixes {describe(first)} and {describe(e.sort)}", el.span
                )
                return None
        elem_sort = self.scope.sorts.get(root_of(first, self.scope.sorts), first)
        return ir.SetLit(tuple(elems), ir.set_of(elem_sort), node.span)

    # ------------------------------------------------------------ calls
    def _allowed_heads(self, ctx: Context) -> list[str]:
        heads = [op.value for op in EXPRESSION_OPERATORS]
        if ctx is Context.OBJECTIVE:
            heads += list(_OBJECTIVE_HEADS)
        return heads

    def _call(self, node: ast.Call, ctx: Context, expected: Sort | None) -> ir.Expr | None:
        head = node.head.text
        allowed = self._allowed_heads(ctx)
        if head not in allowed:
            self._bad_head(node, ctx, allowed)
            return None
        args = node.args
        if head in _BOOL:
            return self._boolean(node, ctx)
        if head in _CMP:
            return self._compare(node, ctx)
        if head in _ARITH:
            return self._arith(node, ctx)
        if head == "if":
            if not self._arity(node, 3, 3):
                return None
            cond = self.condition(args[0], ctx)
            then = self.term(args[1], ctx, expected)
            orelse = self.term(args[2], ctx, expected if then is None else then.sort)
            if cond is None or then is None or orelse is None:
                return None
            if not compatible(then.sort, orelse.sort, self.scope.sorts):
                self.diags.report(
                    codes.TYPE_MISMATCH,
                    f"'if' branches differ: {describe(then.sort)} and {describe(orelse.sort)}",
                    node.span,
                )
                return None
            sort = numeric_join([then, orelse]) if then.sort.is_numeric else then.sort
            return ir.Ite(cond, then, orelse, sort, node.span)
        if head == "member":
            return self._member(node, ctx)
        return self._objective_term(node)

    def _bad_head(self, node: ast.Call, ctx: Context, allowed: list[str]) -> None:
        head = node.head.text
        sc = self.scope
        if head in _EFFECT_HEADS:
            msg = f"'{head}' is an effect and cannot appear in a {ctx.value}"
            self.diags.report(codes.MISPLACED_OPERATOR, msg, node.head.span)
        elif head in _OBJECTIVE_HEADS:
            self.diags.report(
                codes.MISPLACED_OPERATOR,
                f"'({head} ...)' is an objective term; it is only allowed in (:metric ...)",
                node.head.span,
            )
        elif head in sc.resources or head in sc.constants or head in sc.params:
            self.diags.report(
                codes.UNKNOWN_OPERATOR,
                f"'{head}' is not an operator; names are written without parentheses: use {head} instead of ({head} ...)",
                node.head.span,
            )
        else:
            hint = Suggestion(head, allowed, node.head.span)
            self.diags.report(
                codes.UNKNOWN_OPERATOR, f"unknown operator '{head}'{hint.hint}", node.head.span, fixes=hint.fixes
            )
        return None

    def _arity(self, node: ast.Call, lo: int, hi: int | None) -> bool:
        n = len(node.args)
        if n < lo or (hi is not None and n > hi):
            if hi == lo:
                want = f"{lo} argument{'s' if lo != 1 else ''}"
            elif hi is None:
                want = f"at least {lo} argument{'s' if lo != 1 else ''}"
            else:
                want = f"{lo} to {hi} arguments"
            self.diags.report(codes.ARITY, f"'{node.head.text}' takes {want}, got {n}", node.span)
            return False
        return True

    def _boolean(self, node: ast.Call, ctx: Context) -> ir.Expr | None:
        op = _BOOL[node.head.text]
        if op is ir.BoolOpKind.NOT and not self._arity(node, 1, 1):
            return None
        if op is ir.BoolOpKind.IMPLY and not self._arity(node, 2, 2):
            return None
        checked = [self.condition(a, ctx) for a in node.args]
        args = [a for a in checked if a is not None]
        if len(args) != len(checked):
            return None
        return ir.BoolOp(op, tuple(args), node.span)

    def _compare(self, node: ast.Call, ctx: Context) -> ir.Expr | None:
        if not self._arity(node, 2, 2):
            return None
        op = _CMP[node.head.text]
        left_node, right_node = node.args
        # Type a set literal against the other side.
        if isinstance(left_node, ast.SetLit) and not isinstance(right_node, ast.SetLit):
            right = self.term(right_node, ctx)
            left = self.term(left_node, ctx, right.sort if right is not None else None)
        else:
            left = self.term(left_node, ctx)
            right = self.term(right_node, ctx, left.sort if left is not None else None)
        if left is None or right is None:
            return None
        if op is ir.CmpOp.EQ:
            if not compatible(left.sort, right.sort, self.scope.sorts):
                self.diags.report(
                    codes.TYPE_MISMATCH,
                    f"cannot compare {describe(left.sort)} with {describe(right.sort)}",
                    node.span,
                )
                return None
        else:
            for side, n in ((left, left_node), (right, right_node)):
                if not side.sort.is_numeric:
                    self.diags.report(
                        codes.TYPE_MISMATCH,
                        f"'{node.head.text}' compares numbers, but this is {describe(side.sort)}",
                        n.span,
                    )
                    return None
        return ir.Compare(op, left, right, node.span)

    def _arith(self, node: ast.Call, ctx: Context) -> ir.Expr | None:
        op = _ARITH[node.head.text]
        if op is ir.ArithOp.DIV:
            if not self._arity(node, 2, 2):
                return None
        elif op is ir.ArithOp.SUB:
            if not self._arity(node, 1, None):
                return None
        elif not self._arity(node, 1, None):
            return None
        self.require(Requirement.NUMERIC, node.span, f"arithmetic '{node.head.text}'")
        checked = [self.term(a, ctx) for a in node.args]
        args = [a for a in checked if a is not None]
        if len(args) != len(checked):
            return None
        for a, n in zip(args, node.args):
            if not a.sort.is_numeric:
                self.diags.report(
                    codes.TYPE_MISMATCH,
                    f"'{node.head.text}' needs numbers, but this is {describe(a.sort)}",
                    n.span,
                )
                return None
        if op is ir.ArithOp.DIV:
            divisor = args[1]
            if isinstance(divisor, ir.Const) and divisor.value == 0:
                self.diags.report(codes.DIVISION_BY_ZERO, "division by zero", node.args[1].span)
                return None
            sort = REAL
        else:
            sort = numeric_join(args)
        out = ir.Arith(op, tuple(args), sort, node.span)
        return out if self._bounded(out) else None

    def _bounded(self, e: ir.Arith) -> bool:
        """Whether ``e``, when all its arguments are constant, has a value within the
        constant-digits limit (E1103 when not); its value is kept for the nodes above."""
        values = []
        for a in e.args:
            v = a.value if isinstance(a, ir.Const) else self._values.get(id(a), (None, None))[1]
            if not isinstance(v, Fraction):
                return True
            values.append(v)
        try:
            self._values[id(e)] = (e, bounded_arith(e.op, values, e))
        except ZeroDivisionError:  # a divisor that folds to 0: the validator's strict semantics
            pass
        except ConstantTooLarge as exc:
            self.diags.report(codes.CONSTANT_TOO_LARGE, str(exc), e.span)
            return False
        return True

    def _member(self, node: ast.Call, ctx: Context) -> ir.Expr | None:
        if not self._arity(node, 2, 2):
            return None
        self.require(Requirement.SETS, node.span, "'member'")
        coll = self.term(node.args[1], ctx)
        elem = self.term(node.args[0], ctx)
        if coll is None or elem is None:
            return None
        if coll.sort.kind is not SortKind.SET:
            self.diags.report(
                codes.NOT_A_SET,
                f"'member' needs a set as its second argument, found {describe(coll.sort)}",
                node.args[1].span,
            )
            return None
        if not elem.sort.is_symbolic or not compatible(elem.sort, coll.sort.element, self.scope.sorts):  # type: ignore[arg-type]
            self.diags.report(
                codes.TYPE_MISMATCH,
                f"{describe(elem.sort)} can never be a member of {describe(coll.sort)}",
                node.args[0].span,
            )
            return None
        return ir.Member(elem, coll, node.span)

    def _objective_term(self, node: ast.Call) -> ir.Expr | None:
        head = node.head.text
        morphisms = self.scope.morphisms or {}
        if head in ("total-churn", "total-cost"):
            if not self._arity(node, 0, 0):
                return None
            if head == "total-churn":
                self.require(Requirement.RECOMPOSITION, node.span, "(total-churn)")
                return ir.TotalChurn(node.span)
            return ir.TotalCost(node.span)
        if head == "uses":
            if not self._arity(node, 1, 1):
                return None
            m = self._morphism_arg(node.args[0], morphisms)
            return ir.Uses(m.name, node.span) if m else None
        # param
        if not self._arity(node, 2, 2):
            return None
        m = self._morphism_arg(node.args[0], morphisms)
        if m is None:
            return None
        pnode = node.args[1]
        if not isinstance(pnode, ast.Ref) or m.param(pnode.name) is None:
            names = [p.name for p in m.params]
            label = pnode.name if isinstance(pnode, ast.Ref) else "this"
            hint = Suggestion(label, names, pnode.span if isinstance(pnode, ast.Ref) else None)
            self.diags.report(
                codes.UNKNOWN_NAME,
                f"morphism '{m.name}' has no parameter '{label}'{hint.hint}",
                pnode.span,
                fixes=hint.fixes,
            )
            return None
        p = m.param(pnode.name)
        assert p is not None
        if not p.fixed and m.uses not in (0, 1):  # at most one activation: one value (or none)
            self.diags.report(
                codes.AMBIGUOUS_PARAMETER,
                f"parameter '{p.name}' of '{m.name}' takes one value per activation; "
                f"declare it :fixed or limit '{m.name}' to :uses 1 to use it in an objective",
                node.span,
                *([Note("the parameter is declared here", p.span)] if p.span else []),
            )
            return None
        return ir.ParamValue(m.name, p.name, p.sort, node.span)

    def _morphism_arg(self, node: ast.Expr, morphisms: Mapping[str, ir.Morphism]) -> ir.Morphism | None:
        if isinstance(node, ast.Ref) and node.name in morphisms:
            return morphisms[node.name]
        label = node.name if isinstance(node, ast.Ref) else "this"
        hint = Suggestion(label, list(morphisms), node.span if isinstance(node, ast.Ref) else None)
        self.diags.report(codes.UNKNOWN_NAME, f"unknown morphism '{label}'{hint.hint}", node.span, fixes=hint.fixes)
        return None
