"""Certificates of optima whose objectives were given on the command line (issue 31):
``catc optimize --minimize EXPR --certificate FILE`` stores each objective's text as typed;
``catc certify`` — an interface — parses it against the model and hands the IR to the
queries' checker (which may not import the parser).  A certificate claiming a better value
than its witness reaches, or whose stored text was edited, is rejected."""

from __future__ import annotations

import json
from fractions import Fraction

import pytest
from conftest import ROOT, run_catc

from catc.frontend.workspace import load_instance
from catc.interfaces.command import objectives as parse_objectives
from catc.ir.views import apply_view
from catc.queries.base import InputError
from catc.queries.certify import (
    CertifyStatus,
    certify,
    cvc5_command,
    objective_texts,
    optimal_obligation,
    z3_command,
)
from catgrammar.diagnostics import Diagnostics

pytestmark = pytest.mark.skipif(
    z3_command() is None or cvc5_command() is None, reason="needs the z3 binary (z3-solver) and cvc5 (PyPI)"
)

MAX_CONFIDENCE = ROOT / "examples/gpu-allocation/max-confidence.cat"
DESIGN = ROOT / "examples/pareto-design/design.cat"
# -confidence, least at -21/25 (the file's comment: m = 16 - 2.25 - 9.5 = 4.25 → 0.84), then the
# GPU left in GB less the confidence: 0 - 21/25 (that composition uses all 16 GB). "1 GB" carries
# a unit that catc's own printing of the term drops ("(- (/ gpu 1) confidence)" subtracts a
# dimensionless number from GB: E0312), so the certificate must keep the text as typed.
TERMS = [("minimize", "(- 0 confidence)"), ("maximize", "(- (/ gpu 1 GB) confidence)")]


def load(path):
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, diags
    return apply_view(inst, None)


def flags(terms):
    return [word for sense, text in terms for word in (f"--{sense}", text)]


def written(tmp_path, path=MAX_CONFIDENCE, query="optimize", terms=TERMS):
    cert = tmp_path / "cert.json"
    res = run_catc(query, path, *flags(terms), "--certificate", cert)
    assert res.exit_code == 0, res.output
    return cert, json.loads(cert.read_text())


def claiming(inst, doc, values):
    """``doc`` claiming ``values``, its "nothing better" obligation rebuilt to match (so
    only the checkers and the witness's replay can tell)."""
    objectives = parse_objectives(inst, objective_texts(doc))
    best = optimal_obligation(inst, objectives, list(inst.problem.softs), doc["horizon"], False, values)
    witness = next(o for o in doc["obligations"] if o["name"] == "witness")
    return {**doc, "values": [str(v) for v in values], "obligations": [witness, best | {"producer": "z3"}]}


def test_a_command_line_objective_is_stored_as_typed_and_certified(tmp_path):
    cert, doc = written(tmp_path)
    assert doc["objectives"] == {"kind": "command-line", "terms": [{"sense": s, "term": t} for s, t in TERMS]}
    assert doc["values"] == ["-21/25", "-21/25"]
    res = run_catc("certify", MAX_CONFIDENCE, cert, "--json")
    assert res.exit_code == 0, res.output
    rows = {r["name"]: r for r in json.loads(res.stdout)["obligations"]}
    assert rows["witness"]["proved_by"] == ["catc.validator"]
    assert rows["optimal"]["proved_by"] == ["cvc5"]  # z3 answered it: its own "unsat" is no proof
    assert rows["optimal"]["checkers"]["z3"]["answer"] == "unsat"


def test_a_better_value_than_the_witness_reaches_is_rejected(tmp_path):
    inst = load(MAX_CONFIDENCE)
    _, doc = written(tmp_path)
    better = claiming(inst, doc, [Fraction(-22, 25), Fraction(-22, 25)])  # 0.88 needs m = 4.75 > 4.25
    objectives = parse_objectives(inst, TERMS)
    result = certify(inst, better, objectives=objectives)
    assert {r["name"]: r["status"] for r in result.obligations} == {"witness": "refuted", "optimal": "proved"}
    assert result.status is CertifyStatus.REFUTED
    cert = tmp_path / "better.json"  # the same through the command line: exit 1
    cert.write_text(json.dumps(better))
    res = run_catc("certify", MAX_CONFIDENCE, cert, "--json")
    assert res.exit_code == 1 and json.loads(res.stdout)["failed"] == ["witness"], res.output


def test_a_worse_value_is_refuted_by_the_solvers(tmp_path):
    inst = load(MAX_CONFIDENCE)
    _, doc = written(tmp_path)
    worse = claiming(inst, doc, [Fraction(-4, 5), Fraction(-4, 5)])  # 0.84 > 0.8: better exists
    rows = {r["name"]: r for r in certify(inst, worse, objectives=parse_objectives(inst, TERMS)).obligations}
    assert rows["optimal"]["status"] == "refuted" and rows["optimal"]["checkers"]["cvc5"]["answer"] == "sat"


def test_an_edited_objective_text_does_not_match(tmp_path):
    cert, doc = written(tmp_path)
    doc["objectives"]["terms"][0]["term"] = "(- 1 confidence)"  # another objective, same claims
    cert.write_text(json.dumps(doc))
    res = run_catc("certify", MAX_CONFIDENCE, cert, "--json")
    assert res.exit_code == 1 and "optimal" in json.loads(res.stdout)["failed"], res.output


def test_the_objectives_must_come_from_an_interface_and_agree(tmp_path):
    inst = load(MAX_CONFIDENCE)
    cert, doc = written(tmp_path)
    with pytest.raises(InputError) as raised:  # the queries stage cannot parse the text itself
        certify(inst, doc)
    assert raised.value.code == "E1304" and "(- 0 confidence)" in str(raised.value)
    res = run_catc("certify", MAX_CONFIDENCE, cert, "--maximize", "confidence")  # restated, but not these
    assert res.exit_code == 2 and "error[E1303]" in res.stderr
    res = run_catc("certify", MAX_CONFIDENCE, cert, *flags([("minimize", "(- 0.0 confidence)"), TERMS[1]]))
    assert res.exit_code == 0, res.output  # restated in other words: the same objectives
    metric = tmp_path / "metric.json"
    assert run_catc("optimize", MAX_CONFIDENCE, "--certificate", metric).exit_code == 0
    res = run_catc("certify", MAX_CONFIDENCE, metric, "--minimize", "gpu-used")
    assert res.exit_code == 2 and "error[E1303]" in res.stderr


def test_a_stored_objective_that_does_not_check_is_located(tmp_path):
    cert, doc = written(tmp_path)
    doc["objectives"]["terms"][1]["term"] = "(- (/ gpu 1) confidence)"  # GB - dimensionless: E0312
    cert.write_text(json.dumps(doc))
    res = run_catc("certify", MAX_CONFIDENCE, cert)
    assert res.exit_code == 2 and "error[E0312]" in res.stderr and "Traceback" not in res.stderr, res.output


def test_a_front_of_command_line_objectives_is_certified(tmp_path):
    terms = [("maximize", "(* mmmu (- 1 wer))"), ("minimize", "(+ stt-gpu vlm-gpu)")]
    cert, doc = written(tmp_path, DESIGN, "pareto", terms)
    assert doc["method"] == "pareto" and doc["objectives"]["kind"] == "command-line"
    res = run_catc("certify", DESIGN, cert)
    assert res.exit_code == 0 and res.stdout.startswith("CERTIFIED  pareto certificate"), res.output
