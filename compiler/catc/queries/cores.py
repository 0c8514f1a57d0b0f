"""Cores of catalog-scale infeasibility for diagnose (issue 24).

Global budget, power, RAM and GPU conflicts across competing alternatives are invisible to
relaxed reachability and cost the step encoding seconds per check.  The horizon-free
consumption abstraction (:mod:`catc.smt.consumption`) proves them in milliseconds on one
incremental solver with assumption literals; its irreducible core is a core of the full
semantics (the abstraction only says less), and diagnose's deletion pass then checks that
each member is needed in the full semantics — those checks are feasible ones, which the
relaxation's witness or the solver settle quickly — and shrinks further where the
abstraction was too weak.
"""

from __future__ import annotations

import heapq
import math
import time
from collections.abc import Callable, Collection, Iterable, Sequence
from fractions import Fraction
from itertools import chain
from typing import Protocol

from catc import ir
from catc.ir.labels import label_index
from catc.semantics.plan import Activation, Plan
from catc.semantics.validate import validate
from catc.semantics.witness import BIG, _candidate, _restricted
from catc.smt.backend import Check
from catc.smt.consumption import (
    Atom,
    Consumption,
    _atoms,
    _givers,
    _holds,
    cheapest_support,
    least_restoration,
    room,
)
from catgrammar import limits
from catgrammar.record import replace


class _Model(Protocol):
    inst: ir.Instance
    labels: list[str]
    components: tuple[str, ...] | None


class AbstractCores:
    """The abstraction of one labelled model, built on first use and kept for every test."""

    def __init__(self, model: _Model) -> None:
        self.model = model
        self._abstraction: Consumption | None = None
        self.found = 0  # subsets the abstraction proved infeasible

    @property
    def abstraction(self) -> Consumption:
        if self._abstraction is None:
            m = self.model
            self._abstraction = Consumption(m.inst, m.components, known=m.labels)
        return self._abstraction

    def core(self, labels: Sequence[str]) -> list[str] | None:
        """An irreducible core of ``labels`` for the abstraction, or None (it cannot refute
        them, or the time ran out)."""
        limits.check_time("diagnosing")
        a = self.abstraction
        if not a.labels:
            return None
        wanted = set(a.labels)
        relevant = [label for label in labels if label in wanted]
        core = a.irreducible(relevant, limits.for_check())
        if core is None:
            return None
        self.found += 1
        keep = set(core)
        return [label for label in labels if label in keep]

    def witnessed(self, labels: Sequence[str], horizon: int, extended: int) -> bool:
        """Whether the abstraction's model of ``labels`` gives a composition (the supporting
        components in rank order, one per step) that the independent validator accepts on
        the instance enforcing exactly ``labels`` — then ``labels`` are feasible."""
        limits.check_time("diagnosing")
        if self.model.components is not None:  # a fixed composition: diagnose's own witness
            return False
        a = self.abstraction
        r, _ = a.check(labels, limits.for_check())
        if r is not Check.SAT:
            return False
        order = a.support(labels)
        if order is None:
            return False
        enforced = frozenset(labels)
        steps = horizon if "horizon" in enforced else extended
        if len(order) > steps:
            return False
        plan = _candidate(self.model.inst, enforced, order, order)
        if plan is None:
            return False
        inst = self.model.inst
        for candidate in (plan, _unbounded(inst, plan, enforced)):
            for big in (False, True):
                if validate(_freed(_restricted(inst, enforced, big), enforced), candidate, horizon=steps).ok:
                    return True
        return False


def _unbounded(inst: ir.Instance, plan: Plan, enforced: frozenset[str]) -> Plan:
    """The plan with every numeric θ whose bound is dropped at -10⁹ (a decrease by it then
    gives the resource back: one of the values the solver may choose)."""

    def params(a: Activation) -> dict:
        m = inst.morphisms[a.morphism]
        out = dict(a.params)
        for p in m.params:
            if p.sort.is_numeric and f"bound/{m.name}/{p.name}" not in enforced:
                out[p.name] = -BIG
        return out

    return Plan([[Activation(a.morphism, params(a)) for a in step] for step in plan.steps], plan.fresh)


