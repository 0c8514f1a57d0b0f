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
from catc.queries.certify import (
    CertifyStatus,
    NotCertifiable,
    certificate,
    certify,
    consumption_obligations,
    cvc5_command,
    state_bounded_obligations,
    z3_command,
)
from catc.queries.certify import checkers as checkers_module
from catc.queries.certify import unsat as unsat_module
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


def test_a_bounded_no_with_few_reachable_states_is_certified_for_every_length():
    """The SMT search's UNSAT within 10 sequential steps is not final (nothing has a use
    limit); the 12 reachable states, none a goal state, prove it for every length."""
    inst = toggle()
    result = solve(inst, sequential=True)
    assert result.status.value == "unsat" and not result.final
    doc = certificate(inst, result)
    assert doc["method"] == "reachable" and len(doc["states"]["values"]) == 12
    assert certify(inst, doc).status is CertifyStatus.CERTIFIED
    with pytest.raises(NotCertifiable):  # parallel steps: no reachable-states certificate
        certificate(inst, solve(inst))


def test_a_dropped_state_is_refuted_at_consecution():
    inst, doc = searched()
    bad = copy.deepcopy(doc)
    bad["states"]["values"] = [s for s in bad["states"]["values"] if s != [True, False, "0"]]
    bad["obligations"] = unsat_module.reachable_obligations(inst, bad["states"], bad["horizon"])
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
    bad["obligations"] = unsat_module.reachable_obligations(inst, bad["states"], bad["horizon"])
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


def test_more_reachable_states_than_the_limit_go_into_a_bdd():
    """Above the explicit list's limit the states are a BDD (tests/test_certify_bdd.py); above
    the BDD's, no certificate."""
    inst = toggle()
    result = solve(inst, strategy="search", sequential=True)
    assert certificate(inst, result, state_limit=5)["method"] == "bdd"
    with pytest.raises(NotCertifiable, match="more than 10"):
        certificate(inst, result, state_limit=5, bdd_limit=10)


def test_both_new_kinds_follow_the_schema():
    import jsonschema

    schema = json.loads((ROOT / "docs/schemas/catc.certificate-1.json").read_text())
    inst = catalog("budget")
    for doc in (
        certificate(inst, solve(inst)),
        certificate(toggle(), solve(toggle(), horizon=15)),  # state-bounded
        searched()[1],
        front()[1],
        two_cores()[1],
        discrete(loads({"two.cat": TWO}, "two.cat").instance),
    ):
        jsonschema.validate(json.loads(json.dumps(doc)), schema)


# ---------------------------------------------------------------- the reachable-state bound (SMT route)
# toggle's states: a, b Boolean and n in 0..3, so at most 2 · 2 · 4 = 16 — by hand, not by catc


