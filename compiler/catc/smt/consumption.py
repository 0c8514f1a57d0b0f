"""A horizon-free consumption abstraction: which components a composition uses, in which
order they first fire, and what they consume in total (issue 24).

Catalogs with competing alternatives fail *combinatorially*: every single alternative is
affordable, but no choice of one alternative per capability fits the budget (or the power,
RAM, GPU memory) together.  Relaxed reachability cannot see that, and the step encoding
proves it only by exhausting orderings at every horizon.  This abstraction forgets the
steps: a Boolean ``u_m`` per morphism (used at least once), an integer rank per morphism
(the step of its first firing), and per numeric resource one sum.  Its constraints, each
guarded by the indicator of the source label it comes from:

* a used morphism's positive facts (a Boolean resource, or a constant member of a set) hold
  initially or are given by a used provider of smaller rank (``pre/m/i``, ``init/r``,
  ``eff/p/j``); a goal's facts hold initially or are given by a used provider (``goal/i``);
* a numeric resource whose every effect is a decrease by a non-negative amount (a constant,
  or a parameter whose lower bound ``bound/m/p`` is non-negative) and which has a lower bound
  ``lo`` (``bounds/r``) starting at ``v`` (``init/r``): the decreases of the used morphisms
  sum to at most ``v - lo`` (``eff/m/i``);
* a use limit of 0 keeps a morphism unused (``uses/m``).

Every composition of any length satisfying a set of labels gives a model of the abstraction
for the same labels (deletes, negative and numeric preconditions are forgotten: the
abstraction only says less), so an UNSAT answer here — and its core — holds for every
horizon.  Its cores are not always irreducible for the full semantics (the step encoding
sees more): :mod:`catc.queries.cores` checks each member there.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Iterable, Sequence
from fractions import Fraction
from typing import Any

from catc import ir
from catc.smt.backend import DEFAULT_BACKEND, Backend, Check, open_backend
from catc.smt.script import SmtSort, Symbol, and_text, or_text, real_literal
from catgrammar import limits

Atom = tuple[str, str | None]
#: The most time relax's lower bound gives the solver (the h_max bound needs none).
OPTIMISE_SECONDS = 10.0  # (resource, element): element None for a Boolean resource


def _atoms(e: ir.Expr) -> list[Atom]:
    """The positive facts a condition needs (others are forgotten)."""
    if isinstance(e, ir.ResourceRef) and e.sort.kind is ir.SortKind.BOOL:
        return [(e.name, None)]
    if isinstance(e, ir.Member) and isinstance(e.set, ir.ResourceRef) and isinstance(e.element, ir.Const):
        return [(e.set.name, str(e.element.value))]
    if isinstance(e, ir.BoolOp) and e.op is ir.BoolOpKind.AND:
        return [a for x in e.args for a in _atoms(x)]
    return []


def _holds(init: ir.InitValue, atom: Atom) -> bool:
    """Whether the fact holds in the initial value ``init`` (an open set literal: it may)."""
    v = init.value
    if atom[1] is None:
        return isinstance(v, ir.Const) and v.value is not False
    if isinstance(v, ir.SetLit):
        return any(not isinstance(x, ir.Const) or str(x.value) == atom[1] for x in v.elements)
    return True


def _givers(
    inst: ir.Instance,
) -> tuple[dict[Atom, list[tuple[str, str | None]]], dict[str, list[tuple[str, str | None]]]]:
    """Who gives each fact (a Boolean set true, a constant added to a set), and who adds a θ
    element to each set resource (any element); the label slot is None (unconditional)."""
    providers: dict[Atom, list[tuple[str, str | None]]] = {}
    wildcard: dict[str, list[tuple[str, str | None]]] = {}
    for m in inst.morphisms.values():
        for eff in m.effects:
            res = inst.resources.get(eff.resource)
            if res is None or res.sort.is_numeric:
                continue
            if res.sort.kind is ir.SortKind.BOOL and eff.kind is ir.EffectKind.ASSIGN:
                if not (isinstance(eff.value, ir.Const) and eff.value.value is False):
                    providers.setdefault((eff.resource, None), []).append((m.name, None))
            elif eff.kind is ir.EffectKind.ADD:
                if isinstance(eff.value, ir.Const):
                    providers.setdefault((eff.resource, str(eff.value.value)), []).append((m.name, None))
                else:
                    wildcard.setdefault(eff.resource, []).append((m.name, None))
    return providers, wildcard


class Consumption:
    """The abstraction of one instance (see the module docstring); ``labels`` are the labels
    it can assume, ``known`` (default: all) the labels the caller asks about — a label the
    caller does not know is enforced always."""

    def __init__(
        self,
        inst: ir.Instance,
        components: Collection[str] | None = None,
        known: Iterable[str] | None = None,
        slack: dict[str, Symbol] | None = None,
        backend: str = DEFAULT_BACKEND,
        optimize: bool = False,
    ) -> None:
        self.inst = inst
        self.known = None if known is None else set(known)
        self.indicator: dict[str, Symbol] = {}
        decls: list[Symbol] = []
        asserts: list[str] = []
        morphisms = list(inst.morphisms.values())
        fixed = None if components is None else set(components)
        used = {m.name: Symbol(f"u:{m.name}", SmtSort.BOOL) for m in morphisms}
        rank = {m.name: Symbol(f"rank:{m.name}", SmtSort.INT) for m in morphisms}
        decls += list(used.values()) + list(rank.values())
        asserts += [f"(>= {r} 0)" for r in rank.values()]
        if fixed is not None:
            asserts += [used[m] if m in fixed else f"(not {used[m]})" for m in used]

        def on(label: str) -> str:
            if self.known is not None and label not in self.known:
                return "true"
            sym = self.indicator.get(label)
            if sym is None:
                sym = self.indicator[label] = Symbol(f"A:{label}", SmtSort.BOOL)
                decls.append(sym)
            return sym

        # a used giver gives whether its effect's label is enforced or not (a dropped effect
        # may or may not happen — the encoder's tracking semantics)
        providers, wildcard = _givers(inst)

        def initially(atom: Atom) -> str:
            init = inst.problem.init.get(atom[0])
            if init is None or _holds(init, atom):
                return "true"
            return f"(not {on(init.label)})"

        def support(atom: Atom, before: str | None) -> str:
            options = [initially(atom)]
            for p, label in providers.get(atom, []) + wildcard.get(atom[0], []):
                if p == before:
                    continue
                order = [] if before is None else [f"(< {rank[p]} {rank[before]})"]
                free = [] if label is None else [f"(not {on(label)})"]
                options.append(and_text([used[p], *free, *order]))
            return or_text(options)

        self.providers, self.wildcard, self.rank = providers, wildcard, rank
        self.needs: dict[str, list[tuple[str, list[Atom]]]] = {}
        self.goal_needs = [(lit.label, _atoms(lit.expr)) for lit in inst.problem.goal]
        for m in morphisms:
            for lit in m.pre:
                atoms = _atoms(lit.expr)
                self.needs.setdefault(m.name, []).append((lit.label, atoms))
                if atoms:
                    need = and_text([support(a, m.name) for a in atoms])
                    asserts.append(f"(=> (and {used[m.name]} {on(lit.label)}) {need})")
            if m.uses == 0:
                asserts.append(f"(=> {on(f'uses/{m.name}')} (not {used[m.name]}))")
        for lit in inst.problem.goal:
            atoms = _atoms(lit.expr)
            if atoms:
                asserts.append(f"(=> {on(lit.label)} {and_text([support(a, None) for a in atoms])})")
        self.resources: list[str] = []
        for name, res in inst.resources.items():
            texts = self._sum(inst, name, res, used, rank, on, slack)
            if texts:
                asserts += texts
                self.resources.append(name)
        self.used = used
        self.backend: Backend = open_backend(backend, optimize=optimize)
        self.backend.add([*(slack or {}).values(), *decls], [(None, a) for a in asserts])
        self.declarations, self.assertions = [*(slack or {}).values(), *decls], asserts  # a certificate's text
        self._label_of = {s: label for label, s in self.indicator.items()}
        self.checks = 0

    @staticmethod
    def _sum(
        inst: ir.Instance,
        name: str,
        res: ir.Resource,
        used: dict[str, Symbol],
        rank: dict[str, Symbol],
        on: Callable[[str], str],
        slack: dict[str, Symbol] | None,
    ) -> list[str]:
        """The total-consumption constraints of one numeric resource (none: not modelled):
        the sum over every used consumer, and — when some consumer's amount is a θ whose
        bound may be dropped (it could give the resource back) — the sum up to each
        consumer's first firing (ranks), since the bound holds in every state."""
        init = inst.problem.init.get(name)
        if not res.sort.is_numeric or res.lower is None or init is None or not isinstance(init.value, ir.Const):
            return []
        consumers: list[tuple[str, Fraction, str, str | None]] = []  # morphism, amount, label, θ bound
        for m in inst.morphisms.values():
            for eff in m.effects:
                if eff.resource != name:
                    continue
                if eff.kind is not ir.EffectKind.DECREASE:
                    return []
                v = eff.value
                if isinstance(v, ir.Const) and isinstance(v.value, Fraction | int) and v.value >= 0:
                    consumers.append((m.name, Fraction(v.value), eff.label, None))
                elif isinstance(v, ir.ParamRef):
                    p = next((p for p in m.params if p.name == v.name), None)
                    if p is None or p.lower is None or p.lower < 0:
                        return []
                    consumers.append((m.name, Fraction(p.lower), eff.label, f"bound/{m.name}/{p.name}"))
                else:
                    return []
        if not any(amount for _, amount, _, _ in consumers):
            return []
        room = real_literal(Fraction(init.value.value) - res.lower)
        if slack and init.label in slack:
            room = f"(+ {room} {slack[init.label]})"
        base = [on(init.label), on(f"bounds/{name}")]

        def constraint(upto: str | None) -> str:
            """The sum of the consumers first firing no later than ``upto`` (None: all)."""
            guards, terms = list(base), []
            for m, amount, label, bound in consumers:
                when = [] if upto is None else [f"(<= {rank[m]} {rank[upto]})"]
                if bound is not None:  # without its bound the θ may be negative: no claim then
                    guards.append(or_text([f"(not {used[m]})", on(bound), *(f"(not {w})" for w in when)]))
                if amount:  # dropped, the decrease may or may not happen: at least 0
                    terms.append(f"(ite {and_text([used[m], on(label), *when])} {real_literal(amount)} 0.0)")
            if upto is not None:
                guards.append(used[upto])
            return f"(=> {and_text(guards)} (<= (+ 0.0 {' '.join(terms)}) {room}))"

        out = [constraint(None)]
        if any(bound is not None and on(bound) != "true" for _, _, _, bound in consumers):  # a droppable θ bound
            out += [constraint(m) for m in dict.fromkeys(m for m, _, _, _ in consumers)]
        return out

    @property
    def labels(self) -> list[str]:
        return list(self.indicator)

    def check(self, labels: Iterable[str], timeout: float | None = None) -> tuple[Check, list[str]]:
        """Satisfiability with exactly ``labels`` enforced (of those it knows); on UNSAT a
        core among them."""
        wanted = [label for label in labels if label in self.indicator]
        if timeout is not None:
            self.backend.set_timeout(timeout)
        self.checks += 1
        r = self.backend.check([self.indicator[label] for label in wanted])
        if r is Check.UNSAT:
            core = {self._label_of[s] for s in self.backend.core() if s in self._label_of}
            return r, [label for label in wanted if label in core]
        return r, []

    def support(self, labels: Collection[str]) -> list[str] | None:
        """After a SAT :meth:`check` of ``labels``: the morphisms the model uses to support the
        goal (each fact from the used provider of least rank), in rank order — a candidate
        composition for :func:`catc.semantics.witness.witnessed`; None when the model has none."""
        b = self.backend
        if not b.has_model():
            return None
        enforced = set(labels)

        def on(label: str) -> bool:
            return label in enforced or label not in self.indicator

        def holds(atom: Atom) -> bool:
            init = self.inst.problem.init.get(atom[0])
            return init is None or not on(init.label) or _holds(init, atom)

        used = {m for m, u in self.used.items() if b.value(u) is True}
        extra: list[tuple[Atom, str | None]] = []
        rank = {m: b.value(self.rank[m]) for m in used}
        chosen: dict[str, None] = {}
        for m in sorted(used, key=lambda x: rank[x]):  # a θ without its bound may give a resource back
            if any(p.sort.is_numeric and not on(f"bound/{m}/{p.name}") for p in self.inst.morphisms[m].params):
                chosen[m] = None
                todo_extra = [(a, m) for label, atoms in self.needs.get(m, []) if on(label) for a in atoms]
                extra.extend(todo_extra)
        todo: list[tuple[Atom, str | None]] = [
            (a, None) for label, atoms in self.goal_needs if on(label) for a in atoms
        ] + extra
        while todo:
            atom, before = todo.pop()
            if holds(atom):
                continue
            offers = self.providers.get(atom, []) + self.wildcard.get(atom[0], [])
            options = [
                p
                for p, label in offers
                if p in used
                and (label is None or not on(label))
                and p != before
                and (before is None or rank[p] < rank[before])
            ]
            if not options:
                return None
            p = min(options, key=lambda x: rank[x])
            if p in chosen:
                continue
            chosen[p] = None
            todo += [(a, p) for label, atoms in self.needs.get(p, []) if on(label) for a in atoms]
        return sorted(chosen, key=lambda m: rank[m])

    def irreducible(self, labels: Sequence[str], timeout: float | None = None) -> list[str] | None:
        """An irreducible core of ``labels`` for the abstraction (None when they are
        satisfiable or a check gives up): deletion on this one incremental solver, each
        UNSAT answer's core replacing the candidate (clause-set refinement)."""
        r, core = self.check(labels, timeout)
        if r is not Check.UNSAT:
            return None
        i = 0
        while i < len(core):
            r, smaller = self.check(core[:i] + core[i + 1 :], timeout)
            if r is Check.UNSAT:
                core = smaller
            elif r is Check.SAT:
                i += 1
            else:
                return None
        return core


