"""The checked IR: typed, immutable, exact; views are functors on it."""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import pytest

from catgrammar.diagnostics import Diagnostics
from catc import ir
from catc.loader import load_instance
from catc.view import ViewError, apply_view, project_instance

from conftest import ROOT

EX = ROOT / "examples"
EVERY = ROOT / "tests" / "fixtures" / "valid" / "every-construct.cat"


def instance(problem, domain=None) -> ir.Instance:
    diags = Diagnostics()
    _, inst = load_instance(str(domain) if domain else None, str(problem), diags)
    assert inst is not None, [f"{d.span}: {d.message}" for d in diags]
    return inst


def test_ir_is_frozen():
    inst = instance(EX / "navigation" / "farthest.cat")
    with pytest.raises(dataclasses.FrozenInstanceError):
        inst.problem.horizon = 5  # type: ignore[misc]
    with pytest.raises(TypeError):
        inst.domain.resources["x"] = None  # type: ignore[index]


def test_navigation_numbers_are_exact():
    inst = instance(EX / "navigation" / "farthest.cat")
    assert inst.problem.init["battery"].value.value == Fraction(733, 10)
    move = inst.morphisms["move"]
    (pre,) = move.pre
    # (>= (- battery (+ 5 (* 0.8 d))) reserve): the 0.8 is exactly 4/5
    coeff = pre.expr.left.args[1].args[1].args[0]
    assert isinstance(coeff, ir.Const) and coeff.value == Fraction(4, 5)
    assert move.params[0].lower == 0 and move.params[0].upper == 1000
    assert pre.label == "pre/move/1"


def test_sorts_of_expressions():
    inst = instance(EVERY)
    det = inst.morphisms["detector"]
    effects = {e.resource: e for e in det.effects}
    assert effects["confidence"].value.sort is ir.REAL or effects["confidence"].value.sort == ir.REAL
    assert effects["restarts"].kind is ir.EffectKind.INCREASE and effects["restarts"].value.sort == ir.INT
    assert effects["online"].value.sort == ir.BOOL
    assert det.param("mem").fixed and not det.param("target").fixed
    assert [lit.label for lit in det.pre] == [f"pre/detector/{i}" for i in range(1, 5)]
    assert det.reads >= {"mounted", "ambient", "ram", "restarts"}
    assert det.writes == {"ram", "detects", "confidence", "online", "restarts"}


def test_imports_merge_the_standard_library():
    inst = instance(EVERY)
    assert inst.domain.imports == ("robot-base",)
    assert {"ram", "budget", "mounted", "slots"} <= set(inst.resources)
    assert inst.resources["budget"].unit == "USD"


def test_subsorts_and_problem_objects_ground_the_open_sort():
    inst = instance(EVERY)
    cls = inst.domain.sorts["class"]
    assert set(inst.constants_of(cls)) == {"person", "fire-extinguisher", "hot-spot"}
    assert inst.constants_of(inst.domain.sorts["thermal-class"]) == ["hot-spot"]
    assert inst.constants_of(inst.domain.sorts["lighting"]) == ["bright", "dark"]


def test_closed_world_defaults_for_bool_and_set_resources():
    inst = instance(EX / "gpu-allocation" / "max-confidence.cat")
    assert inst.problem.init["slam-running"].value.value is False
    inst = instance(EX / "detection" / "person.cat")
    assert inst.problem.init["detects"].value.elements == ()


# ---------------------------------------------------------------- views as functors


def test_view_drops_resources_and_every_literal_over_them():
    inst = instance(EVERY)
    v = apply_view(inst, "software")
    assert v.view == "software"
    dropped = {"mounted", "slots", "power", "budget"}
    assert not dropped & set(v.resources)
    lidar = v.morphisms["mount-lidar"]
    assert lidar.pre == () and lidar.effects == ()
    det = v.morphisms["detector"]
    assert [lit.label for lit in det.pre] == ["pre/detector/2", "pre/detector/3", "pre/detector/4"]
    for m in v.morphisms.values():
        assert (m.reads | m.writes) <= set(v.resources)
    assert set(v.problem.init) == set(v.resources)


def test_identity_view_is_identity():
    inst = instance(EVERY)
    same = project_instance(inst, frozenset(inst.resources), "id")
    assert same.domain.morphisms == inst.domain.morphisms
    assert same.problem.init == inst.problem.init and same.problem.goal == inst.problem.goal


@pytest.mark.parametrize("first, second", [("software", "perception"), ("perception", "software")])
def test_views_compose_as_intersection(first, second):
    inst = instance(EVERY)
    a, b = inst.domain.views[first], inst.domain.views[second]
    composed = project_instance(project_instance(inst, a.kept, first), b.kept, second)
    direct = project_instance(inst, a.kept & b.kept, "both")
    assert set(composed.resources) == set(direct.resources) == a.kept & b.kept
    assert composed.domain.morphisms == direct.domain.morphisms
    assert composed.problem.init == direct.problem.init
    assert composed.problem.goal == direct.problem.goal and composed.problem.softs == direct.problem.softs


def test_view_keeps_morphism_identity():
    inst = instance(EVERY)
    v = apply_view(inst, "perception")
    assert list(v.morphisms) == list(inst.morphisms)
    for name, m in v.morphisms.items():
        orig = inst.morphisms[name]
        assert (m.params, m.churn, m.uses, m.kind) == (orig.params, orig.churn, orig.uses, orig.kind)


def test_view_rejects_an_objective_over_a_dropped_resource(tmp_path):
    inst = instance(EVERY)
    with pytest.raises(ViewError, match="drops"):
        apply_view(dataclasses.replace(inst, problem=dataclasses.replace(
            inst.problem, metric=ir.Metric(ir.MetricMode.SINGLE, (ir.Objective(ir.Sense.MAXIMIZE, ir.ResourceRef("budget", ir.REAL)),)))), "software")
