"""unified-planning problems into catc's IR.

A front end: a UP ``Problem`` → catc's checked IR (:class:`~catc.ir.Instance`).

The problem is *grounded* first (:mod:`catc.frontend.up_ground`: quantifiers removed by UP's
``QuantifiersRemover``, each action's parameter tuples chosen by their static preconditions
before any is instantiated, the instances made and simplified by UP's ``GrounderHelper``): catc's resources hold one value
each and its sets one sort's values, so a fluent of arity k > 0 cannot be one resource — each
ground fluent that a ground action, the goal or the metric reads or writes becomes one resource
(``at(r1, l2)`` → ``at_r1_l2``), and each ground action one morphism without parameters. Static
fluents (written by no action) are replaced by their initial values. User types become open
symbolic sorts (with their hierarchy) and objects constants, which object-valued fluents need.

UP's sequential semantics are kept exactly, and the queries must be run with
``sequential=True`` (one activation per step: catc's parallel steps could merge two UP actions
into one step). Effects follow UP's sequential simulator: the effects of an action read the
state before it; on a Boolean fluent an assignment of true wins over one of false (add after
delete); two assignments of different values to a numeric or object fluent, or an assignment
and an increase of one fluent, make the action inapplicable (a precondition says they do not
happen); increases and decreases add up; conditional effects become ``if`` terms.

Action costs that read fluents the actions change are summed in a resource of their own (each
in the state before its action, as UP evaluates them) and minimised in the final state.

A fluent without an initial value is refused only when a remaining ground action, the goal or
the metric reads it (the refusal names it); one only ever assigned before any read gets a
placeholder (a note says which).

What catc cannot express — time, processes, hierarchies, undefined initial values read, trajectory
constraints, unbounded or real action parameters, a makespan metric — is refused:
:func:`up_to_instance` raises :class:`UpImportError` (code ``E1201``) whose
:class:`ImportReport` lists every reason; nothing is dropped silently.

unified-planning is imported only inside these functions (the ``up`` extra).
"""

from __future__ import annotations

import re
import time
from collections.abc import Callable, Iterable, Mapping
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import BOOL, INT, REAL, Sort, SortKind
from catc.ir.fold import FoldError, fold_constant
from catc.semantics.plan import Plan
from catgrammar import codes, limits
from catgrammar.symbols import RESERVED_NAMES

__all__ = [
    "MISSING",
    "ImportReport",
    "UpImportError",
    "UpImportStopped",
    "UpMissing",
    "plan_to_up",
    "supported_kind",
    "up_to_instance",
]

MISSING = "this needs unified-planning: pip install 'catc-lang[up]'"

#: The ProblemKind features catc accepts (by UP's feature name); anything else is refused.
SUPPORTED_FEATURES: tuple[str, ...] = (
    "ACTION_BASED",
    "SIMPLE_NUMERIC_PLANNING",
    "GENERAL_NUMERIC_PLANNING",
    "BOUNDED_TYPES",
    "CONTINUOUS_NUMBERS",
    "DISCRETE_NUMBERS",
    "NEGATIVE_CONDITIONS",
    "DISJUNCTIVE_CONDITIONS",
    "EQUALITIES",
    "EXISTENTIAL_CONDITIONS",
    "UNIVERSAL_CONDITIONS",
    "CONDITIONAL_EFFECTS",
    "INCREASE_EFFECTS",
    "DECREASE_EFFECTS",
    "STATIC_FLUENTS_IN_BOOLEAN_ASSIGNMENTS",
    "STATIC_FLUENTS_IN_NUMERIC_ASSIGNMENTS",
    "STATIC_FLUENTS_IN_OBJECT_ASSIGNMENTS",
    "FLUENTS_IN_BOOLEAN_ASSIGNMENTS",
    "FLUENTS_IN_NUMERIC_ASSIGNMENTS",
    "FLUENTS_IN_OBJECT_ASSIGNMENTS",
    "FORALL_EFFECTS",
    "FLAT_TYPING",
    "HIERARCHICAL_TYPING",
    "BOOL_FLUENT_PARAMETERS",
    "BOUNDED_INT_FLUENT_PARAMETERS",
    "BOOL_ACTION_PARAMETERS",
    "BOUNDED_INT_ACTION_PARAMETERS",
    "INT_FLUENTS",
    "REAL_FLUENTS",
    "OBJECT_FLUENTS",
    "NUMERIC_FLUENTS",
    "ACTIONS_COST",
    "FINAL_VALUE",
    "PLAN_LENGTH",
    "OVERSUBSCRIPTION",
    "STATIC_FLUENTS_IN_ACTIONS_COST",
    "INT_NUMBERS_IN_ACTIONS_COST",
    "REAL_NUMBERS_IN_ACTIONS_COST",
    "FLUENTS_IN_ACTIONS_COST",
    "INT_NUMBERS_IN_OVERSUBSCRIPTION",
    "REAL_NUMBERS_IN_OVERSUBSCRIPTION",
    "STATE_INVARIANTS",
)

