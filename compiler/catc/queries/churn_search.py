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

Any doubt gives no claim (None; the caller asks the solver): more than :data:`EXPANSIONS`
branches, a built set without a firing order (a cyclic support), a set the validator
rejects or whose replay scores less than its optimistic key.
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

from catc import ir
from catc.smt.consumption import (
    Atom,
    FixedSet,
    _atom_costs,
    _atoms,
    _givers,
    _holds,
    init_value,
    overdrawing,
)

#: The most branches :func:`best_set` tries before it gives up (no claim).
EXPANSIONS = 200_000

Key = tuple[Fraction, ...]  # greater is better: objective values, then -churn (or the reverse)


class _GiveUp(Exception):
    pass


def best_set(
    inst: ir.Instance, objectives: Sequence[ir.Objective], expansions: int = EXPANSIONS
) -> tuple[list[str], Key] | None:
    """The passing component set of greatest optimistic key for ``objectives`` (churn and
    maximised only-decreasing resources, in their lexicographic order), in an order it can
    fire, with that key (each objective as a value to maximise: churn negated); None when
    the search cannot say (see the module docstring) or no set passes."""
    fixed = FixedSet(inst)
    decreasing = fixed.decreasing
    rooms = fixed.rooms
    slots: list[str | None] = []  # per objective: the resource it maximises, None for churn
    for o in objectives:
        if isinstance(o.term, ir.TotalChurn) and o.sense is ir.Sense.MINIMIZE:
            slots.append(None)
        elif o.sense is ir.Sense.MAXIMIZE and isinstance(o.term, ir.ResourceRef) and o.term.name in decreasing:
            slots.append(o.term.name)
        else:
            return None
    weight = {m.name: Fraction(m.churn) for m in inst.morphisms.values()}
    if any(w <= 0 for w in weight.values()):
        return None
    deployed_set = set(inst.problem.deployed)
    deployed = [m for m in inst.morphisms if m in deployed_set]
    given, any_element = _givers(inst)
    never = overdrawing(inst, decreasing) | fixed.unusable
    needs = {m: list(dict.fromkeys(ns)) for m, ns in fixed.needs.items()}
    goal = list(dict.fromkeys(fixed.goal))
    atoms = set(given) | {a for ns in needs.values() for a in ns} | set(goal)
    costs = {r: _atom_costs(inst, given, any_element, needs, atoms, decreasing[r], never) for r in decreasing}
    inits = {r: init_value(inst, r) for r in decreasing}
    gives_of, adds_of = fixed.gives_of, fixed.adds_of
    if any(m not in never and m not in needs for m in deployed):
        return None

    lost = sum((weight[x] for x in deployed if x in never), Fraction(0))  # never fire: removed

    def amount(m: str, r: str) -> Fraction:
        return decreasing[r].get(m, Fraction(0))

    def sort_key(m: str) -> tuple:
        """Givers tried first: the best contribution to the key, then cheapest overall."""
        own = []
        for r in slots:
            own.append(-(weight[m] if m not in deployed_set else Fraction(0)) if r is None else -amount(m, r))
        spend = sum((amount(m, r) / rooms[r] for r in decreasing if rooms[r] > 0), Fraction(0))
        return (*(-x for x in own), spend)

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
            and set(gives_of.get(a, [])) == set(gives_of.get(b, []))
            and set(adds_of.get(a, [])) == set(adds_of.get(b, []))
            and all(amount(a, r) <= amount(b, r) for r in decreasing)
        )

    order_of = {m: i for i, m in enumerate(inst.morphisms)}
    offers: dict[Atom, list[str]] = {}
    for a in atoms:
        ms = [m for m, _ in given.get(a, []) + (any_element.get(a[0], []) if a[1] is not None else [])]
        ms = [m for m in dict.fromkeys(ms) if m not in never]
        kept = [
            b
            for b in ms
            if not any(
                x != b and dominates(x, b) and (not dominates(b, x) or order_of[x] < order_of[b]) for x in ms
            )
        ]
        offers[a] = sorted(kept, key=sort_key)

    def initially(a: Atom) -> bool:
        init = inst.problem.init.get(a[0])
        return init is None or _holds(init, a)

    spent = dict.fromkeys(decreasing, Fraction(0))
    chosen: list[str] = []
    inside: set[str] = set()
    out: set[str] = set()  # deployed components decided out
    gives: dict[Atom, int] = {}
    wild: dict[str, int] = {}
    added = [Fraction(0)]  # the churn weight of the chosen components that are not deployed
    left = [expansions]
    best: list = [None]  # (key, components)

    def given_now(a: Atom) -> bool:
        return initially(a) or gives.get(a, 0) > 0 or (a[1] is not None and wild.get(a[0], 0) > 0)

    def choose(m: str, sign: int) -> None:
        for r in decreasing:
            spent[r] += sign * amount(m, r)
        for a in gives_of.get(m, []):
            gives[a] = gives.get(a, 0) + sign
        for r in adds_of.get(m, []):
            wild[r] = wild.get(r, 0) + sign
        if m not in deployed_set:
            added[0] += sign * weight[m]
        if sign > 0:
            chosen.append(m)
            inside.add(m)
        else:
            chosen.pop()
            inside.discard(m)

    def bound(open_: list[Atom], extra: str | None = None, gone: Fraction = Fraction(0)) -> Key | None:
        """The optimistic key of every completion (with ``extra`` in it as well; ``gone``:
        the churn of deployed components known out besides ``out``); None: none fits."""
        worst: dict[str, Fraction] = {}
        for r, cost in costs.items():
            w = Fraction(0)
            for a in open_:
                c = cost.get(a)
                if c is None:
                    return None
                w = max(w, c)
            total = spent[r] + w + (amount(extra, r) if extra is not None else Fraction(0))
            if total > rooms[r]:
                return None
            worst[r] = total
        churn = added[0] + gone + lost + sum((weight[x] for x in out), Fraction(0))
        if extra is not None and extra not in deployed_set:
            churn += weight[extra]
        return tuple(-churn if r is None else inits[r] - worst[r] for r in slots)

    def promising(open_: list[Atom]) -> bool:
        """Whether some completion may beat the best set found (see the module docstring)."""
        key = bound(open_)
        if key is None:
            return False
        incumbent = best[0][0] if best[0] is not None else None
        if incumbent is not None and key <= incumbent:
            return False
        gone = Fraction(0)
        for x in deployed:
            if x in inside or x in out or x in never:
                continue
            with_x = bound(open_, x)
            if with_x is None or (incumbent is not None and with_x <= incumbent):
                gone += weight[x]  # every completion keeping x is no better
        if gone:
            key = bound(open_, gone=gone)
            if key is None or (incumbent is not None and key <= incumbent):
                return False
        return True

    def leaf() -> None:
        components = set(chosen)
        order = fixed.order(components)
        if order is None:
            raise _GiveUp  # a cyclic support: no claim
        spent_now = fixed.spent(components)
        churn = sum((weight[m] for m in components if m not in deployed_set), Fraction(0))
        churn += sum((weight[m] for m in deployed if m not in components), Fraction(0))
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
        for keep in (True, False):
            if keep:
                choose(x, 1)
                rest = [b for b in needs[x] if not given_now(b)]
                if promising(rest):
                    support(list(reversed(rest)), i + 1, 0)
                choose(x, -1)
            else:
                out.add(x)
                if promising([]):
                    extras(i + 1)
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
            left[0] -= 1
            if left[0] < 0:
                raise _GiveUp
            choose(m, 1)
            rest = [b for b in open_[:-1] + needs[m] if not given_now(b)]
            if promising(rest):
                support(rest, i, depth + 1)
            choose(m, -1)

    try:
        if promising(goal):
            support(list(reversed(goal)), 0, 0)
    except _GiveUp:
        return None
    except RecursionError:
        return None
    if best[0] is None:
        return None
    key, order = best[0]
    return order, key
