"""The forward search's reachable states as a reduced ordered BDD (issue 31, ``method:
"bdd"``): the certificate of a sequential UNSAT over more states than the explicit list of
``reachable`` takes (:data:`~catc.queries.certify.unsat.STATE_LIMIT`).

The BDD's variables are *atoms*, in a fixed order: a Boolean resource is one atom (the
resource itself); any other resource (a number, a symbol) is one atom per value it takes in
some reachable state, ``(= r v)``, in the order of those values.  A state sets exactly one
atom of each such resource, so the set of atom vectors the BDD accepts, read back over the
resources, is exactly the set of reachable states: a value no reachable state has makes every
atom of its resource false, and no accepted vector has that.  The BDD is built bottom-up from
the sorted state vectors (hash-consed: one node per distinct (atom, low, high), none whose
children are equal), so it is the canonical ROBDD of the set in that order.

Written to SMT-LIB2 it is one ``let`` per atom level, binding every node of that level as
``(ite atom high low)`` over the names the deeper levels bound: a shared DAG whose text grows
with the nodes, not the states.  :func:`bdd_obligations` states initiation, consecution and
goal exclusion of it over the unrelaxed sequential one-step encoding, as ``reachable`` does;
``catc certify`` reads the atoms and nodes back (:func:`read_bdd`: ordered, children before
parents, E1302 otherwise) and rebuilds the same obligations.  The checkers decide them; the
BDD's canonicity is not claimed by the certificate, only used to make it small.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir import SortKind
from catc.queries.base import InputError
from catc.queries.certify.document import _inductive, _number
from catgrammar import codes

#: The most states the BDD method enumerates (the forward search's own exhaustion); more: E1304.
BDD_STATE_LIMIT = 200_000

FALSE, TRUE = 0, 1  # the terminals; a node k ≥ 2 is ``nodes[k - 2]``


class Robdd:
    """A hash-consed reduced ordered BDD: nodes ``(level, low, high)`` numbered from 2, every
    node's children numbered below it."""

    def __init__(self) -> None:
        self.nodes: list[tuple[int, int, int]] = []
        self._unique: dict[tuple[int, int, int], int] = {}

    def mk(self, level: int, low: int, high: int) -> int:
        if low == high:
            return low
        key = (level, low, high)
        found = self._unique.get(key)
        if found is None:
            found = len(self.nodes) + 2
            self.nodes.append(key)
            self._unique[key] = found
        return found


#: The most atoms a BDD is built over (its depth: the construction recurses once per atom).
ATOM_LIMIT = 500  # below the interpreter's recursion limit (1,000) with room for the callers


def build_set(vectors: Sequence[Sequence[bool]], width: int) -> tuple[Robdd, int]:
    """The ROBDD of the set of ``vectors`` (each ``width`` ≤ :data:`ATOM_LIMIT` bits) and its
    root, built bottom-up from their sorted order: the vectors sharing a prefix are one run."""
    assert width <= ATOM_LIMIT
    bdd = Robdd()
    rows = sorted({tuple(v) for v in vectors})

    def node(first: int, last: int, level: int) -> int:
        if first == last:
            return FALSE
        if level == width:
            return TRUE
        split = first
        while split < last and not rows[split][level]:  # False sorts before True
            split += 1
        return bdd.mk(level, node(first, split, level + 1), node(split, last, level + 1))

    return bdd, node(0, len(rows), 0)


def count(nodes: Sequence[Sequence[int]], root: int, width: int) -> int:
    """How many vectors of ``width`` bits the BDD (``nodes`` as :class:`Robdd` numbers them)
    accepts: a level a path skips counts both ways."""

    def level(k: int) -> int:
        return width if k < 2 else nodes[k - 2][0]

    memo: dict[int, int] = {FALSE: 0, TRUE: 1}
    for k in range(2, len(nodes) + 2):  # children are numbered below their parents
        a, low, high = nodes[k - 2]
        memo[k] = memo[low] * 2 ** (level(low) - a - 1) + memo[high] * 2 ** (level(high) - a - 1)
    return memo[root] * 2 ** level(root)


