"""The validator's expression evaluator: IR expressions on exact values, independent of the encoder.

A value is a :class:`fractions.Fraction`, a bool, a symbol (str) or a frozenset of symbols;
:func:`evaluate` reads resources from a state and θ from an activation's parameters, and the
objective terms (``total-cost``, ``uses``, ...) from a composition.  Part of the independent
validator (:mod:`catc.semantics.validate`), with the same import rules.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from fractions import Fraction
from typing import Never, NoReturn, TypeGuard

from catc import ir
from catc.ir import ArithOp, BoolOpKind, CmpOp
from catc.ir.fold import arith
from catc.ir.numbers import ratio_text
from catc.ir.text import to_text
from catc.semantics.plan import Activation, Plan

# ====================================================================== evaluation


class EvaluationError(Exception):
    """An expression has no value (a resource without a value, a missing parameter, a
    value of the wrong type, an objective term without a composition)."""


class MissingValue(EvaluationError):
    """A resource without a value in the state (an initial value is missing)."""


class DivisionByZero(EvaluationError):
    def __init__(self, expr: ir.Arith, divisor_text: str):
        super().__init__(f"division by zero: {divisor_text} is 0 in {to_text(expr)}")
        self.expr = expr


class Undefined(EvaluationError):
    """An objective term that the composition does not define (``(param m p)`` of an
    unused morphism, or of a morphism used with several values)."""


class _Env:
    __slots__ = ("instance", "state", "params", "plan")

    def __init__(
        self,
        instance: ir.Instance,
        state: Mapping[str, object],
        params: Mapping[str, object] | None,
        plan: Plan | None = None,
    ) -> None:
        self.instance = instance
        self.state = state
        self.params = params
        self.plan = plan


def _norm(v: object) -> object:
    """Plan values as the evaluator uses them: ints become Fractions (bools stay bools)."""
    if isinstance(v, bool):
        return v
    if isinstance(v, int):
        return Fraction(v)
    return v


def _is_num(v: object) -> TypeGuard[Fraction]:
    return isinstance(v, Fraction) and not isinstance(v, bool)


def _num(env: _Env, e: ir.Expr) -> Fraction:
    v = _eval(env, e)
    if not _is_num(v):
        raise EvaluationError(f"{to_text(e)} is {fmt(v)}, not a number")
    return v


def _bool(env: _Env, e: ir.Expr) -> bool:
    v = _eval(env, e)
    if not isinstance(v, bool):
        raise EvaluationError(f"{to_text(e)} is {fmt(v)}, not true or false")
    return v


def _h_const(env: _Env, e: ir.Const) -> object:
    return _norm(e.value)


def _h_resource(env: _Env, e: ir.ResourceRef) -> object:
    try:
        return env.state[e.name]
    except KeyError:
        raise MissingValue(f"resource '{e.name}' has no value") from None


def _h_param(env: _Env, e: ir.ParamRef) -> object:
    if env.params is None or e.name not in env.params:
        raise EvaluationError(f"parameter '{e.name}' has no value")
    return _norm(env.params[e.name])


def _h_setlit(env: _Env, e: ir.SetLit) -> frozenset[str]:
    out: set[str] = set()
    for x in e.elements:
        v = _eval(env, x)
        if not isinstance(v, str):
            raise EvaluationError(f"set element {to_text(x)} is {fmt(v)}, not a symbol")
        out.add(v)
    return frozenset(out)


def _h_arith(env: _Env, e: ir.Arith) -> Fraction:
    args = [_num(env, a) for a in e.args]  # strict: every argument is evaluated
    if not args:
        raise EvaluationError(f"{to_text(e)} has no arguments")
    if e.op is ArithOp.DIV:
        for sub, a in zip(e.args[1:], args[1:]):
            if a == 0:
                raise DivisionByZero(e, to_text(sub))
    return arith(e.op, args)


_ORDER: dict[CmpOp, Callable[[Fraction, Fraction], bool]] = {
    CmpOp.LT: lambda a, b: a < b,
    CmpOp.LE: lambda a, b: a <= b,
    CmpOp.GT: lambda a, b: a > b,
    CmpOp.GE: lambda a, b: a >= b,
}


def _kind_of(v: object) -> str:
    if isinstance(v, bool):
        return "bool"
    if _is_num(v):
        return "number"
    if isinstance(v, str):
        return "symbol"
    if isinstance(v, frozenset):
        return "set"
    return type(v).__name__


def _h_compare(env: _Env, e: ir.Compare) -> bool:
    left, right = _eval(env, e.left), _eval(env, e.right)
    if e.op is CmpOp.EQ:
        if _kind_of(left) != _kind_of(right):
            raise EvaluationError(f"cannot compare {fmt(left)} with {fmt(right)} in {to_text(e)}")
        return left == right
    if not (_is_num(left) and _is_num(right)):
        raise EvaluationError(f"{to_text(e)} compares non-numbers {fmt(left)} and {fmt(right)}")
    return _ORDER[e.op](left, right)


def _h_boolop(env: _Env, e: ir.BoolOp) -> bool:
    args = [_bool(env, a) for a in e.args]  # strict
    op = e.op
    if op is BoolOpKind.AND:
        return all(args)
    if op is BoolOpKind.OR:
        return any(args)
    if op is BoolOpKind.NOT:
        if len(args) != 1:
            raise EvaluationError(f"{to_text(e)}: 'not' takes one argument")
        return not args[0]
    if op is BoolOpKind.IMPLY:
        if not args:
            raise EvaluationError(f"{to_text(e)}: 'imply' needs arguments")
        return (not all(args[:-1])) or args[-1]
    raise EvaluationError(f"unknown boolean operator {op!r}")


def _h_ite(env: _Env, e: ir.Ite) -> object:
    cond = _bool(env, e.cond)
    then, orelse = _eval(env, e.then), _eval(env, e.orelse)  # strict: both branches
    return then if cond else orelse


def _h_member(env: _Env, e: ir.Member) -> bool:
    x, s = _eval(env, e.element), _eval(env, e.set)
    if not isinstance(s, frozenset):
        raise EvaluationError(f"{to_text(e.set)} is {fmt(s)}, not a set")
    return x in s


def _need_plan(env: _Env, e: ir.Expr) -> Plan:
    if env.plan is None:
        raise EvaluationError(f"{to_text(e)} is an objective term: it needs a composition")
    return env.plan


def _morphism(env: _Env, name: str) -> ir.Morphism:
    m = env.instance.morphisms.get(name)
    if m is None:
        raise Undefined(f"unknown morphism '{name}'")
    return m


def _h_total_cost(env: _Env, e: ir.TotalCost) -> Fraction:
    plan = _need_plan(env, e)
    total = Fraction(0)
    for _, act in plan.activations:
        m = _morphism(env, act.morphism)
        if m.cost is None:
            total += 1
        else:
            total += _num(_Env(env.instance, env.state, dict(act.params)), m.cost)
    return total


def _h_total_churn(env: _Env, e: ir.TotalChurn) -> Fraction:
    plan = _need_plan(env, e)
    used = {a.morphism for _, a in plan.activations}
    deployed = set(env.instance.problem.deployed)
    return sum((_morphism(env, n).churn for n in sorted(used ^ deployed)), Fraction(0))


def _h_uses(env: _Env, e: ir.Uses) -> Fraction:
    plan = _need_plan(env, e)
    return Fraction(sum(1 for _, a in plan.activations if a.morphism == e.morphism))


def _h_param_value(env: _Env, e: ir.ParamValue) -> object:
    plan = _need_plan(env, e)
    values = [_norm(a.params[e.param]) for _, a in plan.activations if a.morphism == e.morphism and e.param in a.params]
    uses = sum(1 for _, a in plan.activations if a.morphism == e.morphism)
    if not values or len(values) != uses:
        raise Undefined(f"(param {e.morphism} {e.param}) is undefined: '{e.morphism}' is not used with a value for it")
    if any(v != values[0] for v in values[1:]):
        raise Undefined(f"(param {e.morphism} {e.param}) is undefined: '{e.morphism}' is used with several values")
    return values[0]


def _eval(env: _Env, e: ir.Expr) -> object:
    match e:
        case ir.Const():
            return _h_const(env, e)
        case ir.ResourceRef():
            return _h_resource(env, e)
        case ir.ParamRef():
            return _h_param(env, e)
        case ir.SetLit():
            return _h_setlit(env, e)
        case ir.Arith():
            return _h_arith(env, e)
        case ir.Compare():
            return _h_compare(env, e)
        case ir.BoolOp():
            return _h_boolop(env, e)
        case ir.Ite():
            return _h_ite(env, e)
        case ir.Member():
            return _h_member(env, e)
        case ir.TotalCost():
            return _h_total_cost(env, e)
        case ir.TotalChurn():
            return _h_total_churn(env, e)
        case ir.Uses():
            return _h_uses(env, e)
        case ir.ParamValue():
            return _h_param_value(env, e)
        case _:
            _not_an_expression(e)


def _not_an_expression(e: Never) -> NoReturn:
    """``assert_never`` for mypy (every ``ir.Expr`` is matched above), and an
    :class:`EvaluationError` at run time for what is no expression at all."""
    raise EvaluationError(f"cannot evaluate a {type(e).__name__}")


def evaluate(
    instance: ir.Instance, expr: ir.Expr, state: Mapping[str, object], params: Mapping[str, object] | None = None
) -> object:
    """The value of ``expr`` in ``state`` with parameter values ``params`` (name → value).

    Raises :class:`DivisionByZero` when a divisor anywhere in ``expr`` is 0 and
    :class:`EvaluationError` when the expression has no value."""
    return _eval(_Env(instance, state, dict(params or {})), expr)


def objective_value(
    instance: ir.Instance, plan: Plan, term: ir.Expr, final_state: Mapping[str, object]
) -> Fraction | None:
    """An objective term on the composition: resources on ``final_state``, plus
    ``(total-cost)``, ``(total-churn)`` (against ``(:deployed ...)``), ``(uses m)`` and
    ``(param m p)``.  None when the term is undefined (a parameter of an unused morphism,
    a zero divisor, an unknown morphism in the plan)."""
    try:
        # an objective term is numeric (checked by the front end's sort rules)
        return _eval(_Env(instance, final_state, {}, plan), term)  # type: ignore[return-value]
    except EvaluationError:
        return None


# ====================================================================== presentation


def fmt(v: object) -> str:
    """A value as messages write it (numbers exact: decimals when they terminate, else n/d)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, Fraction):
        return ratio_text(v)
    if isinstance(v, frozenset):
        return "{" + " ".join(sorted(map(str, v))) + "}"
    if isinstance(v, str):
        return v
    return repr(v)


def _activation_text(act: Activation) -> str:
    if not act.params:
        return act.morphism
    return f"{act.morphism}(" + ", ".join(f"{k}={fmt(_norm(v))}" for k, v in act.params.items()) + ")"


def _bindings(expr: ir.Expr, state: Mapping[str, object], params: Mapping[str, object]) -> str:
    """``battery = 73.3, d = 73``: the values an expression reads."""
    parts = []
    for name in sorted(ir.resources_in(expr)):
        parts.append(f"{name} = {fmt(state[name]) if name in state else '(no value)'}")
    for name in sorted(ir.params_in(expr)):
        if name in params:
            parts.append(f"{name} = {fmt(_norm(params[name]))}")
    return ", ".join(parts)
