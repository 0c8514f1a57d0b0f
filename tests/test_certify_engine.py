"""The unified-planning engine's SOLVED_OPTIMALLY carries its certificate in the log (issue
31), as its UNSOLVABLE_PROVEN does: the optimum within the horizon the engine optimised over
(the bound that makes that horizon every plan length's is the log's argument), checked by the
validator and both solvers; a better value claimed is rejected."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("unified_planning")

from test_up_engine import _maximise_x, _solve, catc_engine  # noqa: F401  (the fixture)
from unified_planning.engines import PlanGenerationResultStatus as Status

from catc.frontend.up_import import up_to_instance
from catc.queries.certify import CertifyStatus, certify, cvc5_command, z3_command

SEPARATOR = " (check with catc.queries.certify.certify): "


def logged_certificate(result):
    line = next(m.message for m in result.log_messages if m.message.startswith("catc certificate ("))
    head, _, body = line.partition(SEPARATOR)
    return head, json.loads(body)


@pytest.mark.skipif(z3_command() is None or cvc5_command() is None, reason="needs the z3 binary and cvc5")
def test_an_optimal_answer_carries_a_certificate_both_solvers_check(catc_engine):  # noqa: F811
    problem = _maximise_x(5)  # x ≤ 5, +1 per action, maximise x: 5, over every length (6 states)
    r = _solve(problem)
    assert r.status is Status.SOLVED_OPTIMALLY
    head, doc = logged_certificate(r)
    assert head == "catc certificate (optimal among plans of at most 5 actions)"
    assert doc["method"] == "optimal" and doc["values"] == ["5"] and doc["sequential"] is True
    inst, _ = up_to_instance(problem)
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    better = {**doc, "values": ["6"]}  # the witness scores 5; the obligation's text no longer matches either
    rows = {r["name"]: r["status"] for r in certify(inst, better).obligations}
    assert rows == {"witness": "refuted", "optimal": "mismatch"}
