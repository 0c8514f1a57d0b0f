"""The solver-free refutation of a recomposition that keeps its deployed set (issue 23,
start-up): :func:`catc.queries.churn_search.churn_floor_refutes`.  Its claims are checked by
hand (the prices of examples/lifelong/domain.cat) and against another procedure, the counting
relaxation's proof (:func:`catc.smt.counting.better_refuted`), which must agree wherever it
claims; and recompose answers the same with and without it."""

from __future__ import annotations

from fractions import Fraction
from itertools import combinations

import pytest
from conftest import ROOT

from catc import ir
from catc.api import load
from catc.queries import optimum
from catc.queries.churn_search import churn_floor_refutes, tightened
from catc.queries.optimize import objectives_of
from catc.queries.recompose import recompose
from catc.smt.counting import better_refuted
from catgrammar.record import replace

CHURN = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
#: the lidar, camera and radio of the deployed composition: 20,000 + 150 + 210 USD (domain.cat)
DEPLOYED_PRICES = Fraction(20360)


def _camera(deployed: tuple[str, ...] | None = None) -> ir.Instance:
    inst = load(ROOT / "examples/lifelong/cheaper-camera.cat").instance
    if deployed is not None:
        inst = ir.Instance(inst.domain, replace(inst.problem, deployed=deployed), inst.view)
    return inst


def _order(inst: ir.Instance) -> list[ir.Objective]:
    return [CHURN, *objectives_of(inst)]


def test_keeping_every_component_spends_the_whole_budget():
    inst = _camera()
    order = _order(inst)
    left = Fraction(20360) - DEPLOYED_PRICES  # the initial budget less the three purchases
    assert churn_floor_refutes(inst, order, [Fraction(0), left])
    assert not churn_floor_refutes(inst, order, [Fraction(0), left - 1])  # something may be better
    assert not churn_floor_refutes(inst, order, [Fraction(1), left])  # churn above its floor


def test_no_claim_outside_its_shape():
    inst = _camera()
    budget = objectives_of(inst)[0]
    least = ir.Objective(ir.Sense.MINIMIZE, budget.term)
    assert not churn_floor_refutes(inst, [budget, CHURN], [Fraction(0), Fraction(0)])  # churn not first
    assert not churn_floor_refutes(inst, [CHURN, least], [Fraction(0), Fraction(0)])  # minimised resource
    assert not churn_floor_refutes(inst, [], [])


def _deployed_sets():
    names = list(_camera().morphisms)
    for size in (0, 1, 2, 3, 6):
        yield from combinations(names, size)


@pytest.mark.parametrize("deployed", list(_deployed_sets())[::5], ids=lambda d: "+".join(d) or "none")
def test_every_claim_is_one_the_counting_proof_makes_too(deployed):
    inst = _camera(tuple(deployed))
    order = _order(inst)
    claims = 0
    for left in (Fraction(-1), Fraction(0), Fraction(100), Fraction(20360)):
        if churn_floor_refutes(inst, order, [Fraction(0), left]):
            claims += 1
            assert better_refuted(tightened(inst), order, [Fraction(0), left])
    # its claims are exactly the values at or above the initial budget less the prices kept
    prices = {"buy-lidar": 20000, "buy-camera": 150, "buy-camera-lite": 50, "buy-radio": 210}
    floor = Fraction(20360 - sum(prices.get(m, 0) for m in deployed))
    assert claims == sum(1 for left in (-1, 0, 100, 20360) if left >= floor)


def test_recompose_answers_the_same_without_it_and_needs_no_counting_proof(monkeypatch):
    inst = _camera()
    calls = []
    real = optimum.better_refuted
    monkeypatch.setattr(optimum, "better_refuted", lambda *a, **k: calls.append(a) or real(*a, **k))
    fast = recompose(inst)
    assert calls == []  # the race's refutation of "better than churn 0, 0 USD" needed no solver
    monkeypatch.setattr(optimum, "churn_floor_refutes", lambda *a: False)
    slow = recompose(inst)
    assert len(calls) == 1
    assert fast.churn == slow.churn == 0 and fast.plan == slow.plan
    assert [v.value for v in fast.result.values] == [v.value for v in slow.result.values] == [0, 0]
