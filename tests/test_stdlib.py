"""The standard library as a component catalog (docs/stdlib.md): importing a domain does not
force initial values for the resources the model never mentions; those are left out."""

from __future__ import annotations

import pytest
from conftest import ROOT, run_catc

from catc.api import CatError, loads
from catc.frontend.session import check_files
from catgrammar.diagnostics import Diagnostics

MINE = """\
(define (domain mine)
  (:requirements :numeric :sets)
  (:import robot-base)
  (:constants cam - module)
  (:morphism mount :uses 1 :precondition (>= ram 1) :effect (and (add mounted cam) (decrease ram 1))))
"""


def _model(problem: str, domain: str = MINE):
    return loads({"mine.cat": domain, "p.cat": problem}, "p.cat")


def test_unmentioned_imported_resources_need_no_initial_value_and_are_left_out():
    model = _model("(define (problem p) (:domain mine) (:init (= ram 4)) (:goal (member cam mounted)))")
    # robot-base declares slots, ports, payload, power, energy, cpu, gpu-mem, disk, topics,
    # frames, budget, mission-time and range too; nothing here mentions them (sets included)
    assert set(model.instance.resources) == {"mounted", "ram"}
    answer = model.solve()
    assert answer.status.value == "sat" and answer.states[-1]["ram"] == 3


@pytest.mark.parametrize(
    ("problem", "missing"),
    [
        # the domain's own morphism reads ram: it must be given
        ("(define (problem p) (:domain mine) (:goal (member cam mounted)))", "'ram'"),
        # the problem mentions budget (in its goal): it must be given
        ("(define (problem p) (:domain mine) (:init (= ram 4)) (:goal (>= budget 0)))", "'budget'"),
    ],
)
def test_mentioned_resources_still_need_an_initial_value(problem, missing):
    with pytest.raises(CatError) as err:
        _model(problem)
    assert err.value.codes == ["E0503"]
    assert missing in str(err.value)


def test_a_given_imported_resource_stays():
    model = _model("(define (problem p) (:domain mine) (:init (= ram 4) (= budget 100)) (:goal (member cam mounted)))")
    assert "budget" in model.instance.resources and model.instance.problem.init["budget"].value.value == 100


def test_every_stdlib_domain_checks_clean_and_every_number_has_a_unit():
    for path in sorted((ROOT / "stdlib_domains").glob("*.cat")):
        res = run_catc("check", "--strict", str(path))
        assert res.exit_code == 0, res.output
        diags = Diagnostics()
        domains, _ = check_files([str(path)], diags)
        for dom in domains.values():
            for r in dom.resources.values():
                assert r.unit or not r.sort.is_numeric, f"{path.name}: resource {r.name}"
            for m in dom.morphisms.values():
                for prm in m.params:
                    assert prm.unit or not prm.sort.is_numeric, f"{path.name}: {m.name} {prm.name}"


def test_catalog_domains_are_documented():
    doc = (ROOT / "docs" / "stdlib.md").read_text()
    for path in sorted((ROOT / "stdlib_domains").glob("*.cat")):
        assert f"`{path.stem}`" in doc, path.stem
