"""The independent plan validator: replay a composition on exact rationals.

Every answer of the SMT encoder is re-checked here against docs/semantics.md §4 with plain
Python and :class:`fractions.Fraction`.  This module shares only the IR (:mod:`catc.ir`) and
the plan type (:mod:`catc.semantics.plan`) with the encoder; it has its own expression evaluator
(:mod:`catc.semantics.evaluate`: a match over the IR's expressions), its own successor-state function and its own
non-interference test, so a bug in the encoder cannot hide behind the same bug here.

What is checked (each failure is one :class:`Violation`, all of them are collected):

* per activation, independent of the state: the morphism exists, every parameter has a
  value of its sort within its bounds, no unknown parameter is given, ``:fixed`` parameters
  agree across the composition; per step: a morphism at most once, and with
  ``sequential=True`` at most one activation;
* replayed from s₀: every precondition literal holds in the state before its step, no two
  activations of a step interfere, every effect can be evaluated (a zero divisor makes the
  literal or effect containing it fail), and every state respects the resources' bounds;
* plan-wide: ``:uses`` limits, the horizon, and the goal in the final state.

Replay stops at the first step that cannot be applied (``Report.states`` then ends with the
state before it); state-independent checks still cover every step.

Division by zero is *strict*: a divisor that evaluates to 0 anywhere in a literal (also in
an ``if`` branch not taken or an ``or`` argument not needed) makes the whole literal false,
as the encoder asserts every divisor of a literal that must hold to be non-zero.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Mapping
from fractions import Fraction
from types import MappingProxyType

from catc import ir
from catc.ir import EffectKind, SortKind
from catc.ir.text import to_text
from catc.semantics.evaluate import (  # the evaluator's names, imported from here too
    DivisionByZero,
    EvaluationError,
    MissingValue,
    Undefined,
    _activation_text,
    _bindings,
    _bool,
    _Env,
    _eval,
    _is_num,
    _norm,
    evaluate,
    fmt,
    objective_value,
)
from catc.semantics.plan import Activation, Plan
from catgrammar.limits import check_time
from catgrammar.record import Record, set_field

__all__ = [
    "KINDS",
    "DivisionByZero",
    "EvaluationError",
    "MissingValue",
    "Report",
    "Undefined",
    "ValidationFailure",
    "Violation",
    "evaluate",
    "fmt",
    "initial_state",
    "objective_value",
    "validate",
]

#: Every kind of :class:`Violation`, in the order of the checks.
KINDS = (
    "unknown-morphism",
    "unknown-parameter",
    "missing-parameter",
    "parameter-sort",
    "parameter-bounds",
    "fixed-parameter",
    "duplicate-in-step",
    "precondition",
    "interference",
    "sequential",
    "division-by-zero",
    "resource-bounds",
    "uses",
    "horizon",
    "goal",
    "initial-state",
)

# Violations after which the step's successor state is not defined (the step does not
# apply): everything except these, which leave the successor well defined.
_NON_BLOCKING = frozenset({"sequential", "resource-bounds"})


class ValidationFailure(RuntimeError):
    """A solver's answer did not survive independent validation (a bug in catc)."""


class Violation(Record):
    __slots__ = ("kind", "message", "step", "morphism", "label")
    kind: str
    message: str
    step: int | None  # 1-based; None for whole-plan issues
    morphism: str | None
    label: str | None

    def __init__(
        self, kind: str, message: str, step: int | None, morphism: str | None = None, label: str | None = None
    ) -> None:
        set_field(self, "kind", kind)
        set_field(self, "message", message)
        set_field(self, "step", step)
        set_field(self, "morphism", morphism)
        set_field(self, "label", label)

    def __str__(self) -> str:
        return f"[{self.kind}] {self.message}"


