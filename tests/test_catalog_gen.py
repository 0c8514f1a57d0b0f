"""Issue 24's generated catalogs: catc's answers against the answers derived by construction
(benchmarks/catalog_gen.py's docstring) and against brute force over the tiny catalogs'
selections (one alternative per level).  Cores are checked unsat and irreducible on a fresh
labelled model of the full semantics, not by the code that found them."""

from __future__ import annotations

import sys
from fractions import Fraction
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

import catalog_gen as gen  # noqa: E402

from catc.api import loads  # noqa: E402
from catc.queries.diagnose import DiagnoseStatus, diagnose  # noqa: E402
from catc.queries.recompose import recompose  # noqa: E402
from catc.queries.relax import RelaxStatus, relax  # noqa: E402
from catc.queries.solve import SolveStatus, solve  # noqa: E402
from catc.smt.backend import Check  # noqa: E402
from catc.smt.consumption import Consumption, least_consumption, least_length  # noqa: E402
from catc.smt.labelled import LabelledModel  # noqa: E402

SIZES = [(12, 4), (14, 5)]


def _instance(cat: gen.Catalog, variant: str):
    text, expect = gen.problem_text(cat, variant)
    dom = gen.domain_text(cat, missing=variant == "missing")
    return loads({"domain.cat": dom, f"{variant}.cat": text}, f"{variant}.cat").instance, expect


def _init(inst) -> dict[str, int]:
    return {r: int(inst.problem.init[r].value.value) for r in gen.RESOURCES}


@pytest.mark.parametrize(("n", "d"), SIZES)
def test_sat_variant_solves_and_brute_force_agrees(n: int, d: int) -> None:
    cat = gen.build(n, d)
    inst, _ = _instance(cat, "sat")
    assert gen.feasible_selections(cat, _init(inst))  # the constructed selection fits
    res = solve(inst, timeout=60)
    assert res.status is SolveStatus.SAT  # validated by the independent validator in solve
    # the first horizon solve tries is a sound lower bound: the shortest composition (found
    # with presolve off, every horizon tried) is no shorter; a shortcut skips one level at most
    plain = solve(inst, timeout=60, presolve=False)
    assert d - 1 <= least_length(inst) <= len(plain.plan.steps) == len(res.plan.steps)


@pytest.mark.parametrize(("n", "d"), SIZES)
@pytest.mark.parametrize("variant", ["budget", "power", "ram"])
def test_global_cut_is_final_unsat_and_least_relaxation_is_delta(n: int, d: int, variant: str) -> None:
    cat = gen.build(n, d)
    inst, expect = _instance(cat, variant)
    init = _init(inst)
    assert not gen.feasible_selections(cat, init)  # brute force: infeasible
    # brute force: the least raise of initial values is Δ = 1, on this resource
    assert gen.least_restoration(cat, init) == 1
    assert gen.least_restoration(cat, init, eligible=(variant,)) == 1
    # the h_max consumption bound is the least sum over the levels, derived by hand
    assert least_consumption(inst)[variant] == gen.least_sums(cat)[variant]
    res = solve(inst, timeout=60)
    assert res.status is SolveStatus.UNSAT and res.final
    rel = relax(inst, timeout=60)
    assert rel.status is RelaxStatus.RELAXED and rel.proven
    assert {r.label: r.delta for r in rel.relaxations} == {f"init/{variant}": Fraction(1)} == expect["relax"]


def _check_irreducible(inst, core: list[str]) -> None:
    """Unsat, and each one left out satisfiable, on a fresh model (the extended horizon, as
    diagnose's labels mean)."""
    k = inst.problem.horizon
    model = LabelledModel(inst, k)
    assert model.check(core)[0] is Check.UNSAT
    for label in core:
        assert model.check([x for x in core if x != label])[0] is Check.SAT, label


@pytest.mark.parametrize("variant", ["budget", "ram", "missing"])
def test_diagnose_core_is_irreducible_and_names_the_cause(variant: str) -> None:
    cat = gen.build(12, 4)
    inst, expect = _instance(cat, variant)
    diag = diagnose(inst, timeout=120)
    assert diag.status is DiagnoseStatus.UNSAT
    core = diag.cores[0]
    assert set(expect["core_contains"]) <= set(core)
    _check_irreducible(inst, core)


def test_missing_capability_has_no_numeric_restoration() -> None:
    cat = gen.build(12, 4)
    inst, expect = _instance(cat, "missing")
    assert not gen.feasible_selections(cat, _init(inst), missing=True)
    assert expect["relax"] is None
    assert relax(inst, timeout=60).status is RelaxStatus.UNSAT
    res = solve(inst, timeout=60)
    assert res.status is SolveStatus.UNSAT and res.final


@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5, 6])
def test_consumption_abstraction_agrees_with_brute_force(seed: int) -> None:
    """On tiny catalogs the abstraction with every label enforced is satisfiable exactly when
    some selection fits (its necessary conditions are also sufficient here), for initial
    values around the least sums."""
    cat = gen.build(9, 3, seed)
    least = gen.least_sums(cat)
    for resource in gen.RESOURCES:
        for delta in (-1, 0):
            init = gen.generous(cat)
            init[resource] = least[resource] + delta
            text = (
                "(define (problem p) (:domain catalog-9-3)\n  (:init "
                + " ".join(f"(= {r} {init[r]})" for r in gen.RESOURCES)
                + ")\n  (:goal cap3)\n  (:horizon 5))\n"
            )
            inst = loads({"domain.cat": gen.domain_text(cat), "p.cat": text}, "p.cat").instance
            a = Consumption(inst)
            r, _ = a.check(a.labels)
            assert (r is Check.SAT) == bool(gen.feasible_selections(cat, init)), (resource, delta)


def test_recompose_least_churn_is_two_and_objective_matches_brute_force() -> None:
    cat = gen.build(12, 4)
    inst, expect = _instance(cat, "recompose")
    init = _init(inst)
    stable = recompose(inst, priority="stability", timeout=60)
    assert stable.churn == expect["churn"] == 2
    assert {i.morphism for i in stable.items if i.change == "removed"} <= set(expect["deployed"])
    first = recompose(inst, priority="objective", timeout=60)
    best = max(init["budget"] - gen.sums(list(sel))["budget"] for sel in gen.feasible_selections(cat, init))
    assert first.result.values[0].value == best
