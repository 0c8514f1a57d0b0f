"""IR → SMT-LIB2: the bounded composition formula of paper eq. (logic_formula).

The encoder writes SMT-LIB2 commands (a :class:`~catc.smt.script.Script`), and every backend
(:mod:`catc.smt.backend`) consumes the same script: Z3 and cvc5 read it through their
Python APIs, a step at a time for incremental solving, and ``catc compile --emit smt2``
prints it with every assertion named after its source construct (:mod:`catc.smt.smtlib`).
Building text and letting the solver's C++ parser build the terms is about seven times
faster than building the same terms through Z3's Python API (docs/benchmarks.md), and the
printed file is equivalent to what the API solves by construction; tests still solve it
with the ``z3`` binary and with cvc5.

Variables, for a horizon built one step at a time:

* ``|s.r.t|`` — resource ``r`` in state ``t`` (Bool, Int or Real; an Int index into the
  grounded universe for a symbol; one Bool ``|s.r.t.e|`` per universe element ``e`` for a set);
* ``|b.a.t|`` — morphism ``a`` is activated in step ``t`` (from state ``t`` to ``t+1``);
* ``|th.a.p.t|`` — parameter ``p`` of ``a`` in step ``t`` (``|th.a.p|`` when ``:fixed``).

Constraints (``docs/semantics.md`` §4): ``b ⇒ pre`` per precondition literal; successor-state
axioms (the frame value unless an active morphism writes the resource: assignments, summed
increments, set unions); non-interference (or one activation per step when sequential); θ
bounds and sorts; resource bounds in every state; use limits; initial state; goal.

Every constraint stemming from a source construct is filed under its label (``pre/m/i``,
``eff/m/i``, ``init/r``, ``goal/i``, ``bound/m/p``, ``bounds/r``, ``uses/m``); structural
constraints (frame, interference, typing) have none.  With ``track=True`` an effect's value
is a variable pinned by the effect's labelled constraint, so dropping that label from a
core removes exactly that effect.
"""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Callable, Mapping
from fractions import Fraction
from typing import TypeAlias, assert_never

from catc import ir
from catc.ir import SortKind
from catc.semantics.horizon import check_horizon
from catc.smt.finite import FiniteSorts
from catc.smt.script import Script, SmtSort, Symbol, at_most, int_literal, real_literal
from catc.smt.script import and_text as _and
from catc.smt.script import or_text as _or
from catgrammar import limits
from catgrammar.record import Record, set_field

# A term is SMT-LIB text (a Symbol is one); a symbol may also be a known universe index
# (int); a set is a mapping universe index → Bool text.
Term: TypeAlias = str | int | dict[int, str]
#: The effects of one step on one resource, as :meth:`Encoder.add_step` gathers them (and
#: hands them to ``step_hook``): assignments (guard, value), increments (text),
#: set additions and removals (morphism, guard, element).
Assigns: TypeAlias = list[tuple[str, Term]]
Deltas: TypeAlias = list[str]
SetChanges: TypeAlias = list[tuple[str, str, Term]]
StepHook: TypeAlias = Callable[
    [int, dict[str, Symbol], dict[str, Assigns], dict[str, Deltas], dict[str, SetChanges], dict[str, SetChanges]],
    None,
]


def _text(t: Term) -> str:
    """A term that is SMT-LIB text: Boolean and numeric terms are (symbols may be known
    universe indices, sets are mappings)."""
    assert isinstance(t, str), t
    return t


class _Ctx:
    __slots__ = ("t", "params", "guards", "state")

    def __init__(
        self, t: int, params: dict[str, Term], guards: list[str], state: dict[str, Term] | None = None
    ) -> None:
        self.t = t
        self.params = params
        self.guards = guards
        self.state = state  # the resources read (∃-step: the state after the step's earlier morphisms)


_SMT_SORT = {
    SortKind.BOOL: SmtSort.BOOL,
    SortKind.INT: SmtSort.INT,
    SortKind.REAL: SmtSort.REAL,
    SortKind.SYMBOL: SmtSort.INT,
    SortKind.ENUM: SmtSort.INT,
}


