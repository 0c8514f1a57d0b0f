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


# ---------------------------------------------------------------- help texts and answers as a user reads them

COUNTER = """(define (domain counter)
  (:requirements :numeric)
  (:resources (n int :bounds (0 *)))
  (:morphism bump :kind software :uses 1 :effect (increase n 1)))
"""
ALREADY = "(define (problem already) (:domain counter) (:init (= n 1)) (:goal (>= n 1)))\n"
ONCE = "(define (problem once) (:domain counter) (:init (= n 0)) (:goal (>= n 1)))\n"


def _walk(cmd, ctx, path):
    import click

    yield path, cmd
    if isinstance(cmd, click.Group):
        for name in cmd.list_commands(ctx):
            sub = cmd.get_command(ctx, name)
            assert sub is not None, f"{' '.join(path)} {name} does not load"
            yield from _walk(sub, click.Context(sub, parent=ctx, info_name=name), [*path, name])


def _every_command():
    import click

    from catc.interfaces.cli import main
    from catrt.cli import main as catrt

    for root, name in ((main, "catc"), (catrt, "catrt")):
        yield from _walk(root, click.Context(root, info_name=name), [name])


def test_help_cites_nothing_that_does_not_ship_and_every_option_has_help():
    import re

    import click

    seen = 0
    for path, cmd in _every_command():
        where = " ".join(path)
        for text in [cmd.help or "", *(getattr(p, "help", None) or "" for p in cmd.params)]:
            assert not re.search(r"DESIGN|paper|§", text), f"{where}: {text!r}"
        for p in cmd.params:
            if isinstance(p, click.Option) and not p.hidden:
                assert p.help, f"{where} {p.opts} has no help"
                seen += 1
    assert seen > 100  # the walk reached every command (queries, export pddl, catrt ...)


def test_counts_agree_with_their_nouns(tmp_path):
    (tmp_path / "counter.cat").write_text(COUNTER, encoding="utf-8")
    (tmp_path / "once.cat").write_text(ONCE, encoding="utf-8")
    res = run_catc("solve", tmp_path / "counter.cat", tmp_path / "once.cat")
    assert res.exit_code == 0, res.output
    assert "SAT  composition of 1 step for problem once" in res.stdout
    assert "validated by independent replay: 1 step, 1 activation, goal holds" in res.stdout
    plan = tmp_path / "plan.json"
    plan.write_text('{"schema": "catc.plan/1", "steps": [[{"morphism": "bump"}]]}', encoding="utf-8")
    res = run_catc("validate", tmp_path / "counter.cat", tmp_path / "once.cat", plan)
    assert res.stdout.startswith("valid: 1 step reaches the goal of 'once'"), res.output


def test_an_empty_composition_is_a_sentence_not_an_empty_table(tmp_path):
    (tmp_path / "counter.cat").write_text(COUNTER, encoding="utf-8")
    (tmp_path / "already.cat").write_text(ALREADY, encoding="utf-8")
    for query in ("solve", "optimize"):
        extra = ("--minimize", "n") if query == "optimize" else ()
        res = run_catc(query, tmp_path / "counter.cat", tmp_path / "already.cat", *extra)
        assert res.exit_code == 0, res.output
        assert "the goal holds in the initial state: nothing to compose" in res.stdout
        assert "morphism" not in res.stdout  # no table header over no rows
        assert "0 steps, goal holds in the initial state" in res.stdout


def test_the_terminal_plot_of_a_one_point_front_is_a_sentence():
    from fractions import Fraction as F

    from catc.present.plot import ascii_plot

    assert ascii_plot([(F(1, 2), F(3))], ["x", "y"]) == "a front of one point: nothing to plot"