class Report(Record):
    __slots__ = ("violations", "states")
    violations: tuple[Violation, ...]
    states: tuple[Mapping[str, object], ...]  # s_0 .. s_n, up to the first step that cannot apply

    def __init__(self, violations: tuple[Violation, ...], states: tuple[Mapping[str, object], ...]) -> None:
        set_field(self, "violations", violations)
        set_field(self, "states", states)

    @property
    def ok(self) -> bool:
        return not self.violations

    @property
    def final_state(self) -> Mapping[str, object]:
        return self.states[-1]

    def kinds(self) -> list[str]:
        return [v.kind for v in self.violations]


# ====================================================================== states


def _initial(instance: ir.Instance) -> tuple[dict[str, object], list[Violation]]:
    state: dict[str, object] = {}
    problems: list[Violation] = []
    init = instance.problem.init
    for name, r in instance.resources.items():
        iv = init.get(name)
        label = iv.label if iv is not None else r.init_label
        if iv is None:
            if r.sort.kind is SortKind.BOOL:
                state[name] = False
            elif r.sort.kind is SortKind.SET:
                state[name] = frozenset()
            else:
                problems.append(
                    Violation("initial-state", f"resource '{name}' has no initial value", None, None, label)
                )
            continue
        try:
            value = _eval(_Env(instance, {}, {}), iv.value)
        except EvaluationError as exc:
            problems.append(
                Violation(
                    "initial-state", f"the initial value of '{name}' cannot be evaluated: {exc}", None, None, label
                )
            )
            continue
        state[name] = value
        why = _resource_value_problem(instance, r, value)
        if why:
            problems.append(Violation("initial-state", f"initial value of '{name}': {why}", None, None, label))
    for name, iv in init.items():
        if name not in instance.resources:
            problems.append(
                Violation("initial-state", f"initial value for unknown resource '{name}'", None, None, iv.label)
            )
    return state, problems


def initial_state(instance: ir.Instance) -> dict[str, object]:
    """s₀: the problem's initial values; bools default to false and sets to {} (closed
    world).  A numeric or symbolic resource without an initial value is left out."""
    return _initial(instance)[0]


def _bounds_problem(lower: Fraction | None, upper: Fraction | None, v: Fraction) -> str | None:
    if (lower is not None and v < lower) or (upper is not None and v > upper):
        lo = "*" if lower is None else fmt(lower)
        hi = "*" if upper is None else fmt(upper)
        return f"{fmt(v)} is outside the bounds ({lo} {hi})"
    return None


def _resource_value_problem(instance: ir.Instance, r: ir.Resource, v: object) -> str | None:
    k = r.sort.kind
    if k in (SortKind.INT, SortKind.REAL):
        if not _is_num(v):
            return f"{fmt(v)} is not a number"
        if k is SortKind.INT and v.denominator != 1:
            return f"{fmt(v)} is not an integer"
        return _bounds_problem(r.lower, r.upper, v)
    if k is SortKind.BOOL:
        return None if isinstance(v, bool) else f"{fmt(v)} is not true or false"
    if k is SortKind.SET:
        return None if isinstance(v, frozenset) else f"{fmt(v)} is not a set"
    return None if isinstance(v, str) else f"{fmt(v)} is not a symbol"


# ====================================================================== validation


