"""recompose's branch and bound over component sets, without the solver (issue 24).

Both priorities of ``recompose`` rank a composition by a lexicographic key — the mission
objectives (each the maximum of a bounded resource that only decreases) and the weighted
churn, in either order.  Over a *component set* ``C`` the consumption abstraction for fixed
sets (:class:`~catc.smt.consumption.FixedSet`) gives an optimistic key: each objective's
initial value minus ``C``'s least consumption, and ``C``'s churn (which depends on the set
only).  The component set of every composition passes the abstraction, and the
composition's key is at most its set's optimistic key; so when the passing set of greatest
optimistic key replays in the validator (one step per component, θ at its lower bounds)
with exactly that key, no composition does better: a proven optimum.

The search (:func:`best_set`) builds the passing sets as the goal's support — the open fact
needed last is given by one of its givers, each giver's own facts then open — followed by a
decision per deployed component left out of the support (keep it as well, or remove it).
Every passing set ``C`` has a set it builds with a key at least ``C``'s: the first giver of
each needed fact in ``C``'s firing order, with ``C``'s deployed components; what else ``C``
holds is a non-deployed component no one needs, which only costs and adds churn.  Pruned:

* a giver *dominated* by another giver of the same fact — the same facts needed and given,
  never more of any only-decreasing resource, and no more churn when it replaces the other
  (deployed, or both not deployed with no greater weight): replacing it in any set keeps the
  set passing with a key at least as good (ties broken by declaration order);
* a branch whose optimistic key cannot beat the best set found: each objective's initial
  value minus what is spent and the h_max cost of the open facts
  (:func:`~catc.smt.consumption.least_consumption`'s per-fact costs), and the churn of the
  chosen components that are not deployed plus the deployed ones already out — those
  decided out, and those that no longer fit in a room or would drop the objectives' bound
  to the best found, which any completion keeping them cannot beat either;
* a branch that overdraws a room with the open facts' h_max costs.

Any doubt gives no claim: more than :data:`EXPANSIONS` branches or the time given, a built
set without a firing order (a cyclic support) — then the best set found is returned as
not proven — or a set the validator rejects or whose replay scores less than its
optimistic key (the caller asks the solver).
"""

from __future__ import annotations

import heapq
import math
import time
from collections.abc import Collection, Iterable, Sequence
from fractions import Fraction

from catc import ir
from catc.semantics.bounds import ranges
from catc.semantics.validate import EvaluationError, evaluate, initial_state
from catc.smt.consumption import Atom, FixedSet, _amounts, _givers, _holds, init_value, overdrawing
from catgrammar.record import replace

#: The most branches :func:`best_set` tries before it gives up (no claim).
EXPANSIONS = 200_000

Key = tuple[int, ...]  # greater is better: per objective its scaled value (churn negated)


class _GiveUp(Exception):
    pass


def _scale(values: Iterable[Fraction]) -> int:
    """The least common multiple of the denominators: every value times it is an integer."""
    out = 1
    for v in values:
        out = out * v.denominator // math.gcd(out, v.denominator)
    return out


def _hmax(
    givers: dict[Atom, list[str]],
    need_of: dict[Atom, list[str]],
    needs: dict[str, list[Atom]],
    gives: dict[str, list[Atom]],
    start: Collection[Atom],
    amount: dict[str, int],
    free: str | None = None,
) -> dict[Atom, int]:
    """The h_max cost of each reachable fact (``start``: the facts that hold initially, cost 0)
    — a fact costs the least, over its givers, of the giver's amount (``free``'s: 0) plus the
    greatest cost among the giver's facts — settled in increasing order (Knuth's
    generalisation of Dijkstra's algorithm); an unreachable fact has none."""
    cost: dict[Atom, int] = {}
    heap: list[tuple[int, int, Atom]] = []
    tick = 0
    for a in start:
        heap.append((0, tick, a))
        tick += 1
    best: dict[Atom, int] = dict.fromkeys(start, 0)
    waiting = {m: len(ns) for m, ns in needs.items()}

    def offer(m: str, c: int) -> None:
        nonlocal tick
        c += 0 if m == free else amount.get(m, 0)
        for b in gives.get(m, ()):
            if c < best.get(b, c + 1):
                best[b] = c
                tick += 1
                heapq.heappush(heap, (c, tick, b))

    for m, k in waiting.items():
        if k == 0:
            offer(m, 0)
    heapq.heapify(heap)
    while heap:
        c, _, a = heapq.heappop(heap)
        if a in cost:
            continue
        cost[a] = c
        for m in need_of.get(a, ()):
            waiting[m] -= 1
            if waiting[m] == 0:
                offer(m, c)  # settled in increasing order: c is the greatest of m's facts
    return cost