def test_an_unsat_made_final_by_the_state_count_is_certified_at_n_minus_1():
    inst = toggle()
    result = solve(inst, horizon=15)  # parallel steps: the SMT route, not the forward search
    assert result.status.value == "unsat" and result.final and not result.sequential
    doc = certificate(inst, result)
    assert (doc["method"], doc["state_count"], doc["horizon"]) == ("state-bounded", 16, 15)
    assert [o["name"] for o in doc["obligations"]] == ["bounded"]
    row = certify(inst, doc).obligations[0]
    assert {c: a["answer"] for c, a in row["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}
    assert row["proved_by"] == ["cvc5"]  # z3 produced the answer: only cvc5 counts


def test_a_not_final_unsat_at_n_minus_1_is_certified_too():
    """The unified-planning engine's "at most N states" UNSOLVABLE_PROVEN: an UNSAT the answer
    does not call final, at a horizon of N − 1 or more; below it, no certificate."""
    from catc.queries.solve import SolveResult, SolveStatus

    inst = toggle()
    doc = certificate(inst, SolveResult(SolveStatus.UNSAT, 17, final=False))
    assert (doc["method"], doc["horizon"]) == ("state-bounded", 15)
    assert certify(inst, doc).status is CertifyStatus.CERTIFIED
    with pytest.raises(NotCertifiable):
        certificate(inst, SolveResult(SolveStatus.UNSAT, 14, final=False))


def test_a_state_count_the_model_does_not_give_or_a_short_horizon_does_not_match():
    inst = toggle()
    doc = certificate(inst, solve(inst, horizon=15))
    fewer = {**doc, "state_count": 12, "horizon": 11}  # claims 12 states: a shorter horizon would do
    fewer["obligations"] = [o | {"producer": "z3"} for o in state_bounded_obligations(inst, 11, False)]
    assert certify(inst, fewer).status is CertifyStatus.REFUTED
    assert {r["status"] for r in certify(inst, fewer).obligations} >= {"mismatch"}


def test_a_state_bounded_no_for_a_feasible_problem_is_refuted_by_the_solvers():
    inst = loads({"toggle.cat": TOGGLE.replace("(:goal (and a b))", "(:goal (and a (= n 2)))")}, "toggle.cat").instance
    doc = {"schema": "catc.certificate/1", "problem": "both-on", "domain": "toggle", "view": None}
    doc |= {"answer": "unsat", "method": "state-bounded", "producer": "z3", "horizon": 15, "sequential": False}
    doc |= {
        "state_count": 16,
        "obligations": [o | {"producer": "z3"} for o in state_bounded_obligations(inst, 15, False)],
    }
    rows = certify(inst, doc).obligations
    assert rows[0]["status"] == "refuted" and rows[0]["checkers"]["cvc5"]["answer"] == "sat"


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
    answers = [a for a, _ in checkers_module.run_batch(checker, paths, 30.0)]
    assert answers == ["sat", "sat", "error", "unsat"]


def test_many_obligations_split_over_processes_keep_their_answers():
    """More obligations than one batch takes run in several processes of each checker at
    once; each answer still belongs to its obligation (here sat and unsat alternate, so the
    round-robin chunks hold all the sat ones and all the unsat ones: a mix-up shows)."""
    sat = "(set-logic ALL)\n(declare-fun x () Int)\n(assert (> x {i}))\n(check-sat)\n"
    unsat = "(set-logic ALL)\n(declare-fun x () Int)\n(assert (and (> x {i}) (< x {i})))\n(check-sat)\n"
    obligations = [
        {"smtlib": (sat if i % 2 == 0 else unsat).format(i=i), "checkers": ["z3", "cvc5"]} for i in range(12)
    ]
    answers = checkers_module._run_checkers(obligations, 30.0)
    expected = ["sat" if i % 2 == 0 else "unsat" for i in range(12)]
    assert [a["z3"][0] for a in answers] == expected
    assert [a["cvc5"][0] for a in answers] == expected


@pytest.mark.parametrize("checker", ["z3", "cvc5"])
def test_an_undecided_obligation_in_a_batch_is_unknown_and_the_next_is_answered(tmp_path, monkeypatch, checker):
    """x³ + y³ = z³ over positive integers (no solution, beyond both solvers): with a limit of
    one second each says unknown (cvc5 "unknown (TIMEOUT)" or "(INCOMPLETE)"), which is an
    answer, not an error to run again alone; the obligation after it is still decided."""
    texts = [
        "(set-logic ALL)\n(declare-fun x () Int)\n(declare-fun y () Int)\n(declare-fun z () Int)\n"
        "(assert (and (>= x 1) (>= y 1) (>= z 1) (= (+ (* x x x) (* y y y)) (* z z z))))\n(check-sat)\n",
        "(set-logic ALL)\n(declare-fun x () Int)\n(assert (and (> x 1) (< x 2)))\n(check-sat)\n",
    ]
    paths = []
    for i, text in enumerate(texts):
        paths.append(str(tmp_path / f"{i}.smt2"))
        (tmp_path / f"{i}.smt2").write_text(text)
    monkeypatch.setattr(checkers_module, "run_checker", lambda *args: ("run again alone", 0.0))
    assert [a for a, _ in checkers_module.run_batch(checker, paths, 1.0)] == ["unknown", "unsat"]


# ---------------------------------------------------------------- a Pareto front

DESIGN = ROOT / "examples/pareto-design/design.cat"  # expect.toml: 13 of the 55 pairs non-dominated


def front():
    from catc.frontend.workspace import load_instance
    from catc.ir.views import apply_view
    from catc.queries.certify import pareto_certificate
    from catc.queries.pareto import pareto
    from catgrammar.diagnostics import Diagnostics

    _, inst = load_instance(None, str(DESIGN), Diagnostics())
    inst = apply_view(inst, None)
    return inst, pareto_certificate(inst, pareto(inst), {})


def with_points(inst, doc, points, witnesses):
    """``doc`` claiming ``points`` (exact strings), the witnesses renumbered, its front
    obligation rebuilt for them (so that only the solvers can object)."""
    from catc.queries.certify import pareto_obligation
    from catc.queries.certify.optimal import _pareto_objectives

    model, objectives = _pareto_objectives(inst, doc["objectives"])
    exact = [[Fraction(v) for v in p] for p in points]
    obligation = pareto_obligation(model, objectives, doc["horizon"], False, exact) | {"producer": "z3"}
    renumbered = [w | {"name": f"witness/{i + 1}"} for i, w in enumerate(witnesses)]
    return doc | {"points": points, "obligations": [*renumbered, obligation]}


def test_a_pareto_front_is_certified_point_by_point():
    inst, doc = front()
    assert doc["method"] == "pareto" and len(doc["points"]) == 13
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    rows = {r["name"]: r for r in result.obligations}
    assert {c: a["answer"] for c, a in rows["front"]["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}
    assert all(rows[f"witness/{i}"]["proved_by"] == ["catc.validator"] for i in range(1, 14))


def test_a_front_missing_a_point_is_refuted_by_the_solvers():
    inst, doc = front()
    witnesses = [o for o in doc["obligations"] if o["expect"] == "valid"]
    bad = with_points(inst, doc, doc["points"][1:], witnesses[1:])  # the first point dropped
    rows = {r["name"]: r for r in certify(inst, bad).obligations}
    assert rows["front"]["status"] == "refuted" and rows["front"]["checkers"]["z3"]["answer"] == "sat"


def test_a_better_point_than_its_witness_reaches_is_refuted():
    from catc.queries.certify.optimal import _pareto_objectives

    inst, doc = front()
    _, objectives = _pareto_objectives(inst, doc["objectives"])
    first = [Fraction(v) for v in doc["points"][0]]
    step = [Fraction(-1, 100) if o.sense.value == "minimize" else Fraction(1, 100) for o in objectives]
    better = [str(v + d) for v, d in zip(first, step)]
    witnesses = [o for o in doc["obligations"] if o["expect"] == "valid"]
    bad = with_points(inst, doc, [better, *doc["points"][1:]], witnesses)
    rows = {r["name"]: r["status"] for r in certify(inst, bad).obligations}
    assert rows["witness/1"] == "refuted"


def test_a_front_with_a_dominated_point_is_refuted():
    """A valid composition whose values another point dominates, claimed as a point of the
    front (its witness replays, its values are its own): not Pareto-optimal, refuted."""
    from catc.queries.certify.optimal import _pareto_objectives
    from catc.queries.optimum import _scores
    from catc.queries.pareto import dominates
    from catc.semantics.plan import plan_to_json, read_plan

    inst, doc = front()
    model, objectives = _pareto_objectives(inst, doc["objectives"])
    witnesses = [o for o in doc["obligations"] if o["expect"] == "valid"]
    points = [tuple(Fraction(v) for v in p) for p in doc["points"]]
    firsts = {w["plan"]["steps"][0][0]["morphism"] for w in witnesses}
    seconds = {w["plan"]["steps"][0][1]["morphism"] for w in witnesses}
    for a in sorted(firsts):  # an STT and a VLM from two different points
        for b in sorted(seconds):
            plan_json = {
                **witnesses[0]["plan"],
                "steps": [[{"morphism": a, "params": {}}, {"morphism": b, "params": {}}]],
            }
            values = tuple(_scores(model, read_plan(model, plan_json), objectives, [], doc["horizon"], False))
            if any(dominates(q, values, objectives) for q in points):
                dominated = plan_to_json(read_plan(model, plan_json))
                break
        else:
            continue
        break
    else:
        pytest.fail("no dominated pair among the front's components")
    extra = witnesses[0] | {"plan": dominated}
    bad = with_points(inst, doc, [*doc["points"], [str(v) for v in values]], [*witnesses, extra])
    rows = {r["name"]: r["status"] for r in certify(inst, bad).obligations}
    assert rows["witness/14"] == "refuted" and rows["front"] == "proved"


# ---------------------------------------------------------------- cores after the first

# Two independent conflicts: a needs 10 USD (5 there), b needs 10 W (5 there).
TWO = """
(define (domain two)
  (:requirements :numeric)
  (:resources (a bool) (b bool) (budget int :unit USD) (power int :unit W))
  (:morphism get-a :uses 1 :precondition (>= budget 10) :effect (assign a true))
  (:morphism get-b :uses 1 :precondition (>= power 10) :effect (assign b true)))
(define (problem both)
  (:domain two)
  (:init (= a false) (= b false) (= budget 5) (= power 5))
  (:goal (and a b)))
"""


def two_cores():
    from catc.queries.certify import core_certificate
    from catc.queries.diagnose import diagnose

    inst = loads({"two.cat": TWO}, "two.cat").instance
    return inst, core_certificate(inst, diagnose(inst, all_cores=True), False, "z3")


def test_every_core_of_a_diagnosis_is_certified():
    inst, doc = two_cores()
    cores = [set(doc["core"]), *(set(m["core"]) for m in doc["more"])]
    assert sorted(map(sorted, cores)) == [
        ["goal/1", "init/a", "init/budget", "pre/get-a/1"],
        ["goal/2", "init/b", "init/power", "pre/get-b/1"],
    ]
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    assert {r["name"] for r in result.obligations} >= {"core", "core 2: core"}


def test_a_later_core_with_a_dropped_label_is_refuted():
    from catc.queries.certify import core_obligations

    inst, doc = two_cores()
    later = doc["more"][0]
    smaller = [label for label in later["core"] if not label.startswith("init/")][:2]  # the budget or power dropped
    (unsat,), _ = core_obligations(inst, smaller, later["horizon"], False, later["components"])
    bad = copy.deepcopy(doc)
    bad["more"][0] = later | {"core": smaller, "obligations": [unsat | {"producer": "z3"}]}
    result = certify(inst, bad)
    rows = {r["name"]: r["status"] for r in result.obligations}
    assert result.status is CertifyStatus.REFUTED and rows["core 2: core"] == "refuted"
    assert rows["core"] == "proved"


def test_a_later_core_that_is_not_a_core_certificate_is_an_input_error(tmp_path):
    from catc.queries.base import InputError
    from catc.queries.certify import read_certificate

    _, doc = two_cores()
    doc["more"][0]["method"] = "bounded"
    path = tmp_path / "c.json"
    path.write_text(json.dumps(doc))
    with pytest.raises(InputError, match="core 2 must be a core certificate"):
        read_certificate(str(path))


# ---------------------------------------------------------------- relax --discrete


def discrete(inst):
    from catc.queries.certify import discrete_certificate
    from catc.queries.relax import relax

    return discrete_certificate(inst, relax(inst, discrete=True), {})


def test_relax_discrete_is_certified():
    inst = loads({"two.cat": TWO}, "two.cat").instance
    doc = discrete(inst)
    assert doc["method"] == "discrete" and len(doc["dropped"]) == 2  # one label of each of the two cores
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations


def forged_discrete(inst, doc, dropped):
    from catc.queries.certify import discrete_obligations

    least, restorable = discrete_obligations(inst, dropped, doc["horizon"], False, doc["components"])
    second = {**least, "name": "restorable", "expect": "sat", "smtlib": restorable}
    return doc | {"dropped": dropped, "obligations": [least | {"producer": "z3"}, second | {"producer": "z3"}]}


def test_a_smaller_discrete_set_is_refuted_and_a_larger_one_too():
    inst = loads({"two.cat": TWO}, "two.cat").instance
    doc = discrete(inst)
    smaller = forged_discrete(inst, doc, doc["dropped"][:1])  # the other core still conflicts
    rows = {r["name"]: r["status"] for r in certify(inst, smaller).obligations}
    assert rows == {"least": "proved", "restorable": "refuted"}
    larger = forged_discrete(inst, doc, [*doc["dropped"], "goal/1"])  # two suffice: not least
    rows = {r["name"]: r["status"] for r in certify(inst, larger).obligations}
    assert rows == {"least": "refuted", "restorable": "proved"}