def refutes(inst: ir.Instance, timeout: float | None = None) -> list[str] | None:
    """An irreducible core of the abstraction with every label enforced (None: it cannot
    show the instance infeasible)."""
    a = Consumption(inst)
    return a.irreducible(a.labels, timeout)


def least_slack(
    inst: ir.Instance,
    reqs: Sequence[tuple[str, str, Fraction]],
    components: Collection[str] | None = None,
    timeout: float | None = None,
) -> Fraction | bool | None:
    """A lower bound on the least weighted relaxation of ``reqs`` ((label, kind, weight)):
    the least weighted raise of the initial values that lets the abstraction hold with every
    label enforced.  False: no relaxation of ``reqs`` can restore it; None: unknown.

    Sound because the abstraction forgets every precondition and goal comparison (relaxing
    them is free here) and lowering an initial value never helps a consumption sum."""
    weights = {label: w for label, _, w in reqs}
    quick = _quick_bound(inst, weights) if components is None else Fraction(0)
    if quick is None:
        return False  # cannot be raised: no relaxation of reqs restores it
    slack = {label: Symbol(f"slack:{label}", SmtSort.REAL) for label, kind, _ in reqs if kind == "initial value"}
    a = Consumption(inst, components, slack=slack, optimize=True)
    opt = a.backend
    for s in slack.values():
        opt.assert_term(f"(>= {s} 0.0)")
    for sym in a.indicator.values():
        opt.assert_term(sym)
    cost = "(+ 0.0 " + " ".join(f"(* {real_literal(weights[label])} {s})" for label, s in slack.items()) + ")"
    handle = opt.minimize(opt.intern(cost))
    opt.set_timeout(min(timeout, OPTIMISE_SECONDS) if timeout is not None else OPTIMISE_SECONDS)
    r = opt.check()
    if r is Check.UNSAT:
        return False
    bound = opt.bound(handle) if r is Check.SAT else None
    exact = bound.value if bound is not None and bound.exact and bound.infinite == 0 else None
    if exact is None:
        return quick if quick > 0 else None
    return max(exact, quick)


