"""The independent plan validator (catc.semantics.validate) against hand-written compositions.

Every plan here is written by hand from docs/semantics.md §4 and every expected number is
computed by hand in the comments; nothing comes from a solver.
"""

from __future__ import annotations

import ast
import dataclasses
import functools
import inspect
import textwrap
import typing
from fractions import Fraction as F
from pathlib import Path

import pytest
from conftest import FIXTURES, ROOT
from hypothesis import given, settings
from hypothesis import strategies as st

from catc import ir
from catc.frontend.workspace import load_instance
from catc.ir.views import apply_view
from catc.semantics import validate as validate_module
from catc.semantics.plan import Activation, Plan, plan_from_json, plan_to_json
from catc.semantics.validate import (
    KINDS,
    DivisionByZero,
    EvaluationError,
    Report,
    Violation,
    evaluate,
    initial_state,
    objective_value,
    validate,
)
from catgrammar.diagnostics import Diagnostics

EX = ROOT / "examples"
VAL = FIXTURES / "validate"
EVERY = FIXTURES / "valid" / "every-construct.cat"


@functools.cache
def load(path: Path) -> ir.Instance:
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, [f"{d.span}: {d.message}" for d in diags]
    return inst


def A(morphism: str, **params) -> Activation:
    return Activation(morphism, {k.replace("_", "-"): v for k, v in params.items()})


def plan(*steps, fresh=None) -> Plan:
    return Plan(tuple(tuple(s) if isinstance(s, (list, tuple)) else (s,) for s in steps), fresh or {})


def triples(report: Report) -> list[tuple[str, int | None, str | None]]:
    return [(v.kind, v.step, v.label) for v in report.violations]


def only(report: Report) -> Violation:
    assert len(report.violations) == 1, [str(v) for v in report.violations]
    return report.violations[0]


def assert_ok(report: Report) -> None:
    assert report.ok, "\n".join(str(v) for v in report.violations)


def with_init(inst: ir.Instance, **values) -> ir.Instance:
    """The instance with some initial values replaced (None removes one)."""
    init = dict(inst.problem.init)
    for key, v in values.items():
        name = key.replace("_", "-")
        if v is None:
            init.pop(name)
        else:
            sort = inst.resources[name].sort
            init[name] = ir.InitValue(name, ir.Const(v, sort), f"init/{name}")
    return dataclasses.replace(inst, problem=dataclasses.replace(inst.problem, init=ir.frozen(init)))


def metric_terms(inst: ir.Instance) -> list[ir.Expr]:
    return [o.term for o in inst.problem.metric.objectives]


# ====================================================================== the examples, valid


def test_detection_with_a_fresh_topic():
    inst = load(EX / "detection" / "person.cat")
    p = plan(
        A("mount-rgb-camera"),
        A("camera-driver", out="topic#1", ram_req=F(1, 2)),
        A("open-vocab-detector", **{"in": "topic#1"}, target="person"),
        fresh={"topic#1": "topic"},
    )
    r = validate(inst, p)
    assert_ok(r)
    assert len(r.states) == 4
    assert r.states[0] == {"mounted": frozenset(), "ram": 16, "topics": frozenset(), "detects": frozenset()}
    assert r.states[1]["mounted"] == {"rgb-camera"}
    assert r.states[2]["topics"] == {"topic#1"} and r.states[2]["ram"] == F(31, 2)
    final = r.states[-1]
    assert final["detects"] == {"person"}
    assert final["ram"] == 16 - F(1, 2) - 4 == F(23, 2)


def test_detection_on_the_modelled_topic():
    inst = load(EX / "detection" / "person.cat")
    p = plan(
        A("mount-rgb-camera"),
        A("camera-driver", out="image-raw", ram_req=2),  # the upper bound: inclusive
        A("open-vocab-detector", **{"in": "image-raw"}, target="person"),
    )
    r = validate(inst, p)
    assert_ok(r)
    assert r.final_state["ram"] == 10 and r.final_state["topics"] == {"image-raw"}


def test_detection_of_a_class_declared_only_in_the_problem():
    inst = load(EX / "detection" / "unmodeled-class.cat")
    steps = [A("mount-rgb-camera"), A("camera-driver", out="image-raw", ram_req=1)]
    assert_ok(validate(inst, plan(*steps, A("open-vocab-detector", **{"in": "image-raw"}, target="fire-extinguisher"))))
    # detecting the wrong class leaves the goal unmet
    r = validate(inst, plan(*steps, A("open-vocab-detector", **{"in": "image-raw"}, target="person")))
    assert triples(r) == [("goal", None, "goal/1")]
    assert "fire-extinguisher" in r.violations[0].message


