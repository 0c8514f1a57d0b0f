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

from catc import ir  # noqa: E402
from catc.api import loads  # noqa: E402
from catc.queries.diagnose import DiagnoseStatus, diagnose  # noqa: E402
from catc.queries.optimize import objectives_of  # noqa: E402
from catc.queries.recompose import _least_churn_by_sets, recompose  # noqa: E402
from catc.queries.relax import RelaxStatus, relax  # noqa: E402
from catc.queries.solve import SolveStatus, solve  # noqa: E402
from catc.smt.backend import Check  # noqa: E402
from catc.smt.consumption import Consumption, cheapest_support, least_consumption, least_length  # noqa: E402
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
    # least_length is the chain's depth (every shortcut needs more RAM than there is, so it
    # never fires), and no composition is shorter: the deepening's shortest (presolve off,
    # every horizon tried) has d steps too, as the abstraction's composition solve returns
    plain = solve(inst, timeout=60, presolve=False)
    assert least_length(inst) == d == len(plain.plan.steps) == len(res.plan.steps)
    assert res.horizons_tried == 0  # the consumption abstraction's composition: nothing encoded


@pytest.mark.parametrize(("n", "d", "seed"), [(12, 4, 24), (14, 5, 24), (9, 3, 1), (9, 3, 2), (9, 3, 3)])
def test_cheapest_support_is_a_fitting_selection(n: int, d: int, seed: int) -> None:
    """By construction a composition reaches cap d only through one alternative per level,
    bottom-up; the support found must be such a selection, and fit the sat variant's
    initial values (checked by summing the generator's own needs, not catc's)."""
    cat = gen.build(n, d, seed)
    inst, _ = _instance(cat, "sat")
    order = cheapest_support(inst)
    assert order is not None
    by_name = {a.name: a for alts in cat.levels for a in alts}
    chosen = [by_name[m] for m in order]
    assert [a.level for a in chosen] == list(range(1, d + 1))
    spent = gen.sums(chosen)
    assert all(spent[r] <= _init(inst)[r] for r in gen.RESOURCES)


@pytest.mark.parametrize("variant", ["budget", "power", "ram"])
def test_cheapest_support_finds_none_when_no_selection_fits(variant: str) -> None:
    cat = gen.build(12, 4)
    inst, _ = _instance(cat, variant)
    assert not gen.feasible_selections(cat, _init(inst))
    assert cheapest_support(inst) is None


def test_cheapest_support_gives_up_within_its_budget_of_tries() -> None:
    """One try cannot pick d = 4 alternatives: no answer, which claims nothing."""
    inst, _ = _instance(gen.build(12, 4), "sat")
    assert cheapest_support(inst, expansions=1) is None


_TWO_FACTS = """(define (domain two) (:requirements :numeric)
  (:resources (a bool) (b bool) (x int :bounds (0 9)))
  (:morphism ma :uses 1 :precondition (>= x X) :effect (assign a true))
  (:morphism mb :uses 1 :effect (assign b true)))
(define (problem p) (:domain two) (:init (= x 3)) (:goal (and a b)) (:horizon 3))
"""


def test_a_support_longer_than_the_least_length_is_not_taken() -> None:
    """By hand: ma and mb fire together in one parallel step, so the shortest composition
    has 1 step; the abstraction's support has 2 morphisms (one per step), longer than
    least_length = 1, so solve must not return it."""
    inst = loads({"two.cat": _TWO_FACTS.replace("X", "1")}, "two.cat").instance
    assert least_length(inst) == 1 and len(cheapest_support(inst) or []) == 2
    res = solve(inst, timeout=60)
    assert res.status is SolveStatus.SAT and len(res.plan.steps) == 1


def test_a_support_the_validator_rejects_is_not_taken() -> None:
    """By hand: ma needs x ≥ 5 with x = 3 (the abstraction forgets numeric conditions): the
    support exists, the composition does not."""
    inst = loads({"two.cat": _TWO_FACTS.replace("X", "5")}, "two.cat").instance
    assert cheapest_support(inst) is not None
    assert solve(inst, timeout=60).status is SolveStatus.UNSAT


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


def test_least_churn_by_sets_matches_brute_force_over_selections() -> None:
    """Stability first: churn 2 (the construction), and the best budget among the
    compositions of churn 2 — by brute force, the selections that differ from S at exactly
    one level (a swap: one removed, one added) and fit."""
    cat = gen.build(12, 4)
    inst, expect = _instance(cat, "recompose")
    init = _init(inst)
    k = inst.problem.horizon
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    fast = _least_churn_by_sets(inst, [churn, *objectives_of(inst)], k, False)
    assert fast is not None  # answered without the solver
    swaps = [
        sel
        for sel in gen.feasible_selections(cat, init)
        if sum(a.name != s.name for a, s in zip(sel, cat.selection, strict=True)) == 1
    ]
    best = max(init["budget"] - gen.sums(list(sel))["budget"] for sel in swaps)
    assert [v.value for v in fast.values] == [2, best]
    stable = recompose(inst, priority="stability", timeout=60)
    assert stable.churn == expect["churn"] and stable.result.values[1].value == best


_NUMERIC = """(define (domain numeric) (:requirements :numeric :recomposition)
  (:resources (x int :bounds (0 9)) (done bool))
  (:morphism m1 :uses 1 :precondition (>= x 5) :effect (assign done true))
  (:morphism m2 :uses 1 :effect (assign done true)))
(define (problem p) (:domain numeric) (:init (= x 3)) (:goal done) (:horizon 2) (:deployed m1))
"""


def test_least_churn_by_sets_leaves_a_set_the_validator_rejects_to_the_solver() -> None:
    """By hand: the deployed {m1} passes the abstraction (it forgets x ≥ 5) but cannot fire;
    the sets route gives up, and the solver's answer is churn 2 (m1 out, m2 in)."""
    inst = loads({"n.cat": _NUMERIC}, "n.cat").instance
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    assert _least_churn_by_sets(inst, [churn], 2, False) is None
    rec = recompose(inst, priority="stability", timeout=60)
    assert rec.churn == 2 and {(i.morphism, i.change) for i in rec.items} == {("m1", "removed"), ("m2", "added")}


def test_least_churn_by_sets_declines_objective_first_with_a_mission() -> None:
    inst, _ = _instance(gen.build(12, 4), "recompose")
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    assert _least_churn_by_sets(inst, [*objectives_of(inst), churn], inst.problem.horizon, False) is None
