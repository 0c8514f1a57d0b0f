"""``catc import pddl``: PDDL nobody here wrote → .cat that checks and formats, answers that agree
with ENHSP, plans a third-party validator (unified-planning's) accepts, refusals that are located
and reported (docs/interop.md).

Needs unified-planning (the ``up``/``baselines`` extras); the ENHSP tests need up-enhsp and Java.
The whole corpus runs in the slow group."""

from __future__ import annotations

import json
import re
import sys
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from conftest import run_catc

from catc.bench import corpus
from catc.frontend.formatter import format_text
from catc.interfaces import import_cli
from catc.queries.solve import SolveStatus, solve

WHEEL = corpus.wheel_dir()
assert WHEEL is not None


def _enhsp_missing() -> str | None:
    from catc.targets.enhsp import available

    return available()


needs_enhsp = pytest.mark.skipif(_enhsp_missing() is not None, reason=str(_enhsp_missing()))


def _import(tmp_path: Path, folder: str, problem: str = "problem.pddl", *extra: str):
    out = tmp_path / folder
    r = run_catc(
        "import", "pddl", str(WHEEL / folder / "domain.pddl"), str(WHEEL / folder / problem), "-o", str(out), *extra
    )
    return r, out


def _line_col(path: Path, needle: str) -> str:
    """Where ``needle`` first occurs, counted here by hand (not by catc)."""
    for i, line in enumerate(path.read_text().splitlines(), 1):
        if needle in line:
            return f"{path}:{i}:{line.index(needle) + 1}"
    raise AssertionError(needle)


def test_counters_imports_checks_formats_and_reports(tmp_path):
    r, out = _import(tmp_path, "counters")
    assert r.exit_code == 0, r.output
    dom, prob = out / "domain.cat", out / "problem.cat"
    for f in (dom, prob):  # what catc fmt --check leaves unchanged, and catc check accepts
        assert format_text(f.read_text()) == f.read_text()
    chk = run_catc("check", str(prob))
    assert chk.exit_code == 0 and "0 errors" in chk.output, chk.output
    # 4 counters c0..c3 with increment and decrement each: 8 ground actions, 4 numeric resources
    actions = json.loads((out / "actions.json").read_text())
    assert sorted(actions.values()) == sorted(f"({a} c{i})" for a in ("increment", "decrement") for i in range(4))
    text = dom.read_text()
    assert text.count("(:morphism") == 8 and text.count(" real :doc") == 4
    report = (out / "import-report.md").read_text()
    for heading in ("## What mapped to what", "## What was grounded", "## Sequential semantics"):
        assert heading in report
    assert "--sequential" in report and "Refused" not in report


def test_counters_shortest_plan_is_the_hand_count(tmp_path):
    """c0 < c1 < c2 < c3 from 0 needs 0 + 1 + 2 + 3 = 6 increments, and no fewer."""
    res = import_cli.import_pddl(WHEEL / "counters" / "domain.pddl", WHEEL / "counters" / "problem.pddl", tmp_path)
    five = solve(res.instance, horizon=5, sequential=True)
    six = solve(res.instance, horizon=6, sequential=True)
    assert five.status is SolveStatus.UNSAT and six.status is SolveStatus.SAT
    steps = [res.actions[a.morphism] for step in six.plan.steps for a in step]
    assert sorted(steps) == ["(increment c1)", "(increment c2)", "(increment c2)"] + ["(increment c3)"] * 3
    from unified_planning.io import PDDLReader

    up_problem = PDDLReader().parse_problem(
        str(WHEEL / "counters" / "domain.pddl"), str(WHEEL / "counters" / "problem.pddl")
    )
    assert corpus.up_validates(up_problem, steps)  # a validator catc did not write
    assert not corpus.up_validates(up_problem, steps[:-1])  # and it can say no


def test_horizon_is_written_when_asked(tmp_path):
    r, out = _import(tmp_path, "counters", "problem.pddl", "--horizon", "6")
    assert r.exit_code == 0, r.output
    assert "(:horizon 6)" in (out / "problem.cat").read_text()


