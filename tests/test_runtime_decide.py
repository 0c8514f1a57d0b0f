"""catrt.decide, one decision of the lifelong loop, on a model small enough to decide by hand.

Two lamps light the room: ``lamp-a`` needs a power of at least 3, ``lamp-b`` at least 5;
either one suffices (horizon 1).  So, by hand:

- power 4, nothing deployed: only lamp-a applies → compose [[lamp-a]];
- power 4, lamp-a deployed: it still applies → keep, without a solver;
- power 4, lamp-b deployed: it no longer applies → recompose to [[lamp-a]] (lamp-b out,
  lamp-a in);
- power 1: no lamp applies → restore: the least change of the initial values that makes a
  composition exist, relative to the deployed one (the restoration keeps it): power 1 → 3
  (lamp-a's threshold) with nothing or lamp-a deployed, 1 → 5 with lamp-b deployed.
"""

from __future__ import annotations

import json
from fractions import Fraction

import pytest

from catc.api import loads
from catrt.decide import Action, Decision, Limits, decide, incumbent_plan

LAMPS = """\
(define (domain lamps)
  (:requirements :numeric)
  (:resources
    (power real :bounds (0 *))
    (lit bool))
  (:morphism lamp-a :kind software :uses 1
    :precondition (>= power 3)
    :effect (assign lit true))
  (:morphism lamp-b :kind software :uses 1
    :precondition (>= power 5)
    :effect (assign lit true)))

(define (problem light)
  (:domain lamps)
  (:init (= power {power}))
  (:goal lit)
  (:horizon 1))
"""

LIMITS = Limits(compose=60.0, diagnose=60.0, relax=60.0)


def model(power: str):
    return loads({"lamps.cat": LAMPS.format(power=power)}, "lamps.cat")


def deployed(*morphisms: str) -> dict:
    """A catc.plan/1 document of one step activating ``morphisms``."""
    return {"schema": "catc.plan/1", "steps": [[{"morphism": m, "params": {}} for m in morphisms]], "fresh": {}}


def steps(decision: Decision) -> list[list[str]]:
    assert decision.plan is not None
    return [sorted(a.morphism for a in step) for step in decision.plan.steps]


def test_nothing_deployed_composes_the_only_composition():
    decision = decide(model("4"), None, LIMITS)
    assert decision.action is Action.COMPOSE
    assert steps(decision) == [["lamp-a"]]
    assert list(decision.documents) == ["solve"]  # no metric, no soft constraint: solve (the deploy policy)
    assert decision.solver_calls == 1


def test_a_deployed_composition_that_still_applies_is_kept_without_a_solver():
    for power in ("4", "3", "100"):  # lamp-b applies too at 100: keeping is still right (no churn)
        decision = decide(model(power), deployed("lamp-a"), LIMITS)
        assert decision.action is Action.KEEP, power
        assert steps(decision) == [["lamp-a"]]
        assert decision.solver_calls == 0 and decision.documents == {}


def test_a_deployed_composition_that_no_longer_applies_is_recomposed_with_least_churn():
    decision = decide(model("4"), deployed("lamp-b"), LIMITS)
    assert decision.action is Action.RECOMPOSE
    assert steps(decision) == [["lamp-a"]]
    assert {(c["morphism"], c["change"]) for c in decision.changes} == {("lamp-a", "added"), ("lamp-b", "removed")}
    assert "power" in decision.reason and "recomposed with least churn" in decision.reason


def test_a_deployed_morphism_gone_from_the_catalogue_must_go():
    decision = decide(model("4"), deployed("lamp-c"), LIMITS)
    assert decision.action is Action.RECOMPOSE
    assert steps(decision) == [["lamp-a"]]
    assert "lamp-c is no longer in the catalogue" in decision.reason
    assert {"morphism": "lamp-c", "change": "removed", "weight": None, "vanished": True} in decision.changes


@pytest.mark.parametrize(("incumbent", "power"), [(None, "3"), (deployed("lamp-a"), "3"), (deployed("lamp-b"), "5")])
def test_no_composition_proposes_the_least_restoration(incumbent, power):
    decision = decide(model("1"), incumbent, LIMITS)
    assert decision.action is Action.RESTORE
    assert decision.plan is None
    assert decision.proposal is not None
    assert decision.proposal["set"] == {"power": power}
    assert decision.proposal["proven"] is True
    assert Fraction(decision.proposal["relaxations"][0]["delta"]) == Fraction(power) - 1
    assert {"diagnose", "relax"} <= set(decision.documents)


def test_the_incumbent_is_read_against_the_model_as_it_is_now():
    plan, why = incumbent_plan(model("4").instance, deployed("lamp-a"))
    assert why is None and plan is not None and [a.morphism for _, a in plan.activations] == ["lamp-a"]
    plan, why = incumbent_plan(model("4").instance, deployed("lamp-c", "lamp-d"))
    assert plan is None and why == "lamp-c, lamp-d are no longer in the catalogue"
    assert incumbent_plan(model("4").instance, None) == (None, None)


def test_actions_are_written_as_their_words():
    """The journal keeps ``action`` as text: the enum writes exactly the word."""
    assert json.dumps({"action": Action.RESTORE}) == '{"action": "restore"}'
    assert [a.value for a in Action] == ["keep", "compose", "recompose", "restore", "stuck", "undecided", "infeasible"]
    assert {a for a in Action if a.deploys} == {Action.KEEP, Action.COMPOSE, Action.RECOMPOSE}
