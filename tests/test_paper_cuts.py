"""Paper cuts found by trying catc as a new user (issue 17 §4): each test fails on the code
before its fix."""

from __future__ import annotations

import json

from conftest import ROOT, run_catc

EX = ROOT / "examples"


# ---------------------------------------------------------------- validate reads --json answers


def test_validate_accepts_solve_json_output(tmp_path):
    det = EX / "detection"
    solved = run_catc("solve", det / "domain.cat", det / "person.cat", "--json")
    assert solved.exit_code == 0
    answer = tmp_path / "answer.json"
    answer.write_text(solved.stdout, encoding="utf-8")
    assert json.loads(solved.stdout)["schema"] == "catc.solve/1"
    res = run_catc("validate", det / "domain.cat", det / "person.cat", answer)
    # detection/expect.toml: the shortest composition has 3 steps
    assert res.exit_code == 0, res.output
    assert res.stdout.startswith("valid: 3 steps reach the goal of 'detect-person'")
    # the answer is replayed, not trusted: drop the detector's step and the goal fails
    doc = json.loads(solved.stdout)
    doc["steps"] = doc["steps"][:-1]
    answer.write_text(json.dumps(doc), encoding="utf-8")
    res = run_catc("validate", det / "domain.cat", det / "person.cat", answer)
    assert res.exit_code == 1 and "goal" in res.stdout


def test_validate_accepts_optimize_and_recompose_answers(tmp_path):
    for folder, problem, query in (
        ("gpu-allocation", "retask.cat", "optimize"),
        ("lifelong", "cheaper-camera.cat", "recompose"),
    ):
        d = EX / folder
        out = run_catc(query, d / "domain.cat", d / problem, "--json")
        assert out.exit_code == 0, out.output
        answer = tmp_path / f"{query}.json"
        answer.write_text(out.stdout, encoding="utf-8")
        res = run_catc("validate", d / "domain.cat", d / problem, answer)
        assert res.exit_code == 0, res.output


def test_validate_of_an_answer_without_composition_says_so(tmp_path):
    d = EX / "lifelong"
    out = run_catc("solve", d / "domain.cat", d / "budget-cut.cat", "--json")
    assert out.exit_code == 1  # lifelong/expect.toml: budget-cut is infeasible
    answer = tmp_path / "unsat.json"
    answer.write_text(out.stdout, encoding="utf-8")
    res = run_catc("validate", d / "domain.cat", d / "budget-cut.cat", answer)
    assert res.exit_code == 2
    assert "error[E0802]: this catc.solve/1 answer holds no composition (status 'unsat')" in res.stderr
    answer.write_text('{"schema": "catc.diagnose/1", "steps": []}', encoding="utf-8")
    res = run_catc("validate", d / "domain.cat", d / "budget-cut.cat", answer)
    assert res.exit_code == 2 and "unsupported plan schema 'catc.diagnose/1'" in res.stderr


# ---------------------------------------------------------------- --progress on any stream


def test_progress_forces_the_status_line_when_stderr_is_not_a_terminal():
    det = EX / "detection"
    for via_click in (False, True):
        quiet = run_catc("solve", det / "domain.cat", det / "person.cat", via_click=via_click)
        assert quiet.exit_code == 0 and quiet.stderr == ""  # not a terminal: nothing, as before
        res = run_catc("solve", det / "domain.cat", det / "person.cat", "--progress", via_click=via_click)
        assert res.exit_code == 0
        # the shortest composition has 3 steps (detection/expect.toml): horizons 0, 1, 2, 3 are tried in turn
        shown = [line.rsplit(" (", 1)[0] for line in res.stderr.splitlines()]
        assert shown == [f"catc: solving: horizon {k} of 3" for k in range(4)]
        assert "SAT  composition of 3 steps" in res.stdout


def test_progress_with_json_keeps_stdout_a_document():
    d = EX / "lifelong"
    res = run_catc("diagnose", d / "domain.cat", d / "budget-cut.cat", "--json", "--progress")
    assert json.loads(res.stdout)["schema"] == "catc.diagnose/1"
    assert res.stderr.splitlines()[0].startswith("catc: checking ")


def test_only_the_long_queries_take_progress():
    from catc.queries import registry

    having = {name for name in registry.names() if any(o.flags == ("--progress",) for o in registry.get(name).options)}
    assert having == {"solve", "optimize", "diagnose", "relax", "recompose"}


# ---------------------------------------------------------------- catc.api.load(DOMAIN, PROBLEM)


def test_api_load_takes_the_command_line_order():
    import warnings

    from catc.api import load

    det = EX / "detection"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the command line's order warns of nothing
        model = load(det / "domain.cat", det / "person.cat")
    assert model.instance.problem.name == "detect-person" and model.instance.domain.name == "detection"
    assert model.solve().status.value == "sat"


def test_api_load_in_the_old_order_still_loads_with_a_deprecation_warning():
    import pytest

    from catc.api import load

    det = EX / "detection"
    with pytest.warns(DeprecationWarning, match=r"load\(DOMAIN, PROBLEM\)"):
        model = load(det / "person.cat", det / "domain.cat")
    assert model.instance.problem.name == "detect-person" and model.instance.domain.name == "detection"


def test_api_load_does_not_swap_files_that_define_both(tmp_path):
    import warnings

    import pytest

    from catc.api import CatError, load

    both = tmp_path / "both.cat"
    both.write_text(
        "(define (domain d) (:requirements :numeric) (:resources (n int)) (:morphism m :kind software :effect (increase n 1)))\n"
        "(define (problem p) (:domain d) (:init (= n 0)) (:goal (>= n 1)))\n",
        encoding="utf-8",
    )
    # a domain-only file second: not the old order (the first defines a domain too), so no warning
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert load(both).solve().status.value == "sat"
        with pytest.raises(CatError):
            load(both, EX / "detection" / "domain.cat")
    with pytest.raises(TypeError):
        load()
