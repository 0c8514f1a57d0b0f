"""Certificates of "no" answers (issue 31): every example's final UNSAT writes a
catc.certificate/1 document whose obligations the z3 binary and cvc5 both prove unsat, and
certificates that are wrong — a wrong invariant, edited text, a missing obligation, an
incomplete horizon, another problem's — are rejected with the obligation that failed."""

from __future__ import annotations

import json
import tomllib
from fractions import Fraction

import pytest
from conftest import ROOT, run_catc

from catc.frontend.workspace import load_instance
from catc.ir.views import apply_view
from catc.queries.certify import (
    CertifyStatus,
    certificate,
    certify,
    cvc5_command,
    invariant_obligations,
    z3_command,
)
from catc.queries.solve import solve
from catgrammar.diagnostics import Diagnostics

pytestmark = pytest.mark.skipif(
    z3_command() is None or cvc5_command() is None, reason="needs the z3 binary (z3-solver) and cvc5 (PyPI)"
)


def final_unsat_cases():
    """Every example case expect.toml records as a final UNSAT (its reason written by hand)."""
    for expect in sorted((ROOT / "examples").glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            if case.get("status") == "unsat" and case.get("final_unsat"):
                yield pytest.param(
                    expect.parent / case["file"],
                    case.get("problem"),
                    id=f"{expect.parent.name}/{case['file']}:{case.get('problem', '')}",
                )


def load(path, problem=None):
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags, problem_name=problem)
    assert inst is not None, diags
    return apply_view(inst, None)


def answered(path, problem=None):
    inst = load(path, problem)
    result = solve(inst)
    assert result.status.value == "unsat" and result.final
    return inst, certificate(inst, result)