def _quick_bound(inst: ir.Instance, weights: dict[str, Fraction]) -> Fraction | None:
    """:func:`least_slack`'s bound without a solver (None: no raise of ``weights``' labels
    restores the instance)."""
    quick: Fraction | None = Fraction(0)  # each resource short of its least consumption needs its own raise
    for name, least in least_consumption(inst).items():
        short = least - room(inst, name)
        if short > 0 and quick is not None:
            label = inst.problem.init[name].label
            quick = None if label not in weights else quick + weights[label] * short
    # least_consumption leaves out the morphisms that alone take more than there is: a
    # restoration may instead raise what one of them needs (issue 24: a bound, not the least)
    escape = _cheapest_overdraw(inst, weights)
    if escape is not None:
        quick = escape if quick is None else min(quick, escape)
    return quick


def _cheapest_overdraw(inst: ir.Instance, weights: dict[str, Fraction]) -> Fraction | None:
    """The least weighted raise of initial values that lets some morphism that alone takes
    more of a resource than there is fire once (None: no such morphism can be let fire)."""
    excess: dict[str, Fraction | None] = {}
    for name, res in inst.resources.items():
        init = inst.problem.init.get(name)
        if not res.sort.is_numeric or res.lower is None or init is None or not isinstance(init.value, ir.Const):
            continue
        for m, amount in (_amounts(inst, name) or {}).items():
            gap = amount - room(inst, name)
            if gap > 0 and excess.get(m, Fraction(0)) is not None:
                w = weights.get(init.label)
                excess[m] = None if w is None else excess.get(m, Fraction(0)) + w * gap  # type: ignore[operator]
    costs = [c for c in excess.values() if c is not None]
    return min(costs) if costs else None


