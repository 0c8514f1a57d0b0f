"""The grounding annotations' checker (catc.frontend.check_ground) on one small model.

Expected records are written from docs/grounding.md: a hardware template alternates text and
θ holes (``{{``/``}}`` escape a brace), a software node without ``:node`` is named later from the
morphism (``-`` → ``_``), ``:params``/``:remap`` values are θ, resources or literals, behaviour outputs
are blackboard keys.  Errors are located in the model file.
"""

from __future__ import annotations

from fractions import Fraction

import pytest

from catc import ir
from catc.frontend.session import load_texts
from catc.ir.grounding import (
    BehaviorGrounding,
    HardwareGrounding,
    Profile,
    SoftwareGrounding,
    Template,
    Value,
    ValueKind,
    ros_node_name,
)
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics

MODEL = """(define (domain g)
  (:requirements :numeric :sets :free-parameters :grounding)
  (:sorts topic slot - symbol)
  (:constants image-raw - topic s1 s2 - slot)
  (:resources (ram real) (topics (set topic)) (mounted bool))
  (:morphism mount-cam :kind hardware :uses 1 :parameters ((where slot)) :effect (assign mounted true)
    :ground HW)
  (:morphism cam-driver :kind software :uses 1 :parameters ((out topic) (mem real :bounds (0.5 2)))
    :precondition (and mounted (>= ram mem)) :effect (and (add topics out) (decrease ram mem))
    :ground SW)
  (:morphism explore :kind behavior :uses 1 :parameters ((t topic)) :precondition (member t topics)
    :ground BT)
  (:deployment :project rescue :executor "ghcr.io/acme/bt:2"))
(define (problem p) (:domain g) (:init (= ram 4)) (:goal mounted))
"""
GOOD = {
    "HW": '(hardware :instruction "Mount the camera on slot {where}" :check "LED {{on}}" :parts ("rail"))',
    "SW": '(software :image "ghcr.io/acme/usb-cam:1.0" :params ((memory mem) (fps 30) (budget ram))'
    ' :remap (("image_raw" out)))',
    "BT": "(behavior :id Explore :inputs ((topic t)) :outputs ((found (key victim_pose))))",
}


def load(**changes: str) -> tuple[ir.Instance | None, Diagnostics]:
    text = MODEL
    for key, value in {**GOOD, **changes}.items():
        text = text.replace(key, value)
    diags = Diagnostics()
    return load_texts({"g.cat": text}, "g.cat", diags), diags


def test_well_formed_annotations_become_these_records():
    inst, diags = load()
    assert inst is not None, [(d.code, d.message) for d in diags]
    hw = inst.morphisms["mount-cam"].grounding
    assert isinstance(hw, HardwareGrounding)
    assert hw.instruction == Template(("Mount the camera on slot ", Value(ValueKind.PARAM, "where")))
    assert hw.check is not None and all(isinstance(p, str) for p in hw.check.parts)
    assert "".join(hw.check.parts) == "LED {on}"  # doubled braces are one literal brace, no hole
    assert hw.parts == ("rail",)

    sw = inst.morphisms["cam-driver"].grounding
    assert isinstance(sw, SoftwareGrounding)
    assert (sw.image, sw.profile) == ("ghcr.io/acme/usb-cam:1.0", Profile.DRIVERS)
    assert sw.node == "" and ros_node_name("cam-driver") == "cam_driver"  # none named: derived later
    assert sw.params == (
        ("memory", Value(ValueKind.PARAM, "mem")),
        ("fps", Value(ValueKind.LITERAL, literal=Fraction(30))),
        ("budget", Value(ValueKind.RESOURCE, "ram")),
    )
    assert sw.remap == (("image_raw", Value(ValueKind.PARAM, "out")),)

    bt = inst.morphisms["explore"].grounding
    assert isinstance(bt, BehaviorGrounding)
    assert bt.node_id == "Explore"
    assert bt.inputs == (("topic", Value(ValueKind.PARAM, "t")),)
    assert bt.outputs == (("found", Value(ValueKind.KEY, "victim_pose")),)
    assert inst.domain.deployment is not None
    assert (inst.domain.deployment.project, inst.domain.deployment.executor) == ("rescue", "ghcr.io/acme/bt:2")


@pytest.mark.parametrize(
    "change, code, line",
    [
        ({"HW": '(software :image "a:1")'}, codes.BAD_GROUNDING, 7),  # kind differs from the morphism's
        ({"HW": '(hardware :instruction "slot {slto}")'}, codes.BAD_GROUNDING, 7),  # no such θ
        ({"HW": '(hardware :check "x")'}, codes.BAD_GROUNDING, 7),  # :instruction is required
        ({"SW": '(software :image "Bad/Image")'}, codes.BAD_TARGET_NAME, 10),  # upper case: not an image reference
        ({"SW": '(software :image "a:1" :node "9node")'}, codes.BAD_TARGET_NAME, 10),  # starts with a digit
        ({"SW": '(software :image "a:1" :params ((x rma)))'}, codes.UNKNOWN_NAME, 10),
        ({"BT": "(behavior :id E :outputs ((found 3)))"}, codes.BAD_GROUNDING, 12),  # outputs are keys
    ],
)
def test_each_broken_rule_is_one_located_error(change, code, line):
    inst, diags = load(**change)
    assert inst is None
    errors = [d for d in diags if d.code == code]
    assert len(errors) == 1, [(d.code, d.message) for d in diags]
    span = errors[0].span
    assert span is not None and (span.file, span.line) == ("g.cat", line)


def test_grounding_needs_its_requirement():
    text = MODEL.replace(" :grounding)", ")")
    for key, value in GOOD.items():
        text = text.replace(key, value)
    diags = Diagnostics()
    assert load_texts({"g.cat": text}, "g.cat", diags) is None
    assert any(d.code == codes.MISSING_REQUIREMENT for d in diags), [(d.code, d.message) for d in diags]