#: Why a feature outside :data:`SUPPORTED_FEATURES` is refused (the import report's words).
WHY_NOT: Mapping[str, str] = {
    "UNDEFINED_INITIAL_NUMERIC": "a fluent without an initial value: catc's initial state is complete, "
    "and UP leaves open what reading an undefined value means",
    "UNDEFINED_INITIAL_SYMBOLIC": "a fluent without an initial value: catc's initial state is complete, "
    "and UP leaves open what reading an undefined value means",
    "HIERARCHICAL": "tasks and methods: catc has no task networks",
    "CONTINUOUS_TIME": "time: catc's steps are instantaneous",
    "DISCRETE_TIME": "time: catc's steps are instantaneous",
    "SCHEDULING": "scheduling needs time: catc's steps are instantaneous",
    "PROCESSES": "processes are continuous change over time",
    "EVENTS": "events fire in time (PDDL+)",
    "INCREASE_CONTINUOUS_EFFECTS": "continuous change over time",
    "DECREASE_CONTINUOUS_EFFECTS": "continuous change over time",
    "NON_LINEAR_CONTINUOUS_EFFECTS": "continuous change over time",
    "CONTINGENT": "sensing and contingent plans",
    "ACTION_BASED_MULTI_AGENT": "several agents",
    "TAMP": "motion planning (TAMP)",
    "TEMPORAL_OVERSUBSCRIPTION": "a temporal metric",
    "UNBOUNDED_INT_ACTION_PARAMETERS": "an unbounded int action parameter cannot be grounded",
    "REAL_ACTION_PARAMETERS": "a real action parameter cannot be grounded",
    "MAKESPAN": "a makespan metric is temporal",
    "TRAJECTORY_CONSTRAINTS": "trajectory constraints other than state invariants",
    "SIMULATED_EFFECTS": "simulated effects are Python code, not a model",
}


class ImportReport:
    """What the import did: the refusals (``refused``: feature or construct, reason), notes on
    how UP constructs were expressed (``notes``), and the maps back from catc's names to UP's.

    ``actions`` maps each morphism to the ground UP ``ActionInstance`` of the *original*
    problem it stands for (what :func:`plan_to_up` emits); ``fluents`` maps each resource to
    the UP ground fluent it holds (``"at(r1, l2)"``); ``labels`` maps catc's constraint labels
    (``pre/M/i``, ``eff/M/i``, ``init/R``, ``goal/i``) to UP words, for diagnoses."""

    __slots__ = ("refused", "notes", "actions", "fluents", "labels", "sequential", "optimal_metric")

    def __init__(self) -> None:
        self.refused: list[tuple[str, str]] = []
        self.notes: list[str] = []
        self.actions: dict[str, Any] = {}
        self.fluents: dict[str, str] = {}
        self.labels: dict[str, str] = {}
        self.sequential = True  # the instance must be solved with sequential=True
        self.optimal_metric: str | None = None  # "cost" | "length" | "final" | "gain" | None

    @property
    def ok(self) -> bool:
        return not self.refused

    def refuse(self, what: str, why: str) -> None:
        if (what, why) not in self.refused:
            self.refused.append((what, why))

    def text(self) -> str:
        lines = [f"refused: {what}: {why}" for what, why in self.refused]
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)

    def describe(self, label: str) -> str:
        """A catc label in UP's words (the label itself when unknown)."""
        return self.labels.get(label, label)


class UpImportError(ValueError):
    """The problem uses something catc cannot express; ``report.refused`` says what."""

    def __init__(self, report: ImportReport, code: str = codes.IMPORT_UNSUPPORTED) -> None:
        self.report, self.code = report, code
        super().__init__("catc cannot express this problem: " + "; ".join(f"{w}: {r}" for w, r in report.refused))


class UpImportStopped(Exception):
    """The time given to :func:`up_to_instance` ran out while grounding."""


class UpMissing(ImportError):
    """unified-planning is not installed (code ``E1202``; the message names the extra)."""

    code = codes.IMPORT_NEEDS_EXTRA


def _up() -> Any:
    try:
        import unified_planning
    except ImportError as exc:
        raise UpMissing(MISSING) from exc
    return unified_planning


def supported_kind() -> Any:
    """The UP ``ProblemKind`` catc accepts."""
    from unified_planning.model.problem_kind import LATEST_PROBLEM_KIND_VERSION, ProblemKind

    return ProblemKind(set(SUPPORTED_FEATURES), version=LATEST_PROBLEM_KIND_VERSION)


def refusals(kind: Any) -> list[tuple[str, str]]:
    """The features of ``kind`` catc does not accept, each with its reason."""
    from unified_planning.model.problem_kind import FEATURES

    by_category = {
        "TIME": "time: catc's steps are instantaneous",
        "EXPRESSION_DURATION": "durations: catc's steps are instantaneous",
        "HIERARCHICAL": "tasks and methods: catc has no task networks",
        "MULTI_AGENT": "several agents",
    }
    category = {f: c for c, names in FEATURES.items() for f in names}
    out = []
    for feature in sorted(kind.features):
        if feature not in SUPPORTED_FEATURES:
            why = WHY_NOT.get(feature) or by_category.get(category.get(feature, ""), "not expressible in catc")
            out.append((feature, why))
    return out