def test_navigation_farthest_exact_optimum_and_one_step_beyond():
    inst = load(EX / "navigation" / "farthest.cat")
    # (73.3 - 10 - 5) / 0.8 = 72.875 = 583/8 leaves exactly the 10 Wh reserve
    r = validate(inst, plan(A("move", d=F(583, 8))))
    assert_ok(r)
    assert r.final_state["battery"] == 10 and r.final_state["travelled"] == F(583, 8)
    assert objective_value(inst, plan(A("move", d=F(583, 8))), metric_terms(inst)[0], r.final_state) == F(583, 8)
    # d = 73 needs 5 + 58.4 = 63.4 Wh: 73.3 - 63.4 = 9.9 < 10
    r = validate(inst, plan(A("move", d=73)))
    v = only(r)
    assert (v.kind, v.step, v.morphism, v.label) == ("precondition", 1, "move", "pre/move/1")
    assert "battery = 73.3" in v.message and "d = 73" in v.message
    assert len(r.states) == 1  # step 1 cannot be applied


def test_navigation_precise_and_coarse():
    p = plan(A("move", d=F("9.65")))
    # 22.73 - (5 + 7.72) = 10.01 >= 10
    r = validate(load(EX / "navigation" / "precise.cat"), p)
    assert_ok(r)
    assert r.final_state["battery"] == F("10.01")
    # 22.7 - 12.72 = 9.98 < 10
    assert triples(validate(load(EX / "navigation" / "coarse.cat"), p)) == [("precondition", 1, "pre/move/1")]
    # a shorter trip fits the battery but misses the goal (9.6 < 9.65)
    assert triples(validate(load(EX / "navigation" / "coarse.cat"), plan(A("move", d=F("9.6"))))) == [
        ("goal", None, "goal/1")
    ]


GPU_STEPS = (A("slam"), A("vlm"))


def test_gpu_allocation_max_confidence():
    inst = load(EX / "gpu-allocation" / "max-confidence.cat")
    p = plan(*GPU_STEPS, A("detector", m=F(17, 4)))
    r = validate(inst, p)
    assert_ok(r)
    final = r.final_state
    assert final["confidence"] == F(1, 2) + F(8, 100) * F(17, 4) == F("0.84")
    assert final["gpu"] == 0 and final["gpu-used"] == 16
    assert final["slam-running"] is True and final["detector-running"] is True
    assert objective_value(inst, p, metric_terms(inst)[0], final) == F("0.84")
    # one more quarter GB does not fit after SLAM and the VLM (4.25 GB left)
    r = validate(inst, plan(*GPU_STEPS, A("detector", m=F("4.5"))))
    assert triples(r) == [("precondition", 3, "pre/detector/1")]
    assert len(r.states) == 3


def test_gpu_allocation_retask_and_upgrade():
    retask = load(EX / "gpu-allocation" / "retask.cat")
    r = validate(retask, plan(*GPU_STEPS, A("detector", m=F(5, 2))))
    assert_ok(r)
    assert r.final_state["confidence"] == F("0.7") and r.final_state["gpu-used"] == F("14.25")
    # 0.5 + 0.08 * 2.4 = 0.692 < 0.7: the fourth goal literal fails
    assert triples(validate(retask, plan(*GPU_STEPS, A("detector", m=F("2.4"))))) == [("goal", None, "goal/4")]
    upgrade = load(EX / "gpu-allocation" / "upgrade.cat")
    r = validate(upgrade, plan(*GPU_STEPS, A("detector", m=F(21, 4))))
    assert_ok(r)
    assert r.final_state["confidence"] == F("0.92")


SAR_EVENT1 = [
    A("mount-external-battery"),
    A("mount-rgb-camera"),
    A("mount-lidar"),
    A("mount-speaker-mic"),
    A("mount-long-range-radio"),
    A("rgb-driver", ram_req=F(1, 2)),
    A("lidar-driver"),
    A("open-vocab-detector", **{"in": "rgb-image"}, target="person", mem=1),
    A("slam"),
    A("tracker"),
    A("whisper-stt"),
    A("vlm"),
    A("tts"),
    A("explore"),
    A("approach"),
    A("interact"),
    A("report"),
]


def test_search_and_rescue_event1_sequential_composition():
    inst = load(EX / "search-and-rescue" / "event1-fresh.cat")
    p = plan(*SAR_EVENT1)
    r = validate(inst, p, sequential=True)
    assert_ok(r)
    final = r.final_state
    assert final["budget"] == 25000 - 90 - 150 - 20000 - 60 - 60 == 4640
    assert final["power"] == 20 + 30 - 3 - 12 - 2 - 5 == 28
    assert final["slots"] == 1
    assert final["ram"] == 64 - F(1, 2) - F(1, 2) - 1 - 4 - 1 - 3 - 18 - 1 == 35
    assert final["mounted"] == {"external-battery", "rgb-camera", "lidar", "speaker-mic", "long-range-radio"}
    assert final["reported"] is True
    # total-cost: the five mounts' :cost plus 1 for each of the 12 other activations
    assert objective_value(inst, p, ir.TotalCost(), final) == 90 + 150 + 20000 + 60 + 60 + 12


def test_search_and_rescue_dark_room_rejects_the_rgb_driver():
    inst = load(EX / "search-and-rescue" / "event4-dark.cat")
    r = validate(inst, plan(*SAR_EVENT1))
    assert triples(r) == [("precondition", 6, "pre/rgb-driver/2")]
    assert "ambient = dark" in r.violations[0].message
    assert len(r.states) == 6


