"""The relaxed reachability analysis (catc.semantics.relaxed): sound refutations, by hand and
against the SMT encoding on generated models (issue 16)."""

from __future__ import annotations

import os
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import ROOT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from strategies import models

from catc.api import load, loads
from catc.ir import ArithOp, CmpOp
from catc.ir.labels import label_index
from catc.semantics.relaxed import FALSE, TRUE, TRUTH, Interval, _arith, _compare_numbers, refute
from catc.smt.backend import Check
from catc.smt.labelled import LabelledModel

F = Fraction

# ---------------------------------------------------------------- interval arithmetic


def test_interval_products_treat_zero_times_infinity_as_zero():
    assert _arith(ArithOp.MUL, [Interval(F(0), F(0)), Interval()]) == Interval(F(0), F(0))
    assert _arith(ArithOp.MUL, [Interval(F(-2), F(3)), Interval(F(4), F(5))]) == Interval(F(-10), F(15))
    assert _arith(ArithOp.MUL, [Interval(F(1), None), Interval(F(-1), F(-1))]) == Interval(None, F(-1))


def test_interval_sums_differences_and_division():
    assert _arith(ArithOp.SUB, [Interval(F(0), F(10)), Interval(F(1), F(2))]) == Interval(F(-2), F(9))
    assert _arith(ArithOp.SUB, [Interval(F(1), None)]) == Interval(None, F(-1))
    assert _arith(ArithOp.DIV, [Interval(F(1), F(2)), Interval(F(2), F(4))]) == Interval(F(1, 4), F(1))
    assert _arith(ArithOp.DIV, [Interval(F(1), F(2)), Interval(F(-1), F(4))]) == Interval()  # may divide by 0
    assert _arith(ArithOp.MIN, [Interval(F(1), F(5)), Interval(None, F(3))]) == Interval(None, F(3))


@pytest.mark.parametrize(
    ("op", "a", "b", "want"),
    [
        (CmpOp.GE, (F(0), F(500)), (F(20000), F(20000)), FALSE),
        (CmpOp.GE, (F(0), F(500)), (F(500), F(500)), TRUTH),
        (CmpOp.GT, (F(0), F(500)), (F(500), F(500)), FALSE),
        (CmpOp.LT, (F(0), F(1)), (F(5), None), TRUE),
        (CmpOp.EQ, (F(2), F(2)), (F(2), F(2)), TRUE),
        (CmpOp.EQ, (None, F(1)), (F(2), None), FALSE),
    ],
)
def test_comparisons_of_intervals(op, a, b, want):
    assert _compare_numbers(op, Interval(*a), Interval(*b)) == want


# ---------------------------------------------------------------- small models, by hand

SHOP = """
(define (domain shop)
  (:requirements :numeric :sets)
  (:sorts item - symbol)
  (:constants lidar camera - item)
  (:resources (budget real :bounds (0 *)) (owned (set item)) (done bool))
  (:morphism buy-lidar :kind hardware
    :precondition (and (>= budget 2000) (not (member lidar owned)))
    :effect (and (decrease budget 2000) (add owned lidar)))
  (:morphism buy-camera :kind hardware
    :precondition (>= budget 100)
    :effect (and (decrease budget 100) (add owned camera)))
  (:morphism earn :kind behavior
    :precondition (>= budget 0)
    :effect (increase budget 10))
  (:morphism finish :kind behavior
    :precondition (and (member lidar owned) (member camera owned))
    :effect (assign done true)))
(define (problem p) (:domain shop)
  (:init (= budget 500))
  (:goal done)
  (:horizon 4))
"""


def _shop(*, earn: bool = True):
    text = SHOP if earn else SHOP.replace("(increase budget 10)", "(increase budget 0)")
    return loads({"shop.cat": text}, "shop.cat").instance


def test_a_budget_that_only_decreases_refutes_the_goal():
    inst = _shop(earn=False)
    why = refute(inst)
    assert why is not None and why.label == "goal/1"
    # the proof needs the budget's initial value and the LiDAR's price
    assert refute(inst, set(label_index(inst)) - {"init/budget"}) is None
    assert refute(inst, set(label_index(inst)) - {"pre/buy-lidar/1"}) is None
    # the whole chain, by hand: done starts false, only finish sets it, finish needs the LiDAR
    # owned, nothing is owned at first, the LiDAR costs 2000 and the budget is 500 — and
    # nothing less: dropping any one of these lets the relaxation reach the goal
    chain = {"goal/1", "init/done", "pre/finish/1", "init/owned", "pre/buy-lidar/1", "init/budget"}
    assert refute(inst, chain) is not None
    for label in chain:
        assert refute(inst, chain - {label}) is None, label


def test_an_income_makes_the_budget_unbounded_and_the_goal_reachable():
    assert refute(_shop(earn=True)) is None  # widening: earning 10 at a time reaches any price


