"""Every example's answers are those recorded before the architecture change (issue 11):
the same ``--json`` documents (timings removed; locations as the text they point at), the
same SMT-LIB2 and PDDL text, the same exit codes.  tests/golden/record.py made the file and
says how; the answers were never re-recorded to make this pass.  One additive change was
recorded since (issue 16): the ``unsat`` object of ``catc.solve/1`` gained ``proof``, ``why``
and ``label``; a script checked that every other byte of those 12 documents, their exit codes
and their stderr were unchanged before they were re-recorded.  A second (issue 17, units):
``catc.solve/1`` and ``catc.optimize/1`` gained ``units`` (each resource's declared unit) next
to their states; a script checked that the 73 documents with a composition differ from their
recording by that key alone (every SMT-LIB2, PDDL and text answer is unchanged) before they
were re-recorded.  Then the examples' numeric parameters got units (GB, m, count): 21 answers
changed only by ``parameter_units`` added to their ``--json`` documents (no text answer
changed); a script checked that before they were re-recorded.  The example examples/catalog
(issue 17) was recorded when it was added; its expectation is derived by hand in its
expect.toml.  Last, ``catc.relax/1`` relaxations of initial values gained ``unit``; a script
checked that the four relax documents with one differ by that key alone."""

from __future__ import annotations

import json
import sys

import pytest
from conftest import ROOT

sys.path.insert(0, str(ROOT / "tests" / "golden"))
import record

RECORDED = json.loads(record.ANSWERS.read_text())
COMMANDS = dict(record.commands())


def test_the_recorded_commands_are_those_the_recorder_runs():
    assert set(RECORDED) == set(COMMANDS)


@pytest.mark.parametrize("key", sorted(RECORDED))
def test_answer_unchanged(key, monkeypatch):
    monkeypatch.chdir(ROOT)
    argv = RECORDED[key]["argv"]
    assert argv == COMMANDS[key]
    answer = {"argv": argv, **record.run(argv)}
    assert answer == RECORDED[key]
