"""Certificates of the SMT route's finals without a state count (issue 27's, issue 31): no path
of t steps visits no state twice, with the bounded problem at t − 1 (``simple-path``), and a
sum of numbers that never grows as an inductive invariant (``conserved-sum``) — each checked
by the z3 binary and cvc5; a t too small, a horizon t − 2, a wrong Σ₀ and a feasible
problem's forged "no" are rejected. Every expected answer is argued by hand from the model
(a token on a line of six places; workers moved between three farms)."""

from __future__ import annotations

import copy
import json

import pytest
from conftest import ROOT, run_catc
from test_smt_unsolvable import _farms, _token

from catc.queries.certify import CertifyStatus, certificate, certify, cvc5_command, z3_command
from catc.queries.certify.finals import simple_path_obligations, sum_obligations
from catc.queries.solve import solve

pytestmark = pytest.mark.skipif(
    z3_command() is None or cvc5_command() is None, reason="needs the z3 binary (z3-solver) and cvc5 (PyPI)"
)


def both(result):
    return {r["name"]: {c: a["answer"] for c, a in r["checkers"].items()} for r in result.obligations}


def statuses(result):
    return {r["name"]: r["status"] for r in result.obligations}


# ---------------------------------------------------------------- simple-path (the recurrence diameter)


def token_no():
    """p1 and p2 together: never (one token). The SMT route makes its UNSAT final at t = 8,
    the first horizon of the loop schedule (tests/test_smt_unsolvable.py)."""
    inst = _token("(and p1 p2)")
    result = solve(inst, horizon=30, sequential=True)
    return inst, result, certificate(inst, result)


def test_a_final_unsat_without_a_simple_path_is_certified_by_both_solvers():
    inst, result, doc = token_no()
    assert result.simple_path == 8
    assert (doc["method"], doc["steps"], doc["horizon"], doc["sequential"]) == ("simple-path", 8, 7, True)
    checked = certify(inst, doc)
    assert checked.status is CertifyStatus.CERTIFIED, checked.obligations
    assert both(checked) == {n: {"z3": "unsat", "cvc5": "unsat"} for n in ("simple-path", "bounded")}
    assert all(r["proved_by"] and doc["producer"] not in r["proved_by"] for r in checked.obligations)


def test_parallel_steps_are_certified_the_same_way():
    """With parallel steps a step may fire r1 and, say, l3 together, but the token is in
    one place: each step moves it one place, so the states still lie on the line."""
    inst = _token("(and p1 p2)")
    result = solve(inst, horizon=30)
    doc = certificate(inst, result)
    assert doc["method"] == "simple-path" and doc["sequential"] is False
    assert certify(inst, doc).status is CertifyStatus.CERTIFIED


def forged(inst, doc, steps, horizon):
    """``doc`` with other claims and the obligations written for them (self-consistent:
    only the solvers, or the horizon's check, can reject it)."""
    bad = copy.deepcopy(doc)
    bad["steps"], bad["horizon"] = steps, horizon
    bad["obligations"] = simple_path_obligations(inst, steps, horizon, True)
    for o in bad["obligations"]:
        o["producer"] = doc["producer"]
    return bad


def test_the_least_t_is_six_and_five_has_a_simple_path():
    """The token's six states lie on a line: the longest path visiting no state twice is
    p1 → p6, 5 steps. So t = 6 holds (no simple path of 6 steps), and t = 5 is refuted by
    both solvers: r1..r5 is a path of 5 steps with 6 distinct states."""
    inst, _, doc = token_no()
    assert certify(inst, forged(inst, doc, 6, 5)).status is CertifyStatus.CERTIFIED
    checked = certify(inst, forged(inst, doc, 5, 4))
    assert checked.status is CertifyStatus.REFUTED
    assert both(checked)["simple-path"] == {"z3": "sat", "cvc5": "sat"}
    assert statuses(checked) == {"simple-path": "refuted", "bounded": "proved"}