def test_the_terminal_plot_legend_names_only_the_marks_drawn():
    from fractions import Fraction as F

    from catc.present.plot import ascii_plot

    two = ascii_plot([(F(0), F(0)), (F(1), F(1))], ["x", "y"])
    rows = [line for line in two.splitlines() if "|" in line]
    assert len(rows) == 14 and rows[0].endswith("2") and rows[-1].split("|")[1].startswith("1")
    assert "*" not in two and "digits: the points' numbers in the table" in two
    flat = ascii_plot([(F(0), F(5)), (F(1), F(5))], ["x", "y"])  # equal second values: one row
    assert [line.split("|")[1].strip() for line in flat.splitlines() if "|" in line] == ["1" + " " * 54 + "2"]
    # points 1 and 3 land in one cell of 56 columns (0 and 1/1000 of the x range apart)
    crowded = ascii_plot([(F(0), F(0)), (F(1000), F(1000)), (F(1), F(1))], ["x", "y"])
    assert "*: several points in one place" in crowded
    assert [line for line in crowded.splitlines() if "|" in line][-1].split("|")[1].rstrip() == "*"
    twelve = ascii_plot([(F(i), F(-i)) for i in range(12)], ["x", "y"])
    assert "a-c: points 10-12" in twelve and "*" not in twelve  # points 10, 11, 12: a, b, c


def test_export_names_every_file_it_wrote(tmp_path):
    det = EX / "detection"
    res = run_catc(
        "export", "pddl", det / "domain.cat", det / "person.cat", "--grid", "ram-req=1/2", "-o", tmp_path, "--no-check"
    )
    assert res.exit_code == 0, res.output
    wrote = next(line for line in res.output.splitlines() if line.startswith("wrote "))
    for name in sorted(p.name for p in tmp_path.iterdir()):
        assert str(tmp_path / name) in wrote, name


def test_relax_and_diagnose_end_with_a_timing_line():
    import re

    d = EX / "lifelong"
    for args in (("relax",), ("relax", "--discrete"), ("diagnose",)):
        res = run_catc(*args, d / "domain.cat", d / "budget-cut.cat")
        last = res.stdout.rstrip("\n").splitlines()[-1]
        assert re.fullmatch(r"time: encode \d+ ms, (search|cores) \d+ ms.*", last), (args, last)


PUB = """(define (domain pub)
  (:requirements :numeric :sets)
  (:sorts topic - symbol)
  (:constants scan - topic)
  (:resources
    (n int)
    (topics (set topic)))
  (:morphism publish
    :kind software
    :precondition (>= n 5)
    :effect (add topics scan)))
"""
NEEDS = "(define (problem needs-scan) (:domain pub) (:init (= n 0)) (:goal (member scan topics)) (:horizon 2))\n"


def test_a_default_initial_value_in_a_core_says_where_its_resource_is_declared(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "pub.cat").write_text(PUB, encoding="utf-8")
    (tmp_path / "needs.cat").write_text(NEEDS, encoding="utf-8")
    res = run_catc("diagnose", "pub.cat", "needs.cat")
    assert res.exit_code == 0, res.output  # a core found
    # the core: n starts at 0, publish needs n >= 5 and nothing raises n, the goal needs scan in
    # topics, and topics starts empty — by default, for nothing in needs.cat gives it a value
    assert "initial value  (= topics {})" in res.stdout
    assert "default value of `topics` (declared at pub.cat:7:6)" in res.stdout  # line 7, `topics` at column 6
    assert "no source location" not in res.stdout


def test_check_and_solve_write_a_path_the_same_way(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "counter.cat").write_text(COUNTER, encoding="utf-8")
    (tmp_path / "bad.cat").write_text("(define (problem bad) (:domain counter) (:init (= n 0)) (:goal (>= m 1)))\n")
    for args in (("check", "./bad.cat"), ("solve", "./bad.cat"), ("solve", "./counter.cat", "./bad.cat")):
        res = run_catc(*args)
        first = (res.stdout if args[0] == "check" else res.stderr).splitlines()[0]
        assert first.startswith("bad.cat:1:68: error[E0202]"), (args, first)


# ---------------------------------------------------------------- a dropped ')' located by the layout

LAYOUT = """(define (domain d)
  (:requirements :numeric)
  (:resources
    (n int :bounds (0 10))
    (m int))
  (:morphism up
    :kind software
    :precondition (and (>= n 1)
                       (<= m 3))
    :effect (increase n 1)))
"""


