"""The instance tightened by invariants for the proofs that nothing is better
(catc.queries.churn_search.tightened): the bounds and unusable morphisms by hand, the same
compositions valid in both, and the proof it gives the search-and-rescue mission's event IV
(runtime_bench.py's IV-approved: a counting proof instead of seconds of SMT)."""

from __future__ import annotations

import os
from fractions import Fraction

from conftest import ROOT
from hypothesis import HealthCheck, given, settings
from strategies import models

from catc import ir
from catc.api import loads
from catc.queries.churn_search import tightened
from catc.semantics.validate import validate
from catc.smt.counting import better_refuted

SAR = ROOT / "examples/search-and-rescue"

SHOP = """
(define (domain shop) (:requirements :numeric :symbols :recomposition)
  (:sorts lighting - (enum bright dark))
  (:resources (budget real) (light lighting) (stock real) (a-done bool) (b-done bool) (c-done bool))
  (:morphism a :uses 1 :precondition (>= budget 300) :effect (and (decrease budget 300) (assign a-done true)))
  (:morphism b :uses 1 :precondition (and (<= 250 budget) (>= budget 100))
     :effect (and (decrease budget 200) (assign b-done true)))
  (:morphism c :uses 1 :precondition (and (= light bright) (>= stock 1)) :effect (and (decrease stock 1) (assign c-done true)))
  (:morphism d :uses 1 :precondition (>= stock 5) :effect (assign c-done true)))
(define (problem p) (:domain shop) (:init (= budget 1000) (= light dark) (= stock 3)) (:goal (and a-done c-done))
  (:horizon 3))
"""


def _inst(text: str) -> ir.Instance:
    return loads({"shop.cat": text}, "shop.cat").instance


def test_a_budget_each_purchase_checks_is_bounded_and_a_dark_camera_never_fires():
    """By hand: a needs 300 and spends 300 (leaves ≥ 0), b needs 250 (its greater guard) and
    spends 200 (leaves ≥ 50): the budget never goes below min(1000, 0, 50) = 0.  The stock has
    an unguarded firing (d reads it but c's ``stock ≥ 1`` guards a decrease of 1: ≥ 0) — and
    c needs ``light = bright``, which nothing changes and is dark: c never fires.  d never
    fires either (stock 3 < 5), but ``stock`` is changed by c, so that is not a static fact."""
    inst = _inst(SHOP)
    t = tightened(inst)
    assert t.resources["budget"].lower == 0
    assert t.resources["stock"].lower == 0
    assert t.morphisms["c"].uses == 0
    assert t.morphisms["d"].uses == inst.morphisms["d"].uses == 1
    assert inst.resources["budget"].lower is None and inst.morphisms["c"].uses == 1  # inst unchanged


def test_no_bound_when_a_decrease_is_unguarded_or_by_a_non_constant():
    unguarded = SHOP.replace(":precondition (>= budget 300)", ":precondition (>= stock 0)")
    assert tightened(_inst(unguarded)).resources["budget"].lower is None
    # an increase keeps a lower bound (x only grows): c still leaves stock ≥ 1 − 1 = 0, the
    # initial 3 is above it, b's +2 never lowers it — the bound is min(3, 0) = 0
    refund = SHOP.replace("(assign b-done true)", "(assign b-done true) (increase stock 2)")
    assert tightened(_inst(refund)).resources["stock"].lower == 0
    unguarded_stock = refund.replace("(and (= light bright) (>= stock 1))", "(= light bright)")
    assert tightened(_inst(unguarded_stock)).resources["stock"].lower is None
    by_amount = SHOP.replace("(decrease budget 300)", "(decrease budget stock)")
    assert tightened(_inst(by_amount)).resources["budget"].lower is None
    bright = SHOP.replace("(= light dark)", "(= light bright)")
    assert tightened(_inst(bright)).morphisms["c"].uses == 1


def _event_iv() -> ir.Instance:
    """The mission after event IV's restoration (mission-events.jsonl): the budget at
    21,110, dark, out of range, generation 2 deployed."""
    deployed = (
        "approach explore interact lidar-driver mount-external-battery mount-lidar mount-long-range-radio "
        "mount-rgb-camera-lite mount-speaker-mic open-vocab-detector report return-to-range rgb-lite-driver slam "
        "tracker tts vlm whisper-stt"
    )
    problem = f"""
(define (problem iv) (:domain search-and-rescue)
  (:init (= slots 6) (= power 20) (= ram 64) (= disk 1000) (= budget 21110) (= ambient dark)
         (= range-to-base 14) (= comms-range 10))
  (:goal reported) (:horizon 12) (:deployed {deployed}) (:metric maximize budget))
"""
    return loads({"domain.cat": (SAR / "domain.cat").read_text(), "iv.cat": problem}, "iv.cat").instance


def test_event_iv_churn_four_and_no_budget_left_is_proven_by_counting():
    """By hand: in the dark neither RGB driver fires, so the thermal camera (900 USD) and its
    driver come in and the lite driver goes (churn 3 so far); the deployed hardware costs
    20,260 USD, and with the thermal camera 21,160 > 21,110, so one more mount goes — the
    lite camera (50), the only one the mission can spare — churn 4, and 21,110 − 20,210 − 900
    = 0 left.  The counting relaxation proves it only with the budget bounded by 0 (every
    mount checks its price) and the RGB drivers out; nothing better than (4, −1) or (5, 0)
    is refuted, as (4, 0) beats both."""
    inst = _event_iv()
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    order = [churn, *inst.problem.metric.objectives]
    t = tightened(inst)
    assert t.resources["budget"].lower == 0
    assert {m for m in t.morphisms if t.morphisms[m].uses == 0} == {"rgb-driver", "rgb-lite-driver"}
    assert not better_refuted(inst, order, [Fraction(4), Fraction(0)])  # the instance as written: no proof
    assert better_refuted(t, order, [Fraction(4), Fraction(0)])
    assert not better_refuted(t, order, [Fraction(4), Fraction(-1)])
    assert not better_refuted(t, order, [Fraction(5), Fraction(0)])


SETTINGS = {"deadline": None, "suppress_health_check": [HealthCheck.too_slow]}


@settings(max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "25")) * 2, **SETTINGS)
@given(model=models(max_morphisms=3, max_horizon=3))
def test_every_composition_is_valid_in_the_tightened_instance(model):
    """The tightened instance has the same valid compositions: one found for the instance
    replays in the tightened one (its bounds hold in every state, no unusable morphism in it)."""
    from catc.queries.solve import SolveStatus, solve

    inst = loads({"gen.cat": model.text}, "gen.cat").instance
    sol = solve(inst)
    if sol.status is not SolveStatus.SAT:
        return
    report = validate(tightened(inst), sol.plan, horizon=inst.problem.horizon)
    assert report.ok, (model.text, [v.message for v in report.violations])