def force_order(names: Sequence[str], edges: Sequence[frozenset[str]], rounds: int = 30) -> list[str]:
    """FORCE (Aloul, Markov & Sakallah 2003): resources that morphisms touch together are
    moved together — each round, every resource goes to the mean of the centres of gravity of
    the edges (one per morphism: what it reads and writes) it is in; ties keep the order."""
    order = list(names)
    edges = [e for e in (frozenset(e) & set(names) for e in edges) if len(e) > 1]
    for _ in range(rounds):
        pos = {n: i for i, n in enumerate(order)}
        centre = [sum(pos[n] for n in e) / len(e) for e in edges]
        pull: dict[str, list[float]] = {n: [] for n in order}
        for c, e in zip(centre, edges):
            for n in e:
                pull[n].append(c)
        moved = sorted(order, key=lambda n: (sum(pull[n]) / len(pull[n]) if pull[n] else pos[n], pos[n]))
        if moved == order:
            break
        order = moved
    return order


# -- the reachable states as a BDD (what the certificate holds)


def _value(v: Any) -> Any:
    return v if isinstance(v, bool | str) else str(Fraction(v))


def _key(v: Any) -> tuple[int, Any]:
    return (0, Fraction(v)) if not isinstance(v, str) else (1, v)


def bdd_json(inst: ir.Instance, names: Sequence[str], states: Sequence[Sequence[Any]]) -> dict | None:
    """The reachable ``states`` (one value per resource of ``names``) as the certificate's
    ``bdd``: ``atoms`` ([resource, value] in the BDD's order: a Boolean one atom ``true``,
    another resource one atom per value it takes, in the resources' order or FORCE's,
    :func:`force_order`, whichever gives fewer nodes), ``nodes`` ([atom, low, high], node
    k ≥ 2 at index k − 2; 0 false, 1 true), ``root`` and ``states`` (the count).  None when
    there are more than :data:`ATOM_LIMIT` atoms."""
    column = {n: i for i, n in enumerate(names)}
    seen: dict[Any, Any] = {}  # each value's JSON form, converted once
    rows = [
        tuple(x if x is True or x is False else seen.get(x) or seen.setdefault(x, _value(x)) for x in s) for s in states
    ]
    edges = [m.reads | m.writes for m in inst.morphisms.values()]
    best: dict | None = None
    for order in (list(names), force_order(names, edges)):
        atoms: list[tuple[str, Any]] = []
        for name in order:
            if inst.resources[name].sort.kind is SortKind.BOOL:
                atoms.append((name, True))
            else:
                i = column[name]
                atoms += [(name, v) for v in sorted({s[i] for s in rows}, key=_key)]
        if len(atoms) > ATOM_LIMIT:
            return None
        tests = [(column[n], v) for n, v in atoms]
        vectors = [tuple(s[i] is True if v is True else s[i] == v for i, v in tests) for s in rows]
        bdd, root = build_set(vectors, len(atoms))
        if best is None or len(bdd.nodes) < len(best["nodes"]):
            best = {"atoms": [[n, v] for n, v in atoms], "nodes": [list(x) for x in bdd.nodes], "root": root}
            best["states"] = len(set(vectors))
    return best