def consumption_bound(
    inst: ir.Instance, reqs: Sequence[Any], components: Collection[str] | None = None
) -> Fraction | bool | None:
    """:func:`least_slack` for relax's requirements (objects with label, kind and weight)."""
    return least_slack(inst, [(r.label, r.kind, r.weight) for r in reqs], components, limits.for_check())


def stronger_bound(lower: Fraction | bool | None, mine: Fraction | bool | None) -> Fraction | bool | None:
    """The stronger of two lower bounds (a Fraction; False: no relaxation restores it; None:
    unknown)."""
    if lower is False or mine is False:
        return False
    if not isinstance(mine, Fraction):
        return lower
    return mine if not isinstance(lower, Fraction) or mine > lower else lower


#: How an answer names this module's refutations (:attr:`Refutation.by`).
BY = "a consumption bound (what every composition reaching the goal must take)"


def bound_refutation(inst: ir.Instance) -> Any:
    """A :class:`~catc.semantics.relaxed.Refutation` when some resource's initial room is
    below :func:`least_consumption` (no solver), else None."""
    from catc.semantics.relaxed import Refutation

    for name, least in least_consumption(inst).items():
        if least > room(inst, name):
            return Refutation(
                f"the initial {name} cannot cover the least any composition reaching the goal takes from it "
                f"({least} over the cheapest alternative per needed capability)",
                inst.problem.init[name].label,
                BY,
            )
    return None


def consumption_proof(inst: ir.Instance) -> Any:
    """A :class:`~catc.semantics.relaxed.Refutation` when the abstraction shows that no
    composition of any length exists (None otherwise), naming an initial value of its core
    when there is one (the budget, power, RAM... that cannot cover any composition)."""
    from catc.semantics.relaxed import Refutation

    proof = bound_refutation(inst)
    if proof is not None:
        return proof
    a = Consumption(inst)
    if not a.labels:
        return None
    r, core = a.check(a.labels, limits.for_check())
    if r is not Check.UNSAT:
        return None
    inits = [label for label in core if label.startswith("init/") and label[5:] in a.resources]
    label = inits[0] if inits else next((x for x in core if x.startswith("goal/")), None)
    what = f"the initial {label[5:]}" if inits and label else "the goal's facts"
    return Refutation(
        f"{what} cannot be met by any choice of components: the least total consumption of the "
        "alternatives that reach the goal exceeds what there is",
        label,
        BY,
    )


def least_length(inst: ir.Instance) -> int:
    """A lower bound on the number of steps of any composition reaching the goal: the h_max
    level of the goal's facts (each fact's level is 0 when it holds initially, else one more
    than the least, over its givers, of the greatest level among the giver's facts), with
    deletes, numeric conditions and θ-dependent facts forgotten.  A morphism that alone takes
    more of a bounded, only-decreasing resource than there is never fires and gives nothing
    (:func:`overdrawing`).  0 when it cannot tell."""
    given, any_element = _givers(inst)
    never = overdrawing(inst)
    givers = {a: [m for m, _ in ms if m not in never] for a, ms in given.items()}
    anything = {r: [m for m, _ in ms if m not in never] for r, ms in any_element.items()}
    needs = {m.name: [a for lit in m.pre for a in _atoms(lit.expr)] for m in inst.morphisms.values()}

    def initially(atom: Atom) -> bool:
        init = inst.problem.init.get(atom[0])
        return init is None or _holds(init, atom)

    level: dict[Atom, int] = {}
    atoms = set(givers) | {a for ns in needs.values() for a in ns}
    atoms |= {a for lit in inst.problem.goal for a in _atoms(lit.expr)}
    for a in atoms:
        if initially(a):
            level[a] = 0
    fired: dict[str, int] = {}
    changed = True
    while changed:  # Bellman-Ford style: levels only go down, at most |morphisms| rounds
        changed = False
        for name, ns in needs.items():
            if any(a not in level for a in ns):
                continue
            at = 1 + max((level[a] for a in ns), default=0)
            if fired.get(name, at + 1) <= at:
                continue
            fired[name] = at
            changed = True
        for a in atoms:
            offers = givers.get(a, []) + (anything.get(a[0], []) if a[1] is not None else [])
            best = min((fired[g] for g in offers if g in fired), default=None)
            if best is not None and best < level.get(a, best + 1):
                level[a] = best
                changed = True
    goal = [a for lit in inst.problem.goal for a in _atoms(lit.expr)]
    if any(a not in level for a in goal):
        return 0  # unreachable: the refutations say so; no bound claimed here
    return max((level[a] for a in goal), default=0)