@pytest.mark.parametrize("path, problem", list(final_unsat_cases()))
def test_every_final_unsat_of_the_examples_is_certified_by_z3_and_cvc5(path, problem):
    inst, doc = answered(path, problem)
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    for row in result.obligations:
        # both solvers, each in its own process, answer unsat; at least one is not the producer
        assert {c: a["answer"] for c, a in row["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}
        assert row["proved_by"] and doc["producer"] not in row["proved_by"]


def test_the_examples_cover_both_methods():
    methods = {answered(p.values[0], p.values[1])[1]["method"] for p in final_unsat_cases()}
    assert methods == {"invariant", "bounded"}


# ---------------------------------------------------------------- mutations

BUDGET_CUT = ROOT / "examples/lifelong/budget-cut.cat"  # budget 500 USD; the LiDAR needs 20,000


def with_invariant(inst, doc, changes):
    """``doc`` with its invariant changed and its obligations rebuilt to match (a wrong
    certificate that is consistent with itself: only the solvers can reject it)."""
    inv = {**doc["invariant"], **changes}
    obligations = invariant_obligations(inst, inv, doc["horizon"])
    for o in obligations:
        o["producer"] = doc["producer"]
    return {**doc, "invariant": inv, "obligations": obligations}


def test_an_invariant_the_initial_state_breaks_is_refuted_at_initiation():
    inst, doc = answered(BUDGET_CUT)
    assert doc["method"] == "invariant"
    wrong = with_invariant(inst, doc, {"budget": {"interval": ["0", "100"]}})  # the budget starts at 500
    result = certify(inst, wrong)
    assert result.status is CertifyStatus.REFUTED
    rows = {r["name"]: r for r in result.obligations}
    assert rows["initiation"]["status"] == "refuted"
    assert rows["initiation"]["checkers"]["z3"]["answer"] == "sat"
    assert rows["initiation"]["checkers"]["cvc5"]["answer"] == "sat"


def test_an_invariant_that_allows_the_goal_is_refuted_at_the_goal():
    inst, doc = answered(BUDGET_CUT)
    # nothing known about any resource: trivially inductive, but it no longer excludes the goal
    top = {}
    for name, spec in doc["invariant"].items():
        top[name] = {k: ([None, None] if k == "interval" else None if k in ("values", "may") else []) for k in spec}
    result = certify(inst, with_invariant(inst, doc, top))
    statuses = {r["name"]: r["status"] for r in result.obligations}
    assert statuses == {"initiation": "proved", "consecution": "proved", "goal": "refuted"}
    assert result.status is CertifyStatus.REFUTED


def test_an_invariant_one_step_breaks_is_refuted_at_consecution():
    inst, doc = answered(BUDGET_CUT)
    # 'mounted' starts empty; the morphisms that mount hardware can fire, so "mounted stays
    # empty" holds initially and excludes nothing by itself, but a step breaks it
    spec = doc["invariant"]["mounted"]
    assert spec["must"] == []
    wrong = with_invariant(inst, doc, {"mounted": {"may": [], "must": []}})
    statuses = {r["name"]: r["status"] for r in certify(inst, wrong).obligations}
    assert statuses["initiation"] == "proved" and statuses["consecution"] == "refuted"


def test_edited_obligation_text_does_not_match_the_model():
    inst, doc = answered(BUDGET_CUT)
    edited = json.loads(json.dumps(doc))
    goal = next(o for o in edited["obligations"] if o["name"] == "goal")
    goal["smtlib"] = goal["smtlib"].replace("(check-sat)", "(assert false)\n(check-sat)")
    result = certify(inst, edited)
    rows = {r["name"]: r for r in result.obligations}
    assert result.status is CertifyStatus.REFUTED
    assert rows["goal"]["status"] == "mismatch" and rows["goal"]["checkers"] == {}


def test_a_dropped_obligation_is_missing():
    inst, doc = answered(BUDGET_CUT)
    dropped = {**doc, "obligations": [o for o in doc["obligations"] if o["name"] != "consecution"]}
    result = certify(inst, dropped)
    assert result.status is CertifyStatus.REFUTED
    assert {r["name"]: r["status"] for r in result.obligations}["consecution"] == "missing"


COARSE = ROOT / "examples/navigation/coarse.cat"  # one use of move: horizon 1 is complete


def test_a_bounded_certificate_below_the_use_bound_is_rejected():
    inst, doc = answered(COARSE)
    assert doc["method"] == "bounded" and doc["producer"] == "z3"
    short = {**doc, "horizon": 0}  # a horizon shorter than the use bound proves nothing final
    result = certify(inst, short)
    assert result.status is CertifyStatus.REFUTED
    assert "horizon" in [r["name"] for r in result.obligations if r["status"] == "mismatch"]


def test_an_answer_checked_only_by_its_own_producer_is_unchecked():
    inst, doc = answered(COARSE)
    only_z3 = {**doc, "obligations": [{**o, "checkers": ["z3"]} for o in doc["obligations"]]}
    result = certify(inst, only_z3)
    assert result.status is CertifyStatus.UNCHECKED
    assert all(r["status"] == "unchecked" and r["proved_by"] == [] for r in result.obligations)


# ---------------------------------------------------------------- the command line


def test_solve_writes_and_certify_checks_a_certificate(tmp_path):
    cert = tmp_path / "cut.json"
    res = run_catc("solve", BUDGET_CUT, "--certificate", cert)
    assert res.exit_code == 1, res.output  # UNSAT
    res = run_catc("certify", BUDGET_CUT, cert, "--json")
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert doc["schema"] == "catc.certify/1" and doc["status"] == "certified" and doc["failed"] == []
    assert [o["name"] for o in doc["obligations"]] == ["initiation", "consecution", "goal"]


def test_certify_rejects_a_wrong_certificate_with_exit_1_naming_the_obligation(tmp_path):
    inst, doc = answered(BUDGET_CUT)
    cert = tmp_path / "wrong.json"
    cert.write_text(json.dumps(with_invariant(inst, doc, {"budget": {"interval": ["0", "100"]}})))
    res = run_catc("certify", BUDGET_CUT, cert, "--json")
    assert res.exit_code == 1, res.output
    assert json.loads(res.stdout)["failed"] == ["initiation"]


def test_certificate_input_errors(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    res = run_catc("certify", BUDGET_CUT, bad)
    assert res.exit_code == 2 and "error[E1301]" in res.stderr
    bad.write_text(json.dumps({"schema": "catc.plan/1"}))
    res = run_catc("certify", BUDGET_CUT, bad)
    assert res.exit_code == 2 and "error[E1302]" in res.stderr
    _, doc = answered(COARSE)
    bad.write_text(json.dumps(doc))
    res = run_catc("certify", BUDGET_CUT, bad)  # another problem's certificate
    assert res.exit_code == 2 and "error[E1303]" in res.stderr


def test_a_certificate_of_an_answer_that_has_none(tmp_path):
    cert = tmp_path / "c.json"
    res = run_catc("solve", ROOT / "examples/detection/person.cat", "--certificate", cert)
    assert res.exit_code == 0 and "no certificate written" in res.stderr and not cert.exists()
    # not final: a horizon shorter than the use bound (coarse's move has one use, and 0 steps
    # reach nothing); the relaxation does not refute it, so there is no proof for every horizon
    res = run_catc("solve", COARSE, "--horizon", "0", "--no-presolve", "--certificate", cert)
    assert res.exit_code == 2 and "error[E1304]" in res.stderr


# ---------------------------------------------------------------- cores (catc diagnose)


def diagnose_cases():
    """Every example case whose core expect.toml records by hand."""
    for expect in sorted((ROOT / "examples").glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            if "diagnose" in case:
                yield pytest.param(
                    expect.parent / case["file"],
                    sorted(case["diagnose"]),
                    id=f"{expect.parent.name}/{case['file']}",
                )


def core_certificate_of(path):
    from catc.queries.certify import core_certificate
    from catc.queries.diagnose import diagnose

    inst = load(path)
    diag = diagnose(inst)
    return inst, core_certificate(inst, diag, False, "catc.relaxed" if diag.checks == 0 else "z3")


@pytest.mark.parametrize("path, core", list(diagnose_cases()))
def test_the_examples_cores_are_certified_with_a_witness_per_member(path, core):
    inst, doc = core_certificate_of(path)
    assert sorted(doc["core"]) == core
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    rows = {r["name"]: r for r in result.obligations}
    assert {c: a["answer"] for c, a in rows["core"]["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}
    for label in core:  # irreducible: each member has a witness of the core without it
        row = rows.get(f"witness/{label}") or rows[f"sat/{label}"]
        assert row["status"] == "proved"


def test_a_core_with_a_dropped_label_is_refuted():
    from catc.queries.certify import core_obligations

    inst, doc = core_certificate_of(BUDGET_CUT)
    assert sorted(doc["core"]) == ["init/budget", "pre/buy-lidar/1"]
    smaller = ["init/budget"]  # without the LiDAR's price nothing conflicts with the budget
    built, _ = core_obligations(inst, smaller, doc["horizon"], False, doc["components"])
    witnesses = [o for o in doc["obligations"] if o["name"] == "witness/init/budget"]
    wrong = {**doc, "core": smaller, "obligations": [built[0] | {"producer": doc["producer"]}, *witnesses]}
    result = certify(inst, wrong)
    rows = {r["name"]: r for r in result.obligations}
    assert result.status is CertifyStatus.REFUTED
    assert rows["core"]["status"] == "refuted" and rows["core"]["checkers"]["z3"]["answer"] == "sat"


def test_a_witness_that_does_not_replay_is_refuted():
    inst, doc = core_certificate_of(BUDGET_CUT)
    wrong = json.loads(json.dumps(doc))
    for o in wrong["obligations"]:
        if o["name"] == "witness/init/budget":
            o["plan"] = {"schema": "catc.plan/1", "steps": []}  # reaches nothing: the goal is not met
    result = certify(inst, wrong)
    rows = {r["name"]: r for r in result.obligations}
    assert rows["witness/init/budget"]["status"] == "refuted"
    assert rows["witness/init/budget"]["checkers"] == {
        "catc.validator": {"answer": "invalid", "seconds": pytest.approx(0, abs=60)}
    }
    assert result.status is CertifyStatus.REFUTED


def test_a_core_certificate_missing_a_members_witness_is_rejected():
    inst, doc = core_certificate_of(BUDGET_CUT)
    dropped = {**doc, "obligations": [o for o in doc["obligations"] if o["name"] != "witness/pre/buy-lidar/1"]}
    result = certify(inst, dropped)
    assert result.status is CertifyStatus.REFUTED
    assert {r["name"]: r["status"] for r in result.obligations}["witness/pre/buy-lidar/1"] == "missing"


def test_diagnose_writes_a_certificate_certify_accepts(tmp_path):
    cert = tmp_path / "core.json"
    res = run_catc("diagnose", BUDGET_CUT, "--certificate", cert)
    assert res.exit_code == 0, res.output
    res = run_catc("certify", BUDGET_CUT, cert, "--json")
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["method"] == "core"


# ---------------------------------------------------------------- least restorations (catc relax)


def least_certificate_of(path):
    from catc.queries.certify import least_certificate
    from catc.queries.relax import relax

    inst = load(path)
    return inst, least_certificate(inst, relax(inst), {})


def claiming(inst, doc, budget):
    """``doc`` claiming the budget restoration ``budget`` (consistent: obligations rebuilt)."""
    from catc.queries.certify import least_obligation

    least = least_obligation(inst, doc["requirements"], doc["horizon"], False, doc["components"], Fraction(budget)) | {
        "producer": "z3"
    }
    witness = next(o for o in doc["obligations"] if o["name"] == "witness")
    return {**doc, "relaxations": {"init/budget": budget}, "cost": budget, "obligations": [witness, least]}


def test_the_least_restoration_of_the_budget_cut_is_certified():
    inst, doc = least_certificate_of(BUDGET_CUT)
    # expect.toml: the budget must rise by 20,360 - 500 = 19,860 USD
    assert doc["relaxations"] == {"init/budget": "19860"} and doc["cost"] == "19860"
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    rows = {r["name"]: r for r in result.obligations}
    assert rows["witness"]["checkers"]["catc.validator"]["answer"] == "valid"
    assert {c: a["answer"] for c, a in rows["least"]["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}
    assert rows["least"]["proved_by"] == ["cvc5"]  # z3 produced the answer


def test_a_cheaper_least_is_refuted_by_its_witness():
    inst, doc = least_certificate_of(BUDGET_CUT)
    result = certify(inst, claiming(inst, doc, "19000"))  # 19,500 USD cannot buy the 20,360 USD composition
    statuses = {r["name"]: r["status"] for r in result.obligations}
    assert statuses == {"witness": "refuted", "least": "proved"}
    assert result.status is CertifyStatus.REFUTED


def test_a_restoration_that_is_not_least_is_refuted_by_the_solvers():
    inst, doc = least_certificate_of(BUDGET_CUT)
    result = certify(inst, claiming(inst, doc, "20000"))  # enough, but 19,860 is cheaper
    rows = {r["name"]: r for r in result.obligations}
    assert rows["witness"]["status"] == "proved"
    assert rows["least"]["status"] == "refuted" and rows["least"]["checkers"]["cvc5"]["answer"] == "sat"
    assert result.status is CertifyStatus.REFUTED


# ---------------------------------------------------------------- optima (catc optimize, catc recompose)

MAX_CONFIDENCE = ROOT / "examples/gpu-allocation/max-confidence.cat"  # expect.toml: optimum 21/25
CHEAPER_CAMERA = ROOT / "examples/lifelong/cheaper-camera.cat"


def optimal_certificate_of(path, query="optimize", **options):
    from catc.queries.certify import optimal_certificate
    from catc.queries.optimize import optimize
    from catc.queries.recompose import recompose

    inst = load(path)
    result = optimize(inst) if query == "optimize" else recompose(inst, **options)
    return inst, optimal_certificate(inst, result, {})


def claiming_values(inst, doc, values):
    from catc.queries.certify import optimal_obligation
    from catc.queries.certify.optimal import _objectives

    model, objectives, softs = _objectives(inst, doc["objectives"])
    best = optimal_obligation(model, objectives, softs, doc["horizon"], False, [Fraction(v) for v in values])
    witness = next(o for o in doc["obligations"] if o["name"] == "witness")
    return {**doc, "values": values, "obligations": [witness, best | {"producer": "z3"}]}


def test_an_optimum_is_certified():
    inst, doc = optimal_certificate_of(MAX_CONFIDENCE)
    assert doc["values"] == ["21/25"]  # expect.toml, derived by hand
    result = certify(inst, doc)
    assert result.status is CertifyStatus.CERTIFIED, result.obligations


def test_a_better_optimum_than_the_witness_reaches_is_refuted():
    inst, doc = optimal_certificate_of(MAX_CONFIDENCE)
    result = certify(inst, claiming_values(inst, doc, ["22/25"]))  # 0.88 needs m = 4.75 > 4.25
    assert {r["name"]: r["status"] for r in result.obligations} == {"witness": "refuted", "optimal": "proved"}


def test_a_worse_optimum_is_refuted_by_the_solvers():
    inst, doc = optimal_certificate_of(MAX_CONFIDENCE)
    wrong = claiming_values(inst, doc, ["4/5"])  # 0.8 < 0.84: a better composition exists
    rows = {r["name"]: r for r in certify(inst, wrong).obligations}
    assert rows["optimal"]["status"] == "refuted" and rows["optimal"]["checkers"]["z3"]["answer"] == "sat"
    assert rows["witness"]["status"] == "refuted"  # the witness scores 0.84, not the 0.8 claimed


@pytest.mark.parametrize("priority, churn", [("stability", "0"), ("objective", "4")])
def test_a_recomposition_is_certified(priority, churn):
    inst, doc = optimal_certificate_of(CHEAPER_CAMERA, "recompose", priority=priority)
    # expect.toml: churn 0 keeping the deployed composition, churn 4 for the cheapest one
    values = dict(zip(("churn", "objective") if priority == "stability" else ("objective", "churn"), doc["values"]))
    assert values["churn"] == churn
    assert certify(inst, doc).status is CertifyStatus.CERTIFIED


def test_optimize_writes_a_certificate_certify_accepts(tmp_path):
    cert = tmp_path / "opt.json"
    assert run_catc("optimize", MAX_CONFIDENCE, "--certificate", cert).exit_code == 0
    res = run_catc("certify", MAX_CONFIDENCE, cert)
    assert res.exit_code == 0 and res.stdout.startswith("CERTIFIED  optimal certificate"), res.output


def test_every_kind_of_certificate_follows_the_schema():
    import jsonschema

    schema = json.loads((ROOT / "docs/schemas/catc.certificate-1.json").read_text())
    docs = [
        answered(BUDGET_CUT)[1],  # invariant
        answered(COARSE)[1],  # bounded
        core_certificate_of(COARSE)[1],  # a core with witnesses and satisfiable obligations
        least_certificate_of(BUDGET_CUT)[1],
        optimal_certificate_of(MAX_CONFIDENCE)[1],
        optimal_certificate_of(CHEAPER_CAMERA, "recompose", priority="stability")[1],
    ]
    assert {d["method"] for d in docs} == {"invariant", "bounded", "core", "least", "optimal"}
    for doc in docs:
        jsonschema.validate(json.loads(json.dumps(doc)), schema)