# ---------------------------------------------------------------- names

_NAME = re.compile(r"[a-zA-Z_][a-zA-Z0-9_-]*\Z")


class _Names:
    """Unique .cat names for UP names (one namespace: resources, constants, sorts, morphisms)."""

    def __init__(self) -> None:
        self.taken: set[str] = set()

    def fresh(self, text: str) -> str:
        base = re.sub(r"[^a-zA-Z0-9_-]+", "_", text).strip("_") or "x"
        if not _NAME.match(base):
            base = "_" + base
        if base in RESERVED_NAMES:
            base += "_"
        name, n = base, 1
        while name in self.taken:
            n += 1
            name = f"{base}_{n}"
        self.taken.add(name)
        return name


# ---------------------------------------------------------------- the import


#: Features decided after grounding, per ground fluent actually read (not on UP's problem kind).
_AFTER_GROUNDING = frozenset({"UNDEFINED_INITIAL_NUMERIC", "UNDEFINED_INITIAL_SYMBOLIC"})


def up_to_instance(
    problem: Any, *, name: str | None = None, timeout: float | None = None
) -> tuple[ir.Instance, ImportReport]:
    """Convert a unified-planning ``Problem`` into a catc :class:`~catc.ir.Instance`.

    Returns ``(instance, report)``. The instance must be solved with ``sequential=True``
    (``report.sequential``); its problem has no horizon (pass one to the query). Map a catc
    composition back with :func:`plan_to_up` (``report.actions``). Raises :class:`UpImportError`
    (code ``E1201``, ``.report.refused`` non-empty) when the problem uses anything catc cannot
    express, :class:`~catgrammar.limits.LimitExceeded` when the grounded problem has more
    resources or morphisms than the limits allow (``E1104``/``E1105``), and :class:`UpMissing` (an ``ImportError``, code ``E1202``) naming the ``up`` extra
    without unified-planning. The
    signature is stable: ``catc import pddl`` builds on it. With ``timeout`` (seconds) the
    grounding stops with :class:`UpImportStopped` once it has passed."""
    from catc.frontend.up_ground import GroundingStopped, ground

    _up()
    report = ImportReport()
    for what, why in refusals(problem.kind):
        if what not in _AFTER_GROUNDING:
            report.refuse(what, why)
    if not report.ok:
        raise UpImportError(report)
    deadline = None if timeout is None else time.monotonic() + timeout
    try:
        grounding = ground(problem, deadline)
    except GroundingStopped as stop:
        raise UpImportStopped(str(stop)) from None
    inst = _Converter(grounding.problem, grounding.back, report, name or problem.name).run()
    if not report.ok:
        raise UpImportError(report)
    _within_limits(inst)
    report.notes += [
        f"grounded by catc's grounder (catc.frontend.up_ground): {grounding.candidates} parameter tuples passed "
        f"the static preconditions and were instantiated, {len(inst.morphisms)} ground actions kept → morphisms "
        f"without parameters, {len(inst.resources)} ground fluents read or written → resources",
        "static fluents (written by no action) replaced by their initial values",
        "sequential semantics: solve with sequential=True (one action per step); catc's parallel steps "
        "could put two UP actions in one step",
    ]
    return inst, report


def _within_limits(inst: ir.Instance) -> None:
    """The checker's limits on resources and morphisms hold for an imported instance too."""
    for name, count in (("resources", len(inst.resources)), ("morphisms", len(inst.morphisms))):
        limit = limits.BY_NAME[name]
        most = getattr(limits.current(), limit.field)
        if count > most:
            raise limits.LimitExceeded(
                limit.code,
                f"the grounded problem has {count} {name}, more than the {name} limit ({most}); {limit.how_to_raise}",
            )


