"""The counting lower bound on the least relaxation (catc.smt.counting, issue 16): by hand on
the examples, and never above the least relaxation that search alone proves."""

from __future__ import annotations

import os
from fractions import Fraction

import pytest
from conftest import ROOT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import models

from catc.api import load, loads
from catc.queries.relax import eligible_requirements, relax
from catc.smt.counting import better_refuted, slack_lower_bound

SAR = ROOT / "examples/search-and-rescue"
LIFE = ROOT / "examples/lifelong"


def bound(inst, components=None):
    reqs = [(r.label, r.kind, r.weight) for r in eligible_requirements(inst)]
    return slack_lower_bound(inst, reqs, components)


def test_the_budget_cut_bound_is_the_sum_of_the_prices_less_the_budget():
    """By hand: the deployed SAR composition mounts the LiDAR (20,000 USD), the RGB camera
    (150), the speaker-mic (60), the external battery (90) and the long-range radio (60);
    each mount needs the budget to cover its own price, so the last one needs every price
    at once: 20,360 − 500 = 19,860 — whatever the order."""
    inst = load(SAR / "domain.cat", SAR / "budget-cut.cat").instance
    assert bound(inst, inst.problem.deployed) == Fraction(19860)
    inst = load(LIFE / "budget-cut.cat").instance  # 20,000 + 150 + 210 − 500
    assert bound(inst, inst.problem.deployed) == Fraction(19860)


def test_the_last_firing_sees_every_other_price():
    text = """
(define (domain d) (:requirements :numeric :recomposition)
  (:resources (budget real) (done bool))
  (:morphism a :uses 1 :precondition (>= budget 300) :effect (decrease budget 300))
  (:morphism b :uses 1 :precondition (>= budget 200) :effect (and (decrease budget 200) (assign done true))))
(define (problem p) (:domain d) (:init (= budget 100)) (:goal done) (:horizon 3) (:deployed a b))
"""
    inst = loads({"d.cat": text}, "d.cat").instance
    assert bound(inst, ("a", "b")) == Fraction(400)  # 300 + 200 − 100: the last firing sees both prices
    # with no composition fixed, nothing makes anything fire (Boolean goals are not counted)
    assert bound(inst, None) == Fraction(0)
    r = relax(inst, counting=False)
    assert r.proven and r.cost == Fraction(400)


def test_the_relaxation_of_sar_is_proven_and_unchanged():
    r = relax(load(SAR / "domain.cat", SAR / "budget-cut.cat").instance, timeout=120)
    assert r.status.value == "relaxed" and r.proven
    assert {x.label: x.delta for x in r.relaxations} == {"init/budget": Fraction(19860)}


SETTINGS = {"deadline": None, "suppress_health_check": [HealthCheck.too_slow]}


def test_objective_first_on_sar_needs_some_camera():
    """By hand: the mission must detect a person, the detector reads *some* image topic
    (a θ-parameterised precondition, ``(member in topics)``), and only a camera's driver
    publishes one; the cheapest camera is the lite one (50 USD), so the most budget left is
    25,000 − (20,360 − 150 + 50) = 4,740.  Without the parameter's membership the bound
    allowed no camera at all (4,880)."""
    inst = load(SAR / "domain.cat", SAR / "cheaper-camera.cat").instance
    budget = inst.problem.metric.objectives[0]
    assert better_refuted(inst, [budget], [Fraction(4740)])
    assert not better_refuted(inst, [budget], [Fraction(4739)])