def _amounts(inst: ir.Instance, name: str) -> dict[str, Fraction] | None:
    """The least amount each morphism takes from numeric resource ``name`` per firing, when
    every effect on it is a decrease by a constant or a θ with a non-negative lower bound
    (None otherwise: it may grow)."""
    out: dict[str, Fraction] = {}
    for m in inst.morphisms.values():
        for eff in m.effects:
            if eff.resource != name:
                continue
            v = eff.value
            if eff.kind is not ir.EffectKind.DECREASE:
                return None
            if isinstance(v, ir.Const) and isinstance(v.value, Fraction | int) and v.value >= 0:
                amount = Fraction(v.value)
            elif isinstance(v, ir.ParamRef):
                p = next((p for p in m.params if p.name == v.name), None)
                if p is None or p.lower is None or p.lower < 0:
                    return None
                amount = Fraction(p.lower)
            else:
                return None
            out[m.name] = out.get(m.name, Fraction(0)) + amount
    return out


def least_consumption(inst: ir.Instance) -> dict[str, Fraction]:
    """Per numeric resource that only decreases: a lower bound on what any composition
    reaching the goal takes from it — the h_max cost of the goal's facts, each fact costing
    0 when it holds initially, else the least over its givers of the giver's amount plus the
    greatest cost among the giver's facts (along such a chain the givers are distinct, so
    their amounts add up in every composition).  Polynomial, no solver: it sees the
    cheapest alternative per capability level of a chain, summed."""
    given, any_element = _givers(inst)
    needs = {m.name: [a for lit in m.pre for a in _atoms(lit.expr)] for m in inst.morphisms.values()}
    goal = [a for lit in inst.problem.goal for a in _atoms(lit.expr)]
    decreasing = _decreasing(inst)
    never = overdrawing(inst, decreasing)
    atoms = set(given) | {a for ns in needs.values() for a in ns} | set(goal)

    def goal_cost(amounts: dict[str, Fraction], excluded: set[str]) -> Fraction | None:
        cost = _atom_costs(inst, given, any_element, needs, atoms, amounts, excluded)
        return max((cost[a] for a in goal), default=Fraction(0)) if all(a in cost for a in goal) else None

    out: dict[str, Fraction] = {}
    for name, amounts in decreasing.items():
        # without the overdrawing morphisms, else (the goal then unreachable) with them all
        least = goal_cost(amounts, never)
        least = goal_cost(amounts, set()) if least is None else least
        if least is not None:
            out[name] = least
    return out


def _atom_costs(
    inst: ir.Instance,
    given: dict[Atom, list[tuple[str, str | None]]],
    any_element: dict[str, list[tuple[str, str | None]]],
    needs: dict[str, list[Atom]],
    atoms: Collection[Atom],
    amounts: dict[str, Fraction],
    excluded: Collection[str],
) -> dict[Atom, Fraction]:
    """The h_max cost of each reachable fact (:func:`least_consumption`) with the morphisms
    in ``excluded`` left out; an unreachable fact has none."""
    cost: dict[Atom, Fraction] = {}
    for a in atoms:
        start = inst.problem.init.get(a[0])
        if start is None or _holds(start, a):
            cost[a] = Fraction(0)
    changed = True
    while changed:  # costs only go down; each round settles one more giver at least
        changed = False
        for a in atoms:
            offers = [m for m, _ in given.get(a, []) + (any_element.get(a[0], []) if a[1] is not None else [])]
            for m in offers:
                if m in excluded or any(b not in cost for b in needs[m]):
                    continue
                c = amounts.get(m, Fraction(0)) + max((cost[b] for b in needs[m]), default=Fraction(0))
                if c < cost.get(a, c + 1):
                    cost[a] = c
                    changed = True
    return cost


class _GiveUp(Exception):
    pass