class _Converter:
    """One ground UP problem → one Instance."""

    def __init__(self, ground: Any, back: Callable[[Any], Any], report: ImportReport, name: str) -> None:
        self.g, self.back, self.report = ground, back, report
        self.names = _Names()
        self.problem_name = self.names.fresh(name)
        self.domain_name = self.names.fresh(name + "-domain")
        self.static = {f.name for f in ground.get_static_fluents()}
        self.init = ground.initial_values
        self.sorts: dict[str, Sort] = {}
        self.constants: dict[str, ir.Constant] = {}
        self.object_names: dict[str, str] = {}
        self.resources: dict[str, ir.Resource] = {}
        self.resource_of: dict[Any, str] = {}  # ground fluent FNode → resource name
        self.numeric = False
        self.symbols = False
        self.cost_resource: str | None = None  # the summed costs, when they read changing fluents
        self.reader = "the problem"  # what reads the fluents being converted (for refusals)

    # ------------------------------------------------------------ the whole

    def run(self) -> ir.Instance:
        self._types()
        morphisms: dict[str, ir.Morphism] = {}
        costs = self._costs()
        for action in self.g.actions:
            m = self._morphism(action, costs)
            if m is not None:
                morphisms[m.name] = m
        self.reader = "the goal"
        goal = self._literals(self.g.goals, ir.Label.goal, lambda i: f"goal {i + 1}")
        self.reader = "the metric"
        softs, metric = self._metric()
        self._invariants_hold_initially(goal)
        init = self._initial_state(_readers(morphisms, goal, softs, metric, self.report.actions))
        if self.cost_resource is not None:
            init[self.cost_resource] = ir.InitValue(
                self.cost_resource, ir.Const(Fraction(0), REAL), ir.Label.init(self.cost_resource)
            )
            self.report.labels[ir.Label.init(self.cost_resource)] = "no cost at first"
        reqs = {"numeric", "optimization"} if (self.numeric or metric or softs) else set()
        if self.symbols:
            reqs.add("symbols")
        else:  # no object-valued fluent: the objects live on only in the names
            self.sorts, self.constants = {}, {}
        domain = ir.Domain(
            self.domain_name,
            frozenset(reqs),
            sorts=ir.frozen(self.sorts),
            constants=ir.frozen(self.constants),
            resources=ir.frozen(self.resources),
            morphisms=ir.frozen(morphisms),
        )
        prob = ir.Problem(
            self.problem_name,
            self.domain_name,
            frozenset(),
            init=ir.frozen(init),
            goal=tuple(goal),
            softs=tuple(softs),
            metric=metric,
        )
        return ir.Instance(domain, prob)

    def _types(self) -> None:
        cat = {t.name: self.names.fresh(t.name) for t in self.g.user_types}
        for t in self.g.user_types:
            parent = cat[t.father.name] if t.father is not None else None
            self.sorts[cat[t.name]] = Sort(SortKind.SYMBOL, cat[t.name], parent=parent)
        self._sort_by_up = {up_name: self.sorts[name] for up_name, name in cat.items()}
        for obj in self.g.all_objects:
            cname = self.names.fresh(obj.name)
            self.object_names[obj.name] = cname
            self.constants[cname] = ir.Constant(cname, self._sort_by_up[obj.type.name])

    # ------------------------------------------------------------ sorts and resources

    def _sort(self, t: Any) -> tuple[Sort, Fraction | None, Fraction | None]:
        if t.is_bool_type():
            return BOOL, None, None
        if t.is_int_type() or t.is_real_type():
            self.numeric = True
            lo = None if t.lower_bound is None else Fraction(t.lower_bound)
            hi = None if t.upper_bound is None else Fraction(t.upper_bound)
            return (INT if t.is_int_type() else REAL), lo, hi
        if t.is_user_type():
            self.symbols = True
            return self._sort_by_up[t.name], None, None
        raise _Refused(f"type {t}", "not a bool, int, real or user type")

    def _resource(self, node: Any) -> str:
        name = self.resource_of.get(node)
        if name is None:
            sort, lo, hi = self._sort(node.fluent().type)
            name = self.names.fresh(str(node).replace("(", "_").replace(",", "_").replace(" ", ""))
            self.resource_of[node] = name
            self.resources[name] = ir.Resource(name, sort, lower=lo, upper=hi, doc=f"UP fluent {node}")
            self.report.fluents[name] = str(node)
            if lo is not None or hi is not None:
                self.report.labels[ir.Label.bounds(name)] = f"the bounds of {node.fluent().type} on {node}"
        return name

    def _initial_state(self, readers: Mapping[str, str]) -> dict[str, ir.InitValue]:
        """Each resource's initial value; a fluent without one is refused when something reads
        it (``readers``: resource → the first reader, in UP's words), else given a placeholder
        (it is assigned before any read, so the value never matters)."""
        out = {}
        placeholders = []
        for node, name in self.resource_of.items():
            sort = self.resources[name].sort
            if node not in self.init:
                if name in readers:
                    self._refuse_undefined(node, readers[name])
                    continue
                value = _placeholder(sort, self.constants)
                placeholders.append(str(node))
                out[name] = ir.InitValue(name, value, ir.Label.init(name))
                self.report.labels[ir.Label.init(name)] = (
                    f"no initial value for {node} (a placeholder: nothing reads it)"
                )
                continue
            value = self._constant(self.init[node], sort)
            out[name] = ir.InitValue(name, value, ir.Label.init(name))
            self.report.labels[ir.Label.init(name)] = f"initial value {node} := {self.init[node]}"
        if placeholders:
            self.report.notes.append(
                "fluents without an initial value that no ground action, goal or metric reads (they are only "
                "assigned): given a placeholder, which no plan can observe: " + ", ".join(placeholders)
            )
        return out

    def _refuse_undefined(self, node: Any, reader: str) -> None:
        numeric = node.type.is_int_type() or node.type.is_real_type()
        feature = "UNDEFINED_INITIAL_NUMERIC" if numeric else "UNDEFINED_INITIAL_SYMBOLIC"
        self.report.refuse(
            feature,
            f"{node} has no initial value and {reader} reads it: catc's initial state is complete, and UP "
            "leaves open what reading an undefined value means",
        )

    def _constant(self, node: Any, sort: Sort) -> ir.Const:
        if node.is_bool_constant():
            return ir.Const(bool(node.bool_constant_value()), BOOL)
        if node.is_int_constant() or node.is_real_constant():
            return ir.Const(Fraction(node.constant_value()), INT if sort.kind is SortKind.INT else REAL)
        if node.is_object_exp():
            self.symbols = True
            return ir.Const(self.object_names[node.object().name], self._sort_by_up[node.object().type.name])
        raise _Refused(f"value {node}", "not a constant")

    # ------------------------------------------------------------ expressions

    def expr(self, node: Any) -> ir.Expr:
        if node.is_constant() or node.is_object_exp():
            t = node.type
            return self._constant(node, INT if t.is_int_type() else REAL if t.is_real_type() else BOOL)
        if node.is_fluent_exp():
            if node.fluent().name in self.static:  # never written: its initial value
                if node not in self.init:
                    self._refuse_undefined(node, self.reader)
                    raise _Refused(str(node), "no initial value (above)")
                return self.expr(self.init[node])
            name = self._resource(node)
            return ir.ResourceRef(name, self.resources[name].sort)
        args = [self.expr(a) for a in node.args]
        bool_ops = {
            "is_and": ir.BoolOpKind.AND,
            "is_or": ir.BoolOpKind.OR,
            "is_not": ir.BoolOpKind.NOT,
            "is_implies": ir.BoolOpKind.IMPLY,
        }
        for test, op in bool_ops.items():
            if getattr(node, test)():
                return ir.BoolOp(op, tuple(args))
        cmp_ops = {"is_equals": ir.CmpOp.EQ, "is_iff": ir.CmpOp.EQ, "is_le": ir.CmpOp.LE, "is_lt": ir.CmpOp.LT}
        for test, cop in cmp_ops.items():
            if getattr(node, test)():
                return ir.Compare(cop, args[0], args[1])
        arith_ops = {"is_plus": ir.ArithOp.ADD, "is_minus": ir.ArithOp.SUB, "is_times": ir.ArithOp.MUL}
        for test, aop in arith_ops.items():
            if getattr(node, test)():
                sort = INT if all(a.sort is INT or a.sort == INT for a in args) else REAL
                return ir.Arith(aop, tuple(args), sort)
        if node.is_div():
            return ir.Arith(ir.ArithOp.DIV, tuple(args), REAL)
        raise _Refused(f"expression {node}", f"{node.node_type.name} is not expressible in catc")

    def _literals(
        self, nodes: Iterable[Any], label_of: Callable[[int], ir.Label], say: Callable[[int], str]
    ) -> list[ir.Literal]:
        out: list[ir.Literal] = []
        for node in nodes:
            for part in _conjuncts(node):
                label = label_of(len(out))
                try:
                    out.append(ir.Literal(self.expr(part), label))
                except _Refused as r:
                    self.report.refuse(r.what, r.why)
                    continue
                self.report.labels[label] = f"{say(len(out) - 1)}: {part}"
        return out

    # ------------------------------------------------------------ actions

    def _morphism(self, action: Any, costs: Mapping[Any, Fraction | ir.Expr]) -> ir.Morphism | None:
        name = self.names.fresh(action.name)
        from unified_planning.plans import ActionInstance

        self.report.actions[name] = self.back(ActionInstance(action))
        up_name = str(self.report.actions[name])
        self.reader = f"the ground action {up_name}"
        try:
            pre = self._literals(
                action.preconditions, lambda i: ir.Label.pre(name, i), lambda i: f"precondition {i + 1} of {up_name}"
            )
            effects, guards = _Effects(self, name, up_name).run(action.effects)
            pre += [ir.Literal(g, ir.Label.pre(name, len(pre) + i)) for i, g in enumerate(guards)]
            for i in range(len(pre) - len(guards), len(pre)):
                self.report.labels[pre[i].label] = f"{up_name} has no conflicting effects"
            pre += self._invariants_after(action, name, up_name, effects, len(pre))
        except _Refused as r:
            self.report.refuse(r.what, r.why)
            return None
        cost = costs.get(action)
        if self.cost_resource is not None and cost is not None:  # costs summed in a resource
            amount = ir.Const(cost, REAL) if isinstance(cost, Fraction) else cost
            label = ir.Label.eff(name, len(effects))
            effects.append(ir.Effect(ir.EffectKind.INCREASE, self.cost_resource, amount, label))
            self.report.labels[label] = f"the cost of {up_name}"
            cost = None
        assert cost is None or isinstance(cost, Fraction)  # a fixed cost, else summed above
        return ir.Morphism(
            name,
            ir.MorphismKind.BEHAVIOR,
            (),
            tuple(pre),
            tuple(effects),
            cost=None if cost is None else ir.Const(cost, REAL),
            doc=f"UP action {up_name}",
        )

    # ------------------------------------------------------------ state invariants

    def _invariant_exprs(self) -> list[ir.Expr]:
        return [self.expr(node) for node in self.g.state_invariants]

    def _invariants_after(
        self, action: Any, name: str, up_name: str, effects: list[ir.Effect], start: int
    ) -> list[ir.Literal]:
        """Each state invariant regressed through the action's effects: it holds after the
        action iff its regression holds before."""
        out = []
        post = _post_values(effects, self.resources)
        for i, inv in enumerate(self._invariant_exprs()):
            label = ir.Label.pre(name, start + i)
            out.append(ir.Literal(_substitute(inv, post), label))
            self.report.labels[label] = f"state invariant {i + 1} after {up_name}: {self.g.state_invariants[i]}"
        return out

    def _invariants_hold_initially(self, goal: list[ir.Literal]) -> None:
        """An invariant false in the initial state makes every plan invalid: a false goal."""
        invs = self.g.state_invariants
        if not invs:
            return
        from unified_planning.model import UPState
        from unified_planning.model.walkers import StateEvaluator

        state, evaluator = UPState(self.g.initial_values, self.g), StateEvaluator(self.g)
        for i, inv in enumerate(invs):
            if not evaluator.evaluate(inv, state).bool_constant_value():
                label = ir.Label.goal(len(goal))
                goal.append(ir.Literal(ir.Const(False, BOOL), label))
                self.report.labels[label] = f"state invariant {i + 1} is false in the initial state: {inv}"

    # ------------------------------------------------------------ the metric

    def _costs(self) -> dict[Any, Fraction | ir.Expr]:
        """Each ground action's cost: a number, or (when it reads fluents that actions change)
        a term over the state before the action, summed in a resource of its own."""
        from unified_planning.model.metrics import MinimizeActionCosts, MinimizeSequentialPlanLength

        out: dict[Any, Fraction | ir.Expr] = {}
        for m in self.g.quality_metrics:
            if isinstance(m, MinimizeSequentialPlanLength):
                out.update((a, Fraction(1)) for a in self.g.actions)
            elif isinstance(m, MinimizeActionCosts):
                for a in self.g.actions:
                    node = m.get_action_cost(a)
                    if node is None:
                        self.report.refuse(f"cost of {a.name}", "no cost and no default: UP cannot evaluate the metric")
                        continue
                    out[a] = self._cost(node, a)
        if any(not isinstance(c, Fraction) for c in out.values()):
            name = self.names.fresh("total-cost")
            self.cost_resource = name
            self.resources[name] = ir.Resource(name, REAL, doc="the sum of the UP action costs so far")
            self.report.notes.append(
                f"action costs that read changing fluents: summed in the resource {name} (each in the state "
                "before its action, as UP evaluates them), minimised in the final state"
            )
        return out

    def _cost(self, node: Any, action: Any) -> Fraction | ir.Expr:
        try:
            term = self.expr(node)
        except _Refused as r:
            self.report.refuse(r.what, r.why)
            return Fraction(0)
        try:
            value = fold_constant(term)
        except FoldError:
            value = None
        if isinstance(value, ir.Const) and isinstance(value.value, Fraction):
            if value.value < 0:
                self.report.refuse(f"cost of {action.name}", "a negative action cost; catc's :cost is non-negative")
            return value.value
        return term

    def _metric(self) -> tuple[list[ir.Soft], ir.Metric | None]:
        from unified_planning.model import metrics as um

        metrics = list(self.g.quality_metrics)
        if len(metrics) > 1:
            self.report.refuse("quality metrics", "more than one metric (catc would need an order: lex)")
            return [], None
        if not metrics:
            return [], None
        m = metrics[0]
        self.numeric = True
        if self.cost_resource is not None:
            self.report.optimal_metric = "final"
            return [], _single(ir.Sense.MINIMIZE, ir.ResourceRef(self.cost_resource, REAL))
        if isinstance(m, (um.MinimizeActionCosts, um.MinimizeSequentialPlanLength)):
            self.report.optimal_metric = "cost" if isinstance(m, um.MinimizeActionCosts) else "length"
            return [], _single(ir.Sense.MINIMIZE, ir.TotalCost())
        if isinstance(m, (um.MinimizeExpressionOnFinalState, um.MaximizeExpressionOnFinalState)):
            self.report.optimal_metric = "final"
            sense = ir.Sense.MINIMIZE if isinstance(m, um.MinimizeExpressionOnFinalState) else ir.Sense.MAXIMIZE
            try:
                return [], _single(sense, self.expr(m.expression))
            except _Refused as r:
                self.report.refuse(r.what, r.why)
                return [], None
        if isinstance(m, um.Oversubscription):
            return self._oversubscription(m), None
        self.report.refuse(f"metric {m}", "not expressible in catc")
        return [], None

    def _oversubscription(self, m: Any) -> list[ir.Soft]:
        """Σ gains of the goals reached, maximised = Σ weights of the goals missed, minimised
        (soft constraints: what catc optimize minimises when there is no metric)."""
        self.report.optimal_metric = "gain"
        softs = []
        for i, (goal, up_gain) in enumerate(m.goals.items()):
            gain = Fraction(up_gain)
            if gain <= 0:
                self.report.refuse(f"oversubscription goal {goal}", "a gain that is not positive")
                continue
            label = ir.Label.soft(i)
            softs.append(ir.Soft(self.expr(goal), gain, label))
            self.report.labels[label] = f"oversubscription goal {goal} (gain {gain})"
        return softs