@pytest.mark.parametrize(
    ("topics", "refuted"),
    [("{}", True), ("{image}", False), ("{other}", True)],
)
def test_a_parameter_membership_needs_a_publisher_unless_some_value_is_there(topics, refuted):
    """``use`` needs some ``?in`` of sort ``img`` in ``topics``; only ``pub`` (cost 5) adds one.
    By hand: with ``image`` (an img) already published nothing need be bought, so 10 is the
    most budget left; otherwise ``pub`` must fire and at most 5 is left — `other` is not an img."""
    text = f"""(define (domain d) (:requirements :numeric :sets :free-parameters :optimization)
      (:sorts topic - symbol img - topic)
      (:constants image - img other - topic)
      (:resources (topics (set topic)) (budget real :bounds (0 *)) (done bool))
      (:morphism pub :uses 1 :precondition (>= budget 5) :effect (and (decrease budget 5) (add topics image)))
      (:morphism use :uses 1 :parameters ((in img)) :precondition (member in topics) :effect (assign done true)))
    (define (problem p) (:domain d) (:init (= topics {topics}) (= budget 10)) (:goal done) (:metric maximize budget))"""
    inst = loads({"p.cat": text}, "p.cat").instance
    budget = inst.problem.metric.objectives[0]
    assert better_refuted(inst, [budget], [Fraction(5)]) is refuted
    assert not better_refuted(inst, [budget], [Fraction(4)])


@settings(max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "25")) * 2, **SETTINGS)
@given(model=models(max_morphisms=3, max_horizon=3), data=st.data())
def test_the_bound_never_exceeds_the_least_relaxation_search_proves(model, data):
    """On generated models, relative to a random composition (or none)."""
    inst = loads({"gen.cat": model.text}, "gen.cat").instance
    components = None
    if data.draw(st.booleans(), label="relative"):
        components = tuple(sorted(data.draw(st.sets(st.sampled_from(sorted(inst.morphisms)), min_size=1))))
    lower = bound(inst, components)
    r = relax(inst, counting=False, timeout=30, relative_to=components)
    if not r.proven or r.status.value not in ("relaxed", "sat"):
        if r.status.value == "unsat":
            return  # no restoration: any bound is a lower bound
        pytest.skip("search did not finish")  # pragma: no cover - small models finish
    assert lower is not False, model.text  # a restoration exists: the relaxation is feasible
    if lower is not None:
        assert lower <= (r.cost if r.relaxations else 0), model.text


# ---------------------------------------------------------------- optimality proofs


def test_stability_first_on_sar_is_proven_by_counting():
    """By hand: churn 0 keeps exactly the 17 deployed components, which spend 20,360 USD of
    25,000 (cheaper-camera.cat), so 4,640 is the most budget left at churn 0."""
    from catc import ir
    from catc.smt.counting import better_refuted

    inst = load(SAR / "domain.cat", SAR / "cheaper-camera.cat").instance
    budget = inst.problem.metric.objectives[0]
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    assert better_refuted(inst, [churn, budget], [Fraction(0), Fraction(4640)])
    assert not better_refuted(inst, [churn, budget], [Fraction(0), Fraction(4639)])


@settings(max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "25")) * 2, **SETTINGS)
@given(model=models(max_morphisms=3, max_horizon=3), data=st.data())
def test_counting_never_refutes_a_value_some_composition_beats(model, data):
    """A composition's final value of a numeric resource can never be proven unbeatable by a
    worse value: the proof must leave room for every composition that exists."""
    from catc import ir
    from catc.queries.solve import SolveStatus, solve
    from catc.smt.counting import better_refuted

    inst = loads({"gen.cat": model.text}, "gen.cat").instance
    numeric = [r for r in inst.resources.values() if r.sort.is_numeric]
    sol = solve(inst)
    if sol.status is not SolveStatus.SAT or not numeric:
        return
    r = data.draw(st.sampled_from(numeric), label="resource")
    final = sol.states[-1][r.name]
    ref = ir.ResourceRef(r.name, r.sort)
    half = Fraction(1, 2)
    assert not better_refuted(inst, [ir.Objective(ir.Sense.MAXIMIZE, ref)], [final - half]), model.text
    assert not better_refuted(inst, [ir.Objective(ir.Sense.MINIMIZE, ref)], [final + half]), model.text
    churn = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
    used = sum((inst.morphisms[m].churn for m in sol.plan.components), Fraction(0))  # nothing is deployed
    assert not better_refuted(inst, [churn], [used + half]), model.text