def best_set(
    inst: ir.Instance,
    objectives: Sequence[ir.Objective],
    expansions: int = EXPANSIONS,
    deadline: float | None = None,
) -> tuple[list[str], tuple[Fraction, ...], bool] | None:
    """The passing component set of greatest optimistic key for ``objectives`` (churn and
    maximised only-decreasing resources, in their lexicographic order), in an order it can
    fire, with that key (each objective as a value to maximise: churn negated) and True;
    when the search stops early (see the module docstring; ``deadline``: a
    ``time.monotonic()`` it stops at), the best set found so far and False; None when the
    objectives are not of that kind or nothing passes."""
    fixed = FixedSet(inst)
    slots: list[str | None] = []  # per objective: the resource it maximises, None for churn
    for o in objectives:
        if isinstance(o.term, ir.TotalChurn) and o.sense is ir.Sense.MINIMIZE:
            slots.append(None)
        elif o.sense is ir.Sense.MAXIMIZE and isinstance(o.term, ir.ResourceRef) and o.term.name in fixed.decreasing:
            slots.append(o.term.name)
        else:
            return None
    if any(m.churn <= 0 for m in inst.morphisms.values()):
        return None
    return _Search(inst, fixed, slots, expansions, deadline).run()


class _Search:
    """The branch and bound of :func:`best_set` (see the module docstring): the tables in
    integers, then the search's state — the chosen components, what they spend and give."""

    def __init__(
        self, inst: ir.Instance, fixed: FixedSet, slots: list[str | None], expansions: int, deadline: float | None
    ) -> None:
        self.inst, self.fixed, self.slots, self.deadline = inst, fixed, slots, deadline
        self._numbers()
        self._structure()
        self._offers()
        self.spent = dict.fromkeys(self.resources, 0)
        self.chosen: list[str] = []
        self.inside: set[str] = set()
        self.out: set[str] = set()  # deployed components decided out
        self.have: dict[Atom, int] = {}  # fact → how many chosen components give it
        self.added = 0  # the churn weight of the chosen components that are not deployed
        self.out_weight = 0
        self.left = expansions
        self.best: tuple[Key, list[str]] | None = None

    def _numbers(self) -> None:
        """Integers throughout: each resource (and the churn weights) scaled by its denominators."""
        inst, fixed = self.inst, self.fixed
        decreasing = fixed.decreasing
        weights = {m.name: Fraction(m.churn) for m in inst.morphisms.values()}
        self.scale = {
            r: _scale([*amounts.values(), fixed.rooms[r], init_value(inst, r)]) for r, amounts in decreasing.items()
        }
        self.wscale = _scale(weights.values())
        self.weight = {m: int(w * self.wscale) for m, w in weights.items()}
        self.amt = {r: {m: int(a * self.scale[r]) for m, a in amounts.items()} for r, amounts in decreasing.items()}
        self.rooms = {r: int(fixed.rooms[r] * self.scale[r]) for r in decreasing}
        self.inits = {r: int(init_value(inst, r) * self.scale[r]) for r in decreasing}
        self.resources = list(decreasing)

    def _structure(self) -> None:
        """Who gives and needs which fact, the h_max costs, cones and landmarks."""
        inst, fixed = self.inst, self.fixed
        self.deployed_set = set(inst.problem.deployed)
        self.deployed = [m for m in inst.morphisms if m in self.deployed_set]
        given, any_element = _givers(inst)
        self.never = never = overdrawing(inst, fixed.decreasing) | fixed.unusable
        self.needs = {m: list(dict.fromkeys(ns)) for m, ns in fixed.needs.items()}
        self.goal = list(dict.fromkeys(fixed.goal))
        atoms = set(given) | {a for ns in self.needs.values() for a in ns} | set(self.goal)

        def initially(a: Atom) -> bool:
            init = inst.problem.init.get(a[0])
            return init is None or _holds(init, a)

        self.start = start = {a for a in atoms if initially(a)}
        # who gives each fact (never-firing morphisms left out), and what each morphism gives
        self.givers: dict[Atom, list[str]] = {}
        givers = self.givers
        for a in atoms:
            ms = [m for m, _ in given.get(a, []) + (any_element.get(a[0], []) if a[1] is not None else [])]
            givers[a] = [m for m in dict.fromkeys(ms) if m not in never]
        self.gives: dict[str, list[Atom]] = {}
        for a, ms in givers.items():
            for m in ms:
                self.gives.setdefault(m, []).append(a)
        self.live = live = {m: ns for m, ns in self.needs.items() if m not in never}
        need_of: dict[Atom, list[str]] = {}
        for m, ns in live.items():
            for a in ns:
                need_of.setdefault(a, []).append(m)
        amt, gives = self.amt, self.gives
        self.costs = {r: _hmax(givers, need_of, live, gives, start, amt[r]) for r in self.resources}
        self.free_costs = {
            x: {r: _hmax(givers, need_of, live, gives, start, amt[r], x) for r in self.resources} for x in self.deployed
        }
        self.cones: dict[Atom, frozenset[Atom]] = {}  # the facts a fact's supports may give (not initial)
        self.landmarks = _landmarks(atoms, start, givers, live)
        self.giver_sets = {a: frozenset(ms) for a, ms in givers.items()}
        self.cheapest_new = {
            a: min((self.weight[m] for m in ms if m not in self.deployed_set), default=None) for a, ms in givers.items()
        }
        self.lost = sum(self.weight[x] for x in self.deployed if x in never)  # never fire: removed

    def cone(self, a: Atom) -> frozenset[Atom]:
        if a not in self.cones:
            seen: set[Atom] = set()
            todo = [a]
            while todo:
                b = todo.pop()
                for m in self.givers.get(b, ()):
                    for c in self.live[m]:
                        if c not in seen and c not in self.start:
                            seen.add(c)
                            todo.append(c)
            self.cones[a] = frozenset(seen)
        return self.cones[a]

    def amount(self, m: str, r: str) -> int:
        return self.amt[r].get(m, 0)

    def dominates(self, a: str, b: str) -> bool:
        deployed, weight = self.deployed_set, self.weight
        if a in deployed and b not in deployed:
            churn_ok = True
        elif (a in deployed) == (b in deployed):
            churn_ok = weight[b] <= weight[a] if a in deployed else weight[a] <= weight[b]
        else:
            churn_ok = False
        return (
            churn_ok
            and set(self.needs[a]) == set(self.needs[b])
            and set(self.gives.get(a, [])) == set(self.gives.get(b, []))
            and all(self.amount(a, r) <= self.amount(b, r) for r in self.resources)
        )

    def _offers(self) -> None:
        """Per fact, its givers that no other giver dominates, the most promising first: the
        best contribution to the key, then the cheapest overall."""

        def sort_key(m: str) -> tuple:
            own = [
                (self.weight[m] if m not in self.deployed_set else 0) if r is None else self.amount(m, r)
                for r in self.slots
            ]
            rooms = self.rooms
            spend = sum((Fraction(self.amount(m, r), rooms[r]) for r in self.resources if rooms[r] > 0), Fraction(0))
            return (*own, spend)

        order_of = {m: i for i, m in enumerate(self.inst.morphisms)}
        self.offers: dict[Atom, list[str]] = {}
        for a, ms in self.givers.items():
            kept = [
                b
                for b in ms
                if not any(
                    x != b and self.dominates(x, b) and (not self.dominates(b, x) or order_of[x] < order_of[b])
                    for x in ms
                )
            ]
            self.offers[a] = sorted(kept, key=sort_key)

    def given_now(self, a: Atom) -> bool:
        return a in self.start or self.have.get(a, 0) > 0

    def choose(self, m: str, sign: int) -> None:
        for r in self.resources:
            self.spent[r] += sign * self.amount(m, r)
        for a in self.gives.get(m, ()):
            self.have[a] = self.have.get(a, 0) + sign
        if m not in self.deployed_set:
            self.added += sign * self.weight[m]
        if sign > 0:
            self.chosen.append(m)
            self.inside.add(m)
        else:
            self.chosen.pop()
            self.inside.discard(m)

    def promising(self, open_: list[Atom]) -> bool:
        """Whether some completion may beat the best set found (see the module docstring)."""
        valid = [a for a in open_ if not any(self.given_now(b) for b in self.cone(a))]
        worst = {}
        for r in self.resources:
            w = 0
            for a in open_:
                c = self.costs[r].get(a)
                if c is None:
                    return False  # unreachable
                if a in valid and c > w:
                    w = c
            if self.spent[r] + w > self.rooms[r]:
                return False
            worst[r] = w
        incumbent = self.best[0] if self.best is not None else None
        base = self.added + self.out_weight + self.lost
        key = tuple(-base if r is None else self.inits[r] - self.spent[r] - worst[r] for r in self.slots)
        if incumbent is not None and key <= incumbent:
            return False
        gone = self._gone(valid, base, incumbent)
        if incumbent is None:
            return True
        churn = base + sum(self.weight[x] for x in gone)
        used: set[str] = set()
        for a in open_:
            for f in self.landmarks.get(a, ()):
                if self.given_now(f) or not self.giver_sets[f].isdisjoint(used):
                    continue
                if any(x in self.deployed_set and x not in gone and x not in self.out for x in self.givers[f]):
                    continue
                c = self.cheapest_new[f]
                if c is None:
                    return False
                churn += c
                used |= self.giver_sets[f]
        key = tuple(-churn if r is None else k for r, k in zip(self.slots, key))
        return key > incumbent

    def _gone(self, valid: list[Atom], base: int, incumbent: Key | None) -> set[str]:
        """The deployed components not decided that no completion beating ``incumbent`` keeps:
        keeping one overdraws a room, or bounds the key by no more than the incumbent (its
        consumption plus the valid open facts' h_max with it free)."""
        gone: set[str] = set()
        for x in self.deployed:
            if x in self.inside or x in self.out or x in self.never:
                continue
            free = self.free_costs[x]
            ok = True
            with_x = {}
            for r in self.resources:
                w = max((free[r].get(a, 0) for a in valid), default=0)
                total = self.spent[r] + self.amount(x, r) + w
                if total > self.rooms[r]:
                    ok = False
                    break
                with_x[r] = total
            if ok and incumbent is not None:
                ok = tuple(-base if r is None else self.inits[r] - with_x[r] for r in self.slots) > incumbent
            if not ok:
                gone.add(x)  # every completion keeping x is no better
        return gone

    def leaf(self) -> None:
        components = set(self.chosen)
        order = self.fixed.order(components)
        if order is None:
            raise _GiveUp  # a cyclic support: no claim
        spent = {r: sum(self.amount(m, r) for m in components) for r in self.resources}
        churn = sum(self.weight[m] for m in components if m not in self.deployed_set)
        churn += sum(self.weight[m] for m in self.deployed if m not in components)
        key = tuple(-churn if r is None else self.inits[r] - spent[r] for r in self.slots)
        if self.best is None or key > self.best[0]:
            self.best = (key, order)

    def extras(self, i: int) -> None:
        deployed = self.deployed
        while i < len(deployed) and (
            deployed[i] in self.inside or deployed[i] in self.never or deployed[i] in self.out
        ):
            i += 1
        if i == len(deployed):
            self.leaf()
            return
        x = deployed[i]
        self.choose(x, 1)
        rest = [b for b in self.needs[x] if not self.given_now(b)]
        if self.promising(rest):
            self.support(list(reversed(rest)), i + 1, 0)
        self.choose(x, -1)
        self.out.add(x)
        self.out_weight += self.weight[x]
        if self.promising([]):
            self.extras(i + 1)
        self.out_weight -= self.weight[x]
        self.out.discard(x)

    def support(self, open_: list[Atom], i: int, depth: int) -> None:
        open_ = [a for a in open_ if not self.given_now(a)]
        if not open_:
            self.extras(i)
            return
        if depth > 1000:
            raise _GiveUp
        a = open_[-1]
        for m in self.offers.get(a, []):
            if m in self.inside or m in self.out:
                continue
            self.left -= 1
            if self.left < 0 or (self.deadline is not None and time.monotonic() > self.deadline):
                raise _GiveUp
            self.choose(m, 1)
            rest = [b for b in open_[:-1] + self.needs[m] if not self.given_now(b)]
            if self.promising(rest):
                self.support(rest, i, depth + 1)
            self.choose(m, -1)

    def run(self) -> tuple[list[str], tuple[Fraction, ...], bool] | None:
        proven = True
        try:
            if self.promising(self.goal):
                self.support(list(reversed(self.goal)), 0, 0)
        except (_GiveUp, RecursionError):
            proven = False
        if self.best is None:
            return None
        key, order = self.best
        values = tuple(
            Fraction(k, self.wscale) if r is None else Fraction(k, self.scale[r]) for r, k in zip(self.slots, key)
        )
        return order, values, proven