def test_a_temporal_domain_is_refused_at_its_first_durative_action(tmp_path):
    r, out = _import(tmp_path, "matchcellar")
    assert r.exit_code == 2
    where = _line_col(WHEEL / "matchcellar" / "domain.pddl", "(:durative-action")
    assert f"{where}: error[E1201]: catc cannot express this problem" in r.stderr
    report = (out / "import-report.md").read_text()
    assert "CONTINUOUS_TIME" in report and "## Refused" in report and not (out / "domain.cat").exists()


def test_an_undefined_initial_value_no_ground_action_reads_is_not_refused(tmp_path):
    """tpp_metric's :init leaves drive-cost(m, m) undefined for every market m, but drive needs
    (connected ?from ?to), false of every (m, m): no ground action reads those values."""
    r, out = _import(tmp_path, "tpp_metric")
    assert r.exit_code == 0, r.stderr
    assert "drive-cost(market1, market1)" not in (out / "actions.json").read_text()


def test_an_undefined_initial_value_that_is_read_is_refused_at_the_init(tmp_path):
    """tests/fixtures/pddl/undefined-unread/problem-read.pddl: drive(t2, p, q) reads fuel(t2),
    which has no value: catc's initial state is complete."""
    folder = Path(__file__).parent / "fixtures" / "pddl" / "undefined-unread"
    out = tmp_path / "out"
    r = run_catc("import", "pddl", str(folder / "domain.pddl"), str(folder / "problem-read.pddl"), "-o", str(out))
    assert r.exit_code == 2
    assert f"{_line_col(folder / 'problem-read.pddl', '(:init')}: error[E1201]" in r.stderr
    report = (out / "import-report.md").read_text()
    assert "UNDEFINED_INITIAL_NUMERIC" in report and "catc's initial state is complete" in report


def test_a_process_is_refused(tmp_path):
    out = tmp_path / "car"
    r = run_catc("import", "pddl", str(WHEEL / "car_nl" / "d.pddl"), str(WHEEL / "car_nl" / "p.pddl"), "-o", str(out))
    assert r.exit_code == 2
    assert _line_col(WHEEL / "car_nl" / "d.pddl", "(:process") in r.stderr
    assert "PROCESSES" in (out / "import-report.md").read_text()


def test_a_syntax_error_is_located_where_the_reader_says(tmp_path):
    bad = tmp_path / "bad.pddl"
    bad.write_text(
        "(define (domain x)\n (:requirements :strips)\n (:predicates (p)\n (:action a :parameters ()\n :effect (p)))\n"
    )
    r = run_catc("import", "pddl", str(bad), str(WHEEL / "counters" / "problem.pddl"), "-o", str(tmp_path / "o"))
    assert r.exit_code == 2
    # the (:predicates list is never closed: the reader stops at the "(" of line 4, column 2
    assert f"{bad}:4:2: error[E1210]: unified-planning's PDDL reader rejects it" in r.stderr
    assert "Traceback" not in r.output


def test_a_missing_file_is_an_input_error(tmp_path):
    r = run_catc("import", "pddl", str(tmp_path / "no.pddl"), str(tmp_path / "no2.pddl"), "-o", str(tmp_path / "o"))
    assert r.exit_code == 2 and "error[E0001]" in r.stderr


def test_without_unified_planning_the_error_names_the_extra(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "unified_planning", None)
    monkeypatch.setitem(sys.modules, "unified_planning.shortcuts", None)
    monkeypatch.setitem(sys.modules, "unified_planning.io", None)
    with pytest.raises(import_cli.ImportFailed) as e:
        import_cli.import_pddl(WHEEL / "counters" / "domain.pddl", WHEEL / "counters" / "problem.pddl", tmp_path)
    assert e.value.code == "E1202" and "catc-lang[up]" in e.value.message


