"""The problem file the runtime writes (``STATE/model/problem.cat``) is catc's: written from
the checked instance by catc's one ``.cat`` writer and laid out by ``catc fmt`` — so the
formatter leaves it as it is — and it reads back as the problem the runtime decided on."""

from __future__ import annotations

from pathlib import Path

from test_catsource import norm

from catc.api import load
from catc.frontend.formatter import format_text
from catrt.api import connect, init

MODEL = """\
(define (domain lamps)
  (:requirements :numeric :sets :optimization)
  (:sorts room - symbol)
  (:constants hall porch - room)
  (:resources
    (power real :bounds (0 *))
    (lit (set room))
    (spare int :bounds (0 10)))
  (:morphism lamp-a :kind software :uses 1
    :precondition (>= power 3)
    :effect (add lit hall))
  (:morphism lamp-b :kind software :uses 1
    :precondition (>= power 5)
    :effect (and (add lit hall) (add lit porch))))

(define (problem light)
  (:domain lamps)
  (:objects attic cellar - room)
  (:init (= power 4) (= spare 2))
  (:goal (member hall lit))
  (:horizon 1))
"""

EVENTS = [
    {"id": "e1", "set": {"power": "21/2"}},
    {"id": "e2", "softs": ["(member porch lit) :weight 2"]},
    {"id": "e3", "metric": "maximize power"},
    {"id": "e4", "goal": "(and (member hall lit)\n   (>= power 1))"},  # laid out by the formatter
]


def written(state: Path) -> str:
    return (state / "model" / "problem.cat").read_text(encoding="utf-8")


def test_the_problem_file_is_formatted_and_reads_back_as_the_decided_problem(tmp_path: Path):
    model = tmp_path / "lamps.cat"
    model.write_text(MODEL, encoding="utf-8")
    state = tmp_path / "st"
    init(state, str(model))
    with connect(state) as rt:
        for event in [None, *EVENTS]:
            if event is not None:
                outcome = rt.submit(event)
                assert outcome.status == "accepted", outcome.message
            text = written(state)
            assert format_text(text) == text  # catc fmt --check: unchanged
            assert text.startswith("; Written by catrt from its store")
            again = load(state / "model" / "problem.cat").instance
            assert norm(again.problem) == norm(rt.runtime.current.instance.problem)
    problem = rt.runtime.current.instance.problem
    assert problem.metric is not None and len(problem.softs) == 1 and len(problem.goal) == 2
