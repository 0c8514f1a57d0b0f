"""Certificates of catalog cores (issue 31, with issue 24's catalogs): the core's UNSAT by
the consumption abstraction (the core's indicators asserted, every other denied), and one
witness composition per member replayed by the validator — no satisfiable SMT obligation
left for the checkers.  Wrong ones are rejected: a dropped member, a witness that does not
replay, a witness that frees what the core enforces."""

from __future__ import annotations

import copy
import random
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

import catalog_gen as gen  # noqa: E402

from catc.api import loads  # noqa: E402
from catc.queries.certify import (  # noqa: E402
    CertifyStatus,
    certify,
    consumption_core_text,
    core_certificate,
    core_obligations,
    cvc5_command,
    z3_command,
)
from catc.queries.diagnose import diagnose  # noqa: E402
from catc.smt.backend import Check  # noqa: E402
from catc.smt.consumption import Consumption  # noqa: E402

pytestmark = pytest.mark.skipif(
    z3_command() is None or cvc5_command() is None, reason="needs the z3 binary (z3-solver) and cvc5 (PyPI)"
)


def catalog(variant="budget", n=12, d=4):
    cat = gen.build(n, d)
    text, _ = gen.problem_text(cat, variant)
    return loads({"domain.cat": gen.domain_text(cat), f"{variant}.cat": text}, f"{variant}.cat").instance


@pytest.fixture(scope="module")
def budget_core():
    inst = catalog()
    diag = diagnose(inst)
    assert diag.status.value == "unsat" and diag.cores
    return inst, core_certificate(inst, diag, False, "catc.relaxed")


def test_a_catalog_core_is_certified_by_the_abstraction_and_a_witness_per_member(budget_core):
    inst, doc = budget_core
    assert "init/budget" in doc["core"]  # catalog_gen: every core of the budget cut holds it
    assert doc["core_proof"] == "consumption"
    names = [o["name"] for o in doc["obligations"]]
    assert names == ["core", *(f"witness/{label}" for label in doc["core"])]  # no sat obligation left
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    rows = {r["name"]: r for r in result.obligations}
    assert {c: a["answer"] for c, a in rows["core"]["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}


def test_a_core_without_init_budget_is_refuted_by_the_solvers(budget_core):
    inst, doc = budget_core
    smaller = [label for label in doc["core"] if label != "init/budget"]  # the budget free: the cheapest fit
    (unsat,), _ = core_obligations(inst, smaller, doc["horizon"], False, None, [], "consumption")
    wrong = {**doc, "core": smaller, "obligations": [unsat | {"producer": "catc.relaxed"}]}
    wrong["obligations"] += [o for o in doc["obligations"] if o["name"][8:] in smaller]
    result = certify(inst, wrong)
    rows = {r["name"]: r for r in result.obligations}
    assert rows["core"]["status"] == "refuted" and rows["core"]["checkers"]["cvc5"]["answer"] == "sat"


def test_a_witness_that_does_not_replay_is_refuted(budget_core):
    inst, doc = budget_core
    wrong = copy.deepcopy(doc)
    o = next(o for o in wrong["obligations"] if o["name"] == "witness/init/budget")
    o["plan"] = {"schema": "catc.plan/1", "steps": []}  # the goal needs the chain of capabilities
    rows = {r["name"]: r["status"] for r in certify(inst, wrong).obligations}
    assert rows["witness/init/budget"] == "refuted"


def test_a_witness_may_not_free_what_the_core_enforces(budget_core):
    inst, doc = budget_core
    wrong = copy.deepcopy(doc)
    effect = next(label for label in doc["core"] if label.startswith("eff/"))
    other = next(o for o in wrong["obligations"] if o["name"].startswith("witness/") and o["name"][8:] != effect)
    other.pop("replay", None)
    other["without_effects"] = [effect]  # an effect the rest of the core enforces
    rows = {r["name"]: r["status"] for r in certify(inst, wrong).obligations}
    assert rows[other["name"]] == "refuted"


def test_an_edited_core_proof_does_not_match(budget_core):
    inst, doc = budget_core
    wrong = copy.deepcopy(doc)
    wrong["obligations"][0]["smtlib"] = wrong["obligations"][0]["smtlib"].replace(
        "(check-sat)", "(assert false)\n(check-sat)"
    )
    rows = {r["name"]: r["status"] for r in certify(inst, wrong).obligations}
    assert rows["core"] == "mismatch"


@pytest.mark.parametrize("variant", ["budget", "power", "ram"])
def test_denying_the_other_indicators_keeps_the_answer(variant):
    # the abstraction is antitone in its indicators: with a set of labels enforced and the
    # rest free it is satisfiable exactly when the rest denied is (random sets, both ways)
    inst = catalog(variant)
    a = Consumption(inst)
    rng = random.Random(31)
    seen = set()
    answer, core = a.check(a.labels)
    assert answer is Check.UNSAT and core  # catalog_gen: every cut is infeasible
    for i in range(12):  # the core with others (unsat), or without one member (mostly sat)
        kept = core if i % 2 == 0 else [x for x in core if x != rng.choice(core)]
        labels = [label for label in a.labels if label in kept or rng.random() < 0.5]
        free = a.check(labels)[0]
        denied = Consumption(inst)
        denied.backend.add([], [(None, f"(not {denied.indicator[x]})") for x in denied.labels if x not in labels])
        assert denied.check(labels)[0] is free
        seen.add(free)
    assert seen == {Check.SAT, Check.UNSAT}  # both answers met: the comparison could fail


def test_the_consumption_core_text_asserts_the_core_and_denies_the_rest():
    inst = catalog()
    core = ["init/budget", "bounds/budget"]
    text = consumption_core_text(inst, core, None)
    assert "(assert |A:init/budget|)" in text and "(assert (not |A:init/ram|))" in text


def test_a_witness_solve_finds_is_replayed_too(budget_core):
    # the fallback when diagnose's solver-free try has none: catc solve on the instance the
    # other members leave — an effect member removed, a Boolean initial value flipped
    from catc.queries.certify.cores import _extended, _solved_witness

    inst, doc = budget_core
    steps = _extended(inst, doc["horizon"], None)
    effect = next(label for label in doc["core"] if label.startswith("eff/"))
    flag = next(label for label in doc["core"] if label.startswith("init/cap"))
    solved = {}
    for label in (effect, flag):
        solved[label] = _solved_witness(inst, frozenset(doc["core"]) - {label}, label, steps, False)
        assert solved[label] is not None, label
    assert solved[effect]["without_effects"] == [effect]
    assert list(solved[flag]["initial_values"].values()) == [True]  # the capability flags start false
    mixed = copy.deepcopy(doc)
    mixed["obligations"] = [solved.get(o["name"][8:], o) for o in mixed["obligations"]]
    result = certify(inst, mixed)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations


def test_a_catalog_core_certificate_follows_the_schema(budget_core):
    import json

    import jsonschema

    schema = json.loads((ROOT / "docs/schemas/catc.certificate-1.json").read_text())
    jsonschema.validate(json.loads(json.dumps(budget_core[1])), schema)
