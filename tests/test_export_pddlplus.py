"""`catc export pddl --flavor smtplan`: PDDL+ for SMTPlan+ (DESIGN §6, docs/export.md).

* every example exports without a grid (a real θ becomes a dial: a fluent raised by a
  process between two instantaneous actions) and parses with unified-planning's PDDL+ reader
  and with PyPI ``pddl-plus-parser`` — parsers we did not write;
* timed plans in SMTPlan+'s format (``TIME: (ACTION) [DUR]``), written by hand with values
  derived by hand, are read back with exact θ and replayed by catc's validator: GPU
  allocation's optimum m = 17/4 (confidence 21/25) and navigation's 9.65 m trip (SAT with
  22.73 Wh, rejected with 22.7 Wh); a wrong dial duration is rejected;
* misuse of a dial, inexact times and unknown actions are clear errors; a missing SMTPlan+
  binary exits 2; the report names what the flavour cannot express.

SMTPlan+ itself has no package here, so no test runs it (``--run`` is tested only with a
stand-in script that prints a hand-written plan, to check the plumbing).
"""

from __future__ import annotations

import os
import stat
from fractions import Fraction
from pathlib import Path

import pytest
from click.testing import CliRunner
from test_export_pddl import EXAMPLES, cases, instance

from catc.interfaces.cli import main
from catc.semantics.validate import validate
from catc.targets.pddl import ExportError, export_pddl
from catc.targets.pddlplus import PlanReadError, parse_timed_plan, read_timed_actions, timed_plan_text


def _missing(module: str, hint: str) -> str | None:
    try:
        __import__(module)
    except ImportError:
        return f"{module} is not installed: {hint}"
    return None


UP_MISSING = _missing("unified_planning", "pip install 'catc-lang[baselines]'")
PPP_MISSING = _missing("pddl_plus_parser", "pip install 'catc-lang[baselines]'")
needs_up = pytest.mark.skipif(UP_MISSING is not None, reason=str(UP_MISSING))
needs_ppp = pytest.mark.skipif(PPP_MISSING is not None, reason=str(PPP_MISSING))


def _write(ex, tmp_path: Path) -> tuple[Path, Path]:
    dom, prob = tmp_path / "domain.pddl", tmp_path / "problem.pddl"
    dom.write_text(ex.domain)
    prob.write_text(ex.problem)
    return dom, prob


def _smtplan(folder: str, file: str, problem: str | None = None, **kw):
    inst = instance(EXAMPLES / folder, {"file": file, **({"problem": problem} if problem else {})})
    return inst, export_pddl(inst, flavor="smtplan", **kw)


# ---------------------------------------------------------------- parsers we did not write


@needs_up
@pytest.mark.parametrize("folder, case", list(cases()))
def test_every_example_exports_without_grid_and_parses_with_unified_planning(folder, case, tmp_path):
    from unified_planning.io import PDDLReader

    ex = export_pddl(instance(folder, case), flavor="smtplan")  # no grid: real θ are dials
    dom, prob = _write(ex, tmp_path)
    up = PDDLReader().parse_problem(str(dom), str(prob))
    assert len(up.actions) == len(ex.actions) + 2 * len(ex.dials)  # + start/stop per dial
    assert len(up.processes) == len(ex.dials)
    if ex.dials:
        assert up.kind.has_processes() and ":time" in ex.domain
        assert "(* #t 1)" in ex.domain


@needs_ppp
@pytest.mark.parametrize("folder, case", list(cases()))
def test_every_example_parses_with_pddl_plus_parser(folder, case, tmp_path):
    from pddl_plus_parser.lisp_parsers import DomainParser, ProblemParser

    ex = export_pddl(instance(folder, case), flavor="smtplan")
    dom, prob = _write(ex, tmp_path)
    d = DomainParser(dom).parse_domain()
    p = ProblemParser(prob, d).parse_problem()
    # pddl-plus-parser 3.17 reads :process blocks without keeping them; actions and init are checked
    assert len(d.actions) == len(ex.actions) + 2 * len(ex.dials)
    assert p.name


def test_examples_with_real_theta_have_dials_and_no_grid():
    _, gpu = _smtplan("gpu-allocation", "max-confidence.cat")
    assert set(gpu.dials) == {"detector.m"} and gpu.grid == {}
    d = gpu.dials["detector.m"]
    assert (d.lower, d.upper, d.reset) == (1, 6, False) and d.lock == "fixed-detector-m"
    assert "(= (theta-detector-m) 1)" in gpu.problem
    assert "(decrease (gpu) (theta-detector-m))" in gpu.domain
    assert "(:metric maximize (confidence))" in gpu.problem  # written, though SMTPlan+ ignores it
    _, nav = _smtplan("navigation", "precise.cat")
    assert "(>= (- (battery) (+ 5 (* 0.8 (theta-move-d)))) (reserve))" in nav.domain
    assert "(not (adjusting-move-d))" in nav.domain and "(<= (theta-move-d) 1000)" in nav.domain