def read_bdd(inst: ir.Instance, spec: Any) -> dict:
    """The certificate's BDD, checked for shape against the model (E1302 otherwise): atoms of
    the model's resources with values of their sorts, nodes ordered (a child's atom after its
    parent's) and numbered after their children, and ``states`` its count of accepted vectors."""

    def bad(why: str) -> InputError:
        return InputError(f"the certificate's bdd {why}", codes.BAD_CERTIFICATE)

    if not isinstance(spec, dict) or set(spec) != {"atoms", "nodes", "root", "states"}:
        raise bad("must give its atoms, nodes, root and states")
    atoms, nodes, root = spec["atoms"], spec["nodes"], spec["root"]
    if not isinstance(atoms, list) or not isinstance(nodes, list) or len(atoms) > ATOM_LIMIT:
        raise bad(f"must list its atoms (at most {ATOM_LIMIT}) and its nodes")
    for atom in atoms:
        if not (isinstance(atom, list) and len(atom) == 2 and atom[0] in inst.resources):
            raise bad("has an atom that is not [resource, value] of a resource of the model")
        sort, v = inst.resources[atom[0]].sort, atom[1]
        fits = (
            (sort.kind is SortKind.BOOL and v is True)
            or (sort.is_numeric and isinstance(v, str) and _exact(v))
            or (sort.kind in (SortKind.SYMBOL, SortKind.ENUM) and isinstance(v, str))
        )
        if not fits:
            raise bad(f"has an atom of resource '{atom[0]}' whose value does not fit its sort")

    def level(k: int) -> int:
        return len(atoms) if k < 2 else nodes[k - 2][0]

    for k, n in enumerate(nodes, start=2):
        ints = isinstance(n, list) and len(n) == 3 and all(type(x) is int for x in n)
        if not ints or not 0 <= n[0] < len(atoms) or not all(0 <= c < k for c in n[1:]):
            raise bad(f"node {k} must be [atom, low, high] with children numbered below it")
        if not all(level(c) > n[0] for c in n[1:]):
            raise bad(f"node {k} is not ordered: a child tests an atom before its own")
    if type(root) is not int or not 0 <= root < len(nodes) + 2:
        raise bad("root is not one of its nodes")
    if spec["states"] != count(nodes, root, len(atoms)):
        raise bad("accepts another number of states than it claims")
    return spec


def _exact(text: str) -> bool:
    try:
        Fraction(text)
    except (ValueError, ZeroDivisionError):
        return False
    return True


def bdd_text(enc: Any, spec: Mapping[str, Any], state: Any) -> str:
    """``Inv``: the BDD over ``state``'s variables, one ``let`` per atom level (deepest first)
    binding each node of that level as ``(ite atom high low)``."""

    def name(k: int) -> str:
        return "false" if k == FALSE else "true" if k == TRUE else f"|bdd!{k}|"

    def atom(i: int) -> str:
        resource, v = spec["atoms"][i]
        r, var = enc.inst.resources[resource], state[resource]
        if r.sort.kind is SortKind.BOOL:
            return str(var)
        if r.sort.is_numeric:
            return f"(= {var} {_number(Fraction(v), r.sort.kind)})"
        universe = enc.finite.universe(r.sort)  # a symbol: its index in the horizon's universe
        return f"(= {var} {universe.index(v)})" if v in universe.elements else "false"

    levels: dict[int, list[int]] = {}
    for k, (a, _, _) in enumerate(spec["nodes"], start=2):
        levels.setdefault(a, []).append(k)
    opened = []
    for a in sorted(levels, reverse=True):
        test = atom(a)
        binds = " ".join(
            f"({name(k)} (ite {test} {name(spec['nodes'][k - 2][2])} {name(spec['nodes'][k - 2][1])}))"
            for k in levels[a]
        )
        opened.append(f"(let ({binds})")
    return " ".join(opened) + f" {name(spec['root'])}" + ")" * len(opened)


def bdd_obligations(inst: ir.Instance, spec: Mapping[str, Any], horizon: int) -> list[dict]:
    """Initiation, consecution and goal exclusion of "the state is accepted by the BDD of the
    reachable states" over the unrelaxed sequential one-step encoding."""
    return _inductive(inst, horizon, True, lambda enc, state: bdd_text(enc, spec, state))


def bdd_certificate(
    inst: ir.Instance, doc: dict[str, Any], result: Any, found: tuple[Sequence[str], Sequence[Sequence[Any]]]
) -> dict | None:
    """The BDD certificate (sequential steps) of the states ``found`` — every state
    compositions of any length reach (:func:`catc.semantics.search.reachable_states`), none a
    goal state; None when their BDD would have more than :data:`ATOM_LIMIT` atoms."""
    from catc.queries.certify.document import SEARCH, _produced

    spec = bdd_json(inst, *found)
    if spec is None:
        return None
    doc = doc | {"answer": "unsat", "method": "bdd", "producer": SEARCH, "horizon": result.horizon}
    doc |= {"sequential": True, "bdd": spec, "obligations": bdd_obligations(inst, spec, result.horizon)}
    return _produced(doc, SEARCH)