def _unclosed(text: str, tmp_path):
    from catgrammar.diagnostics import Diagnostics
    from catgrammar.parser import scan_parentheses
    from catgrammar.span import Source

    diags = Diagnostics()
    assert not scan_parentheses(Source(str(tmp_path / "d.cat"), text), diags)
    [diag] = list(diags)
    assert diag.code == "E0103"
    return diag


def _drop(text: str, line: int, old: str, new: str) -> str:
    lines = text.split("\n")
    assert lines[line - 1].endswith(old)
    lines[line - 1] = lines[line - 1][: -len(old)] + new
    return "\n".join(lines)


def test_the_layout_file_is_well_formed(tmp_path):
    from catgrammar.diagnostics import Diagnostics
    from catgrammar.parser import likely_missing_close, scan_parentheses
    from catgrammar.span import Source

    assert scan_parentheses(Source("d.cat", LAYOUT), Diagnostics())
    assert likely_missing_close(LAYOUT) is None


def test_a_section_left_open_is_reported_where_its_close_was_dropped(tmp_path):
    # (:resources loses its ')' at the end of line 5: `    (m int)` is 11 characters, so the ')' goes at 5:12;
    # line 6 starts at column 3, where the '(' of (:resources (3:3) is, and that form is still open
    diag = _unclosed(_drop(LAYOUT, 5, "(m int))", "(m int)"), tmp_path)
    assert (diag.span.line, diag.span.column) == (5, 12)
    assert "probably missing here — line 6 is indented no deeper than the '(' at 3:3" in diag.message
    assert [(n.span.line, n.span.column) for n in diag.notes] == [(3, 3), (1, 1)]  # the form, then (define


def test_an_item_left_open_is_reported_on_its_line(tmp_path):
    # (n int :bounds (0 10) — line 4 is 25 characters; line 5's '(' is in the column of (n (4:5)
    diag = _unclosed(_drop(LAYOUT, 4, "(0 10))", "(0 10)"), tmp_path)
    assert (diag.span.line, diag.span.column) == (4, 26)
    assert [(n.span.line, n.span.column) for n in diag.notes] == [(4, 5), (1, 1)]


def test_an_operand_left_open_in_an_aligned_and_is_reported_on_its_line(tmp_path):
    # (>= n 1 — the (and's operands are aligned at column 24, where line 9 starts
    diag = _unclosed(_drop(LAYOUT, 8, "(>= n 1)", "(>= n 1"), tmp_path)
    assert (diag.span.line, diag.span.column) == (8, 31)
    assert [(n.span.line, n.span.column) for n in diag.notes] == [(8, 24), (1, 1)]


def test_a_domain_left_open_before_a_problem_is_reported_at_its_end(tmp_path):
    text = _drop(LAYOUT, 10, "(increase n 1)))", "(increase n 1))") + "(define (problem p) (:domain d))\n"
    diag = _unclosed(text, tmp_path)
    # line 10 is `    :effect (increase n 1))`: 27 characters; line 11's (define is in (define's column
    assert (diag.span.line, diag.span.column) == (10, 28)
    assert [(n.span.line, n.span.column) for n in diag.notes] == [(1, 1)]  # the form is (define itself


def test_without_evidence_in_the_layout_the_outermost_opener_is_reported(tmp_path):
    diag = _unclosed(_drop(LAYOUT, 10, "(increase n 1)))", "(increase n 1))"), tmp_path)
    assert (diag.span.line, diag.span.column) == (1, 1)
    assert diag.message == "'(' is never closed: the file ends with 1 parenthesis open"


