"""Differential testing (issue 15, item 3): random valid models from tests/strategies.py,
each answered SAT/UNSAT by independent routes that must all agree.

* ``catc solve`` through the Z3 API, incremental deepening (the default, validated) and one
  encoding at the horizon with idle steps (``--strategy single``);
* the ``z3`` binary that z3-solver ships, in its own process, on the text of ``catc compile
  --emit smt2`` at the same horizon — always run;
* cvc5 on the same SMT-LIB2 text (its own parser, its own solver) and catc's cvc5 backend —
  skipped, naming the extra, when cvc5 is not importable;
* ENHSP on the PDDL export, bounded to the horizon's number of actions and compared with
  ``catc solve --sequential`` — for models the export expresses exactly (``int`` parameters
  only: no grid, no reserve values), in the slow group, when Java and up-enhsp are present.

tests/test_smtlib.py does the same for the examples; this file does it for models nobody
wrote by hand.  Any disagreement fails, showing the model.
"""

from __future__ import annotations

import os
import subprocess

import pytest
from hypothesis import HealthCheck, assume, event, given, settings
from strategies import models
from test_smtlib import z3_binary

from catc.frontend.session import load_texts
from catc.ir.views import apply_view
from catc.queries.solve import SolveStatus, solve
from catc.semantics.horizon import default_horizon
from catc.semantics.validate import validate
from catc.smt.smtlib import emit_smt2
from catgrammar.diagnostics import Diagnostics

SETTINGS = {
    "deadline": None,
    "suppress_health_check": [HealthCheck.function_scoped_fixture, HealthCheck.too_slow, HealthCheck.filter_too_much],
}


def _cvc5_missing() -> str | None:
    try:
        import cvc5  # noqa: F401
    except ImportError:
        return "cvc5 is not installed: pip install 'catc-lang[cvc5]'"
    return None


def _instance(text: str):
    diags = Diagnostics()
    inst = load_texts({"gen.cat": text}, "gen.cat", diags)
    assert inst is not None, [d.message for d in diags]
    return apply_view(inst, None)


def z3_binary_answer(smt2: str, tmp_path) -> str:
    path = tmp_path / "model.smt2"
    path.write_text(smt2)
    out = subprocess.run([z3_binary(), str(path)], capture_output=True, text=True, timeout=600)
    return out.stdout.split()[0] if out.stdout.split() else f"no answer: {out.stderr}"


def cvc5_answer(smt2: str) -> str:
    """cvc5's own SMT-LIB2 parser and solver on ``smt2`` (as tests/test_smtlib.py runs it)."""
    import cvc5

    tm = cvc5.TermManager()
    slv = cvc5.Solver(tm)
    sm = cvc5.SymbolManager(tm)
    parser = cvc5.InputParser(slv, sm)
    parser.setStringInput(cvc5.InputLanguage.SMT_LIB_2_6, smt2, "model.smt2")
    answers = []
    while not (cmd := parser.nextCommand()).isNull():
        out = cmd.invoke(slv, sm)
        if out and out.strip():
            answers.append(out.strip())
    return answers[0] if answers else "no answer"


def _agree(tmp_path, model, with_cvc5: bool) -> None:
    inst = _instance(model.text)
    k = default_horizon(inst)
    answers = {
        "catc solve": solve(inst).status.value,
        "catc solve --strategy single": solve(inst, horizon=k, strategy="single", validate_answer=False).status.value,
    }
    smt2 = emit_smt2(inst, k)
    answers["z3 binary on the SMT-LIB2"] = z3_binary_answer(smt2, tmp_path)
    if with_cvc5:
        answers["cvc5 on the SMT-LIB2"] = cvc5_answer(smt2)
        answers["catc solve --backend cvc5"] = solve(inst, backend="cvc5").status.value
    assert set(answers.values()) <= {"sat", "unsat"}, (answers, model.text)
    assert len(set(answers.values())) == 1, (answers, model.text)
    event(f"every solver: {answers['catc solve']}")


@settings(max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "8")), **SETTINGS)
@given(model=models())
def test_z3_binary_agrees_with_catc_solve(tmp_path, model):
    _agree(tmp_path, model, with_cvc5=False)


@pytest.mark.skipif(_cvc5_missing() is not None, reason=str(_cvc5_missing()))
@settings(max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "8")), **SETTINGS)
@given(model=models())
def test_cvc5_and_z3_agree_with_catc_solve(tmp_path, model):
    _agree(tmp_path, model, with_cvc5=True)


@pytest.mark.slow
@settings(max_examples=300, **SETTINGS)
@given(model=models(max_morphisms=5, max_horizon=4))
def test_every_solver_agrees_at_scale(tmp_path, model):
    _agree(tmp_path, model, with_cvc5=_cvc5_missing() is None)


def test_a_disagreement_fails(tmp_path):
    """The comparison can fail: the z3 binary's answer on a goal that contradicts itself is
    unsat where catc, on the model without that goal, says sat."""
    sat = "(define (domain d) (:resources (b bool)) (:morphism m :effect (assign b true)))\n"
    sat += "(define (problem p) (:domain d) (:goal b) (:horizon 1))\n"
    inst = _instance(sat)
    assert solve(inst).status is SolveStatus.SAT
    unsat_text = emit_smt2(_instance(sat.replace("(:goal b)", "(:goal (and b (not b)))")), 1)
    assert z3_binary_answer(unsat_text, tmp_path) == "unsat"


# ---------------------------------------------------------------- ENHSP on the PDDL export


def _enhsp_missing() -> str | None:
    from catc.targets.enhsp import available

    return available()


@pytest.mark.slow
@pytest.mark.skipif(_enhsp_missing() is not None, reason=str(_enhsp_missing()))
@settings(max_examples=int(os.environ.get("CATC_ENHSP_EXAMPLES", "100")), **SETTINGS)
@given(model=models(max_morphisms=3, param_sorts=("int",)))
def test_enhsp_agrees_with_sequential_catc_solve(tmp_path, model):
    from catc.targets.enhsp import run_enhsp
    from catc.targets.pddl import ExportError, export_pddl

    inst = _instance(model.text)
    k = default_horizon(inst)
    try:
        ex = export_pddl(inst, horizon=k)
    except ExportError:
        assume(False)
    assume(not any(category == "components" for category, _ in ex.report.items))
    dom, prob = tmp_path / "domain.pddl", tmp_path / "problem.pddl"
    dom.write_text(ex.domain)
    prob.write_text(ex.problem)
    res = run_enhsp(dom, prob, timeout=300)
    catc = solve(inst, sequential=True)
    assert res.status in ("sat", "unsat"), (res.output[-2000:], model.text)
    assert res.status == catc.status.value, (res.status, catc.status.value, model.text, ex.domain, ex.problem)
    event(f"ENHSP and catc: {res.status}")
    if res.status == "sat":
        plan = ex.plan_from_actions(res.actions)
        report = validate(inst, plan, horizon=k, sequential=True)
        assert report.ok, ([str(v) for v in report.violations], model.text)