def test_a_horizon_below_t_minus_1_does_not_match_though_both_texts_are_unsat():
    """p6 needs five moves (r1..r5). Paths of 6 steps visiting no state twice do not exist
    and nothing reaches p6 within 4 steps — both texts are unsat — yet a composition of 5
    steps exists: the horizon t − 2 leaves length t − 1 uncovered. The certificate is a
    mismatch before any solver is believed."""
    inst = _token("p6")
    _, _, doc = token_no()
    checked = certify(inst, forged(inst, doc, 6, 4))
    assert checked.status is CertifyStatus.REFUTED
    assert set(statuses(checked).values()) == {"mismatch"}
    checked = certify(inst, forged(inst, doc, 6, 5))  # at t − 1 the solvers find r1..r5
    assert checked.status is CertifyStatus.REFUTED
    assert both(checked)["bounded"] == {"z3": "sat", "cvc5": "sat"}


def test_steps_must_be_a_positive_whole_number():
    from catc.queries.base import InputError

    inst, _, doc = token_no()
    for steps in (0, "8", True, None):
        bad = copy.deepcopy(doc)
        bad["steps"] = steps
        with pytest.raises(InputError, match="steps"):
            certify(inst, bad)


def test_solve_writes_and_certify_checks_a_simple_path_certificate(tmp_path):
    src = tmp_path / "token.cat"
    src.write_text(TOKEN_TEXT)  # token_no's model, written out for the command line
    cert = tmp_path / "token.json"
    # the SMT route's certificate (the default, auto, runs the forward search on this ground model)
    res = run_catc("solve", src, "--horizon", "30", "--sequential", "--strategy", "incremental", "--certificate", cert)
    assert res.exit_code == 1, res.output  # UNSAT
    res = run_catc("certify", src, cert, "--json")
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["status"] == "certified" and [o["name"] for o in out["obligations"]] == ["simple-path", "bounded"]
    assert all(set(o["proved_by"]) == {"z3", "cvc5"} - {o["producer"]} for o in out["obligations"])


TOKEN_TEXT = """
(define (domain token) (:requirements :recomposition)
  (:resources (p1 bool) (p2 bool) (p3 bool) (p4 bool) (p5 bool) (p6 bool))
  (:morphism r1 :precondition p1 :effect (and (assign p1 false) (assign p2 true)))
  (:morphism l1 :precondition p2 :effect (and (assign p2 false) (assign p1 true)))
  (:morphism r2 :precondition p2 :effect (and (assign p2 false) (assign p3 true)))
  (:morphism l2 :precondition p3 :effect (and (assign p3 false) (assign p2 true)))
  (:morphism r3 :precondition p3 :effect (and (assign p3 false) (assign p4 true)))
  (:morphism l3 :precondition p4 :effect (and (assign p4 false) (assign p3 true)))
  (:morphism r4 :precondition p4 :effect (and (assign p4 false) (assign p5 true)))
  (:morphism l4 :precondition p5 :effect (and (assign p5 false) (assign p4 true)))
  (:morphism r5 :precondition p5 :effect (and (assign p5 false) (assign p6 true)))
  (:morphism l5 :precondition p6 :effect (and (assign p6 false) (assign p5 true))))
(define (problem t) (:domain token) (:init (= p1 true)) (:goal (and p1 p2)))
"""


# ---------------------------------------------------------------- conserved-sum


def farms_no(workers=2, sequential=True):
    inst = _farms(workers)
    result = solve(inst, horizon=20, sequential=sequential)
    return inst, result


