"""Certificates of the "no" answers issue 24's consumption abstraction and the forward search
prove (issue 31): the abstraction of every composition, unsat, and the reachable states as an
inductive invariant of the sequential one-step encoding — both checked by the z3 binary and
cvc5; a wrong bound, a dropped state, a feasible problem's "no" are rejected."""

from __future__ import annotations

import copy
import json
import sys
from fractions import Fraction

import pytest
from conftest import ROOT

from catc.api import loads
from catc.queries import certify as certify_module
from catc.queries.certify import (
    CertifyStatus,
    NotCertifiable,
    certificate,
    certify,
    consumption_obligations,
    cvc5_command,
    z3_command,
)
from catc.queries.solve import solve

sys.path.insert(0, str(ROOT / "benchmarks"))
import catalog_gen as gen

pytestmark = pytest.mark.skipif(
    z3_command() is None or cvc5_command() is None, reason="needs the z3 binary (z3-solver) and cvc5 (PyPI)"
)

# Two switches, each of which turns the other off: both are never on.  Relaxed reachability
# forgets the deletes (both may be on) and nothing has a use limit, so only the forward
# search's exhaustion of the 2 · 2 · 4 - 4 = 12 reachable states (never a, b together; n in
# 0..3) proves the answer final.
TOGGLE = """
(define (domain toggle)
  (:requirements :numeric)
  (:resources (a bool) (b bool) (n int :unit count :bounds (0 3)))
  (:morphism press-a :effect (and (assign a true) (assign b false)))
  (:morphism press-b :effect (and (assign b true) (assign a false)))
  (:morphism count :precondition (< n 3) :effect (increase n 1)))
(define (problem both-on)
  (:domain toggle)
  (:init (= a false) (= b false) (= n 0))
  (:goal (and a b)))
"""


def toggle():
    return loads({"toggle.cat": TOGGLE}, "toggle.cat").instance


def catalog(variant, delta=1):
    cat = gen.build(12, 4)
    text, _ = gen.problem_text(cat, variant, delta)
    dom = gen.domain_text(cat, missing=variant == "missing")
    return loads({"domain.cat": dom, f"{variant}.cat": text}, f"{variant}.cat").instance


