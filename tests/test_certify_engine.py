"""The unified-planning engine's SOLVED_OPTIMALLY carries its certificate in the log (issue
31), as its UNSOLVABLE_PROVEN does: the optimum within the horizon the engine optimised over
(the bound that makes that horizon every plan length's is the log's argument), checked by the
validator and both solvers; a better value claimed is rejected."""

from __future__ import annotations

import json

import pytest

pytest.importorskip("unified_planning")

from test_up_engine import _maximise_x, _solve, _steps_problem, catc_engine  # noqa: F401  (the fixture)
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


@pytest.mark.skipif(z3_command() is None or cvc5_command() is None, reason="needs the z3 binary and cvc5")
def test_a_shortest_plan_carries_its_certificate_and_a_longer_claim_is_refuted(catc_engine):  # noqa: F811
    from unified_planning.model.metrics import MinimizeSequentialPlanLength

    from catc.queries.certify import shortest_certificate  # noqa: F401  (what the engine calls)
    from catc.queries.certify.optimal import shortest_obligations

    problem = _steps_problem()  # by hand: 1, 3, 1, 1 is shortest (4 actions; 3 + 3 passes x = 3)
    problem.add_quality_metric(MinimizeSequentialPlanLength())
    r = _solve(problem)
    assert r.status is Status.SOLVED_OPTIMALLY
    line = next(m.message for m in r.log_messages if m.message.startswith("catc certificate" + SEPARATOR))
    doc = json.loads(line.partition(SEPARATOR)[2])
    assert (doc["method"], doc["horizon"], doc["producer"]) == ("shortest", 4, "catc.search")
    inst, _ = up_to_instance(problem)
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    rows = {row["name"]: row for row in result.obligations}
    assert {c: a["answer"] for c, a in rows["shorter"]["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}
    assert rows["witness"]["proved_by"] == ["catc.validator"]
    # claimed one longer: the witness has not 5 steps, and 4 steps do reach the goal
    longer = {**doc, "horizon": 5}
    longer["obligations"] = [doc["obligations"][0]] + [
        o | {"producer": "catc.search"} for o in shortest_obligations(inst, 5, True)
    ]
    rows = {row["name"]: row for row in certify(inst, longer).obligations}
    assert rows["witness"]["status"] == "refuted"
    assert rows["shorter"]["status"] == "refuted" and rows["shorter"]["checkers"]["cvc5"]["answer"] == "sat"
    # claimed one shorter: the 4-step witness is not a 3-step composition
    shorter = {**doc, "horizon": 3}
    shorter["obligations"] = [doc["obligations"][0]] + [
        o | {"producer": "catc.search"} for o in shortest_obligations(inst, 3, True)
    ]
    assert {row["name"]: row["status"] for row in certify(inst, shorter).obligations}["witness"] == "refuted"