def _sort_problem(
    instance: ir.Instance, sort: ir.Sort, v: object, fresh: Mapping[str, str], constants: Mapping[str, ir.Constant]
) -> str | None:
    """Why ``v`` is not a value of ``sort`` (None when it is)."""
    k = sort.kind
    if k is SortKind.BOOL:
        return None if isinstance(v, bool) else f"{fmt(v)} is not true or false"
    if k in (SortKind.INT, SortKind.REAL):
        if isinstance(v, float):
            return f"{v!r} is a float; numbers must be exact (Fraction)"
        if not _is_num(v):
            return f"{fmt(v)} is not a number"
        if k is SortKind.INT and v.denominator != 1:
            return f"{fmt(v)} is not an integer"
        return None
    if k is SortKind.ENUM:
        if isinstance(v, str) and v in sort.values:
            return None
        return f"{fmt(v)} is not a value of the enumeration {sort.name} ({' '.join(sort.values)})"
    if k is SortKind.SYMBOL:
        if not isinstance(v, str):
            return f"{fmt(v)} is not a symbol"
        allowed = instance.subsorts(sort)
        c = constants.get(v)
        if c is not None:
            if c.sort.name in allowed:
                return None
            return f"'{v}' is a constant of sort {c.sort.name}, not of {sort.name} or a sub-sort"
        fs = fresh.get(v)
        if fs is None:
            return f"'{v}' is neither a constant of the model nor a fresh value listed in the plan"
        decl = instance.domain.sorts.get(fs)
        if decl is None or decl.kind is not SortKind.SYMBOL:
            return f"fresh value '{v}' has sort '{fs}', which is not an open symbolic sort"
        if fs not in allowed:
            return f"fresh value '{v}' is of sort {fs}, not of {sort.name} or a sub-sort"
        return None
    return f"parameters of sort {sort} are not supported"


def _first_reader(m: ir.Morphism, r: str) -> str | None:
    for lit in m.pre:
        if r in ir.resources_in(lit.expr):
            return lit.label
    for eff in m.effects:
        if r in ir.resources_in(eff.value):
            return eff.label
    return None


def _first_effect(m: ir.Morphism, r: str, kinds: tuple[EffectKind, ...]) -> str | None:
    for eff in m.effects:
        if eff.resource == r and eff.kind in kinds:
            return eff.label
    return None


_UPDATES = (EffectKind.INCREASE, EffectKind.DECREASE, EffectKind.ADD, EffectKind.REMOVE)


class _Live:
    """One activation that takes part in the replay of its step."""

    __slots__ = ("act", "m", "params", "values")

    def __init__(self, act: Activation, m: ir.Morphism, params: dict[str, object]) -> None:
        self.act = act
        self.m = m
        self.params = params
        self.values: list[object] = []  # effect values (None when not evaluable)

    @property
    def name(self) -> str:
        return self.m.name

    @property
    def assigns(self) -> frozenset[str]:
        return frozenset(e.resource for e in self.m.effects if e.kind is EffectKind.ASSIGN)

    @property
    def updates(self) -> frozenset[str]:
        return frozenset(e.resource for e in self.m.effects if e.kind is not EffectKind.ASSIGN)