def test_validation_in_a_view():
    """The software view drops mounted/slots/power/budget, so the software composition
    alone is valid there, and not in the full category."""
    full = load(EX / "search-and-rescue" / "event1-fresh.cat")
    soft = apply_view(full, "software")
    p = plan(*SAR_EVENT1[5:])
    r = validate(soft, p)
    assert_ok(r)
    assert "mounted" not in r.final_state and "budget" not in r.final_state
    assert triples(validate(full, p)) == [("precondition", 1, "pre/rgb-driver/1")]


def test_every_construct_in_its_view():
    full = load(EVERY)
    inst = apply_view(full, None)  # the problem's own (:view software)
    det = A("detector", target="fire-extinguisher", mem=5, retries=0, lit=False)
    p = plan(det, A("forget", c="person"))
    r = validate(inst, p)
    assert_ok(r)
    s1, s2 = r.states[1], r.states[2]
    # min(1, 0.5 + 0.08*5) = 0.9; (if (> 5 4) true lit) = true
    assert s1["confidence"] == F("0.9") and s1["online"] is True and s1["restarts"] == 1
    assert s1["detects"] == {"person", "fire-extinguisher"} and s1["ram"] == 59
    assert s2["detects"] == {"fire-extinguisher"} and s2["ram"] == F("59.5")
    churn, conf, third = metric_terms(inst)
    # deployed {mount-lidar (3)}, used {detector (2), forget (1)}: symmetric difference = 6
    assert objective_value(inst, p, churn, s2) == 3 + 2 + 1
    assert objective_value(inst, p, conf, s2) == F("0.9")
    # total-cost 2*mem + 1 = 11, uses forget 1, param detector mem 5
    assert objective_value(inst, p, third, s2) == 11 + 1 + 5
    # without the view, the lidar must be mounted first
    assert triples(validate(full, plan(det))) == [("precondition", 1, "pre/detector/1")]


def test_every_violated_precondition_literal_is_reported():
    inst = with_init(apply_view(load(EVERY), None), ram=F(1), restarts=F(5))
    r = validate(inst, plan(A("detector", target="person", mem=1, retries=0, lit=True)))
    # ambient is dark and lit demands mem >= 2; ram 1 < max(1, 1.5); restarts 5 >= 3 + 0
    assert triples(r) == [
        ("precondition", 1, "pre/detector/2"),
        ("precondition", 1, "pre/detector/3"),
        ("precondition", 1, "pre/detector/4"),
    ]
    assert all(v.morphism == "detector" for v in r.violations)


# ====================================================================== hand-broken plans

COUNTER = VAL / "counter.cat"
PARAMS = VAL / "params.cat"
INTER = VAL / "interference.cat"


def observe(**over):
    params = dict(a="tweety", c="green", n=1, w=1, loud=False)
    params.update(over)
    return A("observe", **params)


def test_params_fixture_valid_plan():
    r = validate(load(PARAMS), plan(observe(), A("spot-bird", b="tweety")))
    assert_ok(r)
    # score 50 + w 1 - 1; tally + n
    assert r.final_state["score"] == 50 and r.final_state["tally"] == 1 and r.final_state["paint"] == "green"


def test_unknown_morphism():
    r = validate(load(COUNTER), plan(A("teleport")))
    assert [(v.kind, v.step, v.morphism) for v in r.violations] == [("unknown-morphism", 1, "teleport")]
    assert len(r.states) == 1


def test_missing_and_unknown_parameters():
    inst = load(COUNTER)
    r = validate(inst, plan(A("inc")))
    assert [(v.kind, v.step, v.morphism) for v in r.violations] == [("missing-parameter", 1, "inc")]
    assert "'k'" in r.violations[0].message
    r = validate(inst, plan(A("bump", z=1)))
    v = only(r)
    assert (v.kind, v.step, v.morphism) == ("unknown-parameter", 1, "bump") and "'z'" in v.message


@pytest.mark.parametrize(
    "over, fresh",
    [
        pytest.param({"n": F(3, 2)}, {}, id="real-for-int"),
        pytest.param({"n": 2.0}, {}, id="float-for-int"),
        pytest.param({"w": 1.0}, {}, id="float-for-real"),
        pytest.param({"w": True}, {}, id="bool-for-real"),
        pytest.param({"w": "rex"}, {}, id="symbol-for-real"),
        pytest.param({"loud": F(1)}, {}, id="number-for-bool"),
        pytest.param({"a": "dog"}, {}, id="unknown-symbol-not-in-fresh"),
        pytest.param({"a": "red"}, {}, id="enum-value-for-symbol"),
        pytest.param({"a": F(1)}, {}, id="number-for-symbol"),
        pytest.param({"c": "blue"}, {}, id="enum-value-outside-the-enum"),
        pytest.param({"c": "colour#1"}, {"colour#1": "colour"}, id="fresh-value-of-an-enum"),
        pytest.param({"c": "tweety"}, {}, id="symbol-for-enum"),
        pytest.param({"a": "x#1"}, {"x#1": "colour"}, id="fresh-value-of-an-enum-sort"),
        pytest.param({"a": "x#1"}, {"x#1": "no-such-sort"}, id="fresh-value-of-an-unknown-sort"),
    ],
)
def test_parameter_sort(over, fresh):
    r = validate(load(PARAMS), plan(observe(**over), A("spot-bird", b="tweety"), fresh=fresh))
    assert triples(r) == [("parameter-sort", 1, None)]
    assert r.violations[0].morphism == "observe"
    if over.get("a") == "dog":
        assert "neither a constant of the model nor a fresh value" in r.violations[0].message
    assert len(r.states) == 1


