"""Export a checked instance (:mod:`catc.ir`) to PDDL 2.1 numeric planning (DESIGN §6).

The translation grounds everything the PDDL side cannot express symbolically:

* numeric resources → 0-ary functions; bool resources → 0-ary predicates; a set resource
  ``r`` → one 0-ary predicate ``(r-c)`` per constant ``c`` of its element sort; a symbolic
  resource ``r`` → one predicate ``(r-is-v)`` per value ``v``;
* every morphism → one ground action per assignment of its parameters θ: int/bool/symbolic
  θ over their finite/known values, real θ on a grid (``--grid PARAM=STEP``) within bounds;
* ``:uses`` limits → a counter function ``(used-m)``; ``:fixed`` θ → ``(fixed-m-p-v)``
  predicates; resource bounds → preconditions on the successor values;
* the metric → ``(:metric minimize ...)`` only for a single minimisation of
  ``(total-cost)`` with non-negative costs, or of a numeric expression over resources, or for
  ``maximize R`` of a resource R that only decreases by non-negative θ-only amounts (then
  each action costs what it takes from R, and ``minimize (total-cost)`` has the same optimal
  plans).

Everything not expressed is listed in the :class:`ExportReport` (never dropped silently).
Action names are ``a-`` + the sanitized morphism name + a θ suffix; :attr:`Export.actions`
maps each back to an :class:`catc.semantics.plan.Activation` so that a PDDL plan can be replayed by
:func:`catc.semantics.validate.validate`.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Mapping
from fractions import Fraction
from typing import cast

from catc import ir
from catc.ir import ArithOp, BoolOpKind, CmpOp, EffectKind, SortKind
from catc.ir.fold import ConstantTooLarge, FoldError, fold
from catc.ir.numbers import decimal_text, fraction_text
from catc.semantics.plan import Activation, Value
from catc.targets.pddl_base import (
    Export,
    ExportError,
    ExportReport,
    Flavor,
    Names,
    Unsupported,
    grid_values,
    lower_bound,
    nice_step,
    nonnegative_constant,
    number,
    sanitize,
    value_suffix,
)
from catgrammar import codes, limits


class Exporter:
    def __init__(self, inst: ir.Instance, grid: Mapping[str, Fraction], horizon: int | None, flavor: Flavor) -> None:
        self.inst = inst
        self.grid_in = dict(grid)
        self.horizon = horizon
        self.flavor = flavor
        self.report = ExportReport()
        self.names = Names()
        self.requirements: set[str] = {":strips"}
        self.pred: dict[tuple[object, ...], str] = {}  # key → predicate name
        self.func: dict[str | tuple[str, str], str] = {}  # resource name / (counter kind, name) → function name
        self.actions: dict[str, Activation] = {}
        self.grid_used: dict[str, Fraction] = {}
        self._drained: str | None = None  # maximize R exported as minimize the total taken from R
        self.universe: dict[str, list[str]] = {}  # resource → values (set elements / symbols)

    # ---- vocabulary
    def _values_of(self, sort: ir.Sort) -> list[str]:
        return self.inst.constants_of(sort)

    def declare(self) -> None:
        for r in self.inst.resources.values():
            k = r.sort.kind
            if k in (SortKind.INT, SortKind.REAL):
                self.func[r.name] = self.names.fresh(r.name)
                self.requirements.add(":numeric-fluents")
            elif k is SortKind.BOOL:
                self.pred[("bool", r.name)] = self.names.fresh(r.name)
            elif k is SortKind.SET:
                element = r.sort.element
                assert element is not None  # a set sort has an element sort
                vals = self._values_of(element)
                self.universe[r.name] = vals
                for c in vals:
                    self.pred[("mem", r.name, c)] = self.names.fresh(f"{r.name}-{c}")
                if element.kind is SortKind.SYMBOL:
                    self.report.add(
                        "reserve values",
                        f"set resource '{r.name}': only the {len(vals)} known constant(s) of sort '{r.sort.element}' are grounded; PDDL has no fresh (reserve) values",
                    )
            else:
                vals = self._values_of(r.sort)
                self.universe[r.name] = vals
                for c in vals:
                    self.pred[("is", r.name, c)] = self.names.fresh(f"{r.name}-is-{c}")

    # ---- expressions: fold θ, then print
    def _fold(self, e: ir.Expr, theta: Mapping[str, object]) -> ir.Expr:
        try:
            return fold(e, theta)
        except ConstantTooLarge as exc:  # θ of a grid times the model's constants
            values = ", ".join(f"{k} = {fraction_text(v)}" for k, v in theta.items() if isinstance(v, Fraction))
            raise limits.LimitExceeded(codes.CONSTANT_TOO_LARGE, f"with {values}: {exc}", exc.expr.span) from None
        except FoldError:
            raise Unsupported("division by zero") from None

    def num(self, e: ir.Expr) -> str:
        if isinstance(e, ir.Const) and isinstance(e.value, Fraction):
            return number(e.value)
        if isinstance(e, ir.ResourceRef) and e.name in self.func:
            return f"({self.func[e.name]})"
        if isinstance(e, (ir.ParamRef, ir.ParamValue)):
            return self.param_term(e)
        if isinstance(e, ir.Arith) and e.op in (ArithOp.ADD, ArithOp.SUB, ArithOp.MUL, ArithOp.DIV):
            args = [self.num(a) for a in e.args]
            if e.op is ArithOp.SUB and len(args) == 1:
                return f"(- 0 {args[0]})"
            out = args[0]
            for a in args[1:]:  # binary operators only (PDDL 2.1)
                out = f"({e.op.value} {out} {a})"
            return out
        raise Unsupported(f"numeric term {type(e).__name__}{'/' + e.op.value if isinstance(e, ir.Arith) else ''}")

    def is_dial(self, m: ir.Morphism, p: ir.Param) -> bool:
        """Whether θ ``p`` of ``m`` stays symbolic (a PDDL+ dial); never in PDDL 2.1."""
        return False

    def param_term(self, e: ir.ParamRef | ir.ParamValue) -> str:
        """A θ left symbolic by :meth:`_fold` (only the PDDL+ flavour has such θ)."""
        raise Unsupported(f"parameter {getattr(e, 'name', getattr(e, 'param', '?'))} as a numeric term")

    def _sym_atom(self, res: str, value: object) -> str:
        key = ("is", res, value)
        if key not in self.pred:
            return self.false()  # a value the resource can never take (e.g. a fresh one)
        return f"({self.pred[key]})"

    def false(self) -> str:
        if ("false",) not in self.pred:
            self.pred[("false",)] = self.names.fresh("catc-false")
        return f"({self.pred[('false',)]})"

    def cond(self, e: ir.Expr) -> str:
        if isinstance(e, ir.Const) and isinstance(e.value, bool):
            return "(and)" if e.value else self.false()
        if isinstance(e, ir.ResourceRef) and ("bool", e.name) in self.pred:
            return f"({self.pred[('bool', e.name)]})"
        if isinstance(e, ir.BoolOp):
            args = [self.cond(a) for a in e.args]
            if e.op is BoolOpKind.NOT:
                self.requirements.add(":negative-preconditions")
                return f"(not {args[0]})"
            if e.op is BoolOpKind.IMPLY:
                self.requirements.add(":disjunctive-preconditions")
                return f"(imply {args[0]} {args[1]})"
            if e.op is BoolOpKind.OR:
                self.requirements.add(":disjunctive-preconditions")
            return f"({e.op.value} {' '.join(args)})"
        if isinstance(e, ir.Member):
            if not isinstance(e.set, ir.ResourceRef) or not isinstance(e.element, ir.Const):
                raise Unsupported("membership in a set expression or of a state-dependent element")
            key = ("mem", e.set.name, e.element.value)
            return f"({self.pred[key]})" if key in self.pred else self.false()
        if isinstance(e, ir.Compare):
            l, r = e.left, e.right
            if l.sort.is_numeric or r.sort.is_numeric:
                return f"({e.op.value} {self.num(l)} {self.num(r)})"
            if e.op is not CmpOp.EQ:
                raise Unsupported(f"comparison {e.op.value} of non-numbers")
            if l.sort.kind is SortKind.BOOL:
                a, b = (l, r) if isinstance(r, ir.Const) else (r, l)
                if isinstance(b, ir.Const):
                    c = self.cond(a)
                    if b.value:
                        return c
                    self.requirements.add(":negative-preconditions")
                    return f"(not {c})"
                self.requirements.add(":disjunctive-preconditions")
                self.requirements.add(":negative-preconditions")
                ca, cb = self.cond(a), self.cond(b)
                return f"(or (and {ca} {cb}) (and (not {ca}) (not {cb})))"
            if l.sort.is_symbolic:
                if isinstance(l, ir.Const):
                    l, r = r, l
                if isinstance(l, ir.ResourceRef) and isinstance(r, ir.Const):
                    return self._sym_atom(l.name, r.value)
                if isinstance(l, ir.ResourceRef) and isinstance(r, ir.ResourceRef):
                    self.requirements.add(":disjunctive-preconditions")
                    common = [v for v in self.universe.get(l.name, []) if v in self.universe.get(r.name, [])]
                    if not common:
                        return self.false()
                    return (
                        "(or "
                        + " ".join(f"(and {self._sym_atom(l.name, v)} {self._sym_atom(r.name, v)})" for v in common)
                        + ")"
                    )
            raise Unsupported(f"equality of {l.sort} values")
        raise Unsupported(f"condition {type(e).__name__}")

    # ---- actions
    def _theta_values(self, m: ir.Morphism) -> list[list[object]] | None:
        out: list[list[object]] = []
        for p in m.params:
            k = p.sort.kind
            if k is SortKind.BOOL:
                out.append([False, True])
            elif k in (SortKind.SYMBOL, SortKind.ENUM):
                symbols = self._values_of(p.sort)
                if k is SortKind.SYMBOL:
                    self.report.add(
                        "reserve values",
                        f"{m.name}.{p.name} ranges over the {len(symbols)} known constant(s) of sort '{p.sort}' only; catc may also use fresh (reserve) values, PDDL has no fresh constants",
                    )
                out.append(list(symbols))
            elif k is SortKind.INT:
                if p.lower is None or p.upper is None:
                    raise ExportError(
                        f"int parameter {m.name}.{p.name} has no bounds (:bounds (lo hi)); PDDL actions need finitely many values"
                    )
                lo, hi = -(-p.lower // 1), p.upper // 1
                out.append([Fraction(v) for v in range(int(lo), int(hi) + 1)])
            elif k is SortKind.REAL:
                key = f"{m.name}.{p.name}"
                step = self.grid_in.get(key, self.grid_in.get(p.name))
                if p.lower is None or p.upper is None:
                    raise ExportError(
                        f"real parameter {key} has no finite bounds; give it :bounds (lo hi) to export it with --grid"
                    )
                if step is None:
                    raise ExportError(
                        f"real parameter {key} is continuous; give a grid step with --grid {key}=STEP (or --grid {p.name}=STEP)"
                    )
                if step <= 0:
                    raise ExportError(f"grid step for {key} must be positive, got {step}")
                grid = grid_values(p.lower, p.upper, step)
                self.grid_used[key] = step
                self.report.add(
                    "continuous parameters",
                    f"{key} ∈ [{decimal_text(p.lower)}, {decimal_text(p.upper)}] discretised with step {decimal_text(step)} ({len(grid)} values); solutions off the grid are lost",
                )
                out.append(list(grid))
            else:
                raise ExportError(f"parameter {m.name}.{p.name} of sort {p.sort} cannot be grounded")
        return out

    def _bound_checks(self, r: ir.Resource, post: str) -> list[str]:
        out = []
        if r.lower is not None:
            out.append(f"(>= {post} {number(r.lower)})")
        if r.upper is not None:
            out.append(f"(<= {post} {number(r.upper)})")
        return out

    def _effects(self, m: ir.Morphism, theta: Mapping[str, object]) -> tuple[list[str], list[str]]:
        """(effect atoms, extra preconditions for resource bounds)."""
        effs: list[str] = []
        pres: list[str] = []
        for eff in m.effects:
            r = self.inst.resources[eff.resource]
            v = self._fold(eff.value, theta)
            k = r.sort.kind
            if k in (SortKind.INT, SortKind.REAL):
                f = f"({self.func[r.name]})"
                amount = self.num(v)
                if eff.kind is EffectKind.ASSIGN:
                    effs.append(f"(assign {f} {amount})")
                    post = amount
                elif eff.kind is EffectKind.INCREASE:
                    effs.append(f"(increase {f} {amount})")
                    post = f"(+ {f} {amount})"
                else:
                    effs.append(f"(decrease {f} {amount})")
                    post = f"(- {f} {amount})"
                pres.extend(self._bound_checks(r, post))
            elif k is SortKind.BOOL:
                p = f"({self.pred[('bool', r.name)]})"
                if not isinstance(v, ir.Const):  # its new value is a condition on the state before
                    c = self.cond(v)
                    self.requirements.update((":conditional-effects", ":negative-preconditions"))
                    effs.append(f"(when {c} {p})")
                    effs.append(f"(when (not {c}) (not {p}))")
                    continue
                effs.append(p if v.value else f"(not {p})")
            elif k is SortKind.SET:
                if eff.kind in (EffectKind.ADD, EffectKind.REMOVE):
                    if not isinstance(v, ir.Const):
                        raise Unsupported(f"state-dependent element added to/removed from '{r.name}'")
                    key = ("mem", r.name, v.value)
                    if key not in self.pred:
                        raise Unsupported(f"element '{v.value}' of '{r.name}' is not a known constant")
                    effs.append(f"({self.pred[key]})" if eff.kind is EffectKind.ADD else f"(not ({self.pred[key]}))")
                elif isinstance(v, ir.SetLit) and all(isinstance(x, ir.Const) for x in v.elements):
                    members = {x.value for x in v.elements if isinstance(x, ir.Const)}
                    for c in self.universe[r.name]:
                        a = f"({self.pred[('mem', r.name, c)]})"
                        effs.append(a if c in members else f"(not {a})")
                else:
                    raise Unsupported(f"state-dependent assignment to set resource '{r.name}'")
            else:
                if not isinstance(v, ir.Const):
                    raise Unsupported(f"state-dependent assignment to symbolic resource '{r.name}'")
                for c in self.universe[r.name]:
                    a = f"({self.pred[('is', r.name, c)]})"
                    effs.append(a if c == v.value else f"(not {a})")
                if v.value not in self.universe[r.name]:
                    raise Unsupported(f"value '{v.value}' of '{r.name}' is not a known constant")
        return effs, pres

    def action_text(self, m: ir.Morphism, theta: dict[str, object], objective_cost: bool) -> str | None:
        name = self.names.fresh(
            "a-" + m.name + "".join("-" + value_suffix(theta[p.name]) for p in m.params if p.name in theta)
        )
        pre: list[str] = []
        for lit in m.pre:
            e = self._fold(lit.expr, theta)
            if isinstance(e, ir.Const) and e.value is False:
                self.names.used.discard(name)
                return None  # this θ never applies
            pre.append(self.cond(e))
        effs, bounds = self._effects(m, theta)
        pre.extend(bounds)
        if m.uses is not None:
            f = self.func[("uses", m.name)]
            pre.append(f"(< ({f}) {m.uses})")
            effs.append(f"(increase ({f}) 1)")
        for p in m.params:
            if p.fixed and p.name in theta:
                chosen = self.pred[("fixed", m.name, p.name)]
                mine = self.pred[("fixval", m.name, p.name, value_suffix(theta[p.name]))]
                self.requirements.update({":negative-preconditions", ":disjunctive-preconditions"})
                pre.append(f"(or (not ({chosen})) ({mine}))")
                effs.extend([f"({chosen})", f"({mine})"])
        if self.horizon is not None:
            pre.append(f"(< (catc-steps) {self.horizon})")
            effs.append("(increase (catc-steps) 1)")
        self.extra_conditions(m, theta, pre, effs)
        if objective_cost:
            c = self._action_cost(m, theta)
            if c is not None:
                effs.append(f"(increase (total-cost) {self.num(c)})")
        self.actions[name] = Activation(m.name, cast(Mapping[str, Value], theta))
        pre = [p for p in pre if p != "(and)"]
        pre_text = "(and " + " ".join(pre) + ")" if pre else "(and)"
        return (
            f"  (:action {name}\n    :parameters ()\n    :precondition {pre_text}\n"
            f"    :effect (and {' '.join(effs)}))\n"
        )

    def extra_conditions(self, m: ir.Morphism, theta: Mapping[str, object], pre: list[str], effs: list[str]) -> None:
        """Hook for the PDDL+ flavour (dial preconditions and effects); nothing here."""

    def _action_cost(self, m: ir.Morphism, theta: Mapping[str, object]) -> ir.Expr | None:
        """The action's contribution to (total-cost): its cost, or — for a metric maximising a
        resource that only decreases — what it takes from that resource."""
        if self._drained is None:
            return ir.Const(Fraction(1), ir.REAL) if m.cost is None else self._fold(m.cost, theta)
        amounts = [
            self._fold(e.value, theta)
            for e in m.effects
            if e.resource == self._drained and e.kind is ir.EffectKind.DECREASE
        ]
        if not amounts:
            return None
        return amounts[0] if len(amounts) == 1 else ir.Arith(ArithOp.ADD, tuple(amounts), ir.REAL)

    # ---- metric
    def _drain_metric(self, name: str) -> bool:
        """Whether ``maximize NAME`` can be exported as ``minimize (total-cost)``: every effect
        on the resource is a decrease by an amount that depends on θ only and is never
        negative within θ's bounds.  Then NAME's final value is its initial value minus the
        total cost, and the two metrics have the same optimal plans."""
        for m in self.inst.morphisms.values():
            for e in m.effects:
                if e.resource != name:
                    continue
                if e.kind is not ir.EffectKind.DECREASE or ir.resources_in(e.value):
                    return False
                low = lower_bound(e.value, {p.name: p for p in m.params})
                if low is None or low < 0:
                    return False
        return True

    def metric(self) -> tuple[str | None, bool]:
        """(metric text, whether actions must increase total-cost)."""
        met = self.inst.problem.metric
        if met is None:
            return None, False
        if met.mode is not ir.MetricMode.SINGLE or len(met.objectives) != 1:
            self.report.add(
                "objective",
                f"{met.mode.value} metric with {len(met.objectives)} objective(s): only one minimisation can be exported; no metric written",
            )
            return None, False
        obj = met.objectives[0]
        if obj.sense is ir.Sense.MAXIMIZE:
            term = obj.term
            if isinstance(term, ir.ResourceRef) and term.name in self.func and self._drain_metric(term.name):
                self._drained = term.name
                self.requirements.add(":action-costs")
                self.report.add(
                    "objective",
                    f"maximize {term.name} is written as minimize (total-cost): {term.name} only "
                    "decreases, each action costs what it takes from it, so its final value is its "
                    "initial value minus the total cost",
                )
                return "(:metric minimize (total-cost))", True
            self.report.add(
                "objective",
                "maximisation is not exported (ENHSP mishandles maximize, and state-dependent "
                "action costs); no metric written, the planner finds any plan",
            )
            return None, False
        if isinstance(obj.term, ir.TotalCost):
            for m in self.inst.morphisms.values():
                if m.cost is not None and not nonnegative_constant(m.cost):
                    self.report.add(
                        "objective",
                        f"cost of '{m.name}' is not a non-negative constant; total-cost metric not exported",
                    )
                    return None, False
            self.requirements.add(":action-costs")
            return "(:metric minimize (total-cost))", True
        try:
            if any(not isinstance(x, (ir.Const, ir.ResourceRef, ir.Arith)) for x in ir.walk(obj.term)):
                raise Unsupported("objective term")
            return f"(:metric minimize {self.num(obj.term)})", False
        except Unsupported as exc:
            self.report.add("objective", f"objective not exported ({exc})")
            return None, False

    # ---- whole export
    def run(self) -> Export:
        self.declare()
        self._report_unexpressed()
        self._declare_counters()
        metric, with_cost = self.metric()
        self._check_ground_actions()
        actions = self._ground_actions(with_cost)
        goal = self._goal()
        init = self._init()
        prob_text = self._problem_text(init, goal, metric)
        dom_text = self._domain_text(actions, with_cost)
        return Export(dom_text, prob_text, self.report, self.actions, self.grid_used, self.flavor)

    def _report_unexpressed(self) -> None:
        """Report what the model has and the PDDL files leave out: view, holes, soft constraints,
        the deployed composition, the horizon, parallel steps."""
        inst = self.inst
        d, p = inst.domain, inst.problem
        if inst.view is not None:
            v = d.views.get(inst.view)
            dropped = ", ".join(sorted(v.dropped)) if v else "?"
            self.report.add(
                "views",
                f"view '{inst.view}' applied before export: resources {dropped} and the literals mentioning them are dropped",
            )
        for h in d.holes.values():
            self.report.add(
                "holes",
                f"hole '{h.name}' (a missing component) is not exported; the PDDL domain has only the known components",
            )
        for s in p.softs:
            self.report.add(
                "soft constraints", f"soft constraint {s.label} (weight {decimal_text(s.weight)}) is not exported"
            )
        if p.deployed:
            self.report.add(
                "recomposition", f"deployed composition ({', '.join(p.deployed)}) and churn are not exported"
            )
        if self.horizon is not None:
            self.requirements.add(":numeric-fluents")
            self.report.add(
                "horizon",
                f"bounded to {self.horizon} sequential actions with the counter (catc-steps); catc's horizon counts parallel steps",
            )
        elif p.horizon is not None:
            self.report.add(
                "horizon",
                f"the problem's horizon {p.horizon} (parallel steps) is not exported; PDDL plans are unbounded (use --horizon K to bound the number of actions)",
            )
        self.report.add(
            "semantics",
            "PDDL plans are sequential (one action per step): compare with `catc solve --sequential`; catc's parallel steps (⊗ with non-interference) are not expressed",
        )

    def _declare_counters(self) -> None:
        """A ``(used-m)`` counter for every morphism with a ``:uses`` limit, a ``(fixed-m-p)`` flag
        for every ``:fixed`` θ (not a dial)."""
        for m in self.inst.domain.morphisms.values():
            if m.uses is not None:
                self.func[("uses", m.name)] = self.names.fresh(f"used-{m.name}")
                self.requirements.add(":numeric-fluents")
            for prm in m.params:
                if prm.fixed and not self.is_dial(m, prm):
                    self.pred[("fixed", m.name, prm.name)] = self.names.fresh(f"fixed-{m.name}-{prm.name}")

    def _theta_count(self, m: ir.Morphism, p: ir.Param) -> int:
        """How many values :meth:`_theta_values` gives θ ``p`` of ``m``, without making them
        (1 where it will refuse the parameter)."""
        k = p.sort.kind
        if self.is_dial(m, p):
            return 1
        if k is SortKind.BOOL:
            return 2
        if k in (SortKind.SYMBOL, SortKind.ENUM):
            return len(self._values_of(p.sort))
        if p.lower is None or p.upper is None:
            return 1
        if k is SortKind.INT:
            return max(0, int(p.upper // 1) - int(-(-p.lower // 1)) + 1)
        step = self._step_of(m, p)
        if step is None or step <= 0:
            return 1
        n = int((p.upper - p.lower) // step) + 1
        return n + (1 if p.lower + (n - 1) * step != p.upper else 0)

    def _step_of(self, m: ir.Morphism, p: ir.Param) -> Fraction | None:
        return self.grid_in.get(f"{m.name}.{p.name}", self.grid_in.get(p.name))

    def _check_ground_actions(self) -> None:
        """Refuse (E1108, at the morphism) an export of more ground actions than the
        ground-actions limit, counted before any is made."""
        most = limits.current().ground_actions
        counts = {m.name: [self._theta_count(m, p) for p in m.params] for m in self.inst.domain.morphisms.values()}
        total = sum(math.prod(c) for c in counts.values())
        if total <= most:
            return
        m = max(self.inst.domain.morphisms.values(), key=lambda m: math.prod(counts[m.name]))
        n = math.prod(counts[m.name])
        limit = limits.BY_NAME["ground-actions"]
        per = " × ".join(f"{p.name}: {limits.count_text(c)}" for p, c in zip(m.params, counts[m.name]))
        raise limits.LimitExceeded(
            limit.code,
            f"the export would write {limits.count_text(total)} ground actions, more than the ground-actions limit "
            f"({limits.count_text(most)}); '{m.name}' alone has {limits.count_text(n)} ({per}); "
            f"{self._coarser(m, counts[m.name], most - (total - n))}{limit.how_to_raise}",
            m.span,
        )

    def _coarser(self, m: ir.Morphism, counts: list[int], room: int) -> str:
        """A suggestion: the grid step for the real θ of ``m`` with the most values that
        would bring ``m`` within ``room`` ground actions (with the other θ as they are)."""
        reals = [(c, p) for p, c in zip(m.params, counts) if p.sort.kind is SortKind.REAL and self._step_of(m, p)]
        if not reals or room < 2:
            return ""
        c, p = max(reals, key=lambda cp: cp[0])
        assert p.lower is not None and p.upper is not None  # it has a step, so finite bounds
        others = math.prod(counts) // max(1, c)
        values = max(2, room // max(1, others))
        step = nice_step((p.upper - p.lower) / (values - 1))
        return f"use a coarser grid, e.g. --grid {m.name}.{p.name}={decimal_text(step)}, or "

    def _ground_actions(self, with_cost: bool) -> list[str]:
        """The text of every ground action, morphism by morphism (their number checked first:
        :meth:`_check_ground_actions`)."""
        actions: list[str] = []
        count = 0
        for m in self.inst.domain.morphisms.values():
            values = self._theta_values(m)
            assert values is not None  # never None (Optional in the signature only)
            self._declare_fixed_values(m, values)
            count, texts = self._ground_morphism(m, values, with_cost, count)
            actions.extend(texts)
        return actions

    def _declare_fixed_values(self, m: ir.Morphism, values: list[list[object]]) -> None:
        """A ``(fixed-m-p-v)`` predicate for every value ``v`` of a ``:fixed`` θ ``p`` (not a dial)."""
        for prm, vals in zip(m.params, values):
            if prm.fixed and not self.is_dial(m, prm):
                for v in vals:
                    self.pred[("fixval", m.name, prm.name, value_suffix(v))] = self.names.fresh(
                        f"fixed-{m.name}-{prm.name}-{value_suffix(v)}"
                    )

    def _ground_morphism(
        self, m: ir.Morphism, values: list[list[object]], with_cost: bool, count: int
    ) -> tuple[int, list[str]]:
        """(the count of θ tried so far, the texts of ``m``'s ground actions).  A morphism with a
        construct PDDL cannot express is reported and left out whole."""
        texts: list[str] = []
        for combo in itertools.product(*values):
            count += 1
            limits.check_time("exporting")
            theta = {prm.name: v for prm, v in zip(m.params, combo)}
            try:
                text = self.action_text(m, theta, with_cost)
            except Unsupported as exc:
                self.report.add("components", f"'{m.name}' not exported: {exc}")
                for k in [k for k, a in self.actions.items() if a.morphism == m.name]:
                    del self.actions[k]
                return count, []
            if text is not None:
                texts.append(text)
        if m.params and not texts:
            self.report.add(
                "components",
                f"'{m.name}' has no applicable ground action (no parameter value passes its θ-only preconditions)",
            )
        return count, texts

    def _goal(self) -> list[str]:
        goal = []
        for lit in self.inst.problem.goal:
            try:
                goal.append(self.cond(self._fold(lit.expr, {})))
            except Unsupported as exc:
                raise ExportError(f"goal literal {lit.label} cannot be exported: {exc}") from None
        return goal

    def _problem_text(self, init: list[str], goal: list[str], metric: str | None) -> str:
        d, p = self.inst.domain, self.inst.problem
        prob = [
            f";; generated by catc export pddl from problem {p.name}",
            f"(define (problem {sanitize(p.name)})",
            f"  (:domain {sanitize(d.name)})",
            "  (:init",
            *("    " + i for i in init),
            "  )",
            "  (:goal (and " + " ".join(g for g in goal if g != "(and)") + "))",
        ]
        if metric:
            prob.append("  " + metric)
        return "\n".join(prob) + "\n)\n"

    def _domain_text(self, actions: list[str], with_cost: bool) -> str:
        """The domain: requirements, every predicate and function declared so far, the actions."""
        d = self.inst.domain
        preds = list(self.pred.values())
        funcs = list(self.func.values())
        if self.horizon is not None:
            funcs.append("catc-steps")
        if with_cost:
            funcs.append("total-cost")
        reqs = " ".join(sorted(self.requirements))
        dom = [
            f";; generated by catc export pddl from domain {d.name}",
            f"(define (domain {sanitize(d.name)})",
            f"  (:requirements {reqs})",
        ]
        if preds:
            dom.append("  (:predicates " + " ".join(f"({x})" for x in preds) + ")")
        if funcs:
            dom.append("  (:functions " + " ".join(f"({x})" for x in funcs) + ")")
        return "\n".join(dom) + "\n" + "".join(actions) + self.extra_domain_text() + ")\n"

    def extra_domain_text(self) -> str:
        """Hook for the PDDL+ flavour (dial actions and processes)."""
        return ""

    def _init(self) -> list[str]:
        from catc.semantics.validate import initial_state

        s0 = initial_state(self.inst)
        out = []
        for r in self.inst.resources.values():
            if r.name not in s0:
                if r.sort.is_numeric:
                    raise ExportError(f"resource '{r.name}' has no initial value")
                if r.sort.is_symbolic:
                    self.report.add(
                        "initial state", f"symbolic resource '{r.name}' has no initial value (no value predicate holds)"
                    )
                continue
            v = s0[r.name]
            k = r.sort.kind
            if k in (SortKind.INT, SortKind.REAL):
                out.append(f"(= ({self.func[r.name]}) {number(cast(Fraction, v))})")
            elif k is SortKind.BOOL:
                if v:
                    out.append(f"({self.pred[('bool', r.name)]})")
            elif k is SortKind.SET:
                for c in sorted(cast("frozenset[str]", v)):
                    key = ("mem", r.name, c)
                    if key in self.pred:
                        out.append(f"({self.pred[key]})")
            elif ("is", r.name, v) in self.pred:
                out.append(f"({self.pred[('is', r.name, v)]})")
        for fkey, f in self.func.items():
            if isinstance(fkey, tuple):  # a counter
                out.append(f"(= ({f}) 0)")
        if self.horizon is not None:
            out.append("(= (catc-steps) 0)")
        if ":action-costs" in self.requirements:
            out.append("(= (total-cost) 0)")
        return out