def _freed(inst: ir.Instance, enforced: frozenset[str]) -> ir.Instance:
    """The instance enforcing exactly ``enforced`` as the solver reads it: a dropped effect
    may or may not happen — here a dropped decrease, increase, removal or numeric assignment
    does not, a dropped addition or Boolean set true does — and a dropped initial value is free: here every fact
    holds initially."""
    morphisms = {}
    for name, m in inst.morphisms.items():
        effects = tuple(eff for eff in m.effects if eff.label in enforced or _gives(inst, eff))
        morphisms[name] = replace(m, effects=effects)
    init = dict(inst.problem.init)
    for name, given in inst.problem.init.items():  # a dropped initial value is free: the facts hold
        sort = inst.resources[name].sort if name in inst.resources else None
        if given.label in enforced or sort is None:
            continue
        if sort.kind is ir.SortKind.BOOL:
            init[name] = replace(given, value=ir.Const(True, sort))
        elif sort.kind is ir.SortKind.SET and sort.element is not None:
            values = tuple(ir.Const(c, sort.element) for c in inst.constants_of(sort.element))
            init[name] = replace(given, value=ir.SetLit(values, sort))
    problem = replace(inst.problem, init=ir.frozen(init))
    return ir.Instance(replace(inst.domain, morphisms=ir.frozen(morphisms)), problem, inst.view)


def consumption_refutation(inst: ir.Instance, components: Collection[str] | None = None) -> list[str] | None:
    """The labels of an irreducible abstract core when the abstraction refutes ``inst``
    with every label enforced (no composition of any length exists), else None."""
    a = Consumption(inst, components)
    return a.irreducible(a.labels, limits.for_check())


def _gives(inst: ir.Instance, eff: ir.Effect) -> bool:
    """An addition to a set, or a Boolean set true (a dropped one happens in the witness)."""
    if eff.kind is ir.EffectKind.ADD:
        return True
    res = inst.resources.get(eff.resource)
    return (
        res is not None
        and res.sort.kind is ir.SortKind.BOOL
        and eff.kind is ir.EffectKind.ASSIGN
        and isinstance(eff.value, ir.Const)
        and eff.value.value is True
    )


# ====================================================================== the h_max bound over label subsets