def cheapest_support(inst: ir.Instance, expansions: int = 20_000) -> list[str] | None:
    """A set of morphisms that supports the goal in the consumption abstraction — each fact
    a used morphism or the goal needs holds initially or is given by a used morphism that
    fires before — and whose total consumption of every bounded, only-decreasing resource
    fits its room, in an order they can fire (each fact given before it is needed); None
    when none was found within ``expansions`` tries (no claim: the solver decides).

    A depth-first search without a solver, deterministic: the open fact needed last is
    given by one of its givers, the cheapest first (least sum of amount / room), and a
    branch is cut when what it has spent plus the h_max cost (:func:`least_consumption`)
    of an open fact exceeds a resource's room.  On a chain of alternatives this bound is
    exact, and the search hardly backtracks.  Deletes, negative and numeric conditions are
    forgotten: the caller replays the result with the validator."""
    given, any_element = _givers(inst)
    decreasing = _decreasing(inst)
    never = overdrawing(inst, decreasing) | {m.name for m in inst.morphisms.values() if m.uses == 0}
    needs = {m.name: [a for lit in m.pre for a in _atoms(lit.expr)] for m in inst.morphisms.values()}
    goal = list(dict.fromkeys(a for lit in inst.problem.goal for a in _atoms(lit.expr)))
    atoms = set(given) | {a for ns in needs.values() for a in ns} | set(goal)
    rooms = {r: room(inst, r) for r in decreasing}
    costs = {r: _atom_costs(inst, given, any_element, needs, atoms, decreasing[r], never) for r in decreasing}

    def initially(a: Atom) -> bool:
        init = inst.problem.init.get(a[0])
        return init is None or _holds(init, a)

    offers = _offers(given, any_element, atoms, never, decreasing, rooms)
    spent = dict.fromkeys(decreasing, Fraction(0))
    chosen: list[str] = []
    gives: dict[Atom, int] = {}  # fact → how many chosen morphisms give it
    wild: dict[str, int] = {}  # set resource → how many chosen morphisms add any element
    left = [expansions]

    def given_now(a: Atom) -> bool:
        return initially(a) or gives.get(a, 0) > 0 or (a[1] is not None and wild.get(a[0], 0) > 0)

    gives_of, adds_of = _gifts(given, any_element)

    def mark(m: str, step: int) -> None:
        for a in gives_of.get(m, []):
            gives[a] = gives.get(a, 0) + step
        for r in adds_of.get(m, []):
            wild[r] = wild.get(r, 0) + step

    def dfs(open_: list[Atom], depth: int) -> bool:
        open_ = [a for a in open_ if not given_now(a)]
        if not open_:
            return True
        if not _may_fit(costs, spent, rooms, open_):
            return False
        if depth > 400:
            raise _GiveUp
        a = open_[-1]
        for m in offers.get(a, []):
            if m in chosen:
                continue
            left[0] -= 1
            if left[0] < 0:
                raise _GiveUp
            if any(spent[r] + amounts.get(m, Fraction(0)) > rooms[r] for r, amounts in decreasing.items()):
                continue
            for r, amounts in decreasing.items():
                spent[r] += amounts.get(m, Fraction(0))
            chosen.append(m)
            mark(m, 1)
            if dfs(open_[:-1] + list(dict.fromkeys(needs[m])), depth + 1):
                return True
            mark(m, -1)
            chosen.pop()
            for r, amounts in decreasing.items():
                spent[r] -= amounts.get(m, Fraction(0))
        return False

    try:
        if not dfs(list(reversed(goal)), 0):
            return None
    except _GiveUp:
        return None
    return _firing_order(list(reversed(chosen)), needs, initially, gives_of, adds_of)  # the deepest first


def _offers(
    given: dict[Atom, list[tuple[str, str | None]]],
    any_element: dict[str, list[tuple[str, str | None]]],
    atoms: Collection[Atom],
    never: Collection[str],
    decreasing: dict[str, dict[str, Fraction]],
    rooms: dict[str, Fraction],
) -> dict[Atom, list[str]]:
    """Per fact, its givers but ``never``, the cheapest first (least Σ amount / room; ties
    in declaration order)."""

    def weight(m: str) -> Fraction:
        return sum(
            (amounts.get(m, Fraction(0)) / rooms[r] for r, amounts in decreasing.items() if rooms[r] > 0),
            Fraction(0),
        )

    offers: dict[Atom, list[str]] = {}
    for a in atoms:
        ms = [m for m, _ in given.get(a, []) + (any_element.get(a[0], []) if a[1] is not None else [])]
        offers[a] = sorted(dict.fromkeys(m for m in ms if m not in never), key=weight)
    return offers


def _may_fit(
    costs: dict[str, dict[Atom, Fraction]],
    spent: dict[str, Fraction],
    rooms: dict[str, Fraction],
    open_: list[Atom],
) -> bool:
    """Whether what is spent plus each open fact's h_max cost stays within every room (an
    unreachable fact: no)."""
    for r, cost in costs.items():
        worst = Fraction(0)
        for a in open_:
            c = cost.get(a)
            if c is None:
                return False
            worst = max(worst, c)
        if spent[r] + worst > rooms[r]:
            return False
    return True


def _gifts(
    given: dict[Atom, list[tuple[str, str | None]]], any_element: dict[str, list[tuple[str, str | None]]]
) -> tuple[dict[str, list[Atom]], dict[str, list[str]]]:
    """Per morphism, the facts it gives, and the set resources it adds any element to."""
    gives_of: dict[str, list[Atom]] = {}
    for a, givers in given.items():
        for x, _ in givers:
            gives_of.setdefault(x, []).append(a)
    adds_of: dict[str, list[str]] = {}
    for r, adders in any_element.items():
        for x, _ in adders:
            adds_of.setdefault(x, []).append(r)
    return gives_of, adds_of


def _firing_order(
    pending: list[str],
    needs: dict[str, list[Atom]],
    initially: Callable[[Atom], bool],
    gives_of: dict[str, list[Atom]],
    adds_of: dict[str, list[str]],
) -> list[str] | None:
    """An order the ``pending`` morphisms can fire in by relaxed firing from the initial
    state, the first ready one of ``pending`` each time (None: a cyclic support)."""
    order: list[str] = []
    have: set[Atom] = set()
    anyset: set[str] = set()
    pending = list(pending)
    while pending:
        ready = next(
            (
                m
                for m in pending
                if all(initially(a) or a in have or (a[1] is not None and a[0] in anyset) for a in needs[m])
            ),
            None,
        )
        if ready is None:
            return None
        pending.remove(ready)
        order.append(ready)
        have.update(gives_of.get(ready, []))
        anyset.update(adds_of.get(ready, []))
    return order


def _decreasing(inst: ir.Instance) -> dict[str, dict[str, Fraction]]:
    """Per bounded numeric resource with a constant initial value that only decreases: the
    least amount each morphism takes from it per firing (:func:`_amounts`)."""
    out = {}
    for name, res in inst.resources.items():
        init = inst.problem.init.get(name)
        if not res.sort.is_numeric or res.lower is None or init is None or not isinstance(init.value, ir.Const):
            continue
        amounts = _amounts(inst, name)
        if amounts:
            out[name] = amounts
    return out


