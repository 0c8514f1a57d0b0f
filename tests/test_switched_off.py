"""`:uses 0` switches a component off (issue 15, Found 13): the morphism stays in the model —
deployed, named in objectives — but no composition activates it, on every backend and
strategy; the queries of the lifelong loop see the switch."""

from __future__ import annotations

import json

import pytest
from conftest import run_catc

from catc.api import load
from catc.smt.script import at_most

DOMAIN = """\
(define (domain d) (:requirements :numeric :free-parameters :recomposition :optimization)
  (:resources (x real) (done bool))
  (:morphism broken :kind hardware :churn 1 :uses 0
    :parameters ((p real :bounds (0 5)) (q real :bounds (0 5) :fixed))
    :precondition (>= p 1) :effect (and (increase x p) (assign done true)))
  (:morphism spare :kind hardware :churn 1 :uses 1 :effect (assign done true)))
(define (problem p) (:domain d) (:init (= x 0) (= done false)) (:goal done) (:deployed broken))
(define (problem needs) (:domain d) (:init (= x 0) (= done false)) (:goal (>= x 1)))
(define (problem opt) (:domain d) (:init (= x 0) (= done false)) (:goal done)
  (:metric maximize (+ x (param broken p))))
"""

# a sort whose only values would be the reserves of the switched-off morphism's parameter
SYMBOLS = """\
(define (domain s) (:requirements :numeric :sets :free-parameters)
  (:sorts thing)
  (:resources (seen (set thing)) (done bool))
  (:morphism grab :uses 0 :parameters ((o thing)) :effect (add seen o))
  (:morphism spare :uses 1 :effect (assign done true)))
(define (problem p) (:domain s) (:init (= seen {}) (= done false)) (:goal (and done (= seen {}))) (:horizon 3))
"""


@pytest.fixture
def model(tmp_path):
    path = tmp_path / "d.cat"
    path.write_text(DOMAIN)
    return path


def test_uses_zero_is_accepted(model):
    res = run_catc("check", model)
    assert res.exit_code == 0, res.output


def test_a_switched_off_component_is_never_activated(model):
    answer = load(model, problem_name="p").solve()
    assert answer.status == "sat" and answer.plan.components == {"spare"}
    answer = load(model, problem_name="needs").solve()
    assert answer.status == "unsat"


def test_the_validator_rejects_a_composition_that_uses_it(model, tmp_path):
    plan = tmp_path / "plan.json"
    steps = [[{"morphism": "broken", "params": {"p": 1, "q": 0}}]]
    plan.write_text(json.dumps({"schema": "catc.plan/1", "steps": steps}))
    res = run_catc("validate", model, plan, "--problem", "needs")
    assert res.exit_code == 1 and "allows at most 0 (:uses)" in res.stdout


def test_diagnose_names_the_switch(model):
    res = run_catc("diagnose", model, "--problem", "needs", "--json")
    labels = {c["label"] for c in json.loads(res.stdout)["cores"][0]}
    assert "uses/broken" in labels
    result = load(model, problem_name="needs").relax(discrete=True)  # one label of the core
    assert result.status == "relaxed" and len(result.dropped) == 1 and set(result.dropped) <= labels


def test_recompose_replaces_the_switched_off_component(model):
    res = run_catc("recompose", model, "--problem", "p", "--json")
    doc = json.loads(res.stdout)
    assert res.exit_code == 0 and doc["churn"] == 2
    assert {(i["change"], i["morphism"]) for i in doc["changes"]} == {("added", "spare"), ("removed", "broken")}


def test_its_parameter_may_appear_in_an_objective(model):
    answer = load(model, problem_name="opt").optimize()
    assert answer.status == "opt" and answer.plan.components == {"spare"}


@pytest.mark.parametrize("options", [{}, {"strategy": "single"}, {"backend": "cvc5"}])
def test_an_empty_sort_of_its_parameters_does_not_make_everything_impossible(tmp_path, options):
    path = tmp_path / "s.cat"
    path.write_text(SYMBOLS)
    answer = load(path).solve(**options)
    assert answer.status == "sat" and answer.plan.components == {"spare"}


def test_at_most_zero_is_plain_smtlib():
    assert at_most(["b0"], 0) == "(not b0)"
    assert at_most(["b0", "b1"], 0) == "(not (or b0 b1))"


def test_pddl_export_never_applies_it(model, tmp_path):
    out = tmp_path / "out"
    res = run_catc("export", "pddl", model, "--problem", "p", "--flavor", "smtplan", "--no-check", "-o", out)
    assert res.exit_code == 0, res.output
    assert "(< (used-broken) 0)" in (out / "domain.pddl").read_text()