class LeastCost:
    """The h_max least-consumption bound of :func:`catc.smt.consumption.least_consumption`
    over subsets of labels, in pure Python (no solver): with exactly the labels ``E``
    enforced, a numeric resource that only decreases, whose initial value (``init/r``) and
    bounds (``bounds/r``) are enforced and whose θ consumers keep their lower bounds
    (``bound/m/p``), loses at least the h_max cost of the goal's facts — each fact costing
    0 when it holds initially (or its initial value is dropped: then it is free), else the
    least over its givers of the giver's enforced decreases (``eff/m/i``; a dropped one may
    not happen) plus the greatest cost of the facts its enforced preconditions (``pre/m/i``)
    need.  ``E`` is refuted when that cost exceeds what the resource can lose, or when the
    goal's enforced facts (``goal/i``) cannot be reached at all without the morphisms that
    alone take more of a resource than there is.  Deletes, negative and numeric conditions
    are forgotten, so a refutation holds for every composition of any length (sound); it
    is monotone in ``E``.  Costs are settled in increasing order (Knuth's generalisation of
    Dijkstra's algorithm), so one test takes milliseconds at 400 components."""

    def __init__(self, inst: ir.Instance) -> None:
        self.inst = inst
        given, anything = _givers(inst)
        index: dict[Atom, int] = {}

        def atom(a: Atom) -> int:
            return index.setdefault(a, len(index))

        self.names = list(inst.morphisms)
        self.needs: list[list[tuple[str, list[int]]]] = []
        for m in inst.morphisms.values():
            self.needs.append([(lit.label, [atom(a) for a in _atoms(lit.expr)]) for lit in m.pre if _atoms(lit.expr)])
        self.goal = [(lit.label, [atom(a) for a in _atoms(lit.expr)]) for lit in inst.problem.goal]
        for a in given:
            atom(a)
        self.atoms = list(index)
        position = {name: i for i, name in enumerate(self.names)}
        self.gives: list[list[int]] = [[] for _ in self.names]
        for a, i in index.items():
            for name, _ in given.get(a, []) + (anything.get(a[0], []) if a[1] is not None else []):
                self.gives[position[name]].append(i)
        # an atom's initial value: (label, holds as written); None: no initial value (holds)
        self.start: list[tuple[str, bool] | None] = []
        for a in self.atoms:
            init = inst.problem.init.get(a[0])
            self.start.append(None if init is None else (init.label, _holds(init, a)))
        # resources that only decrease: (name, room, init label, bounds label, consumers), the
        # amounts scaled to integers per resource (one common denominator: exact, and fast)
        self.resources: list[tuple[str, int, str, str, list[tuple[int, int, str, str | None]]]] = []
        self.scale: dict[str, int] = {}
        for name, res in inst.resources.items():
            consumers = _consumers(inst, name, res, position)
            if consumers:
                space = room(inst, name)
                scale = math.lcm(space.denominator, *(amount.denominator for _, amount, _, _ in consumers))
                scaled = [(m, int(amount * scale), label, bound) for m, amount, label, bound in consumers]
                init = inst.problem.init[name]
                self.resources.append((name, math.floor(space * scale), init.label, res.bounds_label, scaled))
                self.scale[name] = scale
        #: the resources a test looks at (None: all); :meth:`focus` narrows it
        self.deciding: set[str] | None = None
        # the morphisms that may support the goal (a giver of a fact the goal needs, or one
        # of its givers needs, ...): the others change no cost, and no test looks at them
        offers: dict[int, list[int]] = {}
        for mi, atoms in enumerate(self.gives):
            for ai in atoms:
                offers.setdefault(ai, []).append(mi)
        wanted = {ai for _, atoms in self.goal for ai in atoms}
        todo, self.useful = list(wanted), set[int]()
        while todo:
            for mi in offers.get(todo.pop(), []):
                if mi not in self.useful:
                    self.useful.add(mi)
                    fresh = {ai for _, atoms in self.needs[mi] for ai in atoms} - wanted
                    wanted |= fresh
                    todo += fresh
        self.wanted = wanted
        #: per morphism, the facts it gives that some test may ask for
        self.gives_wanted = [[a for a in atoms if a in wanted] for atoms in self.gives]
        #: per morphism with one condition needing facts: those facts, each once
        self.single = [tuple(dict.fromkeys(ns[0][1])) if len(ns) == 1 else () for ns in self.needs]
        #: per resource: its θ bound labels, and its (morphism, amount, effect label) with amount > 0
        self.bounds_of = [{b for _, _, _, b in c if b is not None} for *_, c in self.resources]
        self.takers = [[(m, a, label) for m, a, label, _ in c if a] for *_, c in self.resources]
        self.relevant = set(self._relevant())
        self.tests = 0

    def _relevant(self) -> Iterable[str]:
        """The labels a test reads (every other label can be left out of a core)."""
        for m in self.useful:
            yield from (label for label, _ in self.needs[m])
        yield from (label for label, _ in self.goal)
        yield from (s[0] for s in self.start if s is not None and not s[1])
        for _, _, init, bounds, consumers in self.resources:
            yield from (init, bounds)
            for m, _, label, bound in consumers:
                if m in self.useful:
                    yield label
                if bound is not None:
                    yield bound

    def claims(self, enforced: Collection[str]) -> list[tuple[str, int, dict[int, int]]]:
        """The resources the bound speaks of with ``enforced``: (name, room, amount per
        morphism), scaled to integers."""
        out = []
        for (name, space, init, bounds, _), needed, takers in zip(
            self.resources, self.bounds_of, self.takers, strict=True
        ):
            if init not in enforced or bounds not in enforced:
                continue
            if not needed.issubset(enforced):
                continue  # a θ without its lower bound may give the resource back
            amounts: dict[int, int] = {}
            for m, amount, label in takers:
                if label in enforced:
                    amounts[m] = amounts.get(m, 0) + amount
            out.append((name, space, amounts))
        return out

    def refuted(self, labels: Iterable[str]) -> bool:
        """Whether the bound shows that no composition satisfies exactly ``labels``."""
        limits.check_time("diagnosing")
        self.tests += 1
        enforced = set(labels)
        claims = self.claims(enforced)
        never = {m for _, space, amounts in claims for m, a in amounts.items() if a > space}
        deciding = [c for c in claims if self.deciding is None or c[0] in self.deciding]
        for _, space, amounts in deciding or [("", 0, {})]:
            cost = self.run(enforced, amounts, never)[0]
            if cost is None or (deciding and cost > space):
                return True
        return False

    def focus(self, labels: Collection[str]) -> None:
        """Look only at the resources the bound refutes ``labels`` by (the cost is monotone
        in the labels: another resource refutes no subset) — reachability is always looked at."""
        enforced = set(labels)
        claims = self.claims(enforced)
        never = {m for _, space, amounts in claims for m, a in amounts.items() if a > space}
        deciding = set()
        for name, space, amounts in claims:
            cost = self.run(enforced, amounts, never)[0]
            if cost is not None and cost > space:
                deciding.add(name)
        self.deciding = deciding

    def run(
        self,
        enforced: Collection[str],
        amounts: dict[int, int],
        never: Collection[int] = (),
        held: Collection[int] = (),
    ) -> tuple[int | None, list[int], list[int]]:
        """The goal's cost (None: unreachable), the giver of each settled atom (-1: initially;
        -2 unsettled) and the morphisms in the order they fire; ``held``: atoms given at no cost."""
        goal = {a for label, atoms in self.goal if label in enforced for a in atoms}
        giver = [-2] * len(self.atoms)
        waiting: list[list[int]] = [[] for _ in self.atoms]
        remaining = [0] * len(self.names)
        heap = [(0, a, -1) for a, s in enumerate(self.start) if s is None or s[1] or s[0] not in enforced or a in held]
        order: list[int] = []
        gives, needs, get, push, pop = self.gives_wanted, self.needs, amounts.get, heapq.heappush, heapq.heappop
        useful = [m for m in self.useful if m not in never]
        for m in useful:
            ns = needs[m]
            if not ns:
                continue
            if len(ns) == 1:  # most morphisms: one condition needing facts
                pending: Collection[int] = self.single[m] if ns[0][0] in enforced else ()
            else:
                pending = {a for label, atoms in ns if label in enforced for a in atoms}
            remaining[m] = len(pending)
            for a in pending:
                waiting[a].append(m)
        heapq.heapify(heap)
        for m in useful:  # (inlined: what fires gives its facts at its cost)
            if remaining[m] == 0:
                order.append(m)
                value = get(m, 0)
                for a in gives[m]:
                    if giver[a] == -2:
                        push(heap, (value, a, m))
        cost = 0
        left = len(goal)
        while heap and left:
            c, a, by = pop(heap)
            if giver[a] != -2:
                continue
            giver[a] = by
            cost = c
            if a in goal:
                left -= 1
            for m in waiting[a]:
                remaining[m] -= 1
                if remaining[m] == 0:
                    order.append(m)
                    value = c + get(m, 0)
                    for b in gives[m]:
                        if giver[b] == -2:
                            push(heap, (value, b, m))
        return (None if left else cost), giver, order

    def support(self, enforced: Collection[str], giver: list[int], order: list[int], roots: Iterable[int]) -> list[str]:
        """The morphisms supporting ``roots`` (atoms) through ``giver``, in firing order."""
        rank = {m: i for i, m in enumerate(order)}
        chosen: set[int] = set()
        todo = list(roots)
        while todo:
            a = todo.pop()
            m = giver[a]
            if m < 0 or m in chosen:
                continue
            chosen.add(m)
            todo += [b for label, atoms in self.needs[m] if label in enforced for b in atoms]
        return [self.names[m] for m in sorted(chosen, key=lambda m: rank.get(m, 0))]

    def candidates(self, enforced: Collection[str], prefer: str | None = None) -> Iterable[list[str]]:
        """Compositions worth replaying for ``enforced``: the cheapest support of the goal for
        each resource (and for none), and the same through ``prefer``'s morphism first."""
        claims = self.claims(enforced)
        never = {m for _, space, amounts in claims for m, a in amounts.items() if a > space}
        goal = [a for label, atoms in self.goal if label in enforced for a in atoms]
        weights = [amounts for _, _, amounts in claims]
        for _, _, init, bounds, consumers in self.resources:
            if init in enforced and bounds in enforced:
                amounts: dict[int, int] = {}
                for m, amount, label, _ in consumers:
                    if label in enforced:
                        amounts[m] = amounts.get(m, 0) + amount
                if amounts not in weights:
                    weights.append(amounts)
        weights.append({})
        first = self.names.index(prefer) if prefer is not None and prefer in self.inst.morphisms else None
        seen: list[list[str]] = []
        for amounts in weights:
            _, giver, order = self.run(enforced, amounts, never)
            for through in ([first] if first is not None else []) + [None]:
                # through the member's morphism first: leaving the member out is what lets it fire
                if through is None:
                    plan = self.support(enforced, giver, order, goal)
                else:
                    plan = self._through(enforced, amounts, never, giver, order, through, goal)
                if plan not in seen:
                    seen.append(plan)
                    yield plan

    def swapped(self, enforced: Collection[str], giver: list[int], order: list[int], first: int) -> list[str]:
        """The support of the goal through ``giver`` (a run's, with more labels enforced) with
        morphism ``first`` giving every fact it gives: the support of ``first``'s facts,
        ``first``, then the rest, each part in the run's firing order."""
        goal = [a for label, atoms in self.goal if label in enforced for a in atoms]
        before = [b for label, atoms in self.needs[first] if label in enforced for b in atoms]
        head = self.support(enforced, giver, order, before)
        mine = list(giver)
        for a in self.gives[first]:
            mine[a] = first
        name = self.names[first]
        tail = [m for m in self.support(enforced, mine, order, goal) if m not in head and m != name]
        return [m for m in head if m != name] + [name] + tail

    def _through(
        self,
        enforced: Collection[str],
        amounts: dict[int, int],
        never: Collection[int],
        giver: list[int],
        order: list[int],
        first: int,
        goal: list[int],
    ) -> list[str]:
        """The support of ``first``'s facts, ``first``, then the goal's support with what
        ``first`` gives held."""
        before = [b for label, atoms in self.needs[first] if label in enforced for b in atoms]
        head = self.support(enforced, giver, order, before)
        _, giver2, order2 = self.run(enforced, amounts, never, held=set(self.gives[first]))
        name = self.names[first]
        tail = [m for m in self.support(enforced, giver2, order2, goal) if m not in head and m != name]
        return [m for m in head if m != name] + [name] + tail


