"""Expression typing: AST expressions → typed IR expressions, with located diagnostics.

One :class:`ExprChecker` per scope (a morphism, a problem's goal, ...).  Every method
returns ``None`` after reporting when its input is ill-typed, so callers keep going and a
run reports all errors.  The sort rules are in ``docs/semantics.md`` §Sorts.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from enum import Enum
from fractions import Fraction
from typing import TYPE_CHECKING, assert_never

from catc import ir
from catc.ir import BOOL, INT, REAL, Sort, SortKind
from catc.ir.fold import ConstantTooLarge, bounded_arith
from catgrammar import ast, codes
from catgrammar.diagnostics import Diagnostics, Fix, Note, Suggestion
from catgrammar.span import Span

if TYPE_CHECKING:
    from catc.frontend.units import Unit
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

    def declares(self, name: str) -> bool:
        return (
            name in self.params
            or name in self.resources
            or name in self.constants
            or (self.morphisms is not None and name in self.morphisms)
        )

    def unit_of(self, name: str) -> Unit | None:
        """The parsed ``:unit`` of a resource or parameter (None: it declares none, or one
        that is reported where it is declared)."""
        decl = self.params.get(name) or self.resources.get(name)
        text = decl.unit if decl is not None else None
        if not text:
            return None
        from catc.frontend import units

        try:
            return units.parse(text)
        except units.UnitError:
            return None

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
        # the unit of every numeric expression that has one, by id (kept with the expression,
        # so no id is reused); an expression without an entry has no unit of its own and takes
        # its context's (a bare number, a resource or parameter declared without :unit)
        self._units: dict[int, tuple[ir.Expr, Unit]] = {}

    # ------------------------------------------------------------ units
    def unit(self, expr: ir.Expr) -> Unit | None:
        entry = self._units.get(id(expr))
        return entry[1] if entry is not None and entry[0] is expr else None

    def _with_unit(self, expr: ir.Expr, unit: Unit | None) -> ir.Expr:
        if unit is not None:
            self._units[id(expr)] = (expr, unit)
        return expr

    def merge_quantities(self, args: tuple[ast.Expr, ...]) -> tuple[ast.Expr, ...]:
        """``512 MB`` in an argument list: a number followed by a name that is no declared
        name but a unit becomes one :class:`ast.Quantity` (declared names win)."""
        if not any(isinstance(a, ast.Num) for a in args[:-1]):
            return args
        out: list[ast.Expr] = []
        i = 0
        while i < len(args):
            a = args[i]
            nxt = args[i + 1] if i + 1 < len(args) else None
            if isinstance(a, ast.Num) and isinstance(nxt, ast.Ref) and not self.scope.declares(nxt.name):
                from catc.frontend import units

                if units.is_unit(nxt.name):
                    out.append(ast.Quantity(a, ast.Name(nxt.name, nxt.span), a.span.cover(nxt.span)))
                    i += 2
                    continue
            out.append(a)
            i += 1
        return tuple(out)

    def unify(
        self,
        exprs: list[ir.Expr],
        nodes: list[ast.Expr],
        code: str,
        verb: Callable[[str, str], str],
        target: Unit | None = None,
        target_label: str | None = None,
    ) -> tuple[list[ir.Expr], Unit | None] | None:
        """Bring numeric ``exprs`` to one unit (``target``, else the first declared unit among
        them, else the first literal's): units of another dimension are an error ``code``,
        ``verb(a, b)`` naming both sides; a literal is converted exactly, any other expression
        of another unit of the same dimension is multiplied by the exact factor.  Expressions
        without a unit take the result's.  None after reporting."""
        units_ = [self.unit(e) for e in exprs]
        if target is None:
            pick = next(
                (i for i, (e, u) in enumerate(zip(exprs, units_)) if u is not None and not _is_literal(e)),
                next((i for i, u in enumerate(units_) if u is not None), None),
            )
            if pick is None:
                return exprs, None
            target, target_label = units_[pick], show_node(nodes[pick])
        assert target is not None
        from catc.frontend import units

        out: list[ir.Expr] = []
        for e, u, n in zip(exprs, units_, nodes):
            if u is None:
                if isinstance(e, ir.ResourceRef):
                    self.diags.report(
                        codes.UNITLESS_RESOURCE,
                        f"resource '{e.name}' has no :unit but meets {target_label} [{target.show()}] here, "
                        f"so it is read in {target.text}; declare its :unit",
                        n.span,
                    )
                out.append(e)
                continue
            if not u.same_dimension(target):
                self.diags.report(
                    code,
                    verb(f"{target_label} [{target.show()}]", f"{show_node(n)} [{u.show()}]"),
                    n.span,
                )
                return None
            out.append(self._scaled(e, units.factor(u, target), target))
        return out, target

    def _scaled(self, e: ir.Expr, f: Fraction, unit: Unit) -> ir.Expr:
        if f == 1:
            return self._with_unit(e, unit)
        if isinstance(e, ir.Const) and isinstance(e.value, Fraction):
            return self._with_unit(const_number(e.value * f, e.span), unit)
        scaled = ir.Arith(ir.ArithOp.MUL, (e, const_number(f, e.span)), REAL, e.span)
        return self._with_unit(scaled, unit)

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
        match node:
            case ast.Num():
                return const_number(node.value, node.span)
            case ast.BoolLit():
                return ir.Const(node.value, BOOL, node.span)
            case ast.Ref():
                return self._ref(node, ctx)
            case ast.SetLit():
                return self._set_literal(node, ctx, expected)
            case ast.Quantity():
                from catc.frontend import units

                return self._with_unit(const_number(node.number.value, node.span), units.parse(node.unit.text))
            case ast.Call():
                return self._call(node, ctx, expected)
            case _:
                assert_never(node)

    # ------------------------------------------------------------ names
    def _ref(self, node: ast.Ref, ctx: Context) -> ir.Expr | None:
        name = node.name
        sc = self.scope
        if name in sc.params:
            p = sc.params[name]
            return self._with_unit(ir.ParamRef(name, p.sort, node.span), sc.unit_of(name) if p.unit else None)
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
            return self._with_unit(ir.ResourceRef(name, r.sort, node.span), sc.unit_of(name) if r.unit else None)
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
        if isinstance(node, ast.Call) and len(node.args) > 1:
            merged = self.merge_quantities(node.args)
            if merged is not node.args:
                node = ast.Call(node.head, merged, node.span)
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
            unit = None
            if then.sort.is_numeric and orelse.sort.is_numeric:
                unified = self.unify(
                    [then, orelse], [args[1], args[2]], codes.UNIT_MISMATCH_ARITH, _verb("'if' branches differ:", "and")
                )
                if unified is None:
                    return None
                (then, orelse), unit = unified
            sort = numeric_join([then, orelse]) if then.sort.is_numeric else then.sort
            return self._with_unit(ir.Ite(cond, then, orelse, sort, node.span), unit)
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
        if left.sort.is_numeric and right.sort.is_numeric:
            unified = self.unify(
                [left, right], [left_node, right_node], codes.UNIT_MISMATCH_COMPARE, _verb("cannot compare", "with")
            )
            if unified is None:
                return None
            left, right = unified[0]
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
        unit = None
        if op in (ir.ArithOp.MUL, ir.ArithOp.DIV):
            unit = self._product_unit(op, args)
        else:
            verb = {
                ir.ArithOp.ADD: _verb("cannot add", "and"),
                ir.ArithOp.SUB: _verb("cannot subtract", "from", swap=True),
            }.get(op, _verb(f"'{node.head.text}' of", "and"))
            unified = self.unify(args, list(node.args), codes.UNIT_MISMATCH_ARITH, verb)
            if unified is None:
                return None
            args, unit = unified
        if op is ir.ArithOp.DIV:
            divisor = args[1]
            if isinstance(divisor, ir.Const) and divisor.value == 0:
                self.diags.report(codes.DIVISION_BY_ZERO, "division by zero", node.args[1].span)
                return None
            sort = REAL
        else:
            sort = numeric_join(args)
        out: ir.Expr = ir.Arith(op, tuple(args), sort, node.span)
        if not self._bounded(out):  # type: ignore[arg-type]
            return None
        if unit is not None and unit.dimensionless and unit.text != "1":
            # GB/MB is a pure number once scaled: (/ ram disk) with ram in GB, disk in MB
            from catc.frontend import units

            one = units.parse("dimensionless")
            return self._scaled(self._with_unit(out, unit), units.factor(unit, one), one)
        return self._with_unit(out, unit)

    def _product_unit(self, op: ir.ArithOp, args: list[ir.Expr]) -> Unit | None:
        """The unit of a product or quotient: the units of its factors combined (a factor
        without a unit counts as a pure number); None when no factor has one."""
        units_ = [self.unit(a) for a in args]
        if all(u is None for u in units_):
            return None
        result: Unit | None = None
        for i, u in enumerate(units_):
            if u is None:
                continue
            if result is None:
                result = u if (op is ir.ArithOp.MUL or i == 0) else u.inverse()
            else:
                result = result.times(u) if op is ir.ArithOp.MUL else result.over(u)
        return result

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
        unit = None
        if p.unit:
            from catc.frontend import units

            try:
                unit = units.parse(p.unit)
            except units.UnitError:
                unit = None
        return self._with_unit(ir.ParamValue(m.name, p.name, p.sort, node.span), unit)

    def _morphism_arg(self, node: ast.Expr, morphisms: Mapping[str, ir.Morphism]) -> ir.Morphism | None:
        if isinstance(node, ast.Ref) and node.name in morphisms:
            return morphisms[node.name]
        label = node.name if isinstance(node, ast.Ref) else "this"
        hint = Suggestion(label, list(morphisms), node.span if isinstance(node, ast.Ref) else None)
        self.diags.report(codes.UNKNOWN_NAME, f"unknown morphism '{label}'{hint.hint}", node.span, fixes=hint.fixes)
        return None


def _is_literal(e: ir.Expr) -> bool:
    return isinstance(e, ir.Const) and isinstance(e.value, Fraction)


def _verb(before: str, between: str, *, swap: bool = False) -> Callable[[str, str], str]:
    """A mismatch message naming both sides: ``cannot compare A with B``."""
    if swap:
        return lambda a, b: f"{before} {b} {between} {a}"
    return lambda a, b: f"{before} {a} {between} {b}"


def show_node(node: ast.Expr, limit: int = 40) -> str:
    """An expression as written, compact (for diagnostics)."""
    if isinstance(node, ast.Ref):
        text = node.name
    elif isinstance(node, ast.Num):
        text = node.text
    elif isinstance(node, ast.Quantity):
        text = f"{node.number.text} {node.unit.text}"
    elif isinstance(node, ast.BoolLit):
        text = "true" if node.value else "false"
    elif isinstance(node, ast.SetLit):
        text = "{" + " ".join(show_node(e, limit) for e in node.elements) + "}"
    else:
        text = "(" + " ".join([node.head.text, *(show_node(a, limit) for a in node.args)]) + ")"
    return text if len(text) <= limit else text[: limit - 1] + "…"
