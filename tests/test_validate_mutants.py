"""The validator's every report, word for word (issue 15, item 4: the mutants of
compiler/catc/semantics/validate.py that tests/test_validate.py let survive).

tests/test_validate.py checks *which* violations a composition has; mutation testing
(benchmarks/mutation.py) showed that it does not pin *what they say*: a message, a step, a
label or a kind could change, or an evaluation error lose its text, with every test still
green.  Here each scenario — a composition that breaks one rule of docs/semantics.md §4, an
instance taken apart by hand past what the checker allows (the validator replays
compositions from elsewhere and must not trust its input), an expression whose evaluation
fails — is rendered in full (every violation's kind, step, morphism, label and message, and
every replayed state) and compared with tests/golden/validate-reports.txt, written once from
this validator and read line by line (``CATC_UPDATE_GOLDEN=1`` rewrites it after a deliberate
change).  A few direct checks pin what the rendering cannot see.
"""

from __future__ import annotations

import functools
import os
from fractions import Fraction as F
from pathlib import Path

import pytest
from conftest import FIXTURES

from catc import ir
from catc.frontend.session import load_texts
from catc.frontend.workspace import load_instance
from catc.semantics import validate as V
from catc.semantics.plan import Activation, Plan
from catgrammar.diagnostics import Diagnostics
from catgrammar.record import replace

GOLDEN = Path(__file__).resolve().parent / "golden" / "validate-reports.txt"
VAL = FIXTURES / "validate"


@functools.cache
def load(name: str) -> ir.Instance:
    diags = Diagnostics()
    _, inst = load_instance(None, str(VAL / name), diags)
    assert inst is not None, [d.message for d in diags]
    return inst


@functools.cache
def text_instance(text: str) -> ir.Instance:
    diags = Diagnostics()
    inst = load_texts({"t.cat": text}, "t.cat", diags)
    assert inst is not None, [d.message for d in diags]
    return inst


def A(morphism: str, **params: object) -> Activation:
    return Activation(morphism, dict(params))


def plan(*steps: object) -> Plan:
    return Plan(tuple(tuple(s) if isinstance(s, (list, tuple)) else (s,) for s in steps), {})


def render(report: V.Report) -> str:
    lines = [f"  {v.kind} | step {v.step} | {v.morphism} | {v.label} | {v.message}" for v in report.violations]
    for i, state in enumerate(report.states):
        lines.append(f"  s{i}: " + ", ".join(f"{k}={V.fmt(v)}" for k, v in sorted(state.items())))
    return "\n".join(lines) if lines else "  (valid, no state)"


# ---------------------------------------------------------------- compositions that break a rule

INTER, PARAMS = "interference.cat", "params.cat"
TALLY = """(define (domain tally) (:requirements :numeric :free-parameters)
  (:resources (n int :bounds (0 *)) (x real :bounds (* 5)) (flag bool))
  (:morphism bump :parameters ((k int :bounds (0 2))) :effect (increase n k))
  (:morphism half :parameters ((d real :bounds (0 2))) :precondition (> (/ x d) 0) :effect (assign x (/ x d)))
  (:morphism twin :parameters ((w real :bounds (0 9))) :precondition (>= x w) :effect (assign flag true))
  (:morphism both :parameters ((w real :bounds (0 9)) (v real :bounds (0 9))) :effect (increase x (- w v))))
(define (problem tally-p) (:domain tally) (:init (= n 0) (= x 4)) (:goal (and flag (>= n 1))) (:horizon 3))
"""

