"""``optimize(..., known=...)``: a composition the caller already has (recompose: the deployed
one) that is better than the first composition found spares the refutation "is there a
better one?" that could only fail — and changes nothing in the answer, as that failure led to
the very next step anyway.  A known composition that is not better, or that the validator
rejects, changes nothing at all."""

from __future__ import annotations

from fractions import Fraction

import pytest
from conftest import ROOT

from catc import ir
from catc.frontend.session import load_checked
from catc.queries import optimum
from catc.queries.optimize import OptStatus, optimize
from catc.queries.recompose import _deployed_plan
from catc.semantics.plan import Activation, Plan
from catgrammar.diagnostics import Diagnostics

CHURN = ir.Objective(ir.Sense.MINIMIZE, ir.TotalChurn())
REFUTE = optimum._better_exists


@pytest.fixture
def camera():
    """examples/lifelong/cheaper-camera.cat, stability first: least churn, then budget left."""
    inst = load_checked(ROOT / "examples/lifelong/cheaper-camera.cat", None, Diagnostics())
    assert inst is not None and inst.problem.metric is not None
    return inst, [CHURN, *inst.problem.metric.objectives]


def _run(monkeypatch, inst, order, known):
    """The answer, and the values each refutation was asked to beat."""
    asked = []

    def counted(inst, objectives, softs, values, *rest, **options):
        asked.append(list(values))
        return REFUTE(inst, objectives, softs, values, *rest, **options)

    monkeypatch.setattr(optimum, "_better_exists", counted)
    return optimize(inst, order, known=known), asked


def _answer(r):
    return r.status, [v.value for v in r.values], r.plan


def test_a_better_known_composition_spares_the_first_refutation(camera, monkeypatch):
    inst, order = camera
    deployed = _deployed_plan(inst)
    assert len(deployed) == 1 and len(deployed[0].steps) == 6
    without, asked_without = _run(monkeypatch, inst, order, ())
    with_known, asked_with = _run(monkeypatch, inst, order, deployed)
    assert _answer(with_known) == _answer(without)
    assert without.status is OptStatus.OPT and [v.value for v in without.values] == [0, 0]  # expect.toml
    # without: the first composition's values (its churn above 0: the deployed one is better),
    # then the optimum's; with: the optimum's only
    assert len(asked_without) == 2 and asked_without[0][0] > 0
    assert asked_with == asked_without[1:]


@pytest.mark.parametrize("which", ["rejected", "too long"])
def test_a_known_composition_that_is_no_composition_changes_nothing(camera, monkeypatch, which):
    inst, order = camera
    if which == "rejected":  # the report before anything is inspected
        known = [Plan([[Activation("send-report", {})]])]
    else:  # 9 steps: beyond the horizon of 8
        known = [Plan([*_deployed_plan(inst)[0].steps, [], [], []])]
    without, asked_without = _run(monkeypatch, inst, order, ())
    with_known, asked_with = _run(monkeypatch, inst, order, known)
    assert _answer(with_known) == _answer(without) and asked_with == asked_without


def test_a_known_composition_no_better_than_the_first_changes_nothing(camera, monkeypatch):
    """Objective first (budget left, then churn): the deployed composition leaves 0 USD, the
    optimum 100 (expect.toml); the refutations asked are the same with or without it."""
    inst, (churn, budget) = camera
    order = [budget, churn]
    without, asked_without = _run(monkeypatch, inst, order, ())
    with_known, asked_with = _run(monkeypatch, inst, order, _deployed_plan(inst))
    assert _answer(with_known) == _answer(without)
    assert [v.value for v in without.values] == [Fraction(100), Fraction(4)]
    assert asked_without[0][0] >= 0  # the first found leaves at least the deployed one's 0 USD
    assert asked_with == asked_without