def overdrawing(inst: ir.Instance, decreasing: dict[str, dict[str, Fraction]] | None = None) -> set[str]:
    """The morphisms that alone take more of some bounded, only-decreasing resource than it
    has room for: they never fire (the bound holds in every state)."""
    decreasing = _decreasing(inst) if decreasing is None else decreasing
    return {m for name, amounts in decreasing.items() for m, a in amounts.items() if a > room(inst, name)}


def init_value(inst: ir.Instance, name: str) -> Fraction:
    """The constant initial value of numeric resource ``name``."""
    init = inst.problem.init[name]
    assert isinstance(init.value, ir.Const)
    return Fraction(init.value.value)


def room(inst: ir.Instance, name: str) -> Fraction:
    """How much resource ``name`` can lose: its initial value minus its lower bound."""
    init, res = inst.problem.init[name], inst.resources[name]
    assert isinstance(init.value, ir.Const) and res.lower is not None
    return Fraction(init.value.value) - res.lower


class FixedSet:
    """The consumption abstraction of one instance for a *given* set of components, every
    label enforced, without a solver: a set passes (:meth:`order`) when its components can
    fire in some order, each once, with every positive fact they and the goal need holding
    initially or given by one fired before, and their least amounts summing within every
    bounded, only-decreasing resource's room.  The component set of every composition
    passes, so a set that does not pass is the component set of no composition."""

    def __init__(self, inst: ir.Instance) -> None:
        self.inst = inst
        given, any_element = _givers(inst)
        self.decreasing = _decreasing(inst)
        self.rooms = {r: room(inst, r) for r in self.decreasing}
        self.needs = {m.name: [a for lit in m.pre for a in _atoms(lit.expr)] for m in inst.morphisms.values()}
        self.goal = [a for lit in inst.problem.goal for a in _atoms(lit.expr)]
        self.unusable = {m.name for m in inst.morphisms.values() if m.uses == 0}
        #: per morphism, its non-zero least amounts: (resource, amount)
        self.amounts: dict[str, list[tuple[str, Fraction]]] = {}
        for r, per in self.decreasing.items():
            for m, amount in per.items():
                if amount:
                    self.amounts.setdefault(m, []).append((r, amount))
        self.gives_of, self.adds_of = _gifts(given, any_element)

    def spent(self, components: Collection[str]) -> dict[str, Fraction]:
        """The least each only-decreasing resource loses when each component fires once."""
        return self.plus(dict.fromkeys(self.decreasing, Fraction(0)), components)

    def plus(self, spent: dict[str, Fraction], components: Iterable[str], sign: int = 1) -> dict[str, Fraction]:
        """``spent`` with the least amounts of ``components`` added (``sign`` -1: taken off)."""
        out = dict(spent)
        for m in components:
            for r, amount in self.amounts.get(m, ()):
                out[r] += amount if sign > 0 else -amount
        return out

    def fits(self, components: Collection[str], spent: dict[str, Fraction] | None = None) -> bool:
        spent = self.spent(components) if spent is None else spent
        return all(v <= self.rooms[r] for r, v in spent.items())

    def order(self, components: Collection[str], spent: dict[str, Fraction] | None = None) -> list[str] | None:
        """An order the set can fire in (None: it does not pass; see the class); ``spent``:
        :meth:`spent` of the set when the caller has it."""
        if any(m in self.unusable for m in components) or not self.fits(components, spent):
            return None
        inst = self.inst

        def holds(a: Atom) -> bool:
            init = inst.problem.init.get(a[0])
            return init is None or _holds(init, a) or a in have or (a[1] is not None and a[0] in anyset)

        have: set[Atom] = set()
        anyset: set[str] = set()
        pending = [m for m in inst.morphisms if m in components]  # declaration order
        out: list[str] = []
        while pending:
            ready = next((m for m in pending if all(holds(a) for a in self.needs[m])), None)
            if ready is None:
                return None
            pending.remove(ready)
            out.append(ready)
            have.update(self.gives_of.get(ready, []))
            anyset.update(self.adds_of.get(ready, []))
        return out if all(holds(a) for a in self.goal) else None