PAIRS = """(define (domain pairs) (:requirements :numeric :sets :free-parameters)
  (:sorts item - symbol) (:constants apple - item)
  (:resources (a real) (b real) (c real) (s (set item)))
  (:morphism w :effect (and (assign a 1) (assign b 2)))
  (:morphism r :effect (assign c b))
  (:morphism u :effect (and (increase c 1) (increase b 1)))
  (:morphism rm2 :effect (and (increase c 1) (remove s apple)))
  (:morphism rm :effect (remove s apple))
  (:morphism grow :effect (and (increase c 1) (add s apple)))
  (:morphism q :parameters ((d real :bounds (0 2)) (e real :bounds (0 2)))
    :precondition (> (/ a d) (+ c e)) :effect (assign b 5)))
(define (problem pairs-p) (:domain pairs) (:init (= a 0) (= b 0) (= c 0)) (:goal (>= a 0)) (:horizon 3))
"""

SCENARIOS: dict[str, tuple[str, Plan, dict]] = {
    "assign/assign": (INTER, plan([A("set-gauge"), A("reset-gauge")]), {}),
    "assign/read": (INTER, plan([A("set-gauge"), A("watch-gauge")]), {}),
    "read/assign": (INTER, plan([A("watch-gauge"), A("set-gauge")]), {}),
    "assign/update": (INTER, plan([A("bump-gauge"), A("set-gauge")]), {}),
    "update/read": (INTER, plan([A("refill"), A("drain-fixed")]), {}),
    "update/update": (INTER, plan([A("drain-fixed"), A("drain-param", x=F(1))]), {}),
    "add/remove": (INTER, plan([A("put", i="apple"), A("take", i="apple")]), {}),
    "add/remove other": (INTER, plan([A("put", i="apple"), A("take", i="pear")]), {}),
    "sequential": (INTER, plan([A("drain-fixed"), A("set-gauge")]), {"sequential": True}),
    "twice in a step": (INTER, plan([A("drain-fixed"), A("drain-fixed")]), {}),
    "an assignment twice in a step": (INTER, plan([A("set-gauge"), A("set-gauge")]), {}),
    "assigns a second effect's resource while another reads it": (PAIRS, plan([A("w"), A("r")]), {}),
    "assigns a resource another updates second": (PAIRS, plan([A("w"), A("u")]), {}),
    "updates a resource another reads in an effect": (PAIRS, plan([A("u"), A("r")]), {}),
    "removes what another removes": (PAIRS, plan([A("rm"), A("rm2")]), {}),
    "adds in a second effect what another removes": (PAIRS, plan([A("grow"), A("rm")]), {}),
    "a missing parameter before a bad one": (PARAMS, plan(A("observe", c="red", n=F(3, 2), w=F(1), loud=True)), {}),
    "unknown morphism": (INTER, plan(A("fly")), {}),
    "unknown parameter": (INTER, plan(A("drain-fixed", x=F(1))), {}),
    "missing parameter": (INTER, plan(A("drain-param")), {}),
    "parameter bounds": (INTER, plan(A("drain-param", x=F(11))), {}),
    "below an open-topped bound": (INTER, plan(A("drain-param", x=F(7)), A("drain-param", x=F(7))), {}),
    "above a closed bound": (INTER, plan(*[A("put", i="apple")] * 4), {}),
    "goal false": (INTER, plan(), {}),
    "past the horizon": (INTER, plan(*[A("refill")] * 4), {"horizon": 3}),
    "symbol for a real": (INTER, plan(A("drain-param", x="apple")), {}),
    "number for a symbol": (INTER, plan(A("put", i=F(3))), {}),
    "non-integer int": (PARAMS, plan(A("observe", a="rex", c="red", n=F(3, 2), w=F(1), loud=True)), {}),
    "not an enumeration value": (PARAMS, plan(A("observe", a="rex", c="blue", n=F(1), w=F(1), loud=True)), {}),
    "number for a bool": (PARAMS, plan(A("observe", a="rex", c="red", n=F(1), w=F(1), loud=F(2))), {}),
    "fixed parameter changes": (
        PARAMS,
        plan(
            A("observe", a="rex", c="red", n=F(1), w=F(1), loud=True),
            A("observe", a="rex", c="red", n=F(1), w=F(2), loud=True),
        ),
        {},
    ),
    "uses exceeded": (PARAMS, plan(A("divide", k=F(1)), A("divide", k=F(1))), {}),
    "division by a zero parameter": (PARAMS, plan(A("divide", k=F(0))), {}),
    "valid": (
        PARAMS,
        plan(
            A("observe", a="tweety", c="green", n=F(1), w=F(1), loud=True),
        ),
        {},
    ),
    "int made fractional": (TALLY, plan(A("bump", k=F(1, 2))), {}),
    "effect divides by zero": (TALLY, plan(A("half", d=F(0))), {}),
    "below an open-bottomed bound": (TALLY, plan(A("both", w=F(9), v=F(0))), {}),
}