def test_enhsp_flavour_is_still_pddl21():
    inst = instance(EXAMPLES / "gpu-allocation", {"file": "max-confidence.cat"})
    ex = export_pddl(inst, grid={"m": Fraction(1, 4)})
    assert ":time" not in ex.domain and ":process" not in ex.domain and not ex.dials
    with pytest.raises(ExportError, match=r"--grid detector\.m=STEP"):
        export_pddl(inst)


def test_a_grid_given_to_the_smtplan_flavour_is_honoured():
    _, ex = _smtplan("gpu-allocation", "max-confidence.cat", grid={"m": Fraction(1, 2)})
    assert not ex.dials and ":process" not in ex.domain and ":time" not in ex.domain
    assert all(a.params.get("m") != Fraction(17, 4) for a in ex.actions.values())  # 4.25 is off a 0.5 grid
    assert any(c == "continuous parameters" and "step 0.5" in t for c, t in ex.report.items)


# ---------------------------------------------------------------- timed plans read back


GPU_PLAN = """\
; SMTPlan+ prints one line per action: time, action, duration (values here derived by hand:
; m = 16 - 2.25 - 9.5 = 4.25 = lower bound 1 + 3.25 of dial time)
0.0:\t(a-slam) [0.0]
0.1:\t(a-vlm) [0.0]
0.2:\t(start-adjust-detector-m) [0.0]
3.45:\t(stop-adjust-detector-m) [0.0]
3.55:\t(a-detector) [0.0]
"""

NAV_PLAN = """\
0.0:\t(start-adjust-move-d) [0.0]
9.65:\t(stop-adjust-move-d) [0.0]
9.75:\t(a-move) [0.0]
"""


def test_gpu_optimum_from_a_timed_plan_is_accepted_by_the_validator():
    inst, ex = _smtplan("gpu-allocation", "max-confidence.cat")
    plan = parse_timed_plan(ex, GPU_PLAN)
    assert [a.morphism for _, a in plan.activations] == ["slam", "vlm", "detector"]
    m = plan.steps[2][0].params["m"]
    assert m == Fraction(17, 4) and isinstance(m, Fraction)
    rep = validate(inst, plan, horizon=3, sequential=True)
    assert rep.ok, [str(v) for v in rep.violations]
    assert rep.final_state["confidence"] == Fraction(21, 25)
    assert rep.final_state["gpu"] == 0


@pytest.mark.parametrize(
    "stop, kind",
    [
        ("5.2", "precondition"),  # m = 6 > the 4.25 GB left: (>= gpu m) fails
        ("5.7", "parameter-bounds"),
    ],
)  # m = 6.5 > 6
def test_gpu_wrong_dial_duration_is_rejected(stop, kind):
    inst, ex = _smtplan("gpu-allocation", "max-confidence.cat")
    plan = parse_timed_plan(ex, GPU_PLAN.replace("3.45:", f"{stop}:").replace("3.55:", "5.8:"))
    rep = validate(inst, plan, horizon=3, sequential=True)
    assert not rep.ok
    assert kind in rep.kinds(), rep.kinds()


def test_navigation_precise_is_accepted_and_coarse_rejected():
    inst, ex = _smtplan("navigation", "precise.cat")
    plan = parse_timed_plan(ex, NAV_PLAN)
    assert plan.steps[0][0].params["d"] == Fraction("9.65")
    rep = validate(inst, plan, horizon=1, sequential=True)
    assert rep.ok, [str(v) for v in rep.violations]
    # 22.73 - (5 + 0.8 × 9.65) = 10.01 Wh left, 0.01 above the reserve
    assert rep.final_state["battery"] == Fraction("10.01")
    coarse, ex2 = _smtplan("navigation", "coarse.cat")
    assert not validate(coarse, parse_timed_plan(ex2, NAV_PLAN), horizon=1, sequential=True).ok  # 22.7 < 22.72
    short = parse_timed_plan(ex, NAV_PLAN.replace("9.65:", "9.6:"))  # d = 9.6 misses the goal
    assert not validate(inst, short, horizon=1, sequential=True).ok


def test_timed_plan_text_round_trips_exact_values():
    _, ex = _smtplan("gpu-allocation", "max-confidence.cat")
    text = timed_plan_text(ex, [("a-slam", {}), ("a-vlm", {}), ("a-detector", {"m": Fraction(17, 4)})])
    assert "(start-adjust-detector-m)" in text and "(stop-adjust-detector-m)" in text
    assert parse_timed_plan(ex, text).steps[2][0].params["m"] == Fraction(17, 4)
    with pytest.raises(ValueError, match="only rises"):
        timed_plan_text(ex, [("a-detector", {"m": Fraction(1, 2)})])  # below the lower bound 1


