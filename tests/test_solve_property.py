"""Property: on small random ground domains, `solve` agrees with a brute-force breadth-first
search on SAT/UNSAT and on the length of the shortest composition.

The search below is a third, deliberately naive implementation of docs/semantics.md §4 for
a fragment (bool resources, one bounded int counter, use limits, parallel steps with
non-interference): it enumerates every set of activations from every reachable state.
"""

from __future__ import annotations

import itertools
import os
from dataclasses import dataclass

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from catc.frontend.workspace import load_instance
from catc.queries.solve import SolveStatus, solve
from catgrammar.diagnostics import Diagnostics

COUNTER_MAX = 3


@dataclass(frozen=True)
class Lit:
    kind: str  # "b" (bool is true), "nb" (bool is false), "ge", "le"
    target: int  # bool index or bound for the counter

    def text(self) -> str:
        return {
            "b": f"b{self.target}",
            "nb": f"(not b{self.target})",
            "ge": f"(>= c {self.target})",
            "le": f"(<= c {self.target})",
        }[self.kind]

    def holds(self, bools, c) -> bool:
        return {
            "b": lambda: bools[self.target],
            "nb": lambda: not bools[self.target],
            "ge": lambda: c >= self.target,
            "le": lambda: c <= self.target,
        }[self.kind]()

    @property
    def reads(self) -> str:
        return f"b{self.target}" if self.kind in ("b", "nb") else "c"


@dataclass(frozen=True)
class Eff:
    kind: str  # "set", "clear", "inc", "dec"
    target: int

    def text(self) -> str:
        return {
            "set": f"(assign b{self.target} true)",
            "clear": f"(assign b{self.target} false)",
            "inc": "(increase c 1)",
            "dec": "(decrease c 1)",
        }[self.kind]

    @property
    def resource(self) -> str:
        return "c" if self.kind in ("inc", "dec") else f"b{self.target}"


@dataclass(frozen=True)
class Morph:
    pre: tuple[Lit, ...]
    effects: tuple[Eff, ...]
    uses: int | None

    def apply(self, bools: list[bool], c: int) -> int:
        """Do the effects to ``bools`` (in place); the counter after them."""
        for e in self.effects:
            if e.kind == "set":
                bools[e.target] = True
            elif e.kind == "clear":
                bools[e.target] = False
            else:
                c += 1 if e.kind == "inc" else -1
        return c


@st.composite
def domains(draw):
    nb = draw(st.integers(2, 3))
    lit = st.one_of(
        st.builds(Lit, st.sampled_from(["b", "nb"]), st.integers(0, nb - 1)),
        st.builds(Lit, st.sampled_from(["ge", "le"]), st.integers(0, COUNTER_MAX)),
    )
    eff = st.one_of(
        st.builds(Eff, st.sampled_from(["set", "clear"]), st.integers(0, nb - 1)),
        st.builds(Eff, st.sampled_from(["inc", "dec"]), st.just(0)),
    )
    morphs = []
    for _ in range(draw(st.integers(1, 4))):
        effects = draw(st.lists(eff, min_size=1, max_size=2, unique_by=lambda e: e.resource))
        morphs.append(
            Morph(tuple(draw(st.lists(lit, max_size=2))), tuple(effects), draw(st.one_of(st.none(), st.integers(1, 2))))
        )
    init_bools = tuple(draw(st.lists(st.booleans(), min_size=nb, max_size=nb)))
    init_c = draw(st.integers(0, COUNTER_MAX))
    goal = tuple(draw(st.lists(lit, min_size=1, max_size=2)))
    horizon = draw(st.integers(0, 3))
    return nb, tuple(morphs), init_bools, init_c, goal, horizon


def to_cat(nb, morphs, init_bools, init_c, goal, horizon) -> str:
    lines = [
        "(define (domain random)",
        "  (:requirements :numeric)",
        f"  (:resources (c int :bounds (0 {COUNTER_MAX})) {' '.join(f'(b{i} bool)' for i in range(nb))})",
    ]
    for i, m in enumerate(morphs):
        uses = f" :uses {m.uses}" if m.uses is not None else ""
        pre = f" :precondition (and {' '.join(l.text() for l in m.pre)})" if m.pre else ""
        lines.append(f"  (:morphism m{i}{uses}{pre} :effect (and {' '.join(e.text() for e in m.effects)}))")
    lines.append(")")
    init = " ".join([f"(= c {init_c})"] + [f"b{i}" for i, v in enumerate(init_bools) if v])
    lines.append(
        f"(define (problem p) (:domain random) (:init {init}) (:goal (and {' '.join(l.text() for l in goal)})) (:horizon {horizon}))"
    )
    return "\n".join(lines)


def interferes(a: Morph, b: Morph) -> bool:
    reads_b = {l.reads for l in b.pre}
    writes_b = {e.resource for e in b.effects}
    for e in a.effects:
        if e.kind in ("set", "clear") and (e.resource in reads_b or e.resource in writes_b):
            return True
        if e.kind in ("inc", "dec") and e.resource in reads_b:
            return True
    return False


def successors(morphs, state):
    """Every state one valid step (a non-empty set of activations) leads to."""
    bools, c, used = state
    for size in range(1, len(morphs) + 1):
        for combo in itertools.combinations(range(len(morphs)), size):
            ms = [morphs[i] for i in combo]
            if any(m.uses is not None and used[i] >= m.uses for i, m in zip(combo, ms)):
                continue
            if not all(l.holds(bools, c) for m in ms for l in m.pre):
                continue
            if any(interferes(x, y) for x in ms for y in ms if x is not y):
                continue
            new_b, new_c = list(bools), c
            for m in ms:
                new_c = m.apply(new_b, new_c)
            if 0 <= new_c <= COUNTER_MAX:
                yield tuple(new_b), new_c, tuple(u + (1 if i in combo else 0) for i, u in enumerate(used))


def shortest_by_bfs(nb, morphs, init_bools, init_c, goal, horizon) -> int | None:
    start = (init_bools, init_c, tuple(0 for _ in morphs))
    frontier = {start}
    seen = {start}
    for depth in range(horizon + 1):
        if any(all(l.holds(b, c) for l in goal) for b, c, _ in frontier):
            return depth
        nxt = set()
        for state in frontier:
            for succ in successors(morphs, state):
                if succ not in seen:
                    seen.add(succ)
                    nxt.add(succ)
        frontier = nxt
    return None


@settings(
    max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "60")),
    deadline=None,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
@given(domain=domains())
def test_solve_agrees_with_breadth_first_search(tmp_path, domain):
    path = tmp_path / "random.cat"
    path.write_text(to_cat(*domain))
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, [d.message for d in diags]
    expected = shortest_by_bfs(*domain)
    result = solve(inst, prune=False)
    if expected is None:
        assert result.status is SolveStatus.UNSAT
    else:
        assert result.status is SolveStatus.SAT and len(result.plan) == expected
    for sequential_ok in (True,):
        seq = solve(inst, sequential=sequential_ok, prune=False)
        assert (seq.status is SolveStatus.SAT) <= (
            result.status is SolveStatus.SAT
        )  # sequential is never more permissive
