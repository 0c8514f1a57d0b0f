"""The benchmark scripts behind docs/benchmarks.md still run (a smoke test: one run each,
the smallest sizes).  The figures themselves are never asserted: timings vary by machine."""

from __future__ import annotations

import re
import subprocess
import sys
import tomllib

import pytest
from conftest import ROOT

pytestmark = pytest.mark.slow


def run(*args: str) -> str:
    proc = subprocess.run([sys.executable, *args], cwd=ROOT, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    return proc.stdout


def test_solve_bench_runs_every_section():
    out = run("benchmarks/solve_bench.py", "--quick", "--runs", "1")
    for heading in (
        "Every example end to end",
        "Detection against a hand-written Z3 script",
        "Lifelong queries end to end",
        "Optimize against plain solve",
        "The refutation behind",
        "Scaling: synthetic catalogs",
    ):
        assert f"### {heading}" in out
    assert "catc / hand-written:" in out and "Largest encoding share:" in out
    # every example and query answered as its expectation says: no ERR, and the refutation is a proof
    assert "| ERR |" not in out and "| unsat |" in out
    # each example row's answer is its hand-derived expectation (examples/*/expect.toml)
    rows = dict(re.findall(r"^\| (\S+\.cat(?: \([\w-]+\))?) \| (SAT|UNSAT|UNKNOWN) \|", out, re.M))
    for expect in sorted((ROOT / "examples").glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            name = f"{expect.parent.name}/{case['file']}" + (f" ({case['problem']})" if "problem" in case else "")
            assert rows[name] == case["status"].upper(), name


def test_parse_check_runs():
    out = run("benchmarks/parse_check.py", "--sizes", "200", "--runs", "1")
    assert "200" in out
    assert re.search(r"^\| 200 \| [\d,]+ \| [\d.]+ \| [\d.]+ \| [\d.]+ \| \d+ \| — \|$", out, re.M), out


def test_runtime_bench_runs():
    out = run("benchmarks/runtime_bench.py", "--runs", "1", "--stream", "8")
    assert "### Search-and-rescue mission" in out and "### Per decision kind" in out
    # the decisions are those tests/test_runtime.py derives by hand for the mission
    actions = re.findall(r"^\| ([\w-]+) \| (\w+) \| \d+ \|", out, re.M)
    assert actions[:8] == [("start", "compose"), ("II-out-of-range", "recompose"), ("III-budget-cut", "restore"),
                           ("III-approved", "keep"), ("refurbished-camera", "keep"), ("IV-dark", "restore"),
                           ("IV-approved", "recompose"), ("lidar-failed", "stuck")]  # fmt: skip
    # a kept composition costs no solver call
    assert re.search(r"^\| keep \| \d+ \| 0 \|", out, re.M)


def test_catalogs_bench_runs_and_checks_its_answers():
    """benchmarks/catalogs.py exits non-zero on any answer other than the hand-derived core
    and relaxation of each variant (its catalog() docstring)."""
    out = run("benchmarks/catalogs.py", "--quick", "--no-enhsp")
    rows = re.findall(r"^\| (price|ram) \| (\d+) \| 3 \|", out, re.M)
    assert sorted(rows) == [("price", "12"), ("price", "25"), ("ram", "12"), ("ram", "25")]
    assert "Fitted exponent" in out


def test_the_catalogs_cores_are_what_their_construction_says():
    """The generator's cores by construction, checked against the solver: the core is
    infeasible and dropping any member is feasible (n = 12, both variants)."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from catalogs import catalog

    from catc.api import loads
    from catc.smt.backend import Check
    from catc.smt.labelled import LabelledModel

    for variant in ("price", "ram"):
        text, expect = catalog(12, 3, variant)
        inst = loads({"c.cat": text}, "c.cat").instance
        model = LabelledModel(inst, inst.problem.horizon, components=inst.problem.deployed)
        assert model.check(expect["core"])[0] is Check.UNSAT
        for drop in expect["core"]:
            assert model.check([x for x in expect["core"] if x != drop])[0] is Check.SAT, (variant, drop)
        assert model.check(model.labels)[0] is Check.UNSAT


def test_warm_bench_runs_and_warm_answers_agree_with_cold():
    """benchmarks/warm_bench.py exits non-zero when a warm answer differs from the cold one.
    By hand (examples/search-and-rescue): every event's mission takes 10 steps except the
    budget cut to 500, which cannot buy the LiDAR (20,000)."""
    out = run("benchmarks/warm_bench.py", "--runs", "1", "--sizes", "25", "--depth", "6")
    answers = dict(re.findall(r"^\| ([^|]+?) \| (sat \d+|unsat) \|", out, re.M))
    assert answers["start"] == "sat 10" and answers["budget 500 (UNSAT, relaxation)"] == "unsat"
    assert answers["goal cap5"] == "sat 5" and answers["ram 10 (UNSAT)"] == "unsat"
    assert out.count("steady state") == 2


def test_reference_bench_runs_and_checks_its_answers():
    """benchmarks/reference_bench.py checks catc's and the hand-written scripts' answers
    against expect.toml before timing (and exits non-zero when one differs)."""
    out = run("benchmarks/reference_bench.py", "--runs", "1")
    assert re.search(r"^\| optimize gpu-allocation/max-confidence \| [\d.]+ \|", out, re.M)
    assert re.search(r"^\| optimize navigation/farthest \| [\d.]+ \|", out, re.M)
    assert "Largest catc / hand-written:" in out


def test_startup_bench_runs_every_query():
    """benchmarks/startup_bench.py exits non-zero when a command's exit code is not the one
    expected (every query answers its example; the yardsticks run)."""
    out = run("benchmarks/startup_bench.py", "--runs", "1", "--no-compile")
    for query in ("solve", "optimize", "diagnose", "relax", "recompose", "pareto", "validate", "check"):
        assert re.search(rf"^\| {query} [^|]* \| [\d.]+ \|", out, re.M), query
    assert "Largest wall ratio against a hand-written script:" in out


def test_maxsmt_bench_runs_and_both_churn_encodings_agree():
    """benchmarks/maxsmt_bench.py exits non-zero when an optimum's churn differs from the one
    derived in its docstring (SAR: 0 and 4, expect.toml; the retired catalog: 2)."""
    out = run("benchmarks/maxsmt_bench.py", "--quick", "--runs", "1")
    assert "| SAR stability-first | " in out and "opt churn 0" in out
    assert "| catalog n=12 d=3, no counting proof | " in out and "opt churn 2" in out