def test_symbols_of_sub_sorts_and_fresh_values():
    inst = load(PARAMS)
    # a bird (constant or fresh) is an animal
    assert_ok(validate(inst, plan(observe(a="bird#1"), observe(a="tweety", c="green"), fresh={"bird#1": "bird"})))
    assert_ok(validate(inst, plan(observe(a="nemo"), observe(a="tweety"))))  # a problem object
    # an animal is not a bird: a constant of the super-sort, a fresh value of the super-sort
    r = validate(inst, plan(observe(a="rex"), A("spot-bird", b="rex")))
    assert [(v.kind, v.step, v.morphism) for v in r.violations][:1] == [("parameter-sort", 2, "spot-bird")]
    assert "constant of sort animal" in r.violations[0].message
    r = validate(inst, plan(observe(a="animal#1"), A("spot-bird", b="animal#1"), fresh={"animal#1": "animal"}))
    assert [(v.kind, v.step, v.morphism) for v in r.violations][:1] == [("parameter-sort", 2, "spot-bird")]
    assert "fresh value 'animal#1' is of sort animal" in r.violations[0].message


@pytest.mark.parametrize(
    "over",
    [{"n": 0}, {"n": 4}, {"w": F(1, 4)}, {"w": F(201, 100)}],
    ids=["int-below", "int-above", "real-below", "real-above"],
)
def test_parameter_bounds(over):
    r = validate(load(PARAMS), plan(observe(**over), A("spot-bird", b="tweety")))
    assert [(v.kind, v.step, v.morphism) for v in r.violations] == [("parameter-bounds", 1, "observe")]


def test_parameter_bounds_are_inclusive():
    inst = load(PARAMS)
    assert_ok(validate(inst, plan(observe(n=3, w=F(1, 2)), A("spot-bird", b="tweety"))))
    assert_ok(validate(inst, plan(observe(n=1, w=2), A("spot-bird", b="tweety"))))


def test_fixed_parameter_must_agree_across_activations():
    inst = load(PARAMS)
    assert_ok(validate(inst, plan(observe(w=F(3, 2), c="red"), observe(w=F(3, 2)), A("spot-bird", b="tweety"))))
    r = validate(inst, plan(observe(w=F(3, 2), c="red"), observe(w=2), A("spot-bird", b="tweety")))
    v = only(r)
    assert (v.kind, v.step, v.morphism) == ("fixed-parameter", 2, "observe")
    assert "1.5" in v.message and "step 1" in v.message
    assert len(r.states) == 2  # step 2 does not apply


def test_same_morphism_twice_in_one_step():
    r = validate(load(COUNTER), plan([A("inc", k=1), A("inc", k=2)]))
    assert [(v.kind, v.step, v.morphism) for v in r.violations] == [("duplicate-in-step", 1, "inc")]


def test_violated_precondition_reports_its_label():
    r = validate(load(COUNTER), plan(A("dec")))
    v = only(r)
    assert (v.kind, v.step, v.morphism, v.label) == ("precondition", 1, "dec", "pre/dec/1")
    assert "n = 0" in v.message and "step 1" in v.message


# ---------------------------------------------------------------------- interference


def test_interference_fixture_valid_parallel_plan():
    r = validate(
        load(INTER),
        plan(
            [A("set-gauge"), A("put", i="apple"), A("drain-fixed"), A("drain-param", x=1), A("take", i="pear")],
            A("watch-gauge"),
        ),
    )
    assert_ok(r)
    assert r.states[1]["tank"] == 10 - 2 - 1 and r.states[1]["gauge"] == 5
    assert r.final_state["alarm"] is True and r.final_state["basket"] == {"apple"}


