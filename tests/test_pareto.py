"""`catc pareto`: the front equals the non-dominated set found by enumerating every choice."""

from __future__ import annotations

import itertools
import json

from conftest import ROOT, run_catc

from catc.frontend.workspace import load_instance
from catc.queries.pareto import dominates, pareto
from catc.semantics.plan import Activation, Plan
from catc.semantics.validate import objective_value, validate
from catgrammar.diagnostics import Diagnostics

DESIGN = ROOT / "examples" / "pareto-design" / "design.cat"


def instance():
    diags = Diagnostics()
    _, inst = load_instance(None, str(DESIGN), diags)
    return inst


def brute_force_front(inst):
    objectives = list(inst.problem.metric.objectives)
    stts = [m for m in inst.morphisms if m.startswith("whisper")]
    vlms = [m for m in inst.morphisms if not m.startswith("whisper")]
    points = {}
    for s, v in itertools.product(stts, vlms):
        plan = Plan(((Activation(s), Activation(v)),))
        report = validate(inst, plan, horizon=1)
        assert report.ok, report.violations
        values = tuple(objective_value(inst, plan, o.term, report.states[-1]) for o in objectives)
        points[(s, v)] = values
    front = {k: p for k, p in points.items() if not any(dominates(q, p, objectives) for q in points.values())}
    return front, len(points)


def test_front_equals_brute_force_enumeration():
    inst = instance()
    expected, total = brute_force_front(inst)
    assert total == 55
    result = pareto(inst)
    assert result.complete and result.status == "front"
    assert {p.values for p in result.points} == set(expected.values())
    for p in result.points:
        chosen = tuple(sorted(p.plan.components, key=lambda m: not m.startswith("whisper")))
        assert expected[chosen] == p.values
    # and no point of the front dominates another
    objectives = result.objectives
    for a, b in itertools.permutations(result.points, 2):
        assert not dominates(a.values, b.values, objectives)


def test_pareto_cli_table_plot_and_json(tmp_path):
    res = run_catc("pareto", str(DESIGN))
    assert res.exit_code == 0 and "FRONT  13 non-dominated compositions (complete)" in res.stdout
    assert "qwen2-vl-7b whisper-tiny" in res.stdout
    png = tmp_path / "front.png"
    res = run_catc("pareto", str(DESIGN), "--plot", str(png))
    assert res.exit_code == 0 and png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    svg = tmp_path / "front.svg"
    run_catc("pareto", str(DESIGN), "--plot", str(svg))
    assert "<svg" in svg.read_text()
    doc = json.loads(run_catc("pareto", str(DESIGN), "--json").stdout)
    assert doc["schema"] == "catc.pareto/1" and len(doc["points"]) == 13 and doc["complete"] is True


def test_two_objectives_from_the_command_line():
    res = run_catc(
        "pareto", str(DESIGN), "--maximize", "(* mmmu (- 1 wer))", "--minimize", "(+ stt-gpu vlm-gpu)", "--json"
    )
    doc = json.loads(res.stdout)
    pts = [tuple(p["values"]) for p in doc["points"]]
    # the best quality per memory budget: strictly increasing quality with memory
    assert len(pts) >= 3 and all(a != b for a, b in itertools.pairwise(pts))


def test_max_points_marks_the_front_incomplete():
    res = run_catc("pareto", str(DESIGN), "--max-points", "3")
    assert res.exit_code == 3 and "incomplete" in res.stdout


def test_one_objective_is_an_input_error():
    res = run_catc("pareto", str(DESIGN), "--minimize", "wer")
    assert res.exit_code == 2 and "at least two objectives" in res.stderr


def test_ctrl_c_between_two_points_stops_the_front(monkeypatch):
    """Issue 28: pareto never looked at Ctrl-C between points; the next check got the 1 ms a
    stopped command has left, and an easy check answers in that (a flake).  Ctrl-C is pressed
    here right after the first point, and the solver answers every check whatever time it is
    given: the front stops with its one point, "interrupted", exit 130."""
    import signal

    from catc.queries import pareto as module
    from catgrammar import limits

    exclude = module._Guided.exclude

    def first_point_then_ctrl_c(self, values):
        exclude(self, values)
        signal.raise_signal(signal.SIGINT)  # the command's handler marks it interrupted

    monkeypatch.setattr(module._Guided, "exclude", first_point_then_ctrl_c)
    monkeypatch.setattr(limits, "for_check", lambda at=None: None)  # a solver that always answers
    res = run_catc("pareto", str(DESIGN), "--json")
    assert res.exit_code == 130, res.output
    doc = json.loads(res.stdout)
    assert len(doc["points"]) == 1 and doc["complete"] is False and doc["reason"] == "interrupted", doc


def test_the_time_limit_between_two_points_stops_the_front(monkeypatch):
    from catc.queries import pareto as module
    from catgrammar import limits

    inst = instance()
    exclude = module._Guided.exclude
    clock = {"points": 0}

    def first_point_then_time_is_up(self, values):
        exclude(self, values)
        clock["points"] += 1
        limits.clock().at = float("-inf")  # the limit passed as the point was taken

    monkeypatch.setattr(module._Guided, "exclude", first_point_then_time_is_up)
    monkeypatch.setattr(limits, "for_check", lambda at=None: None)
    result = pareto(inst, timeout=600)
    assert clock["points"] == 1 and len(result.points) == 1
    assert not result.complete and result.reason == "timeout" and result.status == "front"
