"""`catc synthesize`: the skeleton of the missing component, pasted into the domain, makes the
problem feasible without the hole."""

from __future__ import annotations

import json
import re

from conftest import ROOT, run_catc

from catc.frontend.workspace import load_instance
from catc.queries.solve import SolveStatus, solve
from catc.queries.synthesize import synthesize
from catgrammar.diagnostics import Diagnostics

HOLES = ROOT / "examples" / "holes"


def test_synthesised_effects_are_the_missing_capability():
    diags = Diagnostics()
    _, inst = load_instance(None, str(HOLES / "talk.cat"), diags)
    assert solve(inst).status is SolveStatus.UNSAT  # the catalog alone cannot do it
    r = synthesize(inst)
    assert r.status == "synthesised"
    assert [(e.kind.value, e.resource) for e in r.morphism.effects] == [("assign", "speech-out")]
    assert all(l.expr is not None for l in r.morphism.pre) and len(r.morphism.pre) <= 3


def test_pasted_skeleton_makes_the_problem_feasible_without_the_hole(tmp_path):
    res = run_catc("synthesize", str(HOLES / "talk.cat"), "--emit", "cat")
    assert res.exit_code == 0
    skeleton = res.stdout
    assert skeleton.lstrip().startswith("; synthesised") and "(:morphism voice" in skeleton
    domain = (HOLES / "domain.cat").read_text()
    domain = re.sub(r"\n\s*\(:hole [^()\n]*\)", "", domain)  # the hole goes away
    assert "(:hole" not in domain
    domain = domain.rstrip()
    assert domain.endswith(")")
    (tmp_path / "domain.cat").write_text(domain[:-1] + "\n" + skeleton + ")\n")
    (tmp_path / "talk.cat").write_text((HOLES / "talk.cat").read_text())
    res = run_catc("check", "--strict", str(tmp_path))
    assert res.exit_code == 0, res.output
    res = run_catc("solve", str(tmp_path / "talk.cat"), "--json")
    doc = json.loads(res.stdout)
    assert res.exit_code == 0 and doc["status"] == "sat"
    assert "voice" in {a["morphism"] for step in doc["steps"] for a in step}


def test_synthesize_cli_text_and_errors():
    res = run_catc("synthesize", str(HOLES / "talk.cat"))
    assert res.exit_code == 0 and "SYNTHESISED  hole 'voice' in view 'software'" in res.stdout
    res = run_catc("synthesize", str(ROOT / "examples/detection/person.cat"))
    assert res.exit_code == 2 and "declares no (:hole" in res.stderr