def _consumers(
    inst: ir.Instance, name: str, res: ir.Resource, position: dict[str, int]
) -> list[tuple[int, Fraction, str, str | None]]:
    """The decreases of a numeric resource with a lower bound and a constant initial value:
    (morphism, least amount, effect label, θ bound label or None); [] when some effect on it
    may raise it (then the bound says nothing of it)."""
    init = inst.problem.init.get(name)
    if not res.sort.is_numeric or res.lower is None or init is None or not isinstance(init.value, ir.Const):
        return []
    out: list[tuple[int, Fraction, str, str | None]] = []
    for m in inst.morphisms.values():
        for eff in m.effects:
            if eff.resource != name:
                continue
            v = eff.value
            if eff.kind is not ir.EffectKind.DECREASE:
                return []
            if isinstance(v, ir.Const) and isinstance(v.value, Fraction | int) and v.value >= 0:
                out.append((position[m.name], Fraction(v.value), eff.label, None))
            elif isinstance(v, ir.ParamRef):
                p = next((p for p in m.params if p.name == v.name), None)
                if p is None or p.lower is None or p.lower < 0:
                    return []
                out.append((position[m.name], Fraction(p.lower), eff.label, m.bound_label(p.name)))
            else:
                return []
    return out if any(amount for _, amount, _, _ in out) else []


