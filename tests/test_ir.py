"""The checked IR: typed, immutable, exact; views are functors on it."""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import pytest
from conftest import ROOT

from catc import ir
from catc.frontend.workspace import load_instance
from catc.ir import nodes
from catc.ir.views import ViewError, apply_view, project_instance
from catgrammar import record
from catgrammar.diagnostics import Diagnostics

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
        apply_view(
            dataclasses.replace(
                inst,
                problem=dataclasses.replace(
                    inst.problem,
                    metric=ir.Metric(
                        ir.MetricMode.SINGLE, (ir.Objective(ir.Sense.MAXIMIZE, ir.ResourceRef("budget", ir.REAL)),)
                    ),
                ),
            ),
            "software",
        )


# ---------------------------------------------------------------- records = frozen dataclasses

IR_RECORDS = [
    c for c in vars(nodes).values() if isinstance(c, type) and issubclass(c, nodes.Record) and c is not nodes.Record
]


def _reference_dataclass(cls):
    """The frozen slotted dataclass the IR class used to be: same fields, defaults, compare flags."""
    import inspect

    params = inspect.signature(cls.__init__).parameters
    spec = []
    for name in cls._fields:  # the slots besides the fields are private caches
        default = params[name].default
        kw = {"compare": name in cls._compared, "repr": name in cls._compared}
        if isinstance(default, type(ir.EMPTY)):  # the dataclasses had default_factory=frozen
            kw["default_factory"] = ir.frozen
        elif default is not inspect.Parameter.empty:
            kw["default"] = default
        spec.append((name, object, dataclasses.field(**kw)))
    return dataclasses.make_dataclass(cls.__name__, spec, frozen=True, slots=True)


def test_every_ir_class_is_a_record():
    assert len(IR_RECORDS) >= 29
    assert not [
        c for c in vars(nodes).values() if isinstance(c, type) and dataclasses.is_dataclass(c) and c not in IR_RECORDS
    ]
    assert {"Sort", "Morphism", "Domain", "Problem", "Instance", "Effect", "Literal"} <= {
        c.__name__ for c in IR_RECORDS
    }


@pytest.mark.parametrize("cls", IR_RECORDS, ids=lambda c: c.__name__)
def test_ir_records_behave_like_frozen_slotted_dataclasses(cls):
    import copy
    import pickle

    ref = _reference_dataclass(cls)
    names = cls._fields
    assert tuple(f.name for f in dataclasses.fields(cls)) == tuple(f.name for f in dataclasses.fields(ref)) == names
    assert [f.compare for f in dataclasses.fields(cls)] == [f.compare for f in dataclasses.fields(ref)]
    required = [f.name for f in dataclasses.fields(ref) if f.default is f.default_factory is dataclasses.MISSING]
    # defaults: the required fields alone give the same field values as the dataclass
    minimal = {n: f"r{i}" for i, n in enumerate(required)}
    assert [getattr(cls(**minimal), n) for n in names] == [getattr(ref(**minimal), n) for n in names]

    values = [f"v{i}" for i in range(len(names))]
    node, twin = cls(*values), cls(**dict(zip(names, values)))
    expected = ref(*values)
    assert node == twin and hash(node) == hash(twin) == hash(expected)
    assert repr(node) == repr(expected)
    for _i, name in enumerate(names):  # a compared field changes equality; the others do not
        other = dataclasses.replace(node, **{name: "different"})
        assert [getattr(record.replace(node, **{name: "different"}), n) for n in names] == [
            getattr(other, n) for n in names
        ]
        assert (other == node) == (name not in cls._compared)
        assert (other == node) == (dataclasses.replace(expected, **{name: "different"}) == expected)
    assert not hasattr(node, "__dict__")
    for act in (
        lambda: setattr(node, names[0], "x"),
        lambda: delattr(node, names[0]),
        lambda: setattr(node, "extra", 1),
    ):
        with pytest.raises(dataclasses.FrozenInstanceError):
            act()
    assert pickle.loads(pickle.dumps(node)) == node
    assert copy.deepcopy(node) == node and copy.copy(node) == node
    assert dataclasses.asdict(node) == dict(zip(names, values))


def test_sort_spans_do_not_take_part_in_equality():
    a = ir.Sort(ir.SortKind.SYMBOL, "topic", span=None)
    b = ir.Sort(ir.SortKind.SYMBOL, "topic", span=object())
    assert a == b and hash(a) == hash(b) and "span" not in repr(b)
    assert ir.Sort(ir.SortKind.SYMBOL, "class") != a


def test_a_record_with_one_compared_field_compares_and_hashes_like_a_dataclass():
    # its getter is a lambda (not an attrgetter): stored on the class, it must not bind ``self``
    class One(record.Record):
        __slots__ = ("value", "note")
        _compared = ("value",)
        value: str
        note: str

        def __init__(self, value: str, note: str = "") -> None:
            record.set_field(self, "value", value)
            record.set_field(self, "note", note)

    ref = dataclasses.make_dataclass(
        "One", [("value", str), ("note", str, dataclasses.field(default="", compare=False, repr=False))], frozen=True
    )
    assert One("a", "x") == One("a", "y") != One("b")
    assert hash(One("a")) == hash(ref("a"))
    assert dataclasses.replace(One("a"), value="b") == One("b")