def test_navigation_plan_built_from_the_hand_known_distance_validates():
    inst, ex = _smtplan("navigation", "precise.cat")
    text = timed_plan_text(ex, [("a-move", {"d": Fraction("9.65")})])  # wait 9.65 − 0 on the dial
    assert text.splitlines()[1].startswith("9.65:")
    plan = parse_timed_plan(ex, text)
    assert validate(inst, plan, horizon=1, sequential=True).ok
    coarse, ex2 = _smtplan("navigation", "coarse.cat")
    assert "precondition" in validate(coarse, parse_timed_plan(ex2, text), horizon=1, sequential=True).kinds()


REPEAT = """(define (domain charging) (:requirements :numeric :free-parameters)
  (:resources (charge real :bounds (0 10)) (charges int))
  (:morphism top-up :parameters ((amount real :bounds (0.5 5)))
    :effect (and (increase charge amount) (increase charges 1))))
(define (problem two-top-ups) (:domain charging)
  (:init (= charge 0) (= charges 0)) (:goal (and (= charge 5.5) (= charges 2))) (:horizon 2))
"""


def test_a_repeatable_per_activation_theta_is_reset_after_each_activation(tmp_path):
    (tmp_path / "c.cat").write_text(REPEAT)
    inst = instance(tmp_path, {"file": "c.cat"})
    ex = export_pddl(inst, flavor="smtplan")
    d = ex.dials["top-up.amount"]
    assert d.reset and d.lock is None
    assert "(assign (theta-top-up-amount) 0.5)" in ex.domain
    assert any("resets the dial" in t for _, t in ex.report.items)
    # amount 2 (dial 1.5 from 0.5), then 3.5 (dial 3 from 0.5 again): 2 + 3.5 = 5.5
    text = """0.0: (start-adjust-top-up-amount) [0.0]
1.5: (stop-adjust-top-up-amount) [0.0]
1.6: (a-top-up) [0.0]
1.7: (start-adjust-top-up-amount) [0.0]
4.7: (stop-adjust-top-up-amount) [0.0]
4.8: (a-top-up) [0.0]
"""
    plan = parse_timed_plan(ex, text)
    assert [a.params["amount"] for _, a in plan.activations] == [Fraction(2), Fraction(7, 2)]
    assert validate(inst, plan, horizon=2, sequential=True).ok
    # without the second dial run the second activation reads the lower bound 0.5: 2.5 ≠ 5.5
    lazy = parse_timed_plan(ex, "\n".join(text.splitlines()[:3]) + "\n1.8: (a-top-up) [0.0]\n")
    assert [a.params["amount"] for _, a in lazy.activations] == [Fraction(2), Fraction(1, 2)]
    assert not validate(inst, lazy, horizon=2, sequential=True).ok


@pytest.mark.parametrize(
    "text, message",
    [
        ("0.0: (start-adjust-move-d) [0.0]\n0.1: (start-adjust-move-d) [0.0]\n", "already turning"),
        ("0.0: (stop-adjust-move-d) [0.0]\n", "not turning"),
        ("0.0: (start-adjust-move-d) [0.0]\n0.1: (a-move) [0.0]\n", "still turning"),
        ("0.0: (a-move) [0.0]\n0.1: (start-adjust-move-d) [0.0]\n", "already set"),
        ("0.0: (a-fly) [0.0]\n", "unknown action"),
        ("0.3333333333?: (a-move) [0.0]\n", "truncated decimal"),
        ("0.0: (a-move x) [0.0]\n", "arguments"),
        ("no plan found\n", "no timed actions"),
    ],
)
def test_misread_plans_are_clear_errors(text, message):
    _, ex = _smtplan("navigation", "precise.cat")
    with pytest.raises(PlanReadError, match=message):
        parse_timed_plan(ex, text)


def test_timed_lines_keep_exact_decimals_and_ignore_other_output():
    acts = read_timed_actions("Plan found\n12.345678901234:\t(a-move) [0.0]\ndone\n")
    assert [(a.time, a.name, a.duration) for a in acts] == [(Fraction("12.345678901234"), "a-move", Fraction(0))]


def test_plan_from_actions_refuses_a_dial_export():
    _, ex = _smtplan("navigation", "precise.cat")
    with pytest.raises(ExportError, match="parse_timed_plan"):
        ex.plan_from_actions(["a-move"])


@needs_up
def test_unified_planning_has_no_pddl_plus_plan_validator(tmp_path):
    """No independent PDDL+ plan check is available here: UP 1.3's validators reject processes."""
    from unified_planning.engines.plan_validator import SequentialPlanValidator, TimeTriggeredPlanValidator
    from unified_planning.io import PDDLReader

    _, ex = _smtplan("navigation", "precise.cat")
    up = PDDLReader().parse_problem(*map(str, _write(ex, tmp_path)))
    assert not TimeTriggeredPlanValidator.supports(up.kind)
    assert not SequentialPlanValidator.supports(up.kind)