@pytest.mark.parametrize(
    "step, writer, label",
    [
        pytest.param([A("set-gauge"), A("watch-gauge")], "set-gauge", "eff/set-gauge/1", id="assign-vs-read"),
        pytest.param([A("watch-gauge"), A("set-gauge")], "set-gauge", "eff/set-gauge/1", id="read-vs-assign"),
        pytest.param([A("set-gauge"), A("reset-gauge")], "set-gauge", "eff/set-gauge/1", id="assign-vs-assign"),
        pytest.param([A("bump-gauge"), A("set-gauge")], "set-gauge", "eff/set-gauge/1", id="assign-vs-update"),
        pytest.param([A("drain-fixed"), A("refill")], "drain-fixed", "eff/drain-fixed/1", id="update-vs-read"),
        pytest.param([A("put", i="apple"), A("take", i="apple")], "put", "eff/put/1", id="add-vs-remove"),
    ],
)
def test_interference(step, writer, label):
    r = validate(load(INTER), plan(step))
    v = only(r)
    assert (v.kind, v.step, v.morphism, v.label) == ("interference", 1, writer, label)
    assert len(r.states) == 1
    # the same activations one after the other do not interfere
    seq = validate(load(INTER), plan(*step), sequential=True)
    assert "interference" not in seq.kinds()


def test_update_vs_read_is_reported_in_both_directions():
    # refill both reads tank (precondition) and updates it; drain-param only updates
    r = validate(load(INTER), plan([A("refill"), A("drain-param", x=1)]))
    assert sorted((v.morphism, v.label) for v in r.violations) == [("drain-param", "eff/drain-param/1")]
    gpu = load(EX / "gpu-allocation" / "max-confidence.cat")
    r = validate(gpu, plan(list(GPU_STEPS), A("detector", m=F(17, 4))))
    assert sorted((v.kind, v.morphism, v.label) for v in r.violations) == [
        ("interference", "slam", "eff/slam/1"),
        ("interference", "vlm", "eff/vlm/1"),
    ]


@pytest.mark.parametrize(
    "step",
    [
        pytest.param([A("drain-fixed"), A("drain-param", x=3)], id="two-commutative-decreases"),
        pytest.param([A("put", i="apple"), A("take", i="pear")], id="add-and-remove-of-different-elements"),
        pytest.param([A("set-gauge"), A("put", i="pear"), A("take", i="apple"), A("drain-fixed")], id="four-at-once"),
        pytest.param([A("bump-gauge"), A("drain-fixed"), A("put", i="apple")], id="disjoint-resources"),
    ],
)
def test_parallel_steps_without_interference(step):
    r = validate(load(INTER), plan(step))
    assert "interference" not in r.kinds(), [str(v) for v in r.violations]
    assert len(r.states) == 2


def test_commutative_updates_are_summed():
    r = validate(load(INTER), plan([A("drain-fixed"), A("drain-param", x=F(7, 2))]))
    assert triples(r) == [("goal", None, "goal/1"), ("goal", None, "goal/2")]  # valid step, goal unmet
    assert r.final_state["tank"] == 10 - 2 - F(7, 2)


def test_add_vs_remove_depends_on_the_values():
    # take of the element put in the same step interferes; of another one it does not
    inst = load(INTER)
    assert validate(inst, plan([A("put", i="pear"), A("take", i="pear")])).kinds() == ["interference"]
    r = validate(inst, plan([A("put", i="pear"), A("take", i="apple")]))
    assert "interference" not in r.kinds() and r.final_state["basket"] == {"pear"}


def test_removes_come_before_adds_within_one_activation():
    inst = load(INTER)
    r = validate(inst, plan(A("put", i="apple"), A("swap", x="apple", y="apple"), A("swap", x="apple", y="pear")))
    assert r.states[2]["basket"] == {"apple"}
    assert r.states[3]["basket"] == {"pear"}


def test_sequential_composition_holds_one_activation_per_step():
    inst = load(COUNTER)
    p = plan([A("inc", k=2), A("bump")], A("finish"))
    r = validate(inst, p)
    assert_ok(r)
    assert r.final_state["done"] is True
    assert r.states[1]["n"] == 3  # inc 2 + bump 1, summed
    r = validate(inst, p, sequential=True)
    assert triples(r) == [("sequential", 1, None)]
    # a sequential violation leaves the step's meaning defined: replay continues
    assert len(r.states) == 3


# ---------------------------------------------------------------------- state-level


def test_resource_bounds_violated_by_an_effect():
    r = validate(load(INTER), plan([A("drain-fixed"), A("drain-param", x=9)], A("set-gauge"), A("watch-gauge")))
    assert triples(r)[0] == ("resource-bounds", 1, "eff/drain-fixed/1")
    assert "-1" in r.violations[0].message
    assert r.states[1]["tank"] == -1
    r = validate(load(COUNTER), plan(A("inc", k=2), A("inc", k=2), A("inc", k=2)))
    assert ("resource-bounds", 3, "eff/inc/1") in triples(r)
    r = validate(load(INTER), plan(*[A("put", i="apple")] * 4), horizon=4)
    assert ("resource-bounds", 4, "eff/put/2") in triples(r)


def test_int_resource_must_stay_integral():
    """The checker rejects a real amount on an int resource; the validator does not rely on it."""
    inst = load(COUNTER)
    half = ir.Effect(ir.EffectKind.INCREASE, "n", ir.Const(F(1, 2), ir.REAL), "eff/bump/1")
    morphisms = dict(inst.domain.morphisms, bump=dataclasses.replace(inst.morphisms["bump"], effects=(half,)))
    broken = dataclasses.replace(inst, domain=dataclasses.replace(inst.domain, morphisms=ir.frozen(morphisms)))
    r = validate(broken, plan(A("bump")))
    assert triples(r)[0] == ("resource-bounds", 1, "eff/bump/1")
    assert "not an integer" in r.violations[0].message