class QuickCores:
    """diagnose's first try without any solver or encoding (issue 24): QuickXplain over
    :class:`LeastCost` finds a core it refutes, and each member is shown needed by a
    composition the independent validator accepts on the instance enforcing exactly the
    other members (built from the bound's cheapest supports)."""

    def __init__(self, inst: ir.Instance, horizon: int, extended: int) -> None:
        self.inst = inst
        self.bound = LeastCost(inst)
        self.horizon, self.extended = horizon, extended
        self.witnessed = 0
        self.replayed: tuple[Plan, bool] | None = None  # the last composition accepted, and its 10⁹ flag
        self.witnesses: dict[str, tuple[Plan, bool]] = {}  # irreducible's: member → what showed it needed

    def core(self, labels: Sequence[str]) -> list[str] | None:
        """A core of ``labels`` irreducible for the bound, or None (it does not refute them)."""
        relevant = [label for label in labels if label in self.bound.relevant]
        self.bound.focus(relevant)
        if not self.bound.refuted(relevant):
            return None
        return quickxplain(relevant, self.bound.refuted)

    def feasible(self, labels: Sequence[str], prefer: str | None = None) -> bool:
        """Whether a composition built from the bound's supports satisfies exactly ``labels``
        (the validator says so); False: not shown."""
        limits.check_time("diagnosing")
        enforced = frozenset(labels)
        return any(self._replay(enforced, order) for order in self.bound.candidates(enforced, prefer))

    def _replay(self, enforced: frozenset[str], order: list[str]) -> bool:
        """Whether the validator accepts ``order`` (one per step, θ as the solver might pick
        them) on the instance enforcing exactly ``enforced``."""
        steps = self.horizon if ir.Label.horizon() in enforced else self.extended
        if len(order) > steps:
            return False
        inst = self.inst
        plan = _candidate(inst, enforced, order, order)
        if plan is None:
            return False
        # only the plan's morphisms: the others never fire (the replay is then quick)
        used = set(order)
        sub = ir.Instance(
            replace(inst.domain, morphisms=ir.frozen({m: x for m, x in inst.morphisms.items() if m in used})),
            inst.problem,
            inst.view,
        )
        for candidate in (plan, _unbounded(inst, plan, enforced)):
            for big in (False, True):
                if validate(_freed(_restricted(sub, enforced, big), enforced), candidate, horizon=steps).ok:
                    self.witnessed += 1
                    self.replayed = (candidate, big)
                    return True
        return False

    def irreducible(self, core: Sequence[str]) -> bool:
        """Whether every member of ``core`` is shown needed (the rest witnessed feasible).
        For each member first the cheapest support of the whole core with the member's own
        morphism swapped in (one bound run for all members, :meth:`LeastCost.swapped`), then
        the bound's supports of the core without the member (:meth:`feasible`).  Either way
        it is only a candidate: what shows the member needed is the validator's replay."""
        bound = self.bound
        every = set(core)
        claims = [c for c in bound.claims(every) if bound.deciding is None or c[0] in bound.deciding]
        amounts = claims[0][2] if claims else {}
        never = {m for _, space, amounts_ in bound.claims(every) for m, a in amounts_.items() if a > space}
        cost, giver, order = bound.run(every, amounts, never)
        position = {name: i for i, name in enumerate(bound.names)}
        for i, label in enumerate(core):
            rest = [*core[:i], *core[i + 1 :]]
            m = owner(self.inst, label)
            if cost is not None and m is not None:
                limits.check_time("diagnosing")
                enforced = frozenset(rest)
                if self._replay(enforced, bound.swapped(enforced, giver, order, position[m])):
                    self.witnesses[label] = self.replayed  # type: ignore[assignment]
                    continue
            if not self.feasible(rest, m):
                return False
            self.witnesses[label] = self.replayed  # type: ignore[assignment]
        return True