def _readers(
    morphisms: Mapping[str, ir.Morphism],
    goal: list[ir.Literal],
    softs: list[ir.Soft],
    metric: ir.Metric | None,
    actions: Mapping[str, Any],
) -> dict[str, str]:
    """Each resource something reads (a precondition, an effect's value or condition, an
    increase or decrease of it, the goal, a soft goal, the metric) → the first reader."""
    out: dict[str, str] = {}

    def read(e: ir.Expr, who: str) -> None:
        for r in ir.resources_in(e):
            out.setdefault(r, who)

    for name, m in morphisms.items():
        who = f"the ground action {actions.get(name, name)}"
        for lit in m.pre:
            read(lit.expr, who)
        for eff in m.effects:
            read(eff.value, who)
            if eff.kind is not ir.EffectKind.ASSIGN:
                out.setdefault(eff.resource, who)
    for lit in goal:
        read(lit.expr, "the goal")
    for soft in softs:
        read(soft.expr, "a soft goal")
    for obj in metric.objectives if metric is not None else ():
        read(obj.term, "the metric")
    return out


def _placeholder(sort: Sort, constants: Mapping[str, ir.Constant]) -> ir.Const:
    """A value of ``sort`` for a resource no one reads before assigning it."""
    if sort.kind is SortKind.BOOL:
        return ir.Const(False, BOOL)
    if sort.is_numeric:
        return ir.Const(Fraction(0), sort)
    first = next((c.name for c in constants.values() if c.sort == sort or c.sort.parent == sort.name), None)
    if first is None:
        raise _Refused(f"sort {sort.name}", "no object to stand for an undefined initial value")
    return ir.Const(first, sort)