def churn_floor_refutes(inst: ir.Instance, objectives: Sequence[ir.Objective], values: Sequence[Fraction]) -> bool:
    """True when no composition is lexicographically better than ``values`` for a churn
    minimised first at 0 (issue 23: recompose proves its optimum without a solver when
    nothing changes).  No churn weight is negative, so no composition has a churn below 0;
    one of churn 0 fires every deployed component of positive weight at least once (one
    not fired is removed).  Each later objective must maximise a numeric resource with a
    constant initial value that only ``decrease`` effects change, each by a constant ≥ 0
    or by a θ of lower bound ≥ 0 (the least a firing takes: :func:`_amounts`); its final
    value is then at most the initial value less what those deployed components take once
    each.  When every such bound is at most the given value, nothing of churn 0 is better
    in any objective, and nothing else is better at all.  False: no claim.  The caller
    excludes soft constraints (their penalties would join the first objective)."""
    if not objectives or len(values) != len(objectives):
        return False
    first, *rest = objectives
    if first.sense is not ir.Sense.MINIMIZE or not isinstance(first.term, ir.TotalChurn) or values[0] != 0:
        return False
    if any(m.churn < 0 for m in inst.morphisms.values()):
        return False
    fired = [m for m in set(inst.problem.deployed) if m in inst.morphisms and inst.morphisms[m].churn > 0]
    for o, value in zip(rest, values[1:]):
        term = o.term
        if o.sense is not ir.Sense.MAXIMIZE or not isinstance(term, ir.ResourceRef):
            return False
        res, init = inst.resources.get(term.name), inst.problem.init.get(term.name)
        if res is None or not res.sort.is_numeric or init is None or not isinstance(init.value, ir.Const):
            return False
        amounts = _amounts(inst, term.name)
        if amounts is None:
            return False
        if init_value(inst, term.name) - sum((amounts.get(m, Fraction(0)) for m in fired), Fraction(0)) > value:
            return False
    return True