class _Validator:
    def __init__(self, instance: ir.Instance, plan: Plan, horizon: int | None, sequential: bool) -> None:
        self.inst = instance
        self.plan = plan
        self.horizon = horizon if horizon is not None else instance.problem.horizon
        self.sequential = sequential
        self.constants = instance.constants()
        self.out: list[Violation] = []

    def add(
        self, kind: str, message: str, step: int | None, morphism: str | None = None, label: str | None = None
    ) -> None:
        self.out.append(Violation(kind, message, step, morphism, label))

    # -------------------------------------------------------------- static checks
    def static(self) -> list[list[_Live]]:
        """Checks that do not depend on the state; returns, per step, the activations
        whose parameters are usable (first occurrence of each morphism)."""
        fixed_seen: dict[tuple[str, str], tuple[int, object]] = {}
        live_steps: list[list[_Live]] = []
        for i, step in enumerate(self.plan.steps, 1):
            check_time("validating", finishing=True)
            live: list[_Live] = []
            if self.sequential and len(step) > 1:
                names = ", ".join(a.morphism for a in step)
                self.add(
                    "sequential",
                    f"step {i} runs {len(step)} activations ({names}) but the composition must be sequential",
                    i,
                )
            counts = Counter(a.morphism for a in step)
            for name, n in counts.items():
                if n > 1:
                    self.add(
                        "duplicate-in-step",
                        f"step {i} activates '{name}' {n} times; a morphism occurs at most once in a step",
                        i,
                        name,
                    )
            seen: set[str] = set()
            for act in step:
                usable = self.activation(i, act, fixed_seen)
                if usable is not None and act.morphism not in seen:
                    live.append(usable)
                seen.add(act.morphism)
            live_steps.append(live)
        return live_steps

    def activation(
        self, i: int, act: Activation, fixed_seen: dict[tuple[str, str], tuple[int, object]]
    ) -> _Live | None:
        m = self.inst.morphisms.get(act.morphism)
        if m is None:
            self.add("unknown-morphism", f"step {i}: unknown morphism '{act.morphism}'", i, act.morphism)
            return None
        usable = True
        declared = {p.name for p in m.params}
        for name in act.params:
            if name not in declared:
                self.add(
                    "unknown-parameter",
                    f"step {i}: '{m.name}' has no parameter '{name}' (given {fmt(_norm(act.params[name]))})",
                    i,
                    m.name,
                )
        params: dict[str, object] = {}
        for p in m.params:
            if p.name not in act.params:
                self.add(
                    "missing-parameter",
                    f"step {i}: {_activation_text(act)} gives no value for parameter '{p.name}' ({p.sort})",
                    i,
                    m.name,
                )
                usable = False
                continue
            v = _norm(act.params[p.name])
            why = _sort_problem(self.inst, p.sort, v, self.plan.fresh, self.constants)
            if why:
                self.add(
                    "parameter-sort",
                    f"step {i}: parameter '{p.name}' of '{m.name}' must be of sort {p.sort}: {why}",
                    i,
                    m.name,
                )
                usable = False
            elif p.sort.is_numeric and _is_num(v):  # (no sort problem: a number)
                out = _bounds_problem(p.lower, p.upper, v)
                if out:
                    self.add("parameter-bounds", f"step {i}: parameter '{p.name}' of '{m.name}': {out}", i, m.name)
            if p.fixed:
                key = (m.name, p.name)
                if key not in fixed_seen:
                    fixed_seen[key] = (i, v)
                elif fixed_seen[key][1] != v:
                    j, w = fixed_seen[key]
                    self.add(
                        "fixed-parameter",
                        f"step {i}: :fixed parameter '{p.name}' of '{m.name}' is {fmt(v)}, but {fmt(w)} in step {j}",
                        i,
                        m.name,
                    )
            params[p.name] = v
        return _Live(act, m, params) if usable else None

    # -------------------------------------------------------------- plan-wide checks
    def plan_wide(self) -> None:
        counts = Counter(a.morphism for _, a in self.plan.activations)
        for name, n in counts.items():
            m = self.inst.morphisms.get(name)
            if m is not None and m.uses is not None and n > m.uses:
                self.add("uses", f"'{name}' is activated {n} times but allows at most {m.uses} (:uses)", None, name)
        if self.horizon is not None and len(self.plan) > self.horizon:
            self.add("horizon", f"the composition has {len(self.plan)} steps but the horizon is {self.horizon}", None)

    # -------------------------------------------------------------- replay
    def literal(
        self,
        i: int | None,
        lit: ir.Literal,
        state: Mapping[str, object],
        params: Mapping[str, object],
        morphism: str | None,
        kind: str,
        act: Activation | None,
    ) -> bool:
        """Whether ``lit`` holds (a violation when not).  The message names the activation
        ``act`` (None: the goal), written out only when there is a violation: its θ may be
        fractions of thousands of digits, and most literals hold."""

        def where() -> str:
            return "goal " if act is None else f"step {i}: {_activation_text(act)}: precondition "

        try:
            ok = _bool(_Env(self.inst, state, params), lit.expr)
        except DivisionByZero as exc:
            self.add(
                "division-by-zero",
                f"{where()}{lit.label} {to_text(lit.expr)} is false: {exc} ({_bindings(lit.expr, state, params)})",
                i,
                morphism,
                lit.label,
            )
            return False
        except EvaluationError as exc:
            self.add(
                "initial-state" if isinstance(exc, MissingValue) else kind,
                f"{where()}{lit.label} {to_text(lit.expr)} cannot be evaluated: {exc}",
                i,
                morphism,
                lit.label,
            )
            return False
        if not ok:
            bindings = _bindings(lit.expr, state, params)
            self.add(
                kind,
                f"{where()}{lit.label} {to_text(lit.expr)} is false" + (f" with {bindings}" if bindings else ""),
                i,
                morphism,
                lit.label,
            )
        return ok

    def step(self, i: int, live: list[_Live], state: Mapping[str, object]) -> bool:
        """Check one step in ``state``; True when nothing forbids applying it."""
        ok = True
        for a in live:
            for lit in a.m.pre:
                ok &= self.literal(i, lit, state, a.params, a.name, "precondition", a.act)
            a.values = []
            for eff in a.m.effects:
                try:
                    a.values.append(_eval(_Env(self.inst, state, a.params), eff.value))
                except DivisionByZero as exc:
                    self.add(
                        "division-by-zero",
                        f"step {i}: {_activation_text(a.act)}: effect {eff.label} cannot be applied: {exc}",
                        i,
                        a.name,
                        eff.label,
                    )
                    a.values.append(None)
                    ok = False
                except EvaluationError as exc:
                    self.add(
                        "initial-state",
                        f"step {i}: {_activation_text(a.act)}: effect {eff.label} cannot be evaluated: {exc}",
                        i,
                        a.name,
                        eff.label,
                    )
                    a.values.append(None)
                    ok = False
        ok &= self.interference(i, live)
        return ok

    def interference(self, i: int, live: list[_Live]) -> bool:
        ok = True
        for x in range(len(live)):
            for y in range(x + 1, len(live)):
                for a, b in ((live[x], live[y]), (live[y], live[x])):
                    ok &= self.pair(i, a, b, first=a is live[x])
        return ok

    def pair(self, i: int, a: _Live, b: _Live, first: bool) -> bool:
        ok = True
        rb = b.m.reads
        for r in sorted(a.assigns):
            if r in b.assigns:
                if first:  # assign/assign: report once per pair
                    self.add(
                        "interference",
                        f"step {i}: '{a.name}' and '{b.name}' both assign '{r}' "
                        f"({_first_effect(a.m, r, (EffectKind.ASSIGN,))}, {_first_effect(b.m, r, (EffectKind.ASSIGN,))})",
                        i,
                        a.name,
                        _first_effect(a.m, r, (EffectKind.ASSIGN,)),
                    )
                ok = False
            elif r in rb or r in b.updates:
                how = "reads" if r in rb else "updates"
                other = _first_reader(b.m, r) if r in rb else _first_effect(b.m, r, _UPDATES)
                self.add(
                    "interference",
                    f"step {i}: '{a.name}' assigns '{r}' ({_first_effect(a.m, r, (EffectKind.ASSIGN,))}) while '{b.name}' {how} it ({other})",
                    i,
                    a.name,
                    _first_effect(a.m, r, (EffectKind.ASSIGN,)),
                )
                ok = False
        for r in sorted(a.updates & rb):
            label = _first_effect(a.m, r, _UPDATES)
            self.add(
                "interference",
                f"step {i}: '{a.name}' updates '{r}' ({label}) while '{b.name}' reads it ({_first_reader(b.m, r)})",
                i,
                a.name,
                label,
            )
            ok = False
        for eff, v in zip(a.m.effects, a.values):
            if eff.kind is not EffectKind.ADD or v is None:
                continue
            for eff2, w in zip(b.m.effects, b.values):
                if eff2.kind is EffectKind.REMOVE and eff2.resource == eff.resource and w == v:
                    self.add(
                        "interference",
                        f"step {i}: '{a.name}' adds {fmt(v)} to '{eff.resource}' ({eff.label}) while '{b.name}' removes it ({eff2.label})",
                        i,
                        a.name,
                        eff.label,
                    )
                    ok = False
        return ok

    def successor(self, i: int, live: list[_Live], state: Mapping[str, object]) -> dict[str, object] | None:
        new = dict(state)
        assigned: dict[str, object] = {}
        delta: dict[str, Fraction] = defaultdict(Fraction)
        added: dict[str, set[object]] = defaultdict(set)
        removed: dict[str, set[object]] = defaultdict(set)
        writer: dict[str, tuple[str, str]] = {}
        for a in live:
            for eff, v in zip(a.m.effects, a.values):
                writer.setdefault(eff.resource, (a.name, eff.label))
                k = eff.kind
                if k is EffectKind.ASSIGN:
                    assigned[eff.resource] = v
                # the value of an increase/decrease is a number (the front end's sort rules;
                # one that could not be evaluated stopped the replay before this step)
                elif k is EffectKind.INCREASE:
                    delta[eff.resource] += v  # type: ignore[operator]
                elif k is EffectKind.DECREASE:
                    delta[eff.resource] -= v  # type: ignore[operator]
                elif k is EffectKind.ADD:
                    added[eff.resource].add(v)
                else:
                    removed[eff.resource].add(v)
        try:
            for r, d in delta.items():
                number = state.get(r)
                if not _is_num(number):
                    raise MissingValue(f"resource '{r}' has no value")
                new[r] = number + d
            for r in set(added) | set(removed):
                members = state.get(r)
                if not isinstance(members, frozenset):
                    raise MissingValue(f"resource '{r}' has no value")
                new[r] = frozenset((members - removed[r]) | added[r])
        except EvaluationError as exc:
            self.add("initial-state", f"step {i}: {exc}", i)
            return None
        new.update(assigned)
        for r in sorted(writer):
            res = self.inst.resources.get(r)
            if res is None or not res.sort.is_numeric or r not in new:
                continue
            why = _resource_value_problem(self.inst, res, new[r])  # bounds, and integral for int
            if why:
                name, label = writer[r]
                self.add(
                    "resource-bounds",
                    f"step {i}: after the step '{r}' = {why} (written by '{name}', {label})",
                    i,
                    name,
                    label,
                )
        return new

    # -------------------------------------------------------------- driver
    def run(self) -> Report:
        s0, problems = _initial(self.inst)
        self.out.extend(problems)
        live_steps = self.static()
        self.plan_wide()
        states: list[Mapping[str, object]] = [MappingProxyType(dict(s0))]
        state: Mapping[str, object] = s0
        complete = True
        for i, live in enumerate(live_steps, 1):
            check_time("validating", finishing=True)
            static_blocked = any(v.step == i and v.kind not in _NON_BLOCKING for v in self.out)
            ok = self.step(i, live, state)
            if static_blocked or not ok:
                complete = False
                break
            new = self.successor(i, live, state)
            if new is None:
                complete = False
                break
            state = new
            states.append(MappingProxyType(dict(new)))
        if complete:
            for lit in self.inst.problem.goal:
                self.literal(None, lit, state, {}, None, "goal", None)

        def rank(iv: tuple[int, Violation]) -> tuple[float, int]:
            n, v = iv
            if v.step is not None:
                return (v.step, n)
            return (-1 if v.kind == "initial-state" else float("inf"), n)

        ranked = sorted(enumerate(self.out), key=rank)
        return Report(tuple(v for _, v in ranked), tuple(states))


def validate(instance: ir.Instance, plan: Plan, *, horizon: int | None = None, sequential: bool = False) -> Report:
    """Replay ``plan`` on ``instance`` (whose view is already applied) and report every
    violation of docs/semantics.md §4.  ``horizon`` overrides the problem's ``(:horizon k)``;
    ``sequential`` allows at most one activation per step."""
    return _Validator(instance, plan, horizon, sequential).run()