@pytest.mark.parametrize("sequential", [True, False])
def test_a_sum_that_never_grows_is_certified_as_an_inductive_invariant(sequential):
    """x0 + x1 + x2 ≤ 2: initially 2 + 0 + 0; a slow move keeps it, a fast one lowers it by
    2; the goal needs each ≥ 1, a total ≥ 3."""
    inst, result = farms_no(sequential=sequential)
    doc = certificate(inst, result)
    assert doc["method"] == "conserved-sum" and doc["producer"] == "catc.bounds"
    assert doc["conserved"]["sums"] == [{"resources": ["x0", "x1", "x2"], "initial": "2", "direction": "at most"}]
    checked = certify(inst, doc)
    assert checked.status is CertifyStatus.CERTIFIED, checked.obligations
    assert both(checked) == {n: {"z3": "unsat", "cvc5": "unsat"} for n in ("initiation", "consecution", "goal")}


def with_sum(inst, doc, initial):
    bad = copy.deepcopy(doc)
    bad["conserved"]["sums"][0]["initial"] = initial
    bad["obligations"] = sum_obligations(inst, bad["conserved"], bad["horizon"], True)
    for o in bad["obligations"]:
        o["producer"] = doc["producer"]
    return bad


def test_a_wrong_initial_sum_is_refuted_by_the_solvers():
    """Σ₀ = 1: the initial state has 2 — initiation is sat. Σ₀ = 3: x0 = x1 = x2 = 1
    keeps the sum ≤ 3 and meets the goal — goal exclusion is sat."""
    inst, result = farms_no()
    doc = certificate(inst, result)
    low = certify(inst, with_sum(inst, doc, "1"))
    assert low.status is CertifyStatus.REFUTED and statuses(low)["initiation"] == "refuted"
    assert both(low)["initiation"] == {"z3": "sat", "cvc5": "sat"}
    high = certify(inst, with_sum(inst, doc, "3"))
    assert high.status is CertifyStatus.REFUTED and statuses(high)["goal"] == "refuted"
    assert statuses(high)["initiation"] == statuses(high)["consecution"] == "proved"


def test_a_claimed_sum_a_morphism_raises_is_refuted_at_consecution():
    """x0 + x1 alone ≤ 2 is no invariant: slow12 moves a worker from x1 to x2, but slow21
    moves it back, raising x0 + x1 by 1 from a state where it may be 2."""
    inst, result = farms_no()
    doc = certificate(inst, result)
    bad = copy.deepcopy(doc)
    bad["conserved"]["sums"][0]["resources"] = ["x0", "x1"]
    bad["obligations"] = sum_obligations(inst, bad["conserved"], bad["horizon"], True)
    for o in bad["obligations"]:
        o["producer"] = doc["producer"]
    assert statuses(certify(inst, bad))["consecution"] == "refuted"


def test_a_forged_sum_certificate_for_enough_workers_is_refuted_at_the_goal():
    """Three workers: x0 + x1 + x2 ≤ 3 holds, and 1 + 1 + 1 meets the goal."""
    inst2, result = farms_no()
    doc = certificate(inst2, result)
    inst3 = _farms(3)
    bad = with_sum(inst3, doc, "3")
    checked = certify(inst3, bad)
    assert checked.status is CertifyStatus.REFUTED and statuses(checked)["goal"] == "refuted"


def test_the_new_kinds_follow_the_schema():
    import jsonschema

    schema = json.loads((ROOT / "docs/schemas/catc.certificate-1.json").read_text())
    for doc in (token_no()[2], certificate(*farms_no())):
        jsonschema.validate(json.loads(json.dumps(doc)), schema)


def test_an_exists_step_answer_is_certified_with_sequential_steps():
    """--exists-step: the same line, ∃-steps of a fixed order; the certificate is written
    for sequential steps (a sequential path is an ∃-step one of one activation per step, so
    the ∃-step UNSATs imply the sequential ones) and both solvers prove it."""
    inst = _token("(and p1 p2)")
    result = solve(inst, horizon=30, exists_step=True)
    doc = certificate(inst, result)
    assert (doc["method"], doc["sequential"], doc["steps"]) == ("simple-path", True, result.simple_path)
    assert certify(inst, doc).status is CertifyStatus.CERTIFIED