# ---------------------------------------------------------------- report, refusals, CLI


def test_report_lists_what_smtplan_cannot_express():
    _, holes = _smtplan("holes", "talk.cat")
    assert any(c == "holes" for c, _ in holes.report.items)
    _, soft = _smtplan("semantics", "soft.cat", "fastest")
    cats = {c for c, _ in soft.report.items}
    assert "soft constraints" in cats or "objective" in cats
    _, reserve = _smtplan("detection", "person.cat")
    assert any(c == "reserve values" for c, _ in reserve.report.items)
    _, gpu = _smtplan("gpu-allocation", "max-confidence.cat")
    texts = " ".join(t for _, t in gpu.report.items)
    assert "SMTPlan+ ignores optimisation metrics" in texts
    assert "sequential" in texts and "at least 0.1" in texts
    assert any(c.startswith("continuous parameters") and "no grid" in t for c, t in gpu.report.items)


def test_real_theta_without_lower_bound_is_refused(tmp_path):
    src = tmp_path / "p.cat"
    src.write_text("""(define (domain d) (:requirements :numeric :free-parameters)
  (:resources (x real))
  (:morphism go :parameters ((v real :bounds (* 5))) :effect (increase x v)))
(define (problem p) (:domain d) (:init (= x 0)) (:goal (>= x 1)))
""")
    r = CliRunner().invoke(main, ["export", "pddl", str(src), "-o", str(tmp_path / "out"), "--flavor", "smtplan"])
    assert r.exit_code == 2, r.output
    assert "no finite lower bound" in r.output and "Traceback" not in r.output


def test_cli_smtplan_needs_no_grid_and_checks_with_pddlplus_parsers(tmp_path):
    r = CliRunner().invoke(
        main,
        ["export", "pddl", str(EXAMPLES / "navigation/precise.cat"), "-o", str(tmp_path), "--flavor", "smtplan"]
        + ([] if UP_MISSING is None else ["--no-check"]),
    )
    assert r.exit_code == 0, r.output
    for f in ("domain.pddl", "problem.pddl", "report.md", "actions.json", "dials.json"):
        assert (tmp_path / f).is_file()
    assert "(:process adjust-move-d" in (tmp_path / "domain.pddl").read_text()
    assert '"lower": 0' in (tmp_path / "dials.json").read_text()
    if UP_MISSING is None:
        assert "unified-planning's PDDLReader (3 actions, 1 processes): ok" in r.output
        assert "PyPI 'pddl'" not in r.output


def test_cli_run_without_smtplan_binary_exits_2(tmp_path, monkeypatch):
    from catc.targets import pddlplus

    monkeypatch.setattr(pddlplus.shutil, "which", lambda _: None)
    r = CliRunner().invoke(
        main,
        [
            "export",
            "pddl",
            str(EXAMPLES / "navigation/precise.cat"),
            "-o",
            str(tmp_path),
            "--flavor",
            "smtplan",
            "--no-check",
            "--run",
        ],
    )
    assert r.exit_code == 2
    assert "SMTPlan+ is not on PATH" in r.output and (tmp_path / "domain.pddl").is_file()


@pytest.mark.skipif(os.name != "posix", reason="stand-in script needs a POSIX shell")
@pytest.mark.parametrize("battery, code, words", [("precise.cat", 0, "accepts"), ("coarse.cat", 1, "REJECTS")])
def test_cli_run_plumbing_with_a_stand_in_planner(tmp_path, monkeypatch, battery, code, words):
    """A stand-in 'SMTPlan' prints the hand-written navigation plan (this is not SMTPlan+)."""
    bindir = tmp_path / "bin"
    bindir.mkdir()
    fake = bindir / "SMTPlan"
    fake.write_text(
        "#!/bin/sh\nprintf '0.0:\\t(start-adjust-move-d) [0.0]\\n9.65:\\t(stop-adjust-move-d) [0.0]\\n"
        "9.75:\\t(a-move) [0.0]\\n'\n"
    )
    fake.chmod(fake.stat().st_mode | stat.S_IEXEC)
    monkeypatch.setenv("PATH", f"{bindir}{os.pathsep}{os.environ.get('PATH', '')}")
    r = CliRunner().invoke(
        main,
        [
            "export",
            "pddl",
            str(EXAMPLES / "navigation" / battery),
            "-o",
            str(tmp_path / "out"),
            "--flavor",
            "smtplan",
            "--no-check",
            "--run",
        ],
    )
    assert r.exit_code == code, r.output
    assert words in r.output
