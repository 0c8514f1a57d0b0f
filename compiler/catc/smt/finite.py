"""Finite universes of symbolic sorts (paper Proposition 1: finite grounding).

(Named apart from *deployment* grounding — :mod:`catc.ir.grounding`, :mod:`catc.targets.grounding` —
what a component becomes on the robot.)

Each root symbolic sort (and each enumeration) gets a finite universe: its constants — of
the domain, its imports and the problem — followed by *reserve* values, one per free
variable of that sort that can take a value nobody named.  Symbols are encoded as integer
indices into their root's universe; sets as one Boolean per universe element.

How many reserves: a per-activation parameter θ of sort T of morphism a has one variable
per step, but only activated ones matter and a is activated at most ``min(k, uses_a)``
times, so that many reserves of sort T suffice; a ``:fixed`` θ needs one.  Enumerations are
closed and get none.
"""

from __future__ import annotations

from catc import ir
from catc.ir import SortKind
from catc.semantics.plan import fresh_name
from catgrammar import limits
from catgrammar.record import Record, set_field


class Universe(Record):
    """The grounded values of one root sort."""

    __slots__ = ("root", "elements", "fresh", "sort_of", "_index")
    _fields = ("root", "elements", "fresh", "sort_of")
    root: str
    elements: tuple[str, ...]
    fresh: frozenset[str]  # the reserve values
    sort_of: dict[str, str]  # element → its declared sort
    _index: dict[str, int]  # element → its position (a cache, not a field)

    def __init__(
        self,
        root: str,
        elements: tuple[str, ...],
        fresh: frozenset[str] = frozenset(),
        sort_of: dict[str, str] | None = None,
    ) -> None:
        set_field(self, "root", root)
        set_field(self, "elements", elements)
        set_field(self, "fresh", fresh)
        set_field(self, "sort_of", {} if sort_of is None else sort_of)
        set_field(self, "_index", {e: i for i, e in enumerate(elements)})

    def index(self, name: str) -> int:
        return self._index[name]

    def __len__(self) -> int:
        return len(self.elements)


def _within_limit(sort: ir.Sort, size: int, fresh: int, horizon: int) -> None:
    """E1106 (located at the sort) when a universe is larger than the universe limit."""
    most = limits.current().universe
    if size <= most:
        return
    limit = limits.BY_NAME["universe"]
    raise limits.LimitExceeded(
        limit.code,
        f"sort '{sort.name}' would be grounded with {limits.count_text(size)} values ({limits.count_text(fresh)} "
        f"reserve values for a horizon of {horizon}), more than the universe limit ({limits.count_text(most)}); "
        f"give its morphisms :uses limits or a shorter horizon, or {limit.how_to_raise}",
        sort.span,
    )


class FiniteSorts:
    """Universes for every symbolic sort of an instance, for horizon ``k``."""

    def __init__(self, inst: ir.Instance, horizon: int) -> None:
        self.inst = inst
        sorts = inst.domain.sorts
        self.root: dict[str, str] = {}
        for name in sorts:
            r = name
            seen = set()
            while r not in seen:
                parent = sorts[r].parent
                if not parent:
                    break
                seen.add(r)
                r = parent
            self.root[name] = r
        # reserves needed per declared sort
        need: dict[str, int] = {}
        for m in inst.morphisms.values():
            for p in m.params:
                if p.sort.kind is SortKind.SYMBOL:
                    count = 1 if p.fixed else min(horizon, m.uses if m.uses is not None else horizon)
                    need[p.sort.name] = need.get(p.sort.name, 0) + count
        constants = inst.constants()
        self.universes: dict[str, Universe] = {}
        for name, s in sorts.items():
            if self.root[name] != name:
                continue
            if s.kind is SortKind.ENUM:
                self.universes[name] = Universe(name, s.values, frozenset(), {v: name for v in s.values})
                continue
            members = [
                c for c in constants.values() if c.sort.kind is SortKind.SYMBOL and self.root.get(c.sort.name) == name
            ]
            elements = [c.name for c in members]
            sort_of = {c.name: c.sort.name for c in members}
            subs = sorted(n for n in sorts if self.root[n] == name)
            reserves = sum(need.get(sub, 0) for sub in subs)
            _within_limit(s, len(elements) + reserves, reserves, horizon)
            fresh = []
            for sub in subs:
                for i in range(1, need.get(sub, 0) + 1):
                    f = fresh_name(sub, i)
                    fresh.append(f)
                    sort_of[f] = sub
            self.universes[name] = Universe(name, tuple(elements + fresh), frozenset(fresh), sort_of)

    def universe(self, sort: ir.Sort) -> Universe:
        return self.universes[self.root[sort.name]]

    def allowed(self, sort: ir.Sort) -> list[int]:
        """Indices of the values a variable of ``sort`` may take (its sub-sorts included)."""
        u = self.universe(sort)
        if sort.kind is SortKind.ENUM:
            return list(range(len(u)))
        subs = self.inst.subsorts(sort)
        return [i for i, e in enumerate(u.elements) if u.sort_of[e] in subs]

    @property
    def fresh(self) -> dict[str, str]:
        return {f: u.sort_of[f] for u in self.universes.values() for f in u.fresh}