def _single(sense: ir.Sense, term: ir.Expr) -> ir.Metric:
    return ir.Metric(ir.MetricMode.SINGLE, (ir.Objective(sense, term),))


def _conjuncts(node: Any) -> list[Any]:
    if node.is_and():
        return [c for a in node.args for c in _conjuncts(a)]
    if node.is_true():
        return []
    return [node]


class _Refused(Exception):
    def __init__(self, what: str, why: str) -> None:
        super().__init__(f"{what}: {why}")
        self.what, self.why = what, why


class _Effects:
    """The effects of one ground action, grouped by fluent, in UP's sequential semantics."""

    def __init__(self, conv: _Converter, morphism: str, up_name: str) -> None:
        self.conv, self.morphism, self.up_name = conv, morphism, up_name

    def run(self, effects: Iterable[Any]) -> tuple[list[ir.Effect], list[ir.Expr]]:
        by_fluent: dict[Any, list[Any]] = {}
        for e in effects:
            if e.is_forall():
                raise _Refused(f"effect {e}", "a forall effect left after grounding")
            by_fluent.setdefault(e.fluent, []).append(e)
        out: list[ir.Effect] = []
        guards: list[ir.Expr] = []
        for node, group in by_fluent.items():
            if node.fluent().name in self.conv.static:  # pragma: no cover - UP calls it static only if unwritten
                continue
            r = self.conv._resource(node)
            for kind, value in self._one(r, group, guards):
                label = ir.Label.eff(self.morphism, len(out))
                out.append(ir.Effect(kind, r, value, label))
                self.conv.report.labels[label] = f"effect on {node} of {self.up_name}"
        return out, guards

    def _cond(self, e: Any) -> ir.Expr | None:
        return self.conv.expr(e.condition) if e.is_conditional() else None

    def _one(self, r: str, group: list[Any], guards: list[ir.Expr]) -> list[tuple[ir.EffectKind, ir.Expr]]:
        sort = self.conv.resources[r].sort
        ref = ir.ResourceRef(r, sort)
        assigns = [(self._cond(e), self.conv.expr(e.value)) for e in group if e.is_assignment()]
        steps = [(self._cond(e), self.conv.expr(e.value), e.is_increase()) for e in group if not e.is_assignment()]
        if assigns and steps:  # both fire: UP's simulator rejects the action
            guards.append(
                _not(ir.BoolOp(ir.BoolOpKind.AND, (_any(c for c, _ in assigns), _any(c for c, _, _ in steps))))
            )
            incr = _sum(ref, steps, sort)
            return [(ir.EffectKind.ASSIGN, _ite_chain(assigns, incr, sort))]
        if steps:
            out = []
            for cond, amount, up in steps:
                value = (
                    amount if cond is None else ir.Ite(cond, amount, ir.Const(Fraction(0), amount.sort), amount.sort)
                )
                out.append((ir.EffectKind.INCREASE if up else ir.EffectKind.DECREASE, value))
            return out
        if len(assigns) == 1 and assigns[0][0] is None:
            return [(ir.EffectKind.ASSIGN, assigns[0][1])]
        if sort is BOOL or sort == BOOL:
            return [(ir.EffectKind.ASSIGN, _bool_assigns(assigns, ref))]
        for i in range(len(assigns)):  # two assignments of different values conflict
            for j in range(i + 1, len(assigns)):
                (ci, vi), (cj, vj) = assigns[i], assigns[j]
                both = [c for c in (ci, cj) if c is not None]
                differ = _not(ir.Compare(ir.CmpOp.EQ, vi, vj))
                guards.append(_not(ir.BoolOp(ir.BoolOpKind.AND, (*both, differ))))
        return [(ir.EffectKind.ASSIGN, _ite_chain(assigns, ref, sort))]


