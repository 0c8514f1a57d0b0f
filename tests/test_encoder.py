"""The encoder (catc.smt.encoder) on a model small enough to write its formula by hand.

Every expected assertion below is written from docs/semantics.md §4 (θ bounds, resource
bounds in every state, ``b ⇒ pre``, the successor axioms: the frame value unless an active
morphism writes the resource, increments summed, assignments overriding; the initial state
and the goal), not read from the encoder's output.  One model:

    ram: real in [0, 8], starts at 4;  on: bool, starts false (a Boolean's default);
    start: θ r ∈ [1, 2], pre (>= ram r), eff (decrease ram r) (assign on true), :uses 1;
    goal: on.
"""

from __future__ import annotations

import pytest

from catc import ir
from catc.frontend.session import load_texts
from catc.smt.backend import Check, open_backend
from catc.smt.encoder import Encoder
from catgrammar.diagnostics import Diagnostics

MODEL = """(define (domain d) (:requirements :numeric :free-parameters)
  (:resources (ram real :bounds (0 8)) (on bool))
  (:morphism start :uses 1 :parameters ((r real :bounds (1 2)))
    :precondition (>= ram r) :effect (and (decrease ram r) (assign on true))))
(define (problem p) (:domain d) (:init (= ram INIT)) (:goal on) (:horizon 1))
"""


def instance(init: str = "4") -> ir.Instance:
    diags = Diagnostics()
    inst = load_texts({"m.cat": MODEL.replace("INIT", init)}, "m.cat", diags)
    assert inst is not None, [d.message for d in diags]
    return inst


def encoded(init: str = "4", steps: int = 1) -> Encoder:
    enc = Encoder(instance(init), steps)
    enc.unroll(steps)
    return enc


def test_one_step_is_the_formula_written_by_hand():
    asserts = encoded().script.asserts
    s0, s1, b, th = "|s.ram.0|", "|s.ram.1|", "|b.start.0|", "|th.start.r.0|"
    expected = {
        ("bounds/ram", f"(>= {s0} 0.0)"),
        ("bounds/ram", f"(<= {s0} 8.0)"),
        ("bounds/ram", f"(>= {s1} 0.0)"),
        ("bounds/ram", f"(<= {s1} 8.0)"),
        ("init/ram", f"(= {s0} 4.0)"),
        ("init/on", "(= |s.on.0| false)"),
        ("bound/start/r", f"(>= {th} 1.0)"),
        ("bound/start/r", f"(<= {th} 2.0)"),
        ("pre/start/1", f"(=> {b} (>= {s0} {th}))"),
        # decrease: the frame value plus the (negated) increments of the active morphisms
        (None, f"(= {s1} (+ {s0} (ite {b} (- {th}) 0.0)))"),
        # assign: the assigned value when active, else the frame value
        (None, f"(= |s.on.1| (ite {b} true |s.on.0|))"),
        ("goal/1", "|s.on.1|"),
    }
    assert set(asserts) == expected
    assert len(asserts) == len(expected)  # nothing asserted twice


def test_labels_are_ir_labels_of_their_constructs():
    enc = encoded()
    labels = [label for label, _ in enc.script.asserts if label is not None]
    assert {type(label) for label in labels} == {ir.Label}
    kinds = {label.kind for label in labels}
    assert kinds == {
        ir.LabelKind.BOUNDS,
        ir.LabelKind.INIT,
        ir.LabelKind.BOUND,
        ir.LabelKind.PRE,
        ir.LabelKind.GOAL,
    }
    assert enc.script.labels() == ["bounds/ram", "init/ram", "init/on", "bound/start/r", "pre/start/1", "goal/1"]


def test_variables_are_one_per_state_step_and_parameter():
    names = [s.name for s in encoded(steps=2).script.decls]
    assert sorted(names) == sorted(
        ["s.ram.0", "s.on.0", "s.ram.1", "s.on.1", "s.ram.2", "s.on.2"]
        + ["b.start.0", "th.start.r.0", "b.start.1", "th.start.r.1"]
    )


def test_the_use_limit_over_two_steps():
    enc = encoded(steps=2)
    # :uses 1 over two steps: not both activations (script.at_most's two-Boolean form)
    assert enc.uses_constraints(2) == [("uses/start", "(not (and |b.start.0| |b.start.1|))")]
    assert enc.uses_constraints(1) == []  # one step can use it at most once anyway


@pytest.mark.parametrize(
    "init, sat",
    [
        ("4", True),  # r = 1 fits: ram 4 ≥ 1, afterwards 3 ∈ [0, 8]
        ("1", True),  # r = 1 exactly
        ("0.5", False),  # r ≥ 1 > ram: the precondition never holds, so `on` stays false
    ],
)
def test_the_formula_is_satisfiable_exactly_when_the_goal_is_reachable(init, sat):
    enc = encoded(init)
    backend = open_backend()
    backend.add(enc.script.decls, enc.script.asserts)
    assert backend.check() is (Check.SAT if sat else Check.UNSAT)