def test_uses_exceeded():
    inst = load(COUNTER)
    r = validate(inst, plan(A("inc", k=2), A("bump"), A("finish"), A("finish")))
    v = only(r)
    assert (v.kind, v.step, v.morphism) == ("uses", None, "finish")
    det = load(EX / "detection" / "person.cat")
    r = validate(det, plan(A("mount-rgb-camera"), A("mount-rgb-camera")))
    assert sorted((v.kind, v.step) for v in r.violations) == [("precondition", 2), ("uses", None)]


def test_horizon_exceeded():
    inst = load(COUNTER)
    p = plan(A("bump"), A("bump"), A("dec"), A("bump"), A("bump"), A("finish"))
    r = validate(inst, p)
    assert [(v.kind, v.step) for v in r.violations] == [("horizon", None)]
    assert "6 steps" in r.violations[0].message and "4" in r.violations[0].message
    assert_ok(validate(inst, p, horizon=6))
    assert validate(inst, plan(A("inc", k=2), A("bump"), A("finish")), horizon=2).kinds() == ["horizon"]


def test_goal_not_met():
    r = validate(load(COUNTER), plan(A("inc", k=1)))
    assert triples(r) == [("goal", None, "goal/1")]
    r = validate(load(COUNTER), plan())
    assert triples(r) == [("goal", None, "goal/1")] and len(r.states) == 1


def test_division_by_zero():
    inst = load(PARAMS)
    ok = validate(inst, plan(A("divide", k=2), observe()))
    assert_ok(ok)
    assert ok.states[1]["score"] == 25
    r = validate(inst, plan(A("divide", k=0), observe()))
    assert triples(r) == [("division-by-zero", 1, "pre/divide/1"), ("division-by-zero", 1, "eff/divide/1")]
    assert "k" in r.violations[0].message
    assert len(r.states) == 1


def test_division_by_zero_is_strict_inside_untaken_branches():
    inst = load(PARAMS)
    real = ir.REAL
    k = ir.ParamRef("k", real)
    div = ir.Arith(ir.ArithOp.DIV, (ir.Const(F(1), real), k), real)
    # (or true (> (/ 1 k) 0)) and (if true 1 (/ 1 k)): the divisor still must not be 0
    lit = ir.BoolOp(ir.BoolOpKind.OR, (ir.Const(True, ir.BOOL), ir.Compare(ir.CmpOp.GT, div, ir.Const(F(0), real))))
    ite = ir.Ite(ir.Const(True, ir.BOOL), ir.Const(F(1), real), div, real)
    s = initial_state(inst)
    assert evaluate(inst, lit, s, {"k": F(2)}) is True and evaluate(inst, ite, s, {"k": F(2)}) == 1
    for e in (lit, ite):
        with pytest.raises(DivisionByZero):
            evaluate(inst, e, s, {"k": F(0)})


def test_initial_state_problems():
    inst = load(PARAMS)
    p = plan(observe(), A("spot-bird", b="tweety"))
    r = validate(with_init(inst, score=F(101)), p)
    assert triples(r)[0] == ("initial-state", None, "init/score")
    r = validate(with_init(inst, tally=None), p)
    assert triples(r)[0] == ("initial-state", None, "init/tally")
    assert initial_state(with_init(inst, tally=None)).keys() == {"seen", "paint", "score"}


def test_all_violations_are_collected_in_step_order():
    inst = load(PARAMS)
    p = plan(
        observe(n=4),  # bounds
        [A("spot-bird", b="tweety"), A("spot-bird", b="tweety")],  # duplicate
        A("fly"),  # unknown morphism
        observe(w=2),  # fixed θ differs from step 1
        A("divide", k=1),  # beyond the horizon of 4
    )
    r = validate(inst, p)
    assert [(v.kind, v.step) for v in r.violations] == [
        ("parameter-bounds", 1),
        ("duplicate-in-step", 2),
        ("unknown-morphism", 3),
        ("fixed-parameter", 4),
        ("horizon", None),
    ]
    assert len(r.states) == 1  # replay stopped at step 1
    assert not r.ok


# ====================================================================== objective values


def test_total_cost_default_and_expression():
    counter = load(COUNTER)
    p = plan([A("inc", k=1), A("bump")], A("finish"))
    assert objective_value(counter, p, ir.TotalCost(), validate(counter, p).final_state) == 3  # 1 per activation
    inst = load(PARAMS)
    p = plan(observe(w=F(3, 2), c="red"), observe(w=F(3, 2)), A("spot-bird", b="tweety"))
    final = validate(inst, p).final_state
    assert objective_value(inst, p, ir.TotalCost(), final) == 3 * F(3, 2) * 2 + 1 == 10


