"""Issue 24: dominance between alternatives (catc.smt.consumption.dominated) leaves the
consumption abstraction's least restoration as it is.  The independent reasons: a hand
calculation of which alternatives are dominated, and the least weighted raise found by
enumerating every choice of one alternative per level (with the helper an alternative's
extra precondition needs) on tiny seeded catalogs."""

from __future__ import annotations

import itertools
import random
import re
import sys
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "benchmarks"))

import catalog_gen as gen

from catc.api import loads
from catc.queries.relax import RelaxStatus, relax
from catc.smt.consumption import dominated, least_restoration

# an alternative: (budget, ram, needs the level's helper fact)
Alt = tuple[int, int, bool]


def _catalog(levels: list[list[Alt]], helpers: list[tuple[int, int]], budget: int, ram: int) -> Any:
    """A chain of levels; alternative ``alt{i}-{j}`` needs level ``i - 1`` (and, when its
    third field says so, the fact ``x{i}`` that helper ``h{i}`` gives for its own price)."""
    facts = " ".join(f"(l{i} bool) (x{i} bool)" for i in range(len(levels)))
    parts = [
        "(define (domain dom)\n  (:requirements :numeric)\n  (:resources\n"
        f"    (budget real :bounds (0 *)) (ram real :bounds (0 *)) {facts})"
    ]
    for i, (alts, (hb, hr)) in enumerate(zip(levels, helpers, strict=True)):
        parts.append(
            f"  (:morphism h{i} :uses 1\n    :effect (and (assign x{i} true) (decrease budget {hb}) (decrease ram {hr})))"
        )
        for j, (b, r, aux) in enumerate(alts):
            needs = ([f"l{i - 1}"] if i else []) + ([f"x{i}"] if aux else [])
            pre = f"\n    :precondition (and {' '.join(needs)})" if needs else ""
            parts.append(
                f"  (:morphism alt{i}-{j} :uses 1{pre}\n"
                f"    :effect (and (assign l{i} true) (decrease budget {b}) (decrease ram {r})))"
            )
    domain = "\n".join(parts) + ")\n"
    problem = (
        f"(define (problem p) (:domain dom)\n  (:init (= budget {budget}) (= ram {ram}))\n"
        f"  (:goal l{len(levels) - 1})\n  (:horizon {2 * len(levels)}))\n"
    )
    return loads({"domain.cat": domain, "p.cat": problem}, "p.cat").instance


def _brute(levels: list[list[Alt]], helpers: list[tuple[int, int]], budget: int, ram: int) -> Fraction:
    """The least raise (weight 1 each) over every choice of one alternative per level, its
    helper added when it needs one: more alternatives per level only consume more."""
    best = None
    for pick in itertools.product(*levels):
        b = sum(a[0] + (helpers[i][0] if a[2] else 0) for i, a in enumerate(pick))
        r = sum(a[1] + (helpers[i][1] if a[2] else 0) for i, a in enumerate(pick))
        cost = max(0, b - budget) + max(0, r - ram)
        best = cost if best is None else min(best, cost)
    assert best is not None
    return Fraction(best)


def test_dominated_by_hand() -> None:
    """One level: (1, 10) is beaten by nothing; (2, 10) and (1, 11) take more of one resource
    than it; the second (1, 10) is its twin, later in the catalog; (0, 10) needing the helper
    needs a fact (1, 10) does not, so it stays, and (1, 10) stays beside it (it needs less)."""
    levels = [[(1, 10, False), (2, 10, False), (1, 11, False), (1, 10, False), (0, 10, True), (3, 3, False)]]
    inst = _catalog(levels, [(5, 5)], 100, 100)
    assert dominated(inst) == {"alt0-1", "alt0-2", "alt0-3"}


def test_an_alternative_giving_more_is_not_dominated() -> None:
    """A cheaper morphism that gives less (the helper gives x0, not l0) dominates nothing."""
    levels = [[(4, 4, False)]]
    inst = _catalog(levels, [(1, 1)], 100, 100)
    assert dominated(inst) == set()


def _seeded(rng: random.Random) -> tuple[list[list[Alt]], list[tuple[int, int]]]:
    levels = [
        [(rng.randint(0, 6), rng.randint(0, 6), rng.random() < 0.3) for _ in range(rng.randint(2, 5))]
        for _ in range(rng.randint(2, 3))
    ]
    return levels, [(rng.randint(0, 3), rng.randint(0, 3)) for _ in levels]


@pytest.mark.parametrize("seed", range(12))
def test_least_restoration_with_dominance_is_the_brute_force_least(seed: int) -> None:
    rng = random.Random(seed)
    levels, helpers = _seeded(rng)
    budget = sum(min(a[0] for a in alts) for alts in levels) + rng.randint(-2, 1)
    ram = sum(min(a[1] for a in alts) for alts in levels) + rng.randint(-2, 1)
    budget, ram = max(budget, 0), max(ram, 0)
    inst = _catalog(levels, helpers, budget, ram)
    reqs = [("init/budget", "initial value", Fraction(1)), ("init/ram", "initial value", Fraction(1))]
    least = _brute(levels, helpers, budget, ram)
    pruned = least_restoration(inst, reqs)
    full = least_restoration(inst, reqs, prune=False)
    assert pruned is not None and full is not None
    assert pruned[0] == full[0] == least
    assert not set(pruned[2]) & dominated(inst)
    rel = relax(inst, timeout=60)
    if least == 0:
        assert rel.status is RelaxStatus.SAT
    else:
        assert rel.status is RelaxStatus.RELAXED and rel.proven and rel.cost == least


def test_dominance_prunes_some_alternatives_in_every_seed() -> None:
    """The brute-force test above must exercise pruning, not only pass through it."""
    hits = 0
    for seed in range(12):
        levels, helpers = _seeded(random.Random(seed))
        hits += bool(dominated(_catalog(levels, helpers, 100, 100)))
    assert hits >= 6


@pytest.mark.parametrize(("n", "d", "cut"), [(14, 5, 3), (20, 6, 5), (25, 12, 7)])
def test_coupled_cut_of_a_generated_catalog_is_the_brute_force_least(n: int, d: int, cut: int) -> None:
    """benchmarks/catalog_gen.py's seeded selection with the RAM cut (the coupled cut of
    docs/benchmarks.md): relax, through the pruned abstraction, is proven least and equals
    the least over every choice of one alternative per level (catalog_gen's brute force)."""
    cat = gen.build(n, d)
    text, _ = gen.problem_text(cat, "sat")
    init = gen.sums(list(cat.selection))
    assert init["ram"] > cut  # a cut, not a raise
    init["ram"] = cut
    text = re.sub(r"\(= ram [0-9]+\)", f"(= ram {cut})", text, count=1)
    inst = loads({"domain.cat": gen.domain_text(cat), "sat.cat": text}, "sat.cat").instance
    least = gen.least_restoration(cat, init)
    assert least > 0
    assert dominated(inst)  # the pruning is exercised
    # the brute force weighs every unit of every resource 1 (relax's default weighs unlike
    # units by relative change, docs/cli.md): the same weights, given
    rel = relax(inst, timeout=120, weights={r: Fraction(1) for r in gen.RESOURCES})
    assert rel.status is RelaxStatus.RELAXED and rel.proven
    assert rel.cost == least
