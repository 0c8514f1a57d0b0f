"""The Python API (catc.api): the same answers and documents as the command line, located
errors as exceptions, objectives from .cat text."""

from __future__ import annotations

import doctest
import json
from fractions import Fraction

import pytest
from conftest import ROOT, run_catc

import catc.interfaces.api
from catc.api import CatError, Model, load, loads
from catc.queries.optimize import OptStatus
from catc.queries.solve import SolveStatus

EX = ROOT / "examples"


def test_the_module_example_runs(monkeypatch):
    monkeypatch.chdir(ROOT)
    failures, tried = doctest.testmod(catc.interfaces.api)
    assert tried >= 4 and failures == 0


def without_timings(doc: dict) -> dict:
    doc.pop("timings", None)
    return doc


# every query: the API's document is the command line's (each query works in its own Z3
# context, so the two runs are the same computation)
QUERIES = [
    ("solve", ["detection/person.cat"], lambda m: m.solve()),
    ("solve", ["navigation/coarse.cat"], lambda m: m.solve()),
    ("optimize", ["gpu-allocation/retask.cat"], lambda m: m.optimize()),
    ("pareto", ["pareto-design/design.cat"], lambda m: m.pareto()),
    ("diagnose", ["lifelong/budget-cut.cat"], lambda m: m.diagnose()),
    ("relax", ["lifelong/budget-cut.cat"], lambda m: m.relax()),
    ("relax", ["lifelong/budget-cut.cat", "--discrete"], lambda m: m.relax(discrete=True)),
    (
        "recompose",
        ["lifelong/cheaper-camera.cat", "--priority", "objective"],
        lambda m: m.recompose(priority="objective"),
    ),
    ("synthesize", ["holes/talk.cat"], lambda m: m.synthesize()),
]


@pytest.mark.parametrize("command, args, query", QUERIES, ids=[f"{c} {' '.join(a)}" for c, a, _ in QUERIES])
def test_every_query_gives_the_command_lines_document(command, args, query):
    model = load(EX / args[0])
    cli = run_catc(command, str(EX / args[0]), *args[1:], "--json")
    assert without_timings(model.to_json(query(model))) == without_timings(json.loads(cli.stdout))


def test_objectives_from_cat_text():
    model = load(EX / "gpu-allocation/retask.cat")
    result = model.optimize([model.minimize("gpu-used")])
    # the least footprint 2.25 + 9.5 + 2.5 = 14.25 GB (gpu-allocation/expect.toml)
    assert result.status is OptStatus.OPT and result.values[0].value == Fraction(57, 4)
    with pytest.raises(CatError) as err:
        model.maximize("(+ gpu-used no-such-resource)")
    # located in the term as written (column 13: after "(+ gpu-used "), never in a wrapper around it
    assert err.value.codes == ["E0202"] and str(err.value).startswith("<maximize>:1:13: error[E0202]")
    assert "define" not in str(err.value) and " 1 | (+ gpu-used no-such-resource)" in str(err.value)
    with pytest.raises(CatError) as err:
        model.minimize("(+ gpu-used\n   nope)")
    assert str(err.value).startswith("<minimize>:2:4: error[E0202]")


def test_validate_takes_a_plan_or_a_document():
    model = load(EX / "detection/person.cat")
    answer = model.solve()
    doc = {"schema": "catc.plan/1", "steps": model.to_json(answer)["steps"]}
    assert model.validate(answer.plan).ok and model.validate(doc).ok
    broken = dict(doc, steps=doc["steps"][1:])  # the driver runs before the camera is mounted
    report = model.validate(broken)
    assert not report.ok and model.to_json(report)["valid"] is False


def test_errors_are_located_exceptions(tmp_path):
    with pytest.raises(CatError) as err:
        load(tmp_path / "missing.cat")
    assert err.value.codes == ["E0001"] and "no such file" in str(err.value)
    with pytest.raises(CatError) as err:
        load(tmp_path)
    assert err.value.codes == ["E0001"] and "it is a folder" in str(err.value)
    bad = tmp_path / "bad.cat"
    bad.write_text("(define (problem p) (:domain ghost) (:goal true))\n")
    with pytest.raises(CatError) as err:
        load(bad)
    assert "E0207" in err.value.codes and f"{bad}:1:" in str(err.value)
    with pytest.raises(CatError) as err:
        load(EX / "detection/person.cat", view="no-such-view")
    assert err.value.codes == ["E0506"]


def test_a_model_given_as_text_answers_as_its_files_do():
    """loads: the same answer as load on the same texts; errors located in the given paths,
    which need not exist; a problem path outside the sources is a ValueError."""
    domain = (EX / "detection/domain.cat").read_text()
    problem = (EX / "detection/person.cat").read_text()
    texts = {"robot/domain.cat": domain, "robot/person.cat": problem}
    from_text, from_files = loads(texts, "robot/person.cat"), load(EX / "detection/person.cat")
    assert from_text.instance.problem.name == from_files.instance.problem.name == "detect-person"
    assert from_text.solve().status is from_files.solve().status is SolveStatus.SAT
    broken = {**texts, "robot/person.cat": problem.replace("(member person detects)", "(member persn detects)")}
    with pytest.raises(CatError) as err:
        loads(broken, "robot/person.cat")
    assert "E0202" in err.value.codes and "robot/person.cat:" in str(err.value) and "persn" in str(err.value)
    with pytest.raises(ValueError, match="not among the sources"):
        loads(texts, "robot/other.cat")


def test_views_domains_and_named_problems():
    full = load(EX / "semantics/view.cat", problem_name="shop-full")
    assert full.solve().status is SolveStatus.UNSAT  # semantics/expect.toml
    assert load(EX / "semantics/view.cat", problem_name="shop-software").solve().status is SolveStatus.SAT
    model = load(EX / "detection/domain.cat", EX / "detection/person.cat")
    assert isinstance(model, Model) and "detect-person" in repr(model)
    with pytest.raises(TypeError):
        model.to_json("not a result")


def test_the_examples_in_docs_api_run(monkeypatch, capsys):
    import re

    monkeypatch.chdir(ROOT)
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "docs/api.md").read_text(encoding="utf-8"), re.S)
    assert len(blocks) == 4
    scope: dict = {}
    for block in blocks:
        exec(compile(block, "docs/api.md", "exec"), scope)
    assert scope["answer"].states[-1]["ram"] == Fraction(23, 2)  # 16 - 0.5 - 4 GB, as the comment says
    assert scope["best"].values[0].value == Fraction(57, 4)
    assert scope["doc"]["schema"] == "catc.solve/1"
    out = capsys.readouterr().out
    assert out.startswith("sat\nmount-rgb-camera {}\n") and out.endswith("SolveStatus.SAT\n")  # loads's example last


def test_long_queries_report_progress():
    seen: list[str] = []
    result = load(EX / "lifelong/budget-cut.cat").relax(progress=seen.append)
    assert result.cost == 19860 and seen[0] == "looking for a restoration"  # lifelong/expect.toml
    seen.clear()
    load(EX / "search-and-rescue/event2-out-of-range.cat").optimize(progress=seen.append)
    assert "first composition: 10 steps; is there a better one within 24 steps?" in seen


def test_the_api_does_not_import_click():
    import subprocess
    import sys

    probe = (
        "import sys\nfrom catc.api import load\nm = load('examples/detection/person.cat')\n"
        "m.to_json(m.solve()); m.to_json(m.optimize([m.minimize('ram')]))\n"
        "print(sorted(x for x in sys.modules if x.split('.')[0] == 'click'))"
    )
    proc = subprocess.run([sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[]"