def owner(inst: ir.Instance, label: str) -> str | None:
    """The morphism a ``pre/``, ``eff/``, ``bound/`` or ``uses/`` label belongs to."""
    kind, _, rest = label.partition("/")
    if kind in ("pre", "eff", "bound"):
        rest = rest.rpartition("/")[0]
    elif kind != "uses":
        return None
    return rest if rest in inst.morphisms else None


def restoration(
    inst: ir.Instance,
    horizon: int,
    sequential: bool,
    weights: dict[str, Fraction],
    integral: Collection[str],
    relaxed: Callable[[dict[str, Fraction]], ir.Instance],
) -> tuple[Fraction, dict[str, Fraction], Plan] | None:
    """relax at the least-consumption bound without a search (issue 24).  A restoration
    either uses a morphism that alone takes more of some resource than there is — then it
    raises that resource's initial value by at least the excess — or it uses none of them,
    and then every numeric resource the h_max bound shows short (the goal's least
    consumption without them above what the resource can lose) has its initial value raised
    by at least the shortfall, at ``weights[init/r]`` per unit: no other eligible requirement
    (a comparison, a lowered value) makes a consumption smaller.  When the shortfalls cost
    no more than every excess, raising each short resource by exactly its shortfall is
    least as soon as some composition then exists.  The
    composition is the bound's cheapest support of the goal on the raised instance
    (``relaxed``: the instance with the raises applied) for each resource, or else one that
    fits every resource at once (:func:`catc.smt.consumption.cheapest_support`: the coupled
    cuts, where the cheapest per resource overdraws another); it counts only when the
    independent validator accepts it.  (cost, raise per label, composition), or None."""
    every = set(label_index(inst))
    bound = LeastCost(inst)
    claims = bound.claims(every)
    init = {name: inst.problem.init[name].label for name, _, _ in claims}
    # the morphisms that alone take more of some resource than there is: a restoration that
    # uses one raises each such resource by at least its excess
    excess: dict[int, Fraction] = {}
    for name, space, amounts in claims:
        for m, a in amounts.items():
            if a > space:
                w = weights.get(init[name])
                gap = Fraction(a - space, bound.scale[name])
                excess[m] = excess.get(m, Fraction(0)) + (w * gap if w is not None else Fraction(10**30))
    short: dict[str, Fraction] = {}
    for name, space, amounts in claims:  # a restoration that uses none of them
        cost = bound.run(every, amounts, set(excess))[0]
        if cost is None:
            return None
        if cost > space:
            label, gap = init[name], Fraction(cost - space, bound.scale[name])
            if label not in weights or (label in integral and gap.denominator != 1):
                return None
            short[label] = gap
    total = sum((weights[label] * gap for label, gap in short.items()), Fraction(0))
    if not short or any(e < total for e in excess.values()):
        return None  # not the least, or nothing to restore
    raised = relaxed(short)
    # the bound's cheapest support per resource, then one that fits every resource at once
    # (alternatives trading one resource for another: the coupled cuts)
    for order in chain(LeastCost(raised).candidates(every), _fitting(raised)):
        limits.check_time("relaxing")
        if not order or len(order) > horizon:
            continue
        plan = _candidate(raised, every, order, order)
        if plan is not None and validate(raised, plan, horizon=horizon, sequential=sequential).ok:
            return total, short, plan
    return None