def least_restoration(
    inst: ir.Instance,
    reqs: Sequence[tuple[str, str, Fraction]],
    timeout: Callable[[], float | None] = lambda: None,
    prune: bool = True,
) -> tuple[Fraction, dict[str, Fraction], list[str]] | None:
    """The least weighted raise of the eligible initial values (``reqs``: (label, kind,
    weight)) that lets the whole catalog's abstraction hold with every label enforced —
    exact: a rational slack per initial value, and a bisection on the weighted total with
    one incremental solver (Z3's Optimize takes minutes on these sums), ended by a proof
    that no model costs less — with the raise per label of an optimal model and the
    morphisms that model uses to support the goal, in rank order
    (:meth:`Consumption.support`).  None: unknown (a check gave up; ``timeout`` gives each
    check its time), infeasible, or the model gives no support (issue 24).

    The total is a lower bound on every restoration (:func:`least_slack`); a composition of
    the support that the validator accepts on the raised instance is therefore least.
    ``prune`` keeps the :func:`dominated` morphisms unused, which leaves the optimum as it
    is (see there) and takes Z3 from over 30 s a check to seconds at n = 200–400."""
    weights = {label: w for label, kind, w in reqs if kind == "initial value"}
    slack = {label: Symbol(f"slack:{label}", SmtSort.REAL) for label in weights}
    a = Consumption(inst, slack=slack)
    b = a.backend
    for m in dominated(inst) if prune else ():  # never needed for the optimum (see there)
        b.assert_term(f"(not {a.used[m]})")
    for s in slack.values():
        b.assert_term(f"(>= {s} 0.0)")
    for sym in a.indicator.values():
        b.assert_term(sym)
    cost = "(+ 0.0 " + " ".join(f"(* {real_literal(weights[label])} {s})" for label, s in slack.items()) + ")"
    best: tuple[Fraction, dict[str, Fraction], list[str]] | None = None
    low = _quick_bound(inst, weights)  # no model costs less than low
    if low is None:
        return None
    while best is None or best[0] > low:
        b.push()
        if best is not None:  # halve the gap while it is wide, then ask for anything cheaper
            mid = (low + best[0]) / 2
            wide = best[0] - low > 1
            b.assert_term(f"(<= {cost} {real_literal(mid)})" if wide else f"(< {cost} {real_literal(best[0])})")
        b.set_timeout(timeout())
        r = b.check()
        if r is Check.SAT:  # the raise its support needs (the model's slack may be more)
            order = a.support(a.labels)
            values = None if order is None else _raise_for(inst, order, weights)
            if order is None or values is None:
                b.pop()
                return None
            best = (sum((weights[label] * v for label, v in values.items()), Fraction(0)), values, order)
        b.pop()
        if r is Check.UNKNOWN:
            return None
        if r is Check.UNSAT:
            if best is None or not wide:
                return best
            low = mid
    return best


def _raise_for(
    inst: ir.Instance, components: Collection[str], weights: dict[str, Fraction]
) -> dict[str, Fraction] | None:
    """The raise of each initial value that ``components``, each firing once at its least
    amounts, need (None: a resource they overdraw may not be raised)."""
    out: dict[str, Fraction] = {}
    for name, amounts in _decreasing(inst).items():
        need = sum((amounts.get(m, Fraction(0)) for m in components), Fraction(0)) - room(inst, name)
        if need > 0:
            label = inst.problem.init[name].label
            if label not in weights:
                return None
            out[label] = need
    return out


def dominated(inst: ir.Instance) -> set[str]:
    """The morphisms the abstraction with *every* label enforced never needs (issue 24):
    ``m`` is dominated by ``m2`` when ``m2`` may be used (its use limit is not 0), needs no
    fact ``m`` does not need, gives every fact ``m`` gives (each Boolean set true, each
    constant added to a set, any element added to a set), and takes no more than ``m`` of
    every bounded, only-decreasing resource (:func:`_decreasing`'s least amounts: those of
    the sums); of two that dominate each other the later in the catalog is the dominated one.

    Sound for every question about the optimum of the abstraction (its feasibility, and the
    least weighted slack on initial values of :func:`least_restoration`): every model with
    every label enforced gives a model of the same cost in which no dominated morphism is
    used.  Take ``m`` used and ``m2`` one that dominates it and is itself dominated by
    nobody (one exists: "dominates, and strictly or earlier in the catalog" is a strict
    partial order on a finite set).  Mark ``m`` unused and ``m2`` used at rank ``min(rank
    m, rank m2)`` (``rank m`` when ``m2`` was unused).  Then (a) ``m2``'s facts are
    supported: they are among ``m``'s, supported by givers of rank below ``rank m`` other
    than ``m`` — not ``m2`` itself, which had rank ``>= rank m`` if it was used, or by what
    supported ``m2`` before when its rank stays; (b) a fact ``m`` gave to a later morphism
    or the goal, ``m2`` gives at a rank no greater; (c) every resource sum only loses terms
    or has one amount replaced by a smaller one (with every θ bound enforced the prefix
    sums up to a rank are implied by the total, and they too only shrink); (d) the slack is
    unchanged, so the cost is.  Repeating this for each dominated morphism used ends in a
    model using none.  The optimum over the remaining morphisms is therefore the optimum of
    the whole catalog's abstraction, and so still a lower bound on every restoration.  It
    says nothing about the full semantics (numeric preconditions, deletes): a composition
    built from the remaining morphisms is still replayed by the validator."""
    givers, wildcard = _givers(inst)
    gives: dict[str, set[tuple[str, str | None, bool]]] = {m: set() for m in inst.morphisms}
    for atom, offers in givers.items():
        for m, _ in offers:
            gives[m].add((atom[0], atom[1], False))
    for name, offers in wildcard.items():
        for m, _ in offers:
            gives[m].add((name, None, True))
    needs = {m.name: {a for lit in m.pre for a in _atoms(lit.expr)} for m in inst.morphisms.values()}
    decreasing = _decreasing(inst)
    amount = {m: tuple(per.get(m, Fraction(0)) for per in decreasing.values()) for m in inst.morphisms}
    names = list(inst.morphisms)
    by_gift: dict[frozenset[tuple[str, str | None, bool]], list[str]] = {}
    for m in names:
        by_gift.setdefault(frozenset(gives[m]), []).append(m)

    def covers(m2: str, m: str) -> bool:  # m2 at least as good as m
        return (
            inst.morphisms[m2].uses != 0
            and needs[m2] <= needs[m]
            and gives[m2] >= gives[m]
            and all(x <= y for x, y in zip(amount[m2], amount[m], strict=True))
        )

    index = {m: i for i, m in enumerate(names)}
    out: set[str] = set()
    for m in names:
        for gift, group in by_gift.items():
            if not gift >= gives[m]:
                continue
            if any(m2 != m and covers(m2, m) and (not covers(m, m2) or index[m2] < index[m]) for m2 in group):
                out.add(m)
                break
    return out