def test_every_dropped_paren_of_the_examples_is_found_on_its_line():
    """Drop each ')' of every example and standard-library file in turn: the error is on the
    line the ')' was dropped from — or, when it was on the file's last line of code (no
    line after it to disagree with the layout), at the outermost '(' left open."""
    import re

    from catgrammar.diagnostics import Diagnostics
    from catgrammar.parser import scan_parentheses
    from catgrammar.span import Source

    files = sorted([*(ROOT / "examples").rglob("*.cat"), *(ROOT / "stdlib_domains").glob("*.cat")])
    tried = on_line = 0
    for path in files:
        text = path.read_text(encoding="utf-8")
        code_lines = [n for n, line in enumerate(text.split("\n"), 1) if line.split(";")[0].strip()]
        closes = [m.start() for m in re.finditer(r'\)|;[^\n]*|"[^"\n]*"', text) if m.group() == ")"]
        for at in closes:
            dropped = text[:at] + text[at + 1 :]
            line = text.count("\n", 0, at) + 1
            diags = Diagnostics()
            assert not scan_parentheses(Source(str(path), dropped), diags)
            [diag] = list(diags)
            tried += 1
            if line == code_lines[-1] and "probably" not in diag.message:
                assert diag.span.line == code_lines[0] or diag.span.column == 1, (path, line)
                continue
            assert diag.span.line == line, (path.name, line, diag.span.line, diag.message)
            on_line += 1
    assert tried > 1000 and on_line > 0.9 * tried


# ---------------------------------------------------------------- catc init, explain, completion, reference


def test_init_writes_a_starter_model_that_checks_and_solves(tmp_path):
    folder = tmp_path / "robot"
    res = run_catc("init", folder)
    assert res.exit_code == 0, res.output
    assert sorted(p.name for p in folder.iterdir()) == ["domain.cat", "problem.cat"]
    assert ";" in (folder / "domain.cat").read_text() and ";" in (folder / "problem.cat").read_text()  # commented
    assert run_catc("check", "--strict", folder / "domain.cat", folder / "problem.cat").exit_code == 0
    solved = run_catc("solve", folder / "domain.cat", folder / "problem.cat")
    # the detector needs a topic, only the driver publishes one, and the driver needs the
    # camera mounted: 3 steps, one component each
    assert solved.exit_code == 0 and "SAT  composition of 3 steps" in solved.stdout
    best = run_catc("optimize", folder / "domain.cat", folder / "problem.cat", "--maximize", "ram")
    assert "3.5" in best.stdout  # 8 GB − the driver's least 0.5 − the detector's 4


def test_init_refuses_to_overwrite(tmp_path):
    (tmp_path / "problem.cat").write_text("; mine\n", encoding="utf-8")
    res = run_catc("init", tmp_path)
    assert res.exit_code == 2
    assert "error[E0708]" in res.stderr and "problem.cat already exists; nothing written" in res.stderr
    assert not (tmp_path / "domain.cat").exists()
    assert (tmp_path / "problem.cat").read_text() == "; mine\n"


def test_explain_prints_a_codes_explanation_from_docs_errors_md():
    res = run_catc("explain", "e0202")
    assert res.exit_code == 0
    lines = res.stdout.splitlines()
    assert lines[0] == "E0202 (unknown-name, error) — Names"
    assert lines[2] == "A name is used but never declared."  # its row in docs/errors.md
    assert "did you mean 'ram'?" in res.stdout  # its explanation there
    assert run_catc("explain", "unknown-name").stdout == res.stdout
    limits = run_catc("explain", "E1109").stdout  # its section's prose too, before its own explanation
    assert "Each message says how to raise the limit" in limits
    listing = run_catc("explain").stdout.splitlines()
    from catgrammar.codes import CODES

    assert len(listing) == len(CODES)


def test_explain_refuses_what_is_not_a_code():
    res = run_catc("explain", "E9999")
    assert res.exit_code == 2 and "error[E0707]: 'E9999' is not a diagnostic code" in res.stderr
    res = run_catc("explain", "unknwn-name")
    assert res.exit_code == 2 and "did you mean unknown-name?" in res.stderr


def test_the_explanations_shipped_agree_with_docs_errors_md():
    from catc.interfaces import docgen, errors_doc

    text = (ROOT / "docs" / "errors.md").read_text(encoding="utf-8")
    assert docgen.error_sections(text) == errors_doc.SECTIONS, "run python -m catc.interfaces.docgen"
    assert docgen.explanations(text) == errors_doc.EXPLANATIONS, "run python -m catc.interfaces.docgen"
    from catgrammar.codes import CODES

    assert {code[:3] for code in CODES} <= set(errors_doc.SECTIONS)  # every code has its section
    assert set(errors_doc.EXPLANATIONS) <= set(CODES)