def _fitting(inst: ir.Instance) -> Iterable[list[str]]:
    """:func:`catc.smt.consumption.cheapest_support` of ``inst``, if it finds one."""
    order = cheapest_support(inst)
    if order is not None:
        yield order


#: The most time :func:`optimal_restoration` takes without a time limit.
OPTIMAL_SECONDS = 30.0


def optimal_restoration(
    inst: ir.Instance,
    horizon: int,
    sequential: bool,
    reqs: Sequence[tuple[str, str, Fraction]],
    integral: Collection[str],
    relaxed: Callable[[dict[str, Fraction]], ir.Instance],
) -> tuple[Fraction, dict[str, Fraction], Plan] | None:
    """relax at the exact optimum of the consumption abstraction (issue 24: several
    resources short, alternatives trading one against another): the least weighted raise
    over which alternatives fire (:func:`catc.smt.consumption.least_restoration`, a proven
    lower bound), and a composition of that optimum's supporting morphisms in rank order, θ
    at their lower bounds, on the raised instance.  It counts only when the independent
    validator accepts it — then its cost equals the lower bound, so it is least.  It takes at
    most half the time left (:data:`OPTIMAL_SECONDS` without a limit), then gives up.  (cost,
    raise per label, composition), or None."""
    left = limits.remaining()  # at most half what is left (or 30 s): the search may still answer
    until = time.perf_counter() + (OPTIMAL_SECONDS if left is None else left / 2)
    found = least_restoration(inst, reqs, lambda: limits.for_check(until))
    if found is None:
        return None
    total, raised, order = found
    if not order or len(order) > horizon:
        return None
    if any(label in integral and v.denominator != 1 for label, v in raised.items()):
        return None
    every = set(label_index(inst))
    target = relaxed(raised)
    plan = _candidate(target, every, order, order)
    limits.check_time("relaxing")
    if plan is None or not validate(target, plan, horizon=horizon, sequential=sequential).ok:
        return None
    return total, raised, plan


def quickxplain(labels: list[str], refuted: Callable[[list[str]], bool]) -> list[str]:
    """A subset of ``labels`` that ``refuted`` holds of and no member of which can be left
    out, for a monotone ``refuted`` that holds of ``labels`` (Junker's QuickXplain)."""

    def qx(background: list[str], added: bool, candidates: list[str]) -> list[str]:
        if added and refuted(background):
            return []
        if len(candidates) == 1:
            return candidates
        half = len(candidates) // 2
        first, second = candidates[:half], candidates[half:]
        right = qx(background + first, True, second)
        left = qx(background + right, bool(right), first)
        return left + right

    if not labels or refuted([]):
        return []
    core = qx([], False, labels)
    return core if refuted(core) else labels  # a non-monotone corner: keep what is proven