def _instance(source: str) -> ir.Instance:
    return load(source) if source.endswith(".cat") else text_instance(source)


# ---------------------------------------------------------------- instances taken apart by hand


def _without_init(inst: ir.Instance, *names: str) -> ir.Instance:
    init = {k: v for k, v in inst.problem.init.items() if k not in names}
    return replace(inst, problem=replace(inst.problem, init=init))


def _with_init(inst: ir.Instance, name: str, value: ir.Const | ir.SetLit) -> ir.Instance:
    init = {**inst.problem.init, name: ir.InitValue(name, value, f"init/{name}/by-hand")}
    return replace(inst, problem=replace(inst.problem, init=init))


def _with_goal(inst: ir.Instance, expr: ir.Expr) -> ir.Instance:
    return replace(inst, problem=replace(inst.problem, goal=(ir.Literal(expr, "goal/1"),)))


def broken_instances() -> dict[str, tuple[ir.Instance, Plan]]:
    inter, pairs = load(INTER), text_instance(PAIRS)
    ghost_value = ir.Const(F(1), ir.REAL)
    unreadable = ir.SetLit((ir.Const(F(1), ir.REAL),), inter.resources["basket"].sort)
    return {
        "no initial value": (_without_init(inter, "tank"), plan(A("refill"))),
        "initial value for an unknown resource": (_with_init(inter, "ghost", ghost_value), plan()),
        "initial value out of bounds": (_with_init(inter, "tank", ir.Const(F(-1), ir.REAL)), plan()),
        "initial value that cannot be evaluated": (_with_init(inter, "basket", unreadable), plan()),
        "initial value of the wrong sort": (_with_init(inter, "alarm", ir.Const(F(1), ir.REAL)), plan()),
        "a symbol for a number": (_with_init(inter, "gauge", ir.Const("apple", ir.REAL)), plan()),
        "a number for a set": (_with_init(inter, "basket", ir.Const(F(1), ir.REAL)), plan()),
        "bools false, sets empty": (_without_init(inter, "alarm", "basket"), plan(A("put", i="pear"))),
        "the first initial value cannot be evaluated": (_with_init(inter, "tank", unreadable), plan()),
        "a fraction for an int": (_with_init(inter, "counter", ir.Const(F(1, 2), ir.REAL)), plan()),
        "a number for an enumeration": (_with_init(load(PARAMS), "paint", ir.Const(F(1), ir.REAL)), plan()),
        "an update of a set that is not one": (_with_init(inter, "basket", ghost_value), plan(A("put", i="apple"))),
        "an update of a resource without a value": (_without_init(pairs, "c"), plan(A("u"))),
        "an effect reads a resource without a value": (_without_init(pairs, "b"), plan(A("r"))),
        "a zero divisor beside a resource without a value": (
            _without_init(pairs, "c"),
            plan(A("q", d=F(0), e=F(1))),
        ),
        "a goal without a value after a step out of bounds": (
            _without_init(text_instance(TALLY), "n"),
            plan(A("both", w=F(9), v=F(0))),
        ),
        "a goal that reads nothing": (_with_goal(pairs, ir.Const(False, ir.BOOL)), plan()),
    }


# ---------------------------------------------------------------- expressions that have no value