def tightened(inst: ir.Instance) -> ir.Instance:
    """``inst`` with what holds in every state of every composition made explicit for the
    relaxations that prove "nothing is better" without the step encoding — the counting
    relaxation (:func:`catc.smt.counting.better_refuted`) and the consumption abstraction —
    which count only resources with a bound and no conditions on values; the same
    compositions are valid in both (the relaxations of the result are still relaxations of
    ``inst``):

    * a lower bound on each written numeric resource that declares none, where the ranges
      every reachable state keeps (:func:`catc.semantics.bounds.numeric_ranges`, from the
      guards of its changes, its constant changes and initial value; sound over sequential
      and parallel steps alike) give one.  The budget of a model whose every purchase checks
      the price first is such a resource (bounded by 0);
    * ``:uses 0`` on a morphism with a precondition literal false in the initial state that
      reads only resources no morphism changes (and no parameter): it never fires — as a
      camera driver needing ``(= ambient bright)`` in the dark.

    ``inst`` itself when nothing changes.  (A hole of the domain is no morphism here: only
    ``catc synthesize`` fills one, with an encoding of its own.)"""
    written = {e.resource for m in inst.morphisms.values() for e in m.effects}
    resources = dict(inst.resources)
    start: dict[str, object] | None = None
    if any(r.lower is None and r.sort.is_numeric and r.name in written for r in inst.resources.values()):
        start = initial_state(inst)
        for name, (lo, _hi) in ranges(inst, start).items():
            res = inst.resources[name]
            if res.lower is None and name in written and lo is not None:
                resources[name] = replace(res, lower=Fraction(lo))
    morphisms = dict(inst.morphisms)
    for m in inst.morphisms.values():
        if m.uses == 0:
            continue
        for lit in m.pre:
            if ir.params_in(lit.expr) or ir.resources_in(lit.expr) & written:
                continue
            if start is None:
                start = initial_state(inst)
            try:
                holds = evaluate(inst, lit.expr, start)
            except EvaluationError:  # no claim (a zero divisor among them)
                continue
            if holds is False:
                morphisms[m.name] = replace(m, uses=0)
                break
    if resources == dict(inst.resources) and morphisms == dict(inst.morphisms):
        return inst
    domain = replace(inst.domain, resources=resources, morphisms=morphisms)
    return ir.Instance(domain, inst.problem, inst.view)


def _landmarks(
    atoms: Collection[Atom], start: Collection[Atom], givers: dict[Atom, list[str]], needs: dict[str, list[Atom]]
) -> dict[Atom, frozenset[Atom]]:
    """Per fact, the facts (not holding initially) that every support of it gives, itself
    included: a fact's own and, for every giver, some of the giver's facts' — the
    intersection over its givers of the union of their facts' landmarks (a greatest fixpoint
    from "every fact"); a fact without a giver is left out."""
    everything = frozenset(a for a in atoms if a not in start)
    marks: dict[Atom, frozenset[Atom]] = {a: everything for a in everything if givers.get(a)}
    changed = True
    while changed:
        changed = False
        for a in list(marks):
            common: frozenset[Atom] | None = None
            for m in givers[a]:
                mine: set[Atom] = set()
                for b in needs[m]:
                    if b in start:
                        continue
                    mine |= marks.get(b, everything)
                common = frozenset(mine) if common is None else common & mine
            new = (common or frozenset()) | {a}
            if new != marks[a]:
                marks[a] = new
                changed = True
    return marks