def _not(e: ir.Expr) -> ir.Expr:
    return ir.BoolOp(ir.BoolOpKind.NOT, (e,))


def _any(conds: Iterable[ir.Expr | None]) -> ir.Expr:
    cs = list(conds)
    if any(c is None for c in cs):
        return ir.Const(True, BOOL)
    return ir.BoolOp(ir.BoolOpKind.OR, tuple(c for c in cs if c is not None))


def _ite_chain(assigns: list[tuple[ir.Expr | None, ir.Expr]], default: ir.Expr, sort: Sort) -> ir.Expr:
    out = default
    for cond, value in reversed(assigns):
        out = value if cond is None else ir.Ite(cond, value, out, sort)
    return out


def _sum(ref: ir.Expr, steps: list[tuple[ir.Expr | None, ir.Expr, bool]], sort: Sort) -> ir.Expr:
    terms: list[ir.Expr] = [ref]
    for cond, amount, up in steps:
        signed = amount if up else ir.Arith(ir.ArithOp.SUB, (amount,), amount.sort)
        terms.append(signed if cond is None else ir.Ite(cond, signed, ir.Const(Fraction(0), amount.sort), amount.sort))
    return ir.Arith(ir.ArithOp.ADD, tuple(terms), sort)


def _bool_assigns(assigns: list[tuple[ir.Expr | None, ir.Expr]], ref: ir.Expr) -> ir.Expr:
    """UP's add-after-delete: p' = OR(cᵢ ∧ vᵢ) ∨ (p ∧ ¬OR(cᵢ)) — true wins when both fire."""
    fired = []
    for cond, value in assigns:
        fired.append(value if cond is None else ir.BoolOp(ir.BoolOpKind.AND, (cond, value)))
    keep = ir.BoolOp(ir.BoolOpKind.AND, (ref, _not(_any(c for c, _ in assigns))))
    return ir.BoolOp(ir.BoolOpKind.OR, (*fired, keep))


