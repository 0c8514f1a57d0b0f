"""Labels as IR data (catc.ir.labels): a kind and its parts, written as the text every
report, JSON document and SMT-LIB2 ``:named`` attribute has always used."""

from __future__ import annotations

import copy
import json
import pickle

import pytest

from catc import ir


@pytest.mark.parametrize(
    "label, text, kind, parts",
    [
        (ir.Label.pre("lidar-driver", 2), "pre/lidar-driver/2", ir.LabelKind.PRE, ("lidar-driver", "2")),
        (ir.Label.eff("m", 1), "eff/m/1", ir.LabelKind.EFF, ("m", "1")),
        (ir.Label.init("ram"), "init/ram", ir.LabelKind.INIT, ("ram",)),
        (ir.Label.goal(3), "goal/3", ir.LabelKind.GOAL, ("3",)),
        (ir.Label.soft(1), "soft/1", ir.LabelKind.SOFT, ("1",)),
        (ir.Label.bound("drive", "speed"), "bound/drive/speed", ir.LabelKind.BOUND, ("drive", "speed")),
        (ir.Label.bounds("battery"), "bounds/battery", ir.LabelKind.BOUNDS, ("battery",)),
        (ir.Label.uses("arm"), "uses/arm", ir.LabelKind.USES, ("arm",)),
        (ir.Label.horizon(), "horizon", ir.LabelKind.HORIZON, ()),
    ],
)
def test_a_label_is_its_text(label, text, kind, parts):
    assert label == text and hash(label) == hash(text) and label.text == text
    assert type(label.text) is str
    assert (label.kind, label.parts) == (kind, parts)
    assert ir.Label.parse(text) == label and ir.Label.parse(text).kind is kind
    assert json.dumps({label: [label]}) == json.dumps({text: [text]})
    for back in (pickle.loads(pickle.dumps(label)), copy.deepcopy(label)):
        assert type(back) is ir.Label and back == text and back.kind is kind


@pytest.mark.parametrize(
    "build",
    [
        lambda: ir.Label(ir.LabelKind.BOUND, "m"),  # a bound names its morphism and parameter
        lambda: ir.Label(ir.LabelKind.HORIZON, "x"),
        lambda: ir.Label.init("a/b"),  # '/' separates parts
        lambda: ir.Label.parse("frob/1"),
        lambda: ir.Label.parse("init/x/by-hand"),
    ],
)
def test_malformed_labels_are_refused(build):
    with pytest.raises(ValueError):
        build()


def test_owners_name_their_labels():
    sort = ir.REAL
    r = ir.Resource("ram", sort, lower=None)
    p = ir.Param("speed", sort)
    m = ir.Morphism("drive", ir.MorphismKind.SOFTWARE, (p,), (), (), uses=1)
    assert (r.bounds_label, r.init_label) == ("bounds/ram", "init/ram")
    assert (m.uses_label, m.bound_label("speed")) == ("uses/drive", "bound/drive/speed")