def expressions() -> dict[str, tuple[ir.Expr, dict, dict | None]]:
    one, yes, no, apple = (
        ir.Const(F(1), ir.INT),
        ir.Const(True, ir.BOOL),
        ir.Const(False, ir.BOOL),
        ir.Const("apple", ir.REAL),
    )
    item_set = load(INTER).resources["basket"].sort
    tank = ir.ResourceRef("tank", ir.REAL)
    return {
        "a bool in arithmetic": (ir.Arith(ir.ArithOp.ADD, (yes, one), ir.INT), {}, None),
        "a number as a condition": (ir.BoolOp(ir.BoolOpKind.AND, (one,)), {}, None),
        "a resource without a value": (ir.ResourceRef("ghost", ir.REAL), {}, None),
        "a parameter without a value": (ir.ParamRef("p", ir.REAL), {}, {"q": F(1)}),
        "a number in a set literal": (ir.SetLit((one,), item_set), {}, None),
        "arithmetic without arguments": (ir.Arith(ir.ArithOp.ADD, (), ir.INT), {}, None),
        "a zero divisor": (
            ir.Arith(ir.ArithOp.DIV, (one, ir.Arith(ir.ArithOp.SUB, (one, one), ir.INT)), ir.REAL),
            {},
            None,
        ),
        "= between kinds": (ir.Compare(ir.CmpOp.EQ, one, yes), {}, None),
        "= between sets and symbols": (ir.Compare(ir.CmpOp.EQ, ir.SetLit((), item_set), apple), {}, None),
        "< on a symbol, left": (ir.Compare(ir.CmpOp.LT, apple, one), {}, None),
        "< on a symbol, right": (ir.Compare(ir.CmpOp.LT, one, apple), {}, None),
        "not of two": (ir.BoolOp(ir.BoolOpKind.NOT, (yes, no)), {}, None),
        "imply of none": (ir.BoolOp(ir.BoolOpKind.IMPLY, ()), {}, None),
        "imply true false false": (ir.BoolOp(ir.BoolOpKind.IMPLY, (yes, no, no)), {}, None),
        "imply true true false": (ir.BoolOp(ir.BoolOpKind.IMPLY, (yes, yes, no)), {}, None),
        "if reads the state": (ir.Ite(yes, tank, ir.Const(F(0), ir.REAL), ir.REAL), {"tank": F(7)}, None),
        "member of a number": (ir.Member(apple, one), {}, None),
        "total-churn without a plan": (ir.TotalChurn(), {}, None),
        "uses without a plan": (ir.Uses("refill"), {}, None),
        "param without a plan": (ir.ParamValue("put", "i", ir.REAL), {}, None),
        "a set literal": (ir.SetLit((apple, ir.Const("pear", ir.REAL)), item_set), {}, None),
        "if false": (ir.Ite(no, one, ir.Const(F(2), ir.INT), ir.INT), {}, None),
        "a set literal naming a parameter": (ir.SetLit((ir.ParamRef("i", ir.REAL),), item_set), {}, {"i": "pear"}),
        "an unknown boolean operator": (ir.BoolOp("xor", (yes, no)), {}, None),  # type: ignore[arg-type]
        "something that is no expression": (object(), {}, None),  # type: ignore[dict-item]
    }


def _evaluation(expr: ir.Expr, state: dict, params: dict | None) -> str:
    try:
        value = V.evaluate(load(INTER), expr, state, params)
    except V.EvaluationError as exc:
        return f"  {type(exc).__name__}: {exc}"
    return f"  = {V.fmt(value)}"


OBJ = """(define (domain obj) (:requirements :numeric :free-parameters :recomposition)
  (:resources (r real))
  (:morphism a :churn 2 :cost (* 3 w) :parameters ((w real :bounds (0 9))) :effect (increase r w))
  (:morphism b :churn 5 :parameters ((w real :bounds (0 9)) (z real :bounds (0 9))) :effect (increase r z))
  (:morphism c :churn 7 :effect (increase r 1)))
(define (problem obj-p) (:domain obj) (:init (= r 0)) (:goal (>= r 0)) (:deployed c) (:horizon 3))
"""