def _post_values(effects: list[ir.Effect], resources: Mapping[str, ir.Resource]) -> dict[str, ir.Expr]:
    """Each written resource's value after the step, as a term over the state before it."""
    post: dict[str, ir.Expr] = {}
    for e in effects:
        sort = resources[e.resource].sort
        current = post.get(e.resource, ir.ResourceRef(e.resource, sort))
        if e.kind is ir.EffectKind.ASSIGN:
            post[e.resource] = e.value
        elif e.kind is ir.EffectKind.INCREASE:
            post[e.resource] = ir.Arith(ir.ArithOp.ADD, (current, e.value), sort)
        elif e.kind is ir.EffectKind.DECREASE:
            post[e.resource] = ir.Arith(ir.ArithOp.SUB, (current, e.value), sort)
    return post


def _substitute(e: ir.Expr, post: Mapping[str, ir.Expr]) -> ir.Expr:
    if isinstance(e, ir.ResourceRef):
        return post.get(e.name, e)
    if isinstance(e, (ir.Arith, ir.BoolOp)):
        return type(e)(e.op, tuple(_substitute(a, post) for a in e.args), sort=e.sort)  # type: ignore[arg-type]
    if isinstance(e, ir.Compare):
        return ir.Compare(e.op, _substitute(e.left, post), _substitute(e.right, post))
    if isinstance(e, ir.Ite):
        return ir.Ite(_substitute(e.cond, post), _substitute(e.then, post), _substitute(e.orelse, post), e.sort)
    return e


# ---------------------------------------------------------------- plans back


def plan_to_up(plan: Plan, report: ImportReport, problem: Any | None = None) -> Any:
    """A catc composition of an imported instance → a UP ``SequentialPlan`` of the original
    problem's ``ActionInstance`` s, step by step (idle steps vanish; a step of several
    activations — not produced under ``sequential=True`` — keeps catc's order)."""
    from unified_planning.plans import SequentialPlan

    actions = [report.actions[a.morphism] for step in plan.steps for a in step]
    env = problem.environment if problem is not None else None
    return SequentialPlan(actions, env)