def test_what_cat_text_cannot_spell_is_E1212(tmp_path, monkeypatch):
    """A safety net: the converter makes .cat names, but a string with a line break cannot be
    written; it stops the import with E1212 instead of writing a file that does not read back."""
    from catc import ir
    from catc.frontend import up_import

    real = up_import.up_to_instance

    def with_bad_doc(problem):
        inst, rep = real(problem)
        name, r = next(iter(inst.domain.resources.items()))
        res = dict(inst.domain.resources)
        res[name] = ir.Resource(r.name, r.sort, doc="two\nlines")
        d = inst.domain
        dom = ir.Domain(d.name, d.requirements, d.sorts, d.constants, ir.frozen(res), d.morphisms)
        return ir.Instance(dom, inst.problem), rep

    monkeypatch.setattr(up_import, "up_to_instance", with_bad_doc)
    with pytest.raises(import_cli.ImportFailed) as e:
        import_cli.import_pddl(WHEEL / "counters" / "domain.pddl", WHEEL / "counters" / "problem.pddl", tmp_path)
    assert e.value.code == "E1212" and "line break" in e.value.message


def test_written_files_that_do_not_check_are_E1211(tmp_path, monkeypatch):
    real = import_cli.write_cat

    def broken(inst, out, header=None):
        dom, prob = real(inst, out, header=header)
        dom.write_text(dom.read_text().replace("(:resources", "(:resources (value_c0 real)", 1))
        return dom, prob

    monkeypatch.setattr(import_cli, "write_cat", broken)
    with pytest.raises(import_cli.ImportFailed) as e:
        import_cli.import_pddl(WHEEL / "counters" / "domain.pddl", WHEEL / "counters" / "problem.pddl", tmp_path)
    assert e.value.code == "E1211" and re.match(r".*domain\.cat:\d+:\d+$", e.value.location)


def test_generated_families_import(tmp_path):
    """The bench's families: counters-n has n(n-1)/2 increments as its shortest plan."""
    cases = corpus.family_cases(tmp_path, counters=range(3, 4), sailing=range(1, 2))
    c3 = next(c for c in cases if c.name == "counters-3")
    res = import_cli.import_pddl(c3.domain, c3.problem, tmp_path / "c3")
    assert solve(res.instance, horizon=2, sequential=True).status is SolveStatus.UNSAT
    assert solve(res.instance, horizon=3, sequential=True).status is SolveStatus.SAT
    s1 = next(c for c in cases if c.family == "sailing")
    assert import_cli.import_pddl(s1.domain, s1.problem, tmp_path / "s1").instance.domain.morphisms


@needs_enhsp
@pytest.mark.parametrize("folder", ["counters", "safe_road", "depot"])
def test_small_wheel_problems_agree_with_enhsp(folder, tmp_path):
    """ENHSP on the original PDDL, catc on the import: both SAT, catc's shortest plan no longer
    than ENHSP's, both plans valid for UP's validator, and ENHSP on catc's export of the import
    (the round trip) SAT too."""
    case = next(c for c in corpus.wheel_cases() if c.name == folder)
    row = corpus.run_case(case, tmp_path, timeout=120)
    assert row.imported and row.enhsp == "sat" and row.catc == "sat", row
    assert row.enhsp_valid and row.catc_valid
    assert row.catc_len <= row.enhsp_len
    assert row.roundtrip == "sat" and row.roundtrip_valid  # UP's validator on ENHSP's plan for catc's export
    assert row.agrees is True


def test_the_corpus_table_marks_disagreement():
    case = corpus.Case("x", "x", Path("d"), Path("p"))
    row = corpus.Row(case, imported=True, enhsp="sat", catc="unsat", enhsp_len=3)
    assert row.agrees is False and "| NO |" in corpus.markdown([row], "cmd")
    ok = corpus.Row(
        case, imported=True, enhsp="sat", catc="sat", enhsp_len=3, catc_len=3, enhsp_valid=True, catc_valid=True
    )
    assert ok.agrees is True
    assert corpus.Row(case, imported=True, enhsp="sat", catc="sat", enhsp_len=3, catc_len=4).agrees is False
    cost = corpus.Row(case, imported=True, metric="cost", enhsp="sat", catc="sat", enhsp_cost=5, catc_cost=6)
    assert cost.agrees is False
    par = corpus.Row(case, imported=True, enhsp="sat", catc="unknown", par="sat", par_valid=True, enhsp_valid=True)
    assert par.agrees is True  # the parallel run settles the answer when the sequential one gives up
    par.par_valid = False
    assert par.agrees is False
    assert corpus.Row(case, imported=True, enhsp="sat", catc="sat", par="unsat").agrees is False
    assert corpus.Row(case, imported=True, enhsp="timeout", catc="sat").agrees is None
    refused = corpus.Row(case, refused=[("PROCESSES", "why")])
    assert refused.agrees is None and "refused: PROCESSES" in corpus.markdown([refused], "cmd")


