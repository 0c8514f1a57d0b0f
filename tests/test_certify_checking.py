"""How ``catc certify`` checks (issue 31's time target): a core's consumption text without the
implications a denied indicator makes vacuous — the same models, so the same answer —, cvc5
inside catc's process for a few small obligations, and the obligations rebuilt once between
the query's ``check`` and ``run`` but again when the file changed in between."""

from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "benchmarks"))

import catalog_gen as gen  # noqa: E402

from catc.api import load, loads  # noqa: E402
from catc.queries.certify import CertifyStatus, certificate, certify, cvc5_command, z3_command  # noqa: E402
from catc.queries.certify.check import prepared  # noqa: E402
from catc.queries.certify.checkers import _here  # noqa: E402
from catc.queries.certify.cores import _vacuous, consumption_core_text  # noqa: E402
from catc.queries.solve import solve  # noqa: E402
from catc.smt.consumption import Consumption  # noqa: E402

pytestmark = pytest.mark.skipif(
    z3_command() is None or cvc5_command() is None, reason="needs the z3 binary (z3-solver) and cvc5 (PyPI)"
)

DENIED = {"|A:x|", "|A:y y|"}


@pytest.mark.parametrize(
    ("text", "vacuous"),
    [
        ("(=> (and |u:m| |A:x|) (or a b))", True),  # a top-level conjunct of the guard denied
        ("(=> |A:x| (not |u:m|))", True),  # the guard itself denied
        ("(=> (and |u:m| |A:y y|) b)", True),  # a quoted symbol with a space
        ("(=> (and a (b c) |A:x|) q)", True),  # after a compound conjunct
        ("(=> (and |u:m| |A:z|) (or a b))", False),  # no denied conjunct
        ("(=> (and (or |A:x| q) |A:w|) b)", False),  # denied only inside a disjunction: not vacuous
        ("(=> (and |u:m|) |A:x|)", False),  # denied in the conclusion, not the guard
        ("(>= |rank:m| 0)", False),  # not an implication
        ("(or (not |A:x|) b)", False),  # the same meaning, another shape: kept (only a weaker text)
    ],
)
def test_an_implication_is_vacuous_only_when_a_guard_conjunct_is_denied(text, vacuous):
    assert _vacuous(text, DENIED) is vacuous


def catalog(variant="budget", n=12, d=4):
    cat = gen.build(n, d)
    text, _ = gen.problem_text(cat, variant)
    return loads({"domain.cat": gen.domain_text(cat), f"{variant}.cat": text}, f"{variant}.cat").instance


def test_a_core_text_leaves_out_only_implications_a_denied_indicator_guards():
    inst = catalog()
    core = ["init/budget", "bounds/budget"]
    text = consumption_core_text(inst, core, None)
    whole = Consumption(inst)
    kept = [a for a in whole.assertions if f"(assert {a})" in text.splitlines()]
    left_out = [a for a in whole.assertions if a not in kept]
    assert left_out, "the catalog has implications guarded by the power and RAM labels"
    denied = {str(s) for label, s in whole.indicator.items() if label not in core}
    assert all(a.startswith("(=> ") and _vacuous(a, denied) for a in left_out)
    for label in ("init/ram", "bounds/power"):  # the denials themselves stay, so the models are the same
        assert f"(assert (not |A:{label}|))" in text


@pytest.fixture
def smt_files(tmp_path):
    files = {
        "unsat": "(set-logic ALL)\n(declare-fun x () Int)\n(assert (> x 2))\n(assert (< x 1))\n(check-sat)\n",
        "sat": "(set-logic ALL)\n(declare-fun x () Int)\n(assert (> x 2))\n(check-sat)\n",
        "broken": "(set-logic ALL)\n(assert (> y 2))\n(check-sat)\n",  # y undeclared: cvc5 errs
    }
    paths = {}
    for name, body in files.items():
        paths[name] = str(tmp_path / f"{name}.smt2")
        Path(paths[name]).write_text(body)
    return paths


@pytest.mark.parametrize("checker", ["z3", "cvc5"])
def test_a_checker_in_catc_s_process_answers_each_file_and_an_error_is_no_answer(smt_files, checker):
    answers = _here(checker, [smt_files["unsat"], smt_files["sat"], smt_files["broken"]], 10.0)
    assert answers is not None
    assert [a for a, _ in answers] == ["unsat", "sat", "error"]  # the broken one run again alone: still an error


def test_a_certificate_changed_after_check_is_read_again(tmp_path):
    inst = load(ROOT / "examples/lifelong/budget-cut.cat").instance
    doc = certificate(inst, solve(inst))
    path = tmp_path / "cert.json"
    path.write_text(json.dumps(doc))
    first, _ = prepared(inst, str(path), None)
    assert first["method"] == "invariant"
    again, _ = prepared(inst, str(path), None)
    assert again is first  # the query's run after its check: nothing rebuilt
    wrong = json.loads(json.dumps(doc))
    name = next(n for n, s in wrong["invariant"].items() if s.get("interval", [None, None]) != [None, None])
    wrong["invariant"][name] = {"interval": [None, None]}  # claims nothing of it: the text changes
    path.write_text(json.dumps(wrong, indent=1))
    os.utime(path, ns=(1, 1))  # a stamp of its own even on a coarse clock
    result = certify(inst, str(path))
    assert result.status is CertifyStatus.REFUTED  # its obligations are not the ones the new invariant gives
    assert {r["status"] for r in result.obligations} == {"mismatch"}
    assert prepared(inst, str(path), None)[0]["invariant"][name] == {"interval": [None, None]}