def test_total_churn_uses_and_param():
    inst = load(PARAMS)
    churn, cost, third = metric_terms(inst)
    assert isinstance(churn, ir.TotalChurn) and isinstance(cost, ir.TotalCost)
    p = plan(observe(w=F(3, 2), c="red"), observe(w=F(3, 2)), A("spot-bird", b="tweety"))
    final = validate(inst, p).final_state
    # deployed {divide (3), spot-bird (5)}; used {observe (2), spot-bird}: {observe, divide}
    assert objective_value(inst, p, churn, final) == 2 + 3
    assert objective_value(inst, plan(), churn, initial_state(inst)) == 3 + 5
    assert objective_value(inst, p, ir.Uses("observe"), final) == 2
    assert objective_value(inst, p, ir.Uses("divide"), final) == 0
    assert objective_value(inst, p, ir.ParamValue("observe", "w", ir.REAL), final) == F(3, 2)
    assert objective_value(inst, p, third, final) == 2 + F(3, 2)
    # (param m p) of an unused morphism is undefined, and so is any term containing it
    assert objective_value(inst, p, ir.ParamValue("divide", "k", ir.REAL), final) is None
    assert objective_value(inst, plan(A("spot-bird", b="tweety")), third, final) is None


def test_param_value_of_a_morphism_used_with_several_values():
    inst = load(COUNTER)
    term = ir.ParamValue("inc", "k", ir.INT)
    s = initial_state(inst)
    assert objective_value(inst, plan(A("inc", k=1), A("inc", k=1)), term, s) == 1
    assert objective_value(inst, plan(A("inc", k=1), A("inc", k=2)), term, s) is None


def test_objective_over_the_final_state():
    inst = load(PARAMS)
    score = ir.ResourceRef("score", ir.REAL)
    tally = ir.ResourceRef("tally", ir.INT)
    term = ir.Arith(ir.ArithOp.DIV, (score, ir.Arith(ir.ArithOp.SUB, (tally, ir.Const(F(1), ir.INT)), ir.INT)), ir.REAL)
    p = plan(observe(n=3))
    final = validate(inst, p).final_state
    assert objective_value(inst, p, term, final) == F(51, 2)  # 51 / (3 - 1)
    assert objective_value(inst, plan(observe(n=1)), term, validate(inst, plan(observe(n=1))).final_state) is None


# ====================================================================== the evaluator


def test_evaluator_operators():
    inst = load(PARAMS)
    R, I, B = ir.REAL, ir.INT, ir.BOOL
    c = lambda v, s=R: ir.Const(v, s)  # noqa: E731
    s = initial_state(inst)
    ar = lambda op, *a: ir.Arith(op, a, R)  # noqa: E731
    assert evaluate(inst, ar(ir.ArithOp.SUB, c(F(5))), s) == -5
    assert evaluate(inst, ar(ir.ArithOp.SUB, c(F(5)), c(F(1)), c(F(1, 2))), s) == F(7, 2)
    assert evaluate(inst, ar(ir.ArithOp.DIV, c(F(1)), c(F(3))), s) == F(1, 3)
    assert evaluate(inst, ar(ir.ArithOp.MIN, c(F(2)), c(F(-1)), c(F(7))), s) == -1
    assert evaluate(inst, ar(ir.ArithOp.MAX, c(F(2)), c(F(-1)), c(F(7))), s) == 7
    assert evaluate(inst, ar(ir.ArithOp.MUL, c(F("0.1")), c(F(3))), s) == F(3, 10)
    assert evaluate(inst, ar(ir.ArithOp.ADD, ir.ResourceRef("score", R), c(F(1), I)), s) == 51
    imply = lambda a, b: ir.BoolOp(ir.BoolOpKind.IMPLY, (c(a, B), c(b, B)))  # noqa: E731
    assert [evaluate(inst, imply(a, b), s) for a in (False, True) for b in (False, True)] == [True, True, False, True]
    assert evaluate(inst, ir.BoolOp(ir.BoolOpKind.AND, ()), s) is True
    assert evaluate(inst, ir.BoolOp(ir.BoolOpKind.OR, ()), s) is False
    animal = inst.domain.sorts["animal"]
    seen = ir.ResourceRef("seen", ir.set_of(animal))
    state = dict(s, seen=frozenset({"rex"}))
    assert evaluate(inst, ir.Member(ir.Const("rex", animal), seen), state) is True
    assert evaluate(inst, ir.Member(ir.ParamRef("a", animal), seen), state, {"a": "tweety"}) is False
    lit = ir.SetLit((ir.Const("rex", animal),), ir.set_of(animal))
    assert evaluate(inst, ir.Compare(ir.CmpOp.EQ, seen, lit), state) is True
    assert evaluate(inst, ir.Compare(ir.CmpOp.EQ, seen, ir.SetLit((), ir.set_of(animal))), state) is False
    colour = inst.domain.sorts["colour"]
    assert evaluate(inst, ir.Compare(ir.CmpOp.EQ, ir.ResourceRef("paint", colour), ir.Const("red", colour)), s) is True
    assert evaluate(inst, ir.Ite(c(False, B), c(F(1)), c(F(2)), R), s) == 2
    for op, want in [(ir.CmpOp.LT, False), (ir.CmpOp.LE, True), (ir.CmpOp.GT, False), (ir.CmpOp.GE, True)]:
        assert evaluate(inst, ir.Compare(op, c(F(1, 3)), c(F(2, 6))), s) is want
    with pytest.raises(EvaluationError):
        evaluate(inst, ir.ResourceRef("nothing", R), s)
    with pytest.raises(EvaluationError):
        evaluate(inst, ir.TotalCost(), s)  # objective terms need a composition


