"""`catc solve`, `catc validate`, `catc compile`: outputs, JSON schemas, exit codes."""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

from conftest import ROOT, run_catc, run_catc_process

DET = ROOT / "examples" / "detection"
NAV = ROOT / "examples" / "navigation"
SAR = ROOT / "examples" / "search-and-rescue"


def test_solve_sat_text():
    res = run_catc("solve", str(DET / "domain.cat"), str(DET / "person.cat"))
    assert res.exit_code == 0, res.output
    out = res.stdout
    assert out.startswith("SAT  composition of 3 steps for problem detect-person of domain detection")
    for name in ("mount-rgb-camera", "camera-driver", "open-vocab-detector", "validated by independent replay"):
        assert name in out
    assert "target = person" in out


def test_solve_unsat_final_and_not_final():
    res = run_catc("solve", str(NAV / "coarse.cat"))
    assert res.exit_code == 1 and "UNSAT" in res.stdout and "this is final" in res.stdout
    res = run_catc(
        "solve", str(ROOT / "examples/semantics/interference.cat"), "--problem", "power-both", "--horizon", "1"
    )
    assert res.exit_code == 1 and "not final: compositions may need up to 4 steps" in res.stdout


def test_solve_json_schema_and_nothing_else_on_stdout():
    res = run_catc("solve", str(DET / "unmodeled-class.cat"), "--json")
    assert res.exit_code == 0
    doc = json.loads(res.stdout)
    assert doc["schema"] == "catc.solve/1" and doc["status"] == "sat"
    assert [[a["morphism"] for a in step] for step in doc["steps"]] == [
        ["mount-rgb-camera"],
        ["camera-driver"],
        ["open-vocab-detector"],
    ]
    assert doc["steps"][2][0]["params"]["target"] == "fire-extinguisher"
    assert doc["final_state"]["detects"] == ["fire-extinguisher"]
    assert doc["steps"][1][0]["params"]["ram-req"] in ("1/2", 1, 2) or isinstance(
        doc["steps"][1][0]["params"]["ram-req"], (int, str)
    )
    assert res.stderr == ""


def test_solve_json_unsat():
    res = run_catc("solve", str(NAV / "coarse.cat"), "--json")
    doc = json.loads(res.stdout)
    assert (
        res.exit_code == 1
        and doc["status"] == "unsat"
        and doc["unsat"]
        == {
            "final": True,
            "length_bound": 1,
            "proof": "solver",  # the relaxation sees no obstacle: only the use limit of 1 step does
            "why": None,
            "label": None,
        }
    )


def test_fresh_values_are_marked():
    res = run_catc("solve", str(ROOT / "examples/semantics/reserve.cat"))
    assert "out = topic#1 (fresh)" in res.stdout
    doc = json.loads(run_catc("solve", str(ROOT / "examples/semantics/reserve.cat"), "--json").stdout)
    assert doc["fresh"] == {"topic#1": "topic"}


def test_input_errors_exit_2_with_diagnostics(tmp_path):
    bad = tmp_path / "bad.cat"
    bad.write_text("(define (problem p) (:domain ghost) (:goal true))")
    res = run_catc("solve", str(bad))
    assert res.exit_code == 2 and "error[E0207]" in res.stderr
    res = run_catc("solve", str(bad), "--json")
    assert res.exit_code == 2 and json.loads(res.stdout)["diagnostics"][0]["code"] == "E0207"
    res = run_catc("solve", str(tmp_path / "missing.cat"))
    assert res.exit_code == 2 and "E0001" in res.stderr and "no such file" in res.stderr
    res = run_catc("solve", str(tmp_path))
    assert (
        res.exit_code == 2 and f"error[E0001]: cannot read '{tmp_path}': it is a folder; give a .cat file" in res.stderr
    )
    res = run_catc("solve", "a.cat", "b.cat", "c.cat")
    assert res.exit_code == 2


def test_unknown_view_is_an_input_error():
    res = run_catc("solve", str(DET / "person.cat"), "--view", "nope")
    assert res.exit_code == 2 and "unknown view" in res.stderr


def test_timeout_exits_3():
    res = run_catc("solve", str(SAR / "budget-cut.cat"), "--timeout", "0.001")
    assert res.exit_code == 3 and "UNKNOWN" in res.stdout and "timeout" in res.stdout


def test_sequential_and_view_options():
    res = run_catc("solve", str(ROOT / "examples/semantics/parallel.cat"), "--sequential", "--json")
    doc = json.loads(res.stdout)
    assert all(len(step) == 1 for step in doc["steps"]) and len(doc["steps"]) == 2
    res = run_catc("solve", str(ROOT / "examples/semantics/view.cat"), "--problem", "shop-full", "--view", "software")
    assert res.exit_code == 0 and "view software" in res.stdout