def test_the_cli_reference_is_generated_from_the_cli_and_up_to_date():
    from catc.interfaces import docgen

    reference = (ROOT / "docs" / "cli-reference.md").read_text(encoding="utf-8")
    assert reference == docgen.cli_reference(), "docs/cli-reference.md is stale: run python -m catc.interfaces.docgen"
    for name in ("solve", "explain", "init", "export pddl", "check"):
        assert f"## `catc {name}`" in reference
    assert "--progress" in reference and "Usage: catc solve [OPTIONS] PATHS..." in reference


def test_shell_completion_script_and_completions():
    import os
    import subprocess
    import sys

    env = {**os.environ, "_CATC_COMPLETE": "bash_source"}
    script = subprocess.run([sys.executable, "-m", "catc"], env=env, capture_output=True, text=True, cwd=ROOT)
    assert script.returncode == 0
    assert "_catc_completion()" in script.stdout and "complete -o nosort -F _catc_completion catc" in script.stdout
    env = {**os.environ, "_CATC_COMPLETE": "bash_complete", "COMP_WORDS": "catc sol", "COMP_CWORD": "1"}
    words = subprocess.run([sys.executable, "-m", "catc"], env=env, capture_output=True, text=True, cwd=ROOT)
    assert words.stdout.split() == ["plain,solve"]
    env.update(COMP_WORDS="catc solve --seq", COMP_CWORD="2")
    words = subprocess.run([sys.executable, "-m", "catc"], env=env, capture_output=True, text=True, cwd=ROOT)
    assert words.stdout.split() == ["plain,--sequential"]
    zsh = subprocess.run(
        [sys.executable, "-m", "catc"],
        env={**os.environ, "_CATC_COMPLETE": "zsh_source"},
        capture_output=True,
        text=True,
    )
    assert "#compdef catc" in zsh.stdout


def test_synthesize_and_ground_count_with_their_nouns(tmp_path):
    holes = EX / "holes"
    res = run_catc("synthesize", holes / "domain.cat", holes / "talk.cat")
    # voice must provide speech-out (1 effect; interact needs it) and, the weakest specification, assumes
    # as much as its :max-preconditions 3 allows (holes/domain.cat)
    assert "1 effect it must provide, 3 preconditions it may assume" in res.stdout, res.output
    det = EX / "detection"
    res = run_catc("ground", det / "domain.cat", det / "person.cat", "-o", tmp_path)
    # camera mount (hardware), driver and detector (services), no behaviour tree nodes
    assert "1 hardware step, 2 services, 0 behaviour nodes" in res.stdout, res.output


# ---------------------------------------------------------------- issue 29: filters that accept typos


def test_relax_filters_that_match_nothing_are_said_with_a_did_you_mean():
    """`--only budgett` left nothing eligible and answered UNSAT; `--weights budgett=2` was
    ignored.  Both are input errors now, with the closest name."""
    problem = str(ROOT / "examples" / "lifelong" / "budget-cut.cat")
    for args in (["--only", "budgett"], ["--weights", "budgett=2"]):
        res = run_catc("relax", problem, *args)
        assert res.exit_code == 2 and "matches no eligible requirement" in res.stderr, res.stderr
        assert "did you mean 'budget'?" in res.stderr
    ok = run_catc("relax", problem, "--only", "init/", "--weights", "budget=2")
    assert ok.exit_code == 0 and "weighted total 39720" in ok.stdout  # 2 × 19860: the weight applied


def test_an_unknown_deployed_component_has_a_did_you_mean():
    res = run_catc("recompose", str(ROOT / "examples" / "search-and-rescue" / "cheaper-camera.cat"), "--deployed",
                   "rgb-drivr")  # fmt: skip
    assert res.exit_code == 2 and "rgb-drivr (did you mean 'rgb-driver'?)" in res.stderr