def test_the_evaluator_matches_every_expression_class():
    """``_eval`` is a match over ``ir.Expr`` ending in an ``assert_never`` (mypy checks that
    statically); here, without mypy: every class of the union has its own ``case``."""
    tree = ast.parse(textwrap.dedent(inspect.getsource(validate_module._eval)))
    cased = {
        node.cls.attr
        for node in ast.walk(tree)
        if isinstance(node, ast.MatchClass) and isinstance(node.cls, ast.Attribute)
    }
    assert {c.__name__ for c in typing.get_args(ir.Expr)} <= cased


@pytest.mark.parametrize("module", ["validate", "evaluate"])  # the validator and its evaluator
def test_validator_is_independent_of_the_encoder(module):
    tree = ast.parse((Path(validate_module.__file__).parent / f"{module}.py").read_text())
    imported = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            imported |= {a.name for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            imported.add(node.module or "")
    ours = {m for m in imported if m.split(".")[0] in ("catc", "catgrammar", "z3")}
    # only the IR (with its printers), the plan type and the validator's own evaluator:
    # nothing of the encoder or a solver;
    # catgrammar.record is the generic frozen-record base the IR itself is built on, and
    # catgrammar.limits the command's time limit the replay stops at
    allowed = ("catc.ir.", "catc.semantics.plan", "catc.semantics.evaluate")
    assert all(
        m in {"catc", "catc.ir", "catgrammar.record", "catgrammar.limits"} or m.startswith(allowed) for m in ours
    ), ours
    # `from catc import X` may only bring in ir
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module == "catc":
            assert {a.name for a in node.names} <= {"ir"}


def test_violation_kinds_are_the_documented_ones():
    assert len(KINDS) == 16 and len(set(KINDS)) == 16
    assert "interference" in KINDS and "initial-state" in KINDS


def test_plan_from_json_then_validate():
    inst = load(EX / "gpu-allocation" / "max-confidence.cat")
    p = plan(*GPU_STEPS, A("detector", m=F(17, 4)))
    doc = plan_to_json(p)
    assert doc["steps"][2][0]["params"]["m"] == "17/4"
    sorts = {m.name: {q.name: q.sort.kind.value for q in m.params} for m in inst.morphisms.values()}
    assert_ok(validate(inst, plan_from_json(doc, sorts)))


# ====================================================================== property test


COUNTER_ACTIVATIONS = st.one_of(
    st.builds(lambda k: ("inc", k), st.integers(0, 3)),
    st.sampled_from([("bump", None), ("dec", None), ("finish", None)]),
)


def brute_force(steps, sequential: bool) -> tuple[bool, int | None]:
    """The counter model by hand: n starts at 0 within [0, 5]; inc k∈[1,2] and bump add
    without reading n (they commute); dec needs n ≥ 1; finish needs n = 3, sets done, once."""
    n, done, finishes = 0, False, 0
    valid = len(steps) <= 4
    for step in steps:
        names = [name for name, _ in step]
        if len(set(names)) < len(names) or (sequential and len(step) > 1):
            valid = False
        if len(step) > 1 and not set(names) <= {"inc", "bump"}:
            return False, None  # dec and finish read n, which inc, bump and dec update
        for name, k in step:
            if name == "inc" and not 1 <= k <= 2:
                return False, None
            if (name == "dec" and n < 1) or (name == "finish" and n != 3):
                return False, None
        if len(set(names)) < len(names):
            return False, None
        for name, k in step:
            n += {"inc": k, "bump": 1, "dec": -1}.get(name, 0)
            finishes += name == "finish"
            done = done or name == "finish"
        if not 0 <= n <= 5:
            valid = False
    valid = valid and done and finishes <= 1
    return valid, n


@settings(max_examples=250, deadline=None)
@given(st.lists(st.lists(COUNTER_ACTIVATIONS, min_size=1, max_size=3), max_size=5), st.booleans())
def test_counter_plans_agree_with_brute_force(steps, sequential):
    inst = load(COUNTER)
    p = Plan(tuple(tuple(Activation(name, {} if k is None else {"k": k}) for name, k in step) for step in steps))
    expected, n = brute_force(steps, sequential)
    r = validate(inst, p, sequential=sequential)
    assert r.ok == expected, (steps, [str(v) for v in r.violations])
    if expected:
        assert r.final_state["n"] == n and r.final_state["done"] is True
        assert len(r.states) == len(steps) + 1
    else:
        assert r.violations and all(v.kind in KINDS for v in r.violations)
