"""Errors in what a command was asked (E07xx), in plan files (E08xx) and in exports (E09xx):
each a located one-line report with its own code and exit 2, never a traceback; with --json
a catc.error/1 document."""

from __future__ import annotations

import json

import pytest
from conftest import ROOT, run_catc

EX = ROOT / "examples"
LIFE = str(EX / "lifelong/budget-cut.cat")
CAMERA = str(EX / "lifelong/cheaper-camera.cat")
PERSON = str(EX / "detection/person.cat")


def error(res, code: str) -> None:
    assert res.exit_code == 2, (res.exit_code, res.output)
    assert f"error[{code}]" in res.stderr, res.stderr
    assert "Traceback" not in res.output


@pytest.mark.parametrize("value", ["inf", "nan"])
@pytest.mark.parametrize("query", ["solve", "optimize", "diagnose", "relax"])
def test_a_timeout_must_be_a_finite_number_of_seconds(query, value):
    """Before: inf overflowed Z3's timeout setter (exit 70); nan was taken as 1 ms."""
    target = CAMERA if query == "optimize" else LIFE
    error(run_catc(query, target, "--timeout", value), "E0701")


@pytest.mark.parametrize("query", ["solve", "optimize", "diagnose", "relax"])
def test_a_timeout_too_long_to_matter_is_no_limit(query):
    """1e308 s overflowed Z3's timeout setter (exit 70); it is as good as no limit."""
    target = CAMERA if query == "optimize" else LIFE
    assert run_catc(query, target, "--timeout", "1e308").exit_code in (0, 1)


def test_an_unknown_component_is_named():
    res = run_catc("diagnose", LIFE, "--relative-to", "buy-lidar,no-such-thing")
    error(res, "E0702")
    assert "no-such-thing" in res.stderr and "buy-lidar" not in res.stderr.split("composition:")[1]
    error(run_catc("recompose", CAMERA, "--deployed", "nope"), "E0702")


def test_a_weight_must_be_key_equals_number():
    error(run_catc("relax", LIFE, "--weights", "budget=two"), "E0703")


@pytest.mark.parametrize(
    "args, words",
    [
        (["optimize", PERSON], "nothing to optimise"),
        (["pareto", CAMERA], "at least two objectives"),
        (["recompose", str(EX / "navigation/farthest.cat")], "no deployed composition"),
        (["synthesize", PERSON], "declares no (:hole"),
        (["synthesize", str(EX / "holes/talk.cat"), "--hole", "nu"], "no hole named 'nu'"),
    ],
)
def test_a_query_that_does_not_apply_says_why(args, words):
    res = run_catc(*args)
    error(res, "E0704")
    assert words in res.stderr
    doc = json.loads(run_catc(*args, "--json").stdout)
    assert doc["schema"] == "catc.error/1" and doc["diagnostics"][0]["code"] == "E0704"


def test_an_output_file_that_cannot_be_written(tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("")
    res = run_catc("solve", PERSON, "--diagram", str(blocker / "d.svg"))
    error(res, "E0705")


def test_a_missing_plotting_extra_is_named(monkeypatch, tmp_path):
    from catc.queries import pareto

    def no_matplotlib(*args, **kwargs):
        raise RuntimeError("--plot needs matplotlib: pip install 'catc-lang[plots]'")

    monkeypatch.setattr(pareto, "draw_front", no_matplotlib)
    res = run_catc("pareto", str(EX / "pareto-design/design.cat"), "--plot", str(tmp_path / "f.png"))
    error(res, "E0706")
    assert "catc-lang[plots]" in res.stderr


def test_plan_files_that_are_not_json_or_not_plans(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{ nope")
    res = run_catc("validate", PERSON, str(bad))
    error(res, "E0801")
    assert res.stderr.startswith(f"{bad}:1:3: error[E0801]")
    bad.write_text('{"steps": 3}')
    error(run_catc("validate", PERSON, str(bad)), "E0802")
    error(run_catc("validate", PERSON, str(tmp_path / "missing.json")), "E0001")


def test_an_export_the_model_cannot_take(tmp_path):
    res = run_catc("export", "pddl", PERSON, "-o", str(tmp_path))
    error(res, "E0901")
    assert "--grid" in res.stderr


def test_an_export_a_parser_rejects_is_a_bug_reported_as_such(monkeypatch, tmp_path):
    from catc.targets import pddl_target

    def reject(*args):
        raise ValueError("unexpected token")

    monkeypatch.setattr(pddl_target, "check_pddl", reject)
    monkeypatch.setattr(pddl_target, "_parsers_present", lambda plus, strict: None)  # a parser is there, and rejects
    res = run_catc("export", "pddl", LIFE, "-o", str(tmp_path))
    error(res, "E0902")


def test_a_missing_baseline_planner(monkeypatch, tmp_path):
    from catc.targets import enhsp

    def missing(*args, **kwargs):
        raise enhsp.BaselineMissing("Java 17 is needed to run ENHSP")

    monkeypatch.setattr(enhsp, "run_enhsp", missing)
    res = run_catc("export", "pddl", LIFE, "-o", str(tmp_path), "--no-check", "--run")
    error(res, "E0903")