def test_catrt_journal_refuses_an_unknown_kind(tmp_path):
    import subprocess
    import sys

    state = tmp_path / "st"
    catrt = [sys.executable, "-c", "from catrt.cli import entry; entry()"]
    assert subprocess.run([*catrt, "init", str(state), str(ROOT / "examples" / "detection" / "person.cat")],
                          capture_output=True).returncode == 0  # fmt: skip
    res = subprocess.run([*catrt, "journal", str(state), "--kind", "decisoin"], capture_output=True, text=True)
    assert res.returncode == 2 and "did you mean 'decision'?" in res.stderr and res.stdout == ""
    ok = subprocess.run([*catrt, "journal", str(state), "--kind", "init"], capture_output=True, text=True)
    assert ok.returncode == 0 and " init " in ok.stdout


def test_diagnose_names_the_horizon_in_force_not_the_problems():
    """`-k 1` on a problem with (:horizon 3): the core's horizon is 1, not the file's line."""
    res = run_catc("diagnose", str(ROOT / "examples" / "detection" / "person.cat"), "-k", "1", "--json")
    doc = json.loads(res.stdout)
    (horizon,) = [c for core in doc["cores"] for c in core if c["label"] == "horizon"]
    assert horizon["location"] is None and horizon["text"].startswith("the horizon 1 ")
    text = run_catc("diagnose", str(ROOT / "examples" / "detection" / "person.cat"), "-k", "1").stdout
    assert "(:horizon 3)" not in text and "the horizon 1" in text


def test_export_without_its_parser_writes_nothing(tmp_path, monkeypatch):
    """The export used to write its files, then exit 2 because pddl-plus-parser (which checks
    them) is missing: now it says so first and writes nothing (issue 29)."""
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda name, *a: None if name == "pddl_plus_parser" else real(name, *a)
    )
    out = tmp_path / "out"
    res = run_catc("export", "pddl", str(ROOT / "examples" / "gpu-allocation" / "max-confidence.cat"), "--grid",
                   "m=1/4", "-o", str(out))  # fmt: skip
    assert res.exit_code == 2 and "error[E0706]" in res.stderr and "nothing was written" in res.stderr
    assert not out.exists()


def test_check_takes_json_as_every_command_does(tmp_path):
    res = run_catc("check", "--json", str(ROOT / "examples" / "detection" / "person.cat"))
    assert res.exit_code == 0 and json.loads(res.stdout)["schema"] == "catc.check/1"


def test_help_lists_each_commands_first_sentence_whole():
    """click cut the command list's descriptions at the terminal's width ("print...")."""
    from click.testing import CliRunner

    from catc.interfaces.cli import main

    text = CliRunner().invoke(main, ["--help"], terminal_width=80).output
    commands = text.split("Commands:", 1)[1]
    assert not [line for line in commands.splitlines() if line.endswith("...")], commands
    assert "comparison tables." in commands


def test_a_long_query_is_not_silent_when_piped(capsys):
    """Issue 29: piped (standard error not a terminal) and without --progress, a long optimize
    printed nothing for minutes.  Now, after ten quiet seconds, a line every half minute says
    what the query is doing.  The clock is replaced: the status's waits answer in turn."""
    from catc.interfaces import command

    status = command.progress(True)
    assert isinstance(status, command.ThrottledStatus)  # pytest's stderr is not a terminal

    class Clock:
        def __init__(self) -> None:
            self.waits: list[float] = []

        def wait(self, seconds: float) -> bool:  # False: the time passed; True: stop
            self.waits.append(seconds)
            return len(self.waits) > 3

    status._stop = clock = Clock()  # type: ignore[assignment]
    status.update(type("Live", (), {"message": "optimize: horizon 5, best 12"})())
    status._tick()
    lines = [line for line in capsys.readouterr().err.splitlines() if line]
    assert clock.waits == [command.ThrottledStatus.QUIET] + [command.ThrottledStatus.EVERY] * 3
    assert len(lines) == 3 and all(line.startswith("catc: optimize: horizon 5, best 12 (") for line in lines)
    assert command.progress(False) is not None and command.progress(False, forced=False).__enter__() is None
