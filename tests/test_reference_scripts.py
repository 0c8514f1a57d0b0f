"""The hand-written Z3 scripts of benchmarks/reference/ that benchmarks/startup_bench.py
times catc's recompose and pareto against answer the same question as catc: their printed
answer equals catc's ``--json`` answer on the same example, and both equal the example's
hand-derived expectation (examples/*/expect.toml).  A script answering something else would
make the start-up ratio meaningless."""

from __future__ import annotations

import ast
import json
import re
import subprocess
import sys
import tomllib
from fractions import Fraction

import pytest
from conftest import ROOT, run_catc

REFERENCE = ROOT / "benchmarks" / "reference"


def script(name: str, *args: str) -> list[str]:
    proc = subprocess.run(
        [sys.executable, str(REFERENCE / name), *args], cwd=ROOT, capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    return proc.stdout.splitlines()


def case(folder: str, file: str) -> dict:
    cases = tomllib.loads((ROOT / "examples" / folder / "expect.toml").read_text())["case"]
    return next(c for c in cases if c["file"] == file)


def catc_json(*args: str) -> dict:
    res = run_catc(*args, "--json")
    assert res.exit_code == 0, res.output
    return json.loads(res.stdout)


@pytest.mark.parametrize(
    ("flag", "key"), [((), "recompose_stability"), (("--objective-first",), "recompose_objective")]
)
def test_the_recompose_script_answers_as_catc(flag, key):
    lines = script("cheaper_camera_recompose_z3.py", *flag)
    churn, left = re.fullmatch(r"churn (\d+) budget left (\S+)", lines[0]).groups()
    added, removed = (ast.literal_eval(line.split(" ", 1)[1]) for line in lines[1:3])  # printed lists
    doc = catc_json("recompose", "examples/lifelong/cheaper-camera.cat", *(["--priority", "objective"] if flag else []))
    catc_changes = {(c["morphism"], c["change"]) for c in doc["changes"]}
    assert int(churn) == doc["churn"]
    assert Fraction(left) == Fraction(doc["final_state"]["budget"])
    assert {(m, "added") for m in added} | {(m, "removed") for m in removed} == catc_changes
    want = case("lifelong", "cheaper-camera.cat")[key]
    assert (Fraction(churn), Fraction(left)) == (Fraction(want["churn"]), Fraction(want["objective"]))
    assert sorted(added) == sorted(want.get("added", [])) and sorted(removed) == sorted(want.get("removed", []))
    # the composition printed is one: each step a known component, the deployed ones kept
    steps = [line.split() for line in lines[3:]]
    assert all(len(s) == 2 and 1 <= int(s[0]) <= 8 for s in steps)
    assert {s[1] for s in steps} == set(doc["deployed"]) - set(removed) | set(added)


def test_the_pareto_script_finds_catcs_front():
    lines = script("pareto_design_z3.py")
    assert lines[-1] == f"{case('pareto-design', 'design.cat')['pareto_points']} non-dominated points"
    mine = {}
    for line in lines[:-1]:
        quality, latency, gpu, *chosen = line.split()
        mine[Fraction(quality), Fraction(latency), Fraction(gpu)] = sorted(chosen)
    doc = catc_json("pareto", "examples/pareto-design/design.cat")
    assert doc["complete"] is True
    theirs = {tuple(Fraction(v) for v in p["values"]): sorted(p["components"]) for p in doc["points"]}
    assert mine == theirs