@pytest.mark.slow
@needs_enhsp
@pytest.mark.parametrize("case", [c for c in corpus.wheel_cases() if not c.temporal], ids=lambda c: c.name)
def test_every_non_temporal_wheel_problem_agrees_or_is_refused_with_reasons(case, tmp_path):
    row = corpus.run_case(case, tmp_path, timeout=120)
    if not row.imported:
        report = (tmp_path / case.name.replace("/", "-") / "import-report.md").read_text()
        assert row.refused and all(what in report for what, _ in row.refused), row
        return
    assert row.agrees is not False, row
    assert row.enhsp_valid is not False and row.catc_valid is not False, row


@needs_enhsp
def test_bench_corpus_prints_the_corpus_and_growth_tables(tmp_path):
    r = run_catc(
        "bench", "--corpus", "--only", "counters-2", "--only", "matchcellar", "--timeout", "60", "--no-compile"
    )
    assert r.exit_code == 0, r.output
    assert "| matchcellar | refused: CONTINUOUS_TIME" in r.stdout
    row = next(line for line in r.stdout.splitlines() if line.startswith("| counters-2 | ok"))
    # two counters from 0, c0 < c1: one increment; both tools find it, the validator accepts both
    assert "| sat | -/1 |" in row and row.count("| valid |") == 2 and row.endswith("| yes |")
    assert "## Growth with instance size" in r.stdout and "| counters | 2 | 4 | 1/1 |" in r.stdout


GRIPPER = Path(__file__).parent / "fixtures" / "pddl" / "gripper"


def test_gripper_with_typing_equality_quantifiers_and_conditional_effects(tmp_path):
    """Typed gripper with =, not, exists and forall/when (tests/fixtures/pddl/gripper). By hand:
    2 moves (a→b, b→a; = rules out a→a) + 8 picks + 8 drops (2 balls × 2 rooms × 2 grippers)
    = 18 ground actions; the shortest plan picks both balls (one per gripper), moves, drops
    both: 5 actions, and 4 are not enough."""
    res = import_cli.import_pddl(GRIPPER / "domain.pddl", GRIPPER / "problem.pddl", tmp_path)
    assert len(res.instance.domain.morphisms) == 18
    assert solve(res.instance, horizon=4, sequential=True).status is SolveStatus.UNSAT
    five = solve(res.instance, horizon=5, sequential=True)
    assert five.status is SolveStatus.SAT
    steps = [res.actions[a.morphism] for step in five.plan.steps for a in step]
    assert steps[2] == "(move rooma roomb)" and sorted(s.split()[0] for s in steps) == [
        "(drop", "(drop", "(move", "(pick", "(pick"
    ]  # fmt: skip
    from unified_planning.io import PDDLReader

    up_problem = PDDLReader().parse_problem(str(GRIPPER / "domain.pddl"), str(GRIPPER / "problem.pddl"))
    assert corpus.up_validates(up_problem, steps)


@needs_enhsp
def test_gripper_agrees_with_enhsp_and_round_trips_its_conditional_effects(tmp_path):
    row = corpus.run_case(
        corpus.Case("gripper", "gripper", GRIPPER / "domain.pddl", GRIPPER / "problem.pddl"), tmp_path
    )
    assert row.agrees is True and row.catc_len == 5 and row.roundtrip == "sat", row
