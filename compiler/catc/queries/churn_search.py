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
from catc.smt.consumption import Atom, FixedSet, _givers, _holds, init_value, overdrawing

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
    decreasing = fixed.decreasing
    slots: list[str | None] = []  # per objective: the resource it maximises, None for churn
    for o in objectives:
        if isinstance(o.term, ir.TotalChurn) and o.sense is ir.Sense.MINIMIZE:
            slots.append(None)
        elif o.sense is ir.Sense.MAXIMIZE and isinstance(o.term, ir.ResourceRef) and o.term.name in decreasing:
            slots.append(o.term.name)
        else:
            return None
    weights = {m.name: Fraction(m.churn) for m in inst.morphisms.values()}
    if any(w <= 0 for w in weights.values()):
        return None
    # integers throughout: each resource (and the churn weights) scaled by its denominators
    scale = {r: _scale([*amounts.values(), fixed.rooms[r], init_value(inst, r)]) for r, amounts in decreasing.items()}
    wscale = _scale(weights.values())
    weight = {m: int(w * wscale) for m, w in weights.items()}
    amt = {r: {m: int(a * scale[r]) for m, a in amounts.items()} for r, amounts in decreasing.items()}
    rooms = {r: int(fixed.rooms[r] * scale[r]) for r in decreasing}
    inits = {r: int(init_value(inst, r) * scale[r]) for r in decreasing}
    resources = list(decreasing)

    deployed_set = set(inst.problem.deployed)
    deployed = [m for m in inst.morphisms if m in deployed_set]
    given, any_element = _givers(inst)
    never = overdrawing(inst, decreasing) | fixed.unusable
    needs = {m: list(dict.fromkeys(ns)) for m, ns in fixed.needs.items()}
    goal = list(dict.fromkeys(fixed.goal))
    atoms = set(given) | {a for ns in needs.values() for a in ns} | set(goal)

    def initially(a: Atom) -> bool:
        init = inst.problem.init.get(a[0])
        return init is None or _holds(init, a)

    start = {a for a in atoms if initially(a)}
    # who gives each fact (never-firing morphisms left out), and what each morphism gives
    givers: dict[Atom, list[str]] = {}
    for a in atoms:
        ms = [m for m, _ in given.get(a, []) + (any_element.get(a[0], []) if a[1] is not None else [])]
        givers[a] = [m for m in dict.fromkeys(ms) if m not in never]
    gives: dict[str, list[Atom]] = {}
    for a, ms in givers.items():
        for m in ms:
            gives.setdefault(m, []).append(a)
    live = {m: ns for m, ns in needs.items() if m not in never}
    need_of: dict[Atom, list[str]] = {}
    for m, ns in live.items():
        for a in ns:
            need_of.setdefault(a, []).append(m)
    costs = {r: _hmax(givers, need_of, live, gives, start, amt[r]) for r in resources}
    free_costs = {x: {r: _hmax(givers, need_of, live, gives, start, amt[r], x) for r in resources} for x in deployed}

    cones: dict[Atom, frozenset[Atom]] = {}  # the facts a fact's supports may give (not initial)

    def cone(a: Atom) -> frozenset[Atom]:
        if a not in cones:
            seen: set[Atom] = set()
            todo = [a]
            while todo:
                b = todo.pop()
                for m in givers.get(b, ()):
                    for c in live[m]:
                        if c not in seen and c not in start:
                            seen.add(c)
                            todo.append(c)
            cones[a] = frozenset(seen)
        return cones[a]

    landmarks = _landmarks(atoms, start, givers, live)
    giver_sets = {a: frozenset(ms) for a, ms in givers.items()}
    cheapest_new = {a: min((weight[m] for m in ms if m not in deployed_set), default=None) for a, ms in givers.items()}

    def amount(m: str, r: str) -> int:
        return amt[r].get(m, 0)

    def dominates(a: str, b: str) -> bool:
        if a in deployed_set and b not in deployed_set:
            churn_ok = True
        elif (a in deployed_set) == (b in deployed_set):
            churn_ok = weight[b] <= weight[a] if a in deployed_set else weight[a] <= weight[b]
        else:
            churn_ok = False
        return (
            churn_ok
            and set(needs[a]) == set(needs[b])
            and set(gives.get(a, [])) == set(gives.get(b, []))
            and all(amount(a, r) <= amount(b, r) for r in resources)
        )

    def sort_key(m: str) -> tuple:
        """Givers tried first: the best contribution to the key, then cheapest overall."""
        own = [(weight[m] if m not in deployed_set else 0) if r is None else amount(m, r) for r in slots]
        spend = sum((Fraction(amount(m, r), rooms[r]) for r in resources if rooms[r] > 0), Fraction(0))
        return (*own, spend)

    order_of = {m: i for i, m in enumerate(inst.morphisms)}
    offers: dict[Atom, list[str]] = {}
    for a, ms in givers.items():
        kept = [
            b
            for b in ms
            if not any(x != b and dominates(x, b) and (not dominates(b, x) or order_of[x] < order_of[b]) for x in ms)
        ]
        offers[a] = sorted(kept, key=sort_key)

    spent = dict.fromkeys(resources, 0)
    chosen: list[str] = []
    inside: set[str] = set()
    out: set[str] = set()  # deployed components decided out
    have: dict[Atom, int] = {}  # fact → how many chosen components give it
    state = {"added": 0, "out": 0, "left": expansions}
    lost = sum(weight[x] for x in deployed if x in never)  # never fire: removed
    best: list = [None]  # (key, order)

    def given_now(a: Atom) -> bool:
        return a in start or have.get(a, 0) > 0

    def choose(m: str, sign: int) -> None:
        for r in resources:
            spent[r] += sign * amount(m, r)
        for a in gives.get(m, ()):
            have[a] = have.get(a, 0) + sign
        if m not in deployed_set:
            state["added"] += sign * weight[m]
        if sign > 0:
            chosen.append(m)
            inside.add(m)
        else:
            chosen.pop()
            inside.discard(m)

    def promising(open_: list[Atom]) -> bool:
        """Whether some completion may beat the best set found (see the module docstring)."""
        valid = [a for a in open_ if not any(given_now(b) for b in cone(a))]
        worst = {}
        for r in resources:
            w = 0
            for a in open_:
                c = costs[r].get(a)
                if c is None:
                    return False  # unreachable
                if a in valid and c > w:
                    w = c
            if spent[r] + w > rooms[r]:
                return False
            worst[r] = w
        incumbent = best[0][0] if best[0] is not None else None
        base = state["added"] + state["out"] + lost
        key = tuple(-base if r is None else inits[r] - spent[r] - worst[r] for r in slots)
        if incumbent is not None and key <= incumbent:
            return False
        gone: set[str] = set()
        for x in deployed:
            if x in inside or x in out or x in never:
                continue
            free = free_costs[x]
            ok = True
            with_x = []
            for r in resources:
                w = max((free[r].get(a, 0) for a in valid), default=0)
                total = spent[r] + amount(x, r) + w
                if total > rooms[r]:
                    ok = False
                    break
                with_x.append(total)
            if ok and incumbent is not None:
                by = dict(zip(resources, with_x))
                ok = tuple(-base if r is None else inits[r] - by[r] for r in slots) > incumbent
            if not ok:
                gone.add(x)  # every completion keeping x is no better
        if incumbent is None:
            return True
        churn = base + sum(weight[x] for x in gone)
        used: set[str] = set()
        for a in open_:
            for f in landmarks.get(a, ()):
                if given_now(f) or not giver_sets[f].isdisjoint(used):
                    continue
                if any(x in deployed_set and x not in gone and x not in out for x in givers[f]):
                    continue
                c = cheapest_new[f]
                if c is None:
                    return False
                churn += c
                used |= giver_sets[f]
        key = tuple(-churn if r is None else k for r, k in zip(slots, key))
        return key > incumbent

    def leaf() -> None:
        components = set(chosen)
        order = fixed.order(components)
        if order is None:
            raise _GiveUp  # a cyclic support: no claim
        spent_now = {r: sum(amount(m, r) for m in components) for r in resources}
        churn = sum(weight[m] for m in components if m not in deployed_set)
        churn += sum(weight[m] for m in deployed if m not in components)
        key = tuple(-churn if r is None else inits[r] - spent_now[r] for r in slots)
        if best[0] is None or key > best[0][0]:
            best[0] = (key, order)

    def extras(i: int) -> None:
        while i < len(deployed) and (deployed[i] in inside or deployed[i] in never or deployed[i] in out):
            i += 1
        if i == len(deployed):
            leaf()
            return
        x = deployed[i]
        choose(x, 1)
        rest = [b for b in needs[x] if not given_now(b)]
        if promising(rest):
            support(list(reversed(rest)), i + 1, 0)
        choose(x, -1)
        out.add(x)
        state["out"] += weight[x]
        if promising([]):
            extras(i + 1)
        state["out"] -= weight[x]
        out.discard(x)

    def support(open_: list[Atom], i: int, depth: int) -> None:
        open_ = [a for a in open_ if not given_now(a)]
        if not open_:
            extras(i)
            return
        if depth > 1000:
            raise _GiveUp
        a = open_[-1]
        for m in offers.get(a, []):
            if m in inside or m in out:
                continue
            state["left"] -= 1
            if state["left"] < 0 or (deadline is not None and time.monotonic() > deadline):
                raise _GiveUp
            choose(m, 1)
            rest = [b for b in open_[:-1] + needs[m] if not given_now(b)]
            if promising(rest):
                support(rest, i, depth + 1)
            choose(m, -1)

    proven = True
    try:
        if promising(goal):
            support(list(reversed(goal)), 0, 0)
    except (_GiveUp, RecursionError):
        proven = False
    if best[0] is None:
        return None
    key, order = best[0]
    values = tuple(Fraction(k, wscale) if r is None else Fraction(k, scale[r]) for r, k in zip(slots, key))
    return order, values, proven


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