def objectives() -> dict[str, tuple[Plan, ir.Expr]]:
    a1, b = A("a", w=F(1)), A("b", w=F(4), z=F(2))
    return {
        "total-churn": (plan(a1, b), ir.TotalChurn()),
        "total-churn of nothing new": (plan(A("c")), ir.TotalChurn()),
        "total-cost": (plan(a1, b, A("c")), ir.TotalCost()),
        "uses": (plan(a1, b, a1), ir.Uses("a")),
        "param of a once-used morphism": (plan(b, a1), ir.ParamValue("a", "w", ir.REAL)),
        "param of a twice-used morphism": (plan(a1, A("a", w=F(2))), ir.ParamValue("a", "w", ir.REAL)),
        "param of an unused morphism": (plan(b), ir.ParamValue("a", "w", ir.REAL)),
        "an unknown morphism in the plan": (plan(A("zz")), ir.TotalChurn()),
    }


def _objective(p: Plan, term: ir.Expr) -> str:
    inst = text_instance(OBJ)
    try:
        value = V._eval(V._Env(inst, {"r": F(0)}, {}, p), term)
    except V.EvaluationError as exc:
        return f"  {type(exc).__name__}: {exc} (objective_value: {V.objective_value(inst, p, term, {'r': F(0)})})"
    return f"  = {V.fmt(value)} (objective_value: {V.fmt(V.objective_value(inst, p, term, {'r': F(0)}))})"


# ---------------------------------------------------------------- the golden file


def reports() -> str:
    out = []
    for name, (source, p, options) in SCENARIOS.items():
        out += [f"## {name}", render(V.validate(_instance(source), p, **options))]
    for name, (inst, p) in broken_instances().items():
        out += [f"## instance: {name}", render(V.validate(inst, p))]
    for name, (expr, state, params) in expressions().items():
        out += [f"## evaluate: {name}", _evaluation(expr, state, params)]
    for name, (p, term) in objectives().items():
        out += [f"## objective: {name}", _objective(p, term)]
    return "\n".join(out) + "\n"


def test_every_report_word_for_word():
    text = reports()
    if os.environ.get("CATC_UPDATE_GOLDEN"):
        GOLDEN.write_text(text)
    assert text == GOLDEN.read_text(), (
        "validator output changed; CATC_UPDATE_GOLDEN=1 rewrites tests/golden/validate-reports.txt"
    )


# ---------------------------------------------------------------- what the rendering cannot see


def test_division_by_zero_keeps_its_expression():
    expr = ir.Arith(ir.ArithOp.DIV, (ir.Const(F(1), ir.INT), ir.Const(F(0), ir.INT)), ir.REAL)
    with pytest.raises(V.DivisionByZero) as info:
        V.evaluate(load(INTER), expr, {})
    assert info.value.expr is expr
    assert str(info.value) == "division by zero: 0 is 0 in (/ 1 0)"


@pytest.mark.parametrize(
    "value, text",
    [(True, "true"), (False, "false"), (F(1, 3), "1/3"), (frozenset({"b", "a"}), "{a b}"), (7, "7")],
)
def test_values_as_messages_write_them(value, text):
    assert V.fmt(value) == text


def test_violations_come_in_order_initial_state_first():
    """Initial-state problems come before every step's, then steps in order, then the goal."""
    inst = _without_init(load(INTER), "tank")
    report = V.validate(inst, plan(A("refill"), [A("set-gauge"), A("reset-gauge")]))
    kinds = report.kinds()
    assert kinds[0] == "initial-state"
    steps = [v.step for v in report.violations if v.step is not None]
    assert steps == sorted(steps)


def test_total_churn_is_an_exact_number_even_when_nothing_changes():
    inst = text_instance(OBJ)
    value = V.objective_value(inst, plan(A("c")), ir.TotalChurn(), {"r": F(0)})
    assert value == 0 and isinstance(value, F)