def both_proved(result, producer):
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    for row in result.obligations:
        assert {c: a["answer"] for c, a in row["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}
        assert row["proved_by"] and producer not in row["proved_by"]


# ---------------------------------------------------------------- the consumption abstraction


@pytest.mark.parametrize("variant", ["budget", "power"])  # (ram: the relaxation sees it first)
def test_a_consumption_bounds_unsat_is_certified(variant):
    inst = catalog(variant)  # the resource's initial value is one below the least sum (catalog_gen)
    result = solve(inst)
    assert result.status.value == "unsat" and result.final and result.refutation is not None
    doc = certificate(inst, result)
    assert doc["method"] == "consumption" and doc["producer"] == "catc.consumption"
    assert [b["resource"] for b in doc["bounds"]] == [variant]
    assert [o["name"] for o in doc["obligations"]] == ["consumption"]
    both_proved(certify(inst, doc), doc["producer"])


def test_a_wrong_bound_does_not_match_the_model():
    inst = catalog("budget")
    doc = certificate(inst, solve(inst))
    bad = copy.deepcopy(doc)
    bad["bounds"][0]["room"] = str(int(doc["bounds"][0]["room"]) - 10)  # claims less money than there is
    result = certify(inst, bad)
    assert result.status is CertifyStatus.REFUTED
    assert {r["name"]: r["status"] for r in result.obligations}["bounds"] == "mismatch"


def test_a_consumption_no_for_a_feasible_problem_is_refuted_by_the_solvers():
    feasible = catalog("budget", delta=-1000)  # 999 over the least sum: the abstraction has a model
    doc = certificate(catalog("budget"), solve(catalog("budget")))
    forged = copy.deepcopy(doc) | {"bounds": [], "obligations": consumption_obligations(feasible)}
    for o in forged["obligations"]:
        o["producer"] = "catc.consumption"
    result = certify(feasible, forged)
    assert result.status is CertifyStatus.REFUTED
    row = result.obligations[0]
    assert row["status"] == "refuted" and "sat" in {a["answer"] for a in row["checkers"].values()}


# ---------------------------------------------------------------- the forward search


def searched():
    inst = toggle()
    result = solve(inst, strategy="search", sequential=True)
    assert result.status.value == "unsat" and result.final and result.reason.startswith("forward search")
    return inst, certificate(inst, result)


def test_the_forward_searchs_unsat_is_certified_by_its_reachable_states():
    inst, doc = searched()
    assert doc["method"] == "reachable" and doc["producer"] == "catc.search" and doc["sequential"] is True
    states = {tuple(s) for s in doc["states"]["values"]}
    assert doc["states"]["resources"] == ["a", "b", "n"]
    expected = {(a, b, str(n)) for a, b in [(False, False), (True, False), (False, True)] for n in range(4)}
    assert states == expected
    assert [o["name"] for o in doc["obligations"]] == ["initiation", "consecution", "goal"]
    both_proved(certify(inst, doc), doc["producer"])


def test_a_dropped_state_is_refuted_at_consecution():
    inst, doc = searched()
    bad = copy.deepcopy(doc)
    bad["states"]["values"] = [s for s in bad["states"]["values"] if s != [True, False, "0"]]
    bad["obligations"] = certify_module.reachable_obligations(inst, bad["states"], bad["horizon"])
    for o in bad["obligations"]:
        o["producer"] = "catc.search"
    result = certify(inst, bad)
    assert result.status is CertifyStatus.REFUTED
    status = {r["name"]: r["status"] for r in result.obligations}
    assert status == {"initiation": "proved", "consecution": "refuted", "goal": "proved"}


def test_a_goal_state_in_the_set_is_refuted_at_the_goal():
    inst, doc = searched()
    bad = copy.deepcopy(doc)
    bad["states"]["values"].append([True, True, "0"])
    bad["obligations"] = certify_module.reachable_obligations(inst, bad["states"], bad["horizon"])
    for o in bad["obligations"]:
        o["producer"] = "catc.search"
    assert {r["name"]: r["status"] for r in certify(inst, bad).obligations}["goal"] == "refuted"


def test_a_state_set_edited_after_the_obligations_were_written_does_not_match():
    inst, doc = searched()
    bad = json.loads(json.dumps(doc))
    bad["states"]["values"].pop()  # the obligations still list it
    result = certify(inst, bad)
    assert result.status is CertifyStatus.REFUTED
    assert {r["status"] for r in result.obligations} == {"mismatch"}


def test_more_reachable_states_than_the_limit_are_not_certified(monkeypatch):
    monkeypatch.setattr(certify_module, "STATE_LIMIT", 5)
    inst = toggle()
    with pytest.raises(NotCertifiable, match="more than 5"):
        certificate(inst, solve(inst, strategy="search", sequential=True))


def test_both_new_kinds_follow_the_schema():
    import jsonschema

    schema = json.loads((ROOT / "docs/schemas/catc.certificate-1.json").read_text())
    inst = catalog("budget")
    for doc in (certificate(inst, solve(inst)), searched()[1]):
        jsonschema.validate(json.loads(json.dumps(doc)), schema)


# ---------------------------------------------------------------- one checker process for all


@pytest.mark.parametrize("checker", ["z3", "cvc5"])
def test_one_process_per_checker_keeps_obligations_apart(tmp_path, checker):
    """Files that declare the same symbol with contradicting facts are each satisfiable on
    their own: a batch that leaked one into the next would answer unsat or an error; a file
    that does not parse is an error of its own, and the files after it are still answered."""
    texts = [
        "(set-logic ALL)\n(declare-fun x () Int)\n(assert (> x 5))\n(check-sat)\n",
        "(set-logic ALL)\n(declare-fun x () Int)\n(assert (< x 0))\n(check-sat)\n",
        "(set-logic ALL)\n(assert (> y 0))\n(check-sat)\n",  # y undeclared
        "(set-logic ALL)\n(declare-fun x () Real)\n(assert (and (> x 1.0) (< x 1.0)))\n(check-sat)\n",
    ]
    paths = []
    for i, text in enumerate(texts):
        paths.append(str(tmp_path / f"{i}.smt2"))
        (tmp_path / f"{i}.smt2").write_text(text)
    answers = [a for a, _ in certify_module.run_batch(checker, paths, 30.0)]
    assert answers == ["sat", "sat", "error", "unsat"]


# ---------------------------------------------------------------- objectives given on the command line

MAX_CONFIDENCE = ROOT / "examples/gpu-allocation/max-confidence.cat"  # expect.toml: optimum 21/25


def given_optimum(*terms):
    from catc.frontend.workspace import load_instance
    from catc.interfaces.command import objectives
    from catc.ir.views import apply_view
    from catc.queries.certify import optimal_certificate
    from catc.queries.optimize import optimize
    from catgrammar.diagnostics import Diagnostics

    _, inst = load_instance(None, str(MAX_CONFIDENCE), Diagnostics())
    inst = apply_view(inst, None)
    given = objectives(inst, list(terms))
    return inst, optimal_certificate(inst, optimize(inst, given), {"objectives": given})


def test_an_optimum_of_objectives_given_on_the_command_line_is_certified():
    inst, doc = given_optimum(("maximize", "confidence"))  # the metric's own term, given
    assert doc["objectives"] == {"kind": "given", "terms": [{"sense": "maximize", "term": "confidence"}]}
    assert doc["values"] == ["21/25"]
    assert certify(inst, doc).status is CertifyStatus.CERTIFIED


@pytest.mark.parametrize(
    "claim, refuted",
    [("22/25", {"witness"}), ("4/5", {"witness", "optimal"})],  # better than reachable; worse than the optimum
)
def test_a_wrong_optimum_of_given_objectives_is_refuted(claim, refuted):
    from catc.queries.certify import _objectives, optimal_obligation

    inst, doc = given_optimum(("maximize", "confidence"))
    model, objectives, softs = _objectives(inst, doc["objectives"])
    best = optimal_obligation(model, objectives, softs, doc["horizon"], False, [Fraction(claim)])
    witness = next(o for o in doc["obligations"] if o["name"] == "witness")
    wrong = doc | {"values": [claim], "obligations": [witness, best | {"producer": "z3"}]}
    rows = certify(inst, wrong).obligations
    assert {r["name"] for r in rows if r["status"] == "refuted"} == refuted


def test_a_given_objective_the_model_does_not_have_is_an_input_error():
    from catc.queries.base import InputError

    inst, doc = given_optimum(("maximize", "confidence"))
    doc["objectives"]["terms"][0]["term"] = "(+ confidence nonsense)"
    with pytest.raises(InputError, match="not a term of the model"):
        certify(inst, doc)