def test_a_composition_whose_member_can_never_fire_is_refuted():
    inst = _shop(earn=False)
    no_goal = set(label_index(inst)) - {"goal/1"}  # so that only the composition can refute
    why = refute(inst, no_goal, components={"buy-camera", "buy-lidar"})
    assert why is not None and why.label is None and "'buy-lidar'" in why.reason
    assert refute(inst, no_goal, components={"buy-camera"}) is None
    # with the goal, a composition without `finish` cannot reach it
    why = refute(inst, components={"buy-camera"})
    assert why is not None and why.label == "goal/1"


def test_parameter_bounds_count_only_when_enforced():
    text = (
        SHOP.replace(
            ":precondition (and (>= budget 2000) (not (member lidar owned)))\n    :effect (and (decrease budget 2000)",
            ":parameters ((price real :bounds (2000 3000)))\n"
            "    :precondition (and (>= budget price) (not (member lidar owned)))\n    :effect (and (decrease budget price)",
        )
        .replace("(increase budget 10)", "(increase budget 0)")
        .replace(":numeric :sets)", ":numeric :sets :free-parameters)")
    )
    inst = loads({"shop.cat": text}, "shop.cat").instance
    labels = set(label_index(inst))
    assert "bound/buy-lidar/price" in labels
    assert refute(inst) is not None
    assert refute(inst, labels - {"bound/buy-lidar/price"}) is None


def test_increments_of_one_morphism_are_summed():
    text = """
(define (domain d) (:requirements :numeric)
  (:resources (x int :bounds (0 3)) (y int))
  (:morphism twice :kind software :precondition (= x 0) :effect (and (increase x 2) (assign y 7))))
(define (problem p) (:domain d) (:init (= x 0) (= y 0)) (:goal (and (= x 2) (= y 7))) (:horizon 1))
"""
    assert refute(loads({"d.cat": text}, "d.cat").instance) is None


# ---------------------------------------------------------------- the examples

EXAMPLES = ROOT / "examples"


def _cases():
    import tomllib

    for expect in sorted(EXAMPLES.rglob("expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            if case.get("status") in ("sat", "unsat"):
                name = f"{expect.parent.name}/{case['file']}:{case.get('problem', '')}"
                yield pytest.param(expect.parent, case, id=name)


@pytest.mark.parametrize(("folder", "case"), list(_cases()))
def test_examples_feasible_are_never_refuted(folder: Path, case: dict):
    """(The relaxation is incomplete: an infeasible example may or may not be refuted.)"""
    why = refute(load(folder / case["file"], problem_name=case.get("problem")).instance)
    if case["status"] == "sat":
        assert why is None, why


def test_the_budget_cut_is_refuted_by_the_relaxation():
    sar = EXAMPLES / "search-and-rescue"
    inst = load(sar / "domain.cat", sar / "budget-cut.cat").instance
    assert refute(inst) is not None
    assert refute(inst, {"init/budget", "pre/mount-lidar/1"}, components=inst.problem.deployed) is not None


# ---------------------------------------------------------------- soundness against the solver

SETTINGS = {"deadline": None, "suppress_health_check": [HealthCheck.too_slow]}


@settings(max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "25")) * 2, **SETTINGS)
@given(model=models(), data=st.data())
def test_every_refutation_is_unsat_for_the_solver(model, data):
    """Whatever subset of labels (and composition) the analysis refutes, the labelled SMT
    encoding finds no composition either — over the horizon extended past the problem's."""
    inst = loads({"gen.cat": model.text}, "gen.cat").instance
    labels = sorted(label_index(inst))
    enforced = data.draw(st.sets(st.sampled_from(labels)) if labels else st.just(set()), label="enforced")
    if data.draw(st.booleans(), label="all"):
        enforced = set(labels)
    components = None
    if data.draw(st.booleans(), label="relative"):
        components = data.draw(st.sets(st.sampled_from(sorted(inst.morphisms))), label="components")
    why = refute(inst, enforced, components)
    if why is None:
        return
    k = max(inst.problem.horizon or 0, 1)
    lm = LabelledModel(inst, k, components=components)
    r, _ = lm.check([label for label in lm.labels if label in enforced])
    assert r is Check.UNSAT, (why, sorted(enforced), components, model.text)


@settings(max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "25")) * 2, **SETTINGS)
@given(model=models(), data=st.data())
def test_every_witness_is_feasible_for_the_solver(model, data):
    """Whatever subset of labels (and composition) a witness is accepted for, the labelled
    SMT encoding finds it feasible too (catc.semantics.witness)."""
    from catc.semantics.witness import witnessed

    inst = loads({"gen.cat": model.text}, "gen.cat").instance
    k = max(inst.problem.horizon or 0, 1)
    components = None
    if data.draw(st.booleans(), label="relative"):
        components = data.draw(st.sets(st.sampled_from(sorted(inst.morphisms)), min_size=1), label="components")
    lm = LabelledModel(inst, k, components=components)
    enforced = data.draw(st.sets(st.sampled_from(lm.labels)) if lm.labels else st.just(set()), label="enforced")
    if not witnessed(inst, frozenset(enforced), components, k, lm.extended):
        return
    r, _ = lm.check(sorted(enforced))
    assert r is Check.SAT, (sorted(enforced), components, model.text)