class Encoder:
    def __init__(
        self,
        inst: ir.Instance,
        horizon: int,
        *,
        sequential: bool = False,
        track: bool = False,
        slack: dict[str, str] | None = None,
        extra_written: frozenset[str] = frozenset(),
        assumed: frozenset[str] = frozenset(),
        exists: bool = False,
    ) -> None:
        """``exists`` (not with ``sequential``): ∃-step parallel steps (:meth:`_exists_step`).
        ``slack`` maps labels of relaxable requirements (numeric initial values and
        order comparisons) to the name of a slack term that weakens them (``catc relax``).
        ``extra_written`` names resources something besides the morphisms may write (a hole
        μ, ``catc synthesize``), which then add their effects through ``step_hook``."""
        self.inst = inst
        self.slack = slack or {}
        self.step_hook: StepHook | None = None  # called as hook(t, actions, assigns, deltas, adds, removes)
        self.horizon = horizon
        self.sequential = sequential
        if exists and sequential:
            raise ValueError("∃-step steps are parallel steps: not with sequential=True")
        self.exists = exists
        self.track = track
        self.assumed = assumed
        check_horizon(None, horizon)
        self.finite = FiniteSorts(inst, horizon)
        self.morphisms = list(inst.morphisms.values())
        self.resources = list(inst.resources.values())
        # The labels of bounds, built once (the unrolling files one constraint per step under each)
        self.bound_labels = {(m.name, p.name): m.bound_label(p.name) for m in self.morphisms for p in m.params}
        self.bounds_labels = {r.name: r.bounds_label for r in self.resources}
        self.script = Script()
        self.states: list[dict[str, Term]] = []
        self.act: list[dict[str, Symbol]] = []
        self.theta: list[dict[tuple[str, str], Term]] = []
        self.fixed: dict[tuple[str, str], Term] = {}
        self.indicators: dict[str, Symbol] = {}  # effect label → indicator (tracking)
        #: resources no morphism writes keep one variable for every state
        self.written = frozenset(e.resource for m in self.morphisms for e in m.effects) | extra_written
        self._classify()
        self._fixed_params()
        self.states.append(self._new_state(0))
        self._initial_state()

    # ------------------------------------------------------------------ variables
    def _var(self, name: str, sort: ir.Sort) -> Term:
        if sort.kind is SortKind.SET:
            assert sort.element is not None  # a set sort's element sort
            u = self.finite.universe(sort.element)
            return {i: self.script.declare(f"{name}.{e}", SmtSort.BOOL) for i, e in enumerate(u.elements)}
        return self.script.declare(name, _SMT_SORT[sort.kind])

    def add(self, label: str | None, text: str) -> None:
        if text != "true":
            self.script.asserts.append((label, text))

    def domain_constraint(self, v: str, sort: ir.Sort) -> str:
        """The values a symbolic variable may take: its sort's universe indices."""
        allowed = self.finite.allowed(sort)
        if not allowed:
            return "false"
        if allowed == list(range(allowed[0], allowed[-1] + 1)):
            return f"(and (<= {allowed[0]} {v}) (<= {v} {allowed[-1]}))"
        return _or([f"(= {v} {i})" for i in allowed])

    # ------------------------------------------------------------------ structure
    def _classify(self) -> None:
        self.readers: dict[str, list[str]] = defaultdict(list)
        self.assigners: dict[str, list[str]] = defaultdict(list)
        self.updaters: dict[str, list[str]] = defaultdict(list)
        for m in self.morphisms:
            for r in sorted(m.reads):
                self.readers[r].append(m.name)
            for e in m.effects:
                table = self.assigners if e.kind is ir.EffectKind.ASSIGN else self.updaters
                if m.name not in table[e.resource]:
                    table[e.resource].append(m.name)

    def _fixed_params(self) -> None:
        for m in self.morphisms:
            for p in m.params:
                if p.fixed:
                    v = self._var(f"th.{m.name}.{p.name}", p.sort)
                    self.fixed[(m.name, p.name)] = v
                    self._param_constraints(m, p, v)

    def _param_constraints(self, m: ir.Morphism, p: ir.Param, v: Term) -> None:
        if p.sort.is_symbolic:
            self.add(None, self.domain_constraint(_text(v), p.sort))
        lit = real_literal if p.sort.kind is SortKind.REAL else (lambda f: int_literal(int(f)))
        if p.lower is not None:
            self.add(self.bound_labels[m.name, p.name], f"(>= {v} {lit(p.lower)})")
        if p.upper is not None:
            self.add(self.bound_labels[m.name, p.name], f"(<= {v} {lit(p.upper)})")

    def _new_state(self, t: int) -> dict[str, Term]:
        state: dict[str, Term] = {}
        for r in self.resources:
            if t > 0 and r.name not in self.written:
                state[r.name] = self.states[0][r.name]  # frame: never written, one variable
                continue
            v = self._var(f"s.{r.name}.{t}", r.sort)
            state[r.name] = v
            lit = real_literal if r.sort.kind is SortKind.REAL else (lambda f: int_literal(int(f)))
            if r.lower is not None:
                self.add(self.bounds_labels[r.name], f"(>= {v} {lit(r.lower)})")
            if r.upper is not None:
                self.add(self.bounds_labels[r.name], f"(<= {v} {lit(r.upper)})")
        return state

    def _initial_state(self) -> None:
        for init in self.inst.problem.init.values():
            if init.resource in self.states[0] and init.resource not in self.assumed:
                self.add(init.label, self.init_constraint(init))

    def init_constraint(self, init: ir.InitValue) -> str:
        """State 0 holds ``init``'s value (plus its slack, when it has one)."""
        value = self.term(init.value, _Ctx(0, {}, []))
        if init.label in self.slack:  # s0 = v + δ (δ may be negative: a pair of slacks)
            value = f"(+ {value} {self.slack[init.label]})"
        return self._equal(self.states[0][init.resource], value)

    # ------------------------------------------------------------------ steps
    def add_step(self) -> int:
        """Add step t (state t → t+1); return t.  Stops (:func:`catgrammar.limits.check_time`)
        when the command's time is up."""
        limits.check_time("encoding")
        t = len(self.act)
        s, nxt = self.states[t], self._new_state(t + 1)
        self.states.append(nxt)
        b = {m.name: self.script.declare(f"b.{m.name}.{t}", SmtSort.BOOL) for m in self.morphisms}
        self.act.append(b)
        theta: dict[tuple[str, str], Term] = {}
        for m in self.morphisms:
            for p in m.params:
                if p.fixed:
                    theta[(m.name, p.name)] = self.fixed[(m.name, p.name)]
                else:
                    v = self._var(f"th.{m.name}.{p.name}.{t}", p.sort)
                    theta[(m.name, p.name)] = v
                    if m.uses != 0:  # a morphism switched off (:uses 0) has no values to choose
                        self._param_constraints(m, p, v)
        self.theta.append(theta)
        if self.exists:
            self._exists_step(t, s, nxt, b, theta)
        else:
            self._forall_step(t, s, nxt, b, theta)
        if t > 0:  # symmetry breaking: idle steps only at the end (compositions compact)
            self.add(None, f"(=> (not {_or(list(self.act[t - 1].values()))}) (not {_or(list(b.values()))}))")
        return t

    def _forall_step(
        self,
        t: int,
        s: dict[str, Term],
        nxt: dict[str, Term],
        b: dict[str, Symbol],
        theta: dict[tuple[str, str], Term],
    ) -> None:
        """Sequential steps, or parallel steps whose activations do not interfere (each reads
        state ``t``; any order of them runs alike)."""
        for m in self.morphisms:
            limits.check_time("encoding")  # a step of thousands of morphisms takes seconds (issue 28)
            params = {p.name: theta[(m.name, p.name)] for p in m.params}
            self._preconditions(m, t, params, None, b[m.name])

        assigns: dict[str, Assigns] = defaultdict(list)
        deltas: dict[str, Deltas] = defaultdict(list)
        adds: dict[str, SetChanges] = defaultdict(list)
        removes: dict[str, SetChanges] = defaultdict(list)
        for m in self.morphisms:
            limits.check_time("encoding")
            params = {p.name: theta[(m.name, p.name)] for p in m.params}
            self._changes(m, t, params, None, b[m.name], assigns, deltas, adds, removes)
        if self.step_hook is not None:
            self.step_hook(t, b, assigns, deltas, adds, removes)
        for r in self.resources:
            if r.name in self.written:
                self._successor(
                    r, s[r.name], nxt[r.name], assigns[r.name], deltas[r.name], adds[r.name], removes[r.name]
                )
        self._interference(b, adds, removes)

    def _preconditions(
        self, m: ir.Morphism, t: int, params: dict[str, Term], state: dict[str, Term] | None, active: Symbol
    ) -> None:
        """``active`` implies each of ``m``'s preconditions, read on ``state`` (else state ``t``)."""
        for lit in m.pre:
            ctx = _Ctx(t, params, [], state)
            body = self._literal(lit, ctx)
            self.add(lit.label, f"(=> {active} {_and([body] + ctx.guards)})")

    def _changes(
        self,
        m: ir.Morphism,
        t: int,
        params: dict[str, Term],
        state: dict[str, Term] | None,
        active: Symbol,
        assigns: dict[str, Assigns],
        deltas: dict[str, Deltas],
        adds: dict[str, SetChanges],
        removes: dict[str, SetChanges],
    ) -> None:
        """Collect what ``m``'s effects do to each resource when ``active`` (its values read on
        ``state``, else on state ``t``): "increments are summed, then an assignment overrides
        them" is applied by :meth:`_successor` to what is collected here."""
        for e in m.effects:
            res = self.inst.resources[e.resource]
            ctx = _Ctx(t, params, [], state)
            value = self.term(e.value, ctx)
            if e.kind in (ir.EffectKind.INCREASE, ir.EffectKind.DECREASE, ir.EffectKind.ASSIGN):
                value = self._as(value, e.value.sort, res.sort)
            if ctx.guards:
                self.add(e.label, f"(=> {active} {_and(ctx.guards)})")
            on = self.effect_guard(e, active)
            zero = "0.0" if res.sort.kind is SortKind.REAL else "0"
            if e.kind is ir.EffectKind.ASSIGN:
                assigns[e.resource].append((on, value))
            elif e.kind is ir.EffectKind.INCREASE:
                deltas[e.resource].append(f"(ite {on} {value} {zero})")
            elif e.kind is ir.EffectKind.DECREASE:
                deltas[e.resource].append(f"(ite {on} (- {value}) {zero})")
            elif e.kind is ir.EffectKind.ADD:
                adds[e.resource].append((m.name, on, value))
            else:
                removes[e.resource].append((m.name, on, value))

    def _exists_step(
        self,
        t: int,
        s: dict[str, Term],
        nxt: dict[str, Term],
        b: dict[str, Symbol],
        theta: dict[tuple[str, str], Term],
    ) -> None:
        """∃-step parallel steps, in their relaxed form (R²∃, Bofill et al. 2016): the morphisms
        of a step fire in one fixed order (:attr:`morphisms`), each reading the state its
        predecessors in the step left — an intermediate state, a fresh variable for each
        resource it writes (within the resource's bounds, as every state). An active morphism's
        preconditions hold on the state before it and its effects make the state after it, so
        the step is the sequential execution of its activations in that order: a composition of
        h such steps linearises (``catc.queries.solve.linearised``) to a sequential one of the same
        activations, which the validator replays. No interference rules are needed, and
        neither is the ∃-step condition that no action disables a later one: it holds by
        construction, each precondition read where it applies."""
        assert self.step_hook is None, "∃-step steps have no hook (catc synthesize encodes ∀-steps)"
        cur = dict(s)
        for i, m in enumerate(self.morphisms):
            limits.check_time("encoding")
            params = {p.name: theta[(m.name, p.name)] for p in m.params}
            self._preconditions(m, t, params, cur, b[m.name])
            assigns: dict[str, Assigns] = defaultdict(list)
            deltas: dict[str, Deltas] = defaultdict(list)
            adds: dict[str, SetChanges] = defaultdict(list)
            removes: dict[str, SetChanges] = defaultdict(list)
            self._changes(m, t, params, cur, b[m.name], assigns, deltas, adds, removes)
            after = dict(cur)
            for name in dict.fromkeys(e.resource for e in m.effects):
                r = self.inst.resources[name]
                after[name] = self._intermediate(r, t, i)
                self._successor(r, cur[name], after[name], assigns[name], deltas[name], adds[name], removes[name])
            cur = after
        for r in self.resources:
            if r.name in self.written:
                self.add(None, self._equal(nxt[r.name], cur[r.name]))

    def _intermediate(self, r: ir.Resource, t: int, i: int) -> Term:
        """Resource ``r`` after the ``i``-th morphism of step ``t`` (∃-step), within its bounds."""
        v = self._var(f"s.{r.name}.{t}.{i}", r.sort)
        lit = real_literal if r.sort.kind is SortKind.REAL else (lambda f: int_literal(int(f)))
        if r.lower is not None:
            self.add(self.bounds_labels[r.name], f"(>= {v} {lit(r.lower)})")
        if r.upper is not None:
            self.add(self.bounds_labels[r.name], f"(<= {v} {lit(r.upper)})")
        return v

    def effect_guard(self, e: ir.Effect, on: str) -> str:
        """When the effect acts.  With tracking, an effect also needs its label's indicator
        ``|L:eff/m/i|``: a dropped effect (indicator left free) *may or may not* happen, which
        weakens the formula, so unsat cores and their minimisation stay sound."""
        if not self.track:
            return on
        q = self.indicators.get(e.label)
        if q is None:
            q = self.indicators[e.label] = self.script.declare(f"L:{e.label}", SmtSort.BOOL)
        return f"(and {on} {q})"

    def _successor(
        self,
        r: ir.Resource,
        cur: Term,
        nxt: Term,
        assigns: Assigns,
        deltas: Deltas,
        adds: SetChanges,
        removes: SetChanges,
    ) -> None:
        if r.sort.kind is SortKind.SET:
            assert isinstance(cur, dict) and isinstance(nxt, dict)
            for i in cur:
                limits.check_time("encoding")  # (adds × elements: quadratic in a large catalogue)
                added = [_and([on, self._sym_eq(x, i)]) for _, on, x in adds]
                removed = [_and([on, self._sym_eq(x, i)]) for _, on, x in removes]
                value = cur[i]
                if removed and _or(removed) != "false":
                    value = _and([value, f"(not {_or(removed)})"])
                if added and _or(added) != "false":
                    value = _or([_or(added), value])
                for on, whole in reversed(assigns):
                    assert isinstance(whole, dict)  # a set's value
                    value = f"(ite {on} {whole[i]} {value})"
                self.add(None, f"(= {nxt[i]} {value})")
            return
        term: Term = cur
        if deltas:
            term = f"(+ {cur} {' '.join(deltas)})"
        for on, v in reversed(assigns):
            term = f"(ite {on} {v} {term})"
        self.add(None, f"(= {nxt} {term})")

    def _interference(
        self, b: Mapping[str, str], adds: Mapping[str, SetChanges], removes: Mapping[str, SetChanges]
    ) -> None:
        if self.sequential:
            self.add(None, self._at_most_one(list(b.values())))
            return
        for r in self.resources:
            A = self.assigners.get(r.name, [])
            U = self.updaters.get(r.name, [])
            R = self.readers.get(r.name, [])
            touching = list(dict.fromkeys(A + U + R))
            if A and len(touching) > 1:
                self.add(None, f"(=> {_or([b[a] for a in A])} {self._at_most_one([b[x] for x in touching])})")
            if U and R:
                group = list(dict.fromkeys(U + R))
                if len(group) > 1:
                    self.add(
                        None,
                        f"(=> (and {_or([b[u] for u in U])} {_or([b[x] for x in R])}) {self._at_most_one([b[x] for x in group])})",
                    )
            for ma, on_a, x in adds.get(r.name, []):
                limits.check_time("encoding")
                for mb, on_b, y in removes.get(r.name, []):
                    if ma != mb:
                        eq = self._sym_eq(x, y)
                        if eq != "false":
                            self.add(None, f"(not {_and([on_a, on_b, eq])})")

    def _at_most_one(self, bools: list[str]) -> str:
        """At most one of ``bools``, as a Boolean formula: pairwise for a few, else a ladder
        (sequential counter) over prefix-disjunction variables — O(n), pure SAT, which every
        solver handles far better than a sum of if-then-elses over many Booleans."""
        if len(bools) <= 1:
            return "true"
        if len(bools) <= 4:
            return _and([f"(not (and {x} {y}))" for i, x in enumerate(bools) for y in bools[i + 1 :]])
        prefix = bools[0]
        parts = []
        for x in bools[1:-1]:
            parts.append(f"(not (and {x} {prefix}))")
            q = self.script.declare(f"amo.{len(self.script.decls)}", SmtSort.BOOL)
            self.add(None, f"(= {q} (or {x} {prefix}))")
            prefix = q
        parts.append(f"(not (and {bools[-1]} {prefix}))")
        return _and(parts)

    # ------------------------------------------------------------------ goal, uses
    def goal_constraints(self, t: int, goal: tuple[ir.Literal, ...] | None = None) -> list[tuple[str, str]]:
        """The goal (the problem's, or ``goal``) at state ``t``."""
        out: list[tuple[str, str]] = []
        for lit in self.inst.problem.goal if goal is None else goal:
            ctx = _Ctx(t, {}, [])
            body = self._literal(lit, ctx)
            out.append((lit.label, _and([body] + ctx.guards)))
        return out

    def _literal(self, lit: ir.Literal, ctx: _Ctx) -> str:
        """A labelled literal, weakened by its slack when it has one:
        (>= a b) → (>= (+ a δ) b) and (<= a b) → (<= a (+ b δ)) (likewise > and <)."""
        delta = self.slack.get(lit.label)
        e = lit.expr
        if delta is None or not isinstance(e, ir.Compare) or e.op is ir.CmpOp.EQ:
            return _text(self.term(e, ctx))
        both = ir.REAL if ir.REAL in (e.left.sort, e.right.sort) else ir.INT
        left = self._as(self.term(e.left, ctx), e.left.sort, both)
        right = self._as(self.term(e.right, ctx), e.right.sort, both)
        if e.op in (ir.CmpOp.GE, ir.CmpOp.GT):
            left = f"(+ {left} {delta})"
        else:
            right = f"(+ {right} {delta})"
        return f"({e.op.value} {left} {right})"

    def unroll(self, k: int) -> None:
        """Encode the whole horizon: steps up to ``k``, then the goal at state ``k`` and the
        use limits over those steps (idle steps allowed, so shorter compositions count)."""
        while len(self.act) < k:
            self.add_step()
        for label, c in self.goal_constraints(k) + self.uses_constraints(k):
            self.add(label, c)

    def at_state(self, e: ir.Expr, t: int) -> Term:
        """An expression over the resources of state ``t`` (e.g. a soft constraint at the end)."""
        return self.term(e, _Ctx(t, {}, []))

    def uses_constraints(self, steps: int) -> list[tuple[str, str]]:
        out: list[tuple[str, str]] = []
        for m in self.morphisms:
            if m.uses is not None and steps > m.uses:
                out.append((m.uses_label, at_most([self.act[t][m.name] for t in range(steps)], m.uses)))
        return out

    # ------------------------------------------------------------------ expressions
    def term(self, e: ir.Expr | Encoded, ctx: _Ctx) -> Term:
        match e:
            case ir.Const():
                return self._const(e, ctx)
            case ir.ResourceRef():
                return self._resource(e, ctx)
            case ir.ParamRef():
                return self._param(e, ctx)
            case ir.SetLit():
                return self._setlit(e, ctx)
            case ir.Arith():
                return self._arith(e, ctx)
            case ir.Compare():
                return self._compare(e, ctx)
            case ir.BoolOp():
                return self._boolop(e, ctx)
            case ir.Ite():
                return self._ite(e, ctx)
            case ir.Member():
                return self._member(e, ctx)
            case Encoded():
                return e.text
            case ir.TotalChurn() | ir.TotalCost() | ir.Uses() | ir.ParamValue():
                raise ValueError(f"{type(e).__name__} is a term of objectives only (Encoder.objective)")
            case _:
                assert_never(e)

    def _const(self, e: ir.Const, ctx: _Ctx) -> Term:
        v = e.value
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return self.finite.universe(e.sort).index(v)
        return int_literal(v.numerator) if e.sort.kind is SortKind.INT else real_literal(v)

    def _resource(self, e: ir.ResourceRef, ctx: _Ctx) -> Term:
        if ctx.state is not None:
            return ctx.state[e.name]
        return self.states[ctx.t][e.name]

    def _param(self, e: ir.ParamRef, ctx: _Ctx) -> Term:
        return ctx.params[e.name]

    def _setlit(self, e: ir.SetLit, ctx: _Ctx) -> Term:
        assert e.sort.element is not None  # a set sort's element sort
        u = self.finite.universe(e.sort.element)
        elems = [self.term(x, ctx) for x in e.elements]
        return {i: _or([self._sym_eq(x, i) for x in elems]) for i in range(len(u))}

    def _as(self, text: Term, have: ir.Sort, want: ir.Sort) -> Term:
        """Coerce an Int-sorted term where a Real is expected."""
        if want.kind is SortKind.REAL and have.kind is SortKind.INT:
            return f"(to_real {text})"
        return text

    def _arith(self, e: ir.Arith, ctx: _Ctx) -> str:
        want = e.sort
        args = [
            _text(self._as(self.term(a, ctx), a.sort, want if e.op is not ir.ArithOp.DIV else ir.REAL)) for a in e.args
        ]
        op = e.op
        if op is ir.ArithOp.ADD:
            return args[0] if len(args) == 1 else f"(+ {' '.join(args)})"
        if op is ir.ArithOp.SUB:
            return f"(- {' '.join(args)})"
        if op is ir.ArithOp.MUL:
            return args[0] if len(args) == 1 else f"(* {' '.join(args)})"
        if op is ir.ArithOp.DIV:
            num, den = args
            if not isinstance(e.args[1], ir.Const):
                ctx.guards.append(f"(not (= {den} 0.0))")
            return f"(/ {num} {den})"
        cmp = "<=" if op is ir.ArithOp.MIN else ">="
        out = args[0]
        for a in args[1:]:
            out = f"(ite ({cmp} {out} {a}) {out} {a})"
        return out

    def _compare(self, e: ir.Compare, ctx: _Ctx) -> str:
        left, right = self.term(e.left, ctx), self.term(e.right, ctx)
        if e.left.sort.is_numeric:
            both = ir.REAL if ir.REAL in (e.left.sort, e.right.sort) else ir.INT
            left, right = self._as(left, e.left.sort, both), self._as(right, e.right.sort, both)
        if e.op is ir.CmpOp.EQ:
            return self._equal(left, right)
        return f"({e.op.value} {left} {right})"

    def _boolop(self, e: ir.BoolOp, ctx: _Ctx) -> str:
        args = [_text(self.term(a, ctx)) for a in e.args]
        op = e.op
        if op is ir.BoolOpKind.AND:
            return _and(args)
        if op is ir.BoolOpKind.OR:
            return _or(args)
        if op is ir.BoolOpKind.NOT:
            return f"(not {args[0]})"
        return f"(=> {args[0]} {args[1]})"

    def _ite(self, e: ir.Ite, ctx: _Ctx) -> Term:
        c = self.term(e.cond, ctx)
        a = self._as(self.term(e.then, ctx), e.then.sort, e.sort)
        b = self._as(self.term(e.orelse, ctx), e.orelse.sort, e.sort)
        if isinstance(a, dict):
            assert isinstance(b, dict)  # both branches are sets
            return {i: f"(ite {c} {a[i]} {b[i]})" for i in a}
        return f"(ite {c} {a} {b})"

    def _member(self, e: ir.Member, ctx: _Ctx) -> str:
        x, s = self.term(e.element, ctx), self.term(e.set, ctx)
        assert isinstance(s, dict)
        if isinstance(x, int):
            return s.get(x, "false")
        return _or([f"(and (= {x} {i}) {v})" for i, v in s.items()])

    # ------------------------------------------------------------------ helpers
    @staticmethod
    def _sym_eq(a: Term, b: Term) -> str:
        if isinstance(a, int) and isinstance(b, int):
            return "true" if a == b else "false"
        return f"(= {a} {b})"

    def same_state(self, i: int, j: int) -> str:
        """States ``i`` and ``j`` are equal: on every written resource (the others are one
        variable in every state)."""
        return _and(
            [
                self._equal(self.states[i][r.name], self.states[j][r.name])
                for r in self.resources
                if r.name in self.written
            ]
        )

    def _equal(self, a: Term, b: Term) -> str:
        if isinstance(a, dict):
            assert isinstance(b, dict)  # both sides are sets
            return _and([f"(= {a[i]} {b[i]})" for i in a])
        if isinstance(a, int) or isinstance(b, int):
            return self._sym_eq(a, b)
        return f"(= {a} {b})"

    # ------------------------------------------------------------------ objective terms
    def objective(self, e: ir.Expr, steps: int) -> str:
        """An objective term over a composition of ``steps`` steps, as Real-sorted text."""
        return _text(self._as(self._objective(e, steps), e.sort, ir.REAL))

    def churn_literals(self, steps: int) -> list[tuple[str, Fraction]]:
        """The churn of a composition of ``steps`` steps as (changed, weight) pairs: a deployed
        component left unused, or a new one used (``total-churn`` is the sum of the weights of
        the true ones); components that cannot change are left out."""
        deployed = set(self.inst.problem.deployed)
        out: list[tuple[str, Fraction]] = []
        for m in self.morphisms:
            used = _or([self.act[t][m.name] for t in range(steps)])
            changed = f"(not {used})" if m.name in deployed else used
            if changed != "false":
                out.append((changed, m.churn))
        return out

    def _objective(self, e: ir.Expr, steps: int) -> Term:
        match e:
            case ir.TotalCost():
                acts = [(t, m) for t in range(steps) for m in self.morphisms]
                terms = [f"(ite {self.act[t][m.name]} {self._cost(m, t)} 0.0)" for t, m in acts]
                return f"(+ 0.0 {' '.join(terms)})" if terms else "0.0"
            case ir.TotalChurn():
                terms = [f"(ite {changed} {real_literal(w)} 0.0)" for changed, w in self.churn_literals(steps)]
                return f"(+ 0.0 {' '.join(terms)})" if terms else "0.0"
            case ir.Uses():
                terms = [f"(ite {self.act[t][e.morphism]} 1 0)" for t in range(steps)]
                return f"(+ 0 {' '.join(terms)})" if terms else "0"
            case ir.ParamValue():
                if (e.morphism, e.param) in self.fixed:
                    return self.fixed[(e.morphism, e.param)]
                out = "0.0" if e.sort.kind is SortKind.REAL else "0"
                for t in range(steps):
                    out = f"(ite {self.act[t][e.morphism]} {self.theta[t][(e.morphism, e.param)]} {out})"
                return out
            case ir.Arith():
                args = tuple(Encoded(self._objective(a, steps), a.sort) for a in e.args)
                # an Encoded stands in for an expression (``term`` matches it to its text)
                return self._arith(ir.Arith(e.op, args, e.sort), _Ctx(steps, {}, []))  # type: ignore[arg-type]
            case ir.Ite():
                parts = [Encoded(self._objective(x, steps), x.sort) for x in (e.cond, e.then, e.orelse)]
                # as above: Encoded parts stand in for expressions
                return self._ite(ir.Ite(parts[0], parts[1], parts[2], e.sort), _Ctx(steps, {}, []))  # type: ignore[arg-type]
            case ir.Const() | ir.ResourceRef() | ir.ParamRef() | ir.SetLit() | ir.Compare() | ir.BoolOp() | ir.Member():
                return self.term(e, _Ctx(steps, {}, []))
            case _:
                assert_never(e)

    def _cost(self, m: ir.Morphism, t: int) -> str:
        if m.cost is None:
            return "1.0"
        params = {p.name: self.theta[t][(m.name, p.name)] for p in m.params}
        return _text(self._as(self.term(m.cost, _Ctx(t, params, [])), m.cost.sort, ir.REAL))


class Encoded(Record):
    """An already-encoded term placed inside an IR node (objective arithmetic)."""

    __slots__ = ("text", "sort")
    text: Term
    sort: ir.Sort

    def __init__(self, text: Term, sort: ir.Sort) -> None:
        set_field(self, "text", text)
        set_field(self, "sort", sort)