def test_diagram_is_written(tmp_path):
    out = tmp_path / "det.svg"
    res = run_catc("solve", str(DET / "person.cat"), "--diagram", str(out))
    assert res.exit_code == 0
    root = ET.parse(out).getroot()
    assert root.tag.endswith("svg")
    text = out.read_text()
    for name in ("mount-rgb-camera", "camera-driver", "open-vocab-detector"):
        assert name in text


def test_validate_accepts_a_good_plan_and_reports_a_broken_one(tmp_path):
    good = {"schema": "catc.plan/1", "steps": [[{"morphism": "move", "params": {"d": "193/20"}}]]}
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps(good))
    res = run_catc("validate", str(NAV / "precise.cat"), str(plan))
    assert res.exit_code == 0 and res.stdout.startswith("valid")
    res = run_catc("validate", str(NAV / "coarse.cat"), str(plan), "--json")
    doc = json.loads(res.stdout)
    assert res.exit_code == 1 and doc["valid"] is False
    assert {v["label"] for v in doc["violations"]} >= {"pre/move/1"}


def test_validate_rejects_floats_and_bad_json(tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps({"steps": [[{"morphism": "move", "params": {"d": 9.65}}]]}))
    res = run_catc("validate", str(NAV / "precise.cat"), str(plan))
    assert res.exit_code == 2 and "floats are not exact" in res.stderr
    plan.write_text("{not json")
    res = run_catc("validate", str(NAV / "precise.cat"), str(plan))
    assert res.exit_code == 2 and "not JSON" in res.stderr


def test_solve_in_a_fresh_process_prints_no_progress_when_piped():
    res = run_catc_process("solve", "examples/detection/person.cat", "--json")
    assert res.exit_code == 0 and res.stderr == ""
    json.loads(res.stdout)


def test_an_infeasibility_the_relaxation_sees_is_final_without_encoding():
    """The SAR budget cut: the LiDAR costs 20,000, the budget is 500 and only decreases, and
    every composition needs the LiDAR (expect.toml) — proved for every horizon, nothing encoded."""
    sar = ROOT / "examples/search-and-rescue"
    res = run_catc("solve", str(sar / "domain.cat"), str(sar / "budget-cut.cat"), "--json")
    doc = json.loads(res.stdout)
    assert res.exit_code == 1 and doc["unsat"]["proof"] == "relaxation" and doc["unsat"]["final"] is True
    assert doc["unsat"]["label"] == "goal/1" and doc["timings"]["encode"] == 0
    res = run_catc("solve", str(sar / "domain.cat"), str(sar / "budget-cut.cat"))
    assert "no composition of any length" in res.stdout and "relaxed reachability" in res.stdout
    res = run_catc("solve", str(sar / "domain.cat"), str(sar / "budget-cut.cat"), "--json", "--no-presolve")
    doc = json.loads(res.stdout)
    assert res.exit_code == 1 and doc["unsat"]["proof"] == "solver" and doc["timings"]["encode"] > 0


COMPETING = """(define (domain shop) (:requirements :numeric)
  (:resources (budget real :bounds (0 100)) (cam bool) (done bool))
  (:morphism cam-a :uses 1 :precondition (>= budget 10) :effect (and (decrease budget 10) (assign cam true)))
  (:morphism cam-b :uses 1 :precondition (>= budget 12) :effect (and (decrease budget 12) (assign cam true)))
  (:morphism det-x :uses 1 :precondition (and cam (>= budget 10)) :effect (and (decrease budget 10) (assign done true)))
  (:morphism det-y :uses 1 :precondition (and cam (>= budget 11)) :effect (and (decrease budget 11) (assign done true))))
(define (problem short) (:domain shop) (:init (= budget 15)) (:goal done))
"""


def test_an_infeasibility_only_the_consumption_bound_sees_is_named_so(tmp_path):
    """Each camera and each detector alone is affordable with 15, so relaxed reachability sees
    no obstacle; any composition needs one of each, at least 10 + 10 = 20 (by hand): issue
    24's consumption bound proves it, and the answer names that bound, not the relaxation."""
    path = tmp_path / "shop.cat"
    path.write_text(COMPETING)
    res = run_catc("solve", str(path), "--json")
    doc = json.loads(res.stdout)
    assert res.exit_code == 1 and doc["unsat"]["final"] is True, res.output
    assert doc["unsat"]["proof"] == "consumption" and doc["unsat"]["label"] == "init/budget", doc["unsat"]
    assert "20" in doc["unsat"]["why"]
    res = run_catc("solve", str(path))
    assert "no composition of any length" in res.stdout and "by a consumption bound" in res.stdout, res.output
    assert "relaxed reachability" not in res.stdout.split("time:")[0]
