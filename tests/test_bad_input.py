"""Bad input of every kind: a located diagnostic, exit 1 or 2, never a traceback or a hang."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from conftest import run_catc, run_catc_process

LOCATED = re.compile(r"^(?P<file>[^:\n]+):(?P<line>\d+):(?P<col>\d+): error\[(?P<code>E\d{4})\]: ", re.M)


def check(tmp_path: Path, content: bytes | str, name: str = "input.cat", *extra: Path):
    path = tmp_path / name
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    return path, run_catc("check", str(path), *map(str, extra))


def first_error(output: str) -> re.Match:
    m = LOCATED.search(output)
    assert m, f"no located diagnostic in:\n{output}"
    return m


def test_empty_file(tmp_path):
    _path, res = check(tmp_path, "")
    assert res.exit_code == 1
    m = first_error(res.stdout)
    assert (m["code"], m["line"], m["col"]) == ("E0004", "1", "1")


def test_comments_only_file_is_empty(tmp_path):
    _, res = check(tmp_path, "; nothing but a comment\n\n")
    assert res.exit_code == 1 and first_error(res.stdout)["code"] == "E0004"


def test_binary_file(tmp_path):
    _, res = check(tmp_path, b"(define\n  \x00\x01\x02\xff")
    assert res.exit_code == 2
    m = first_error(res.stdout)
    assert (m["code"], m["line"], m["col"]) == ("E0002", "2", "3")


def test_non_utf8_file(tmp_path):
    _, res = check(tmp_path, b"(define (domain caf\xe9))")
    assert res.exit_code == 2
    m = first_error(res.stdout)
    assert (m["code"], m["line"], m["col"]) == ("E0003", "1", "20")
    assert "0xe9" in res.stdout


def test_missing_file_is_a_usage_error(tmp_path):
    res = run_catc("check", str(tmp_path / "nope.cat"))
    assert res.exit_code == 2 and "E0001" in res.stdout


def test_folder_without_cat_files(tmp_path):
    res = run_catc("check", str(tmp_path))
    assert res.exit_code == 2 and "E0005" in res.stdout


@pytest.mark.parametrize(
    "text, code, line, col",
    [
        ("(define (domain d)\n  (:resources (x bool))", "E0103", 1, 1),
        ("(define (domain d)))\n", "E0102", 1, 20),
        ("(define (domain d) (:morphism m :effect (and))\n)\n)", "E0102", 3, 1),
    ],
)
def test_unbalanced_parentheses(tmp_path, text, code, line, col):
    _, res = check(tmp_path, text)
    assert res.exit_code == 1
    m = first_error(res.stdout)
    assert (m["code"], int(m["line"]), int(m["col"])) == (code, line, col)


def test_nesting_ten_thousand_deep(tmp_path):
    body = "(and " * 10_000 + "true" + ")" * 10_000
    text = f"(define (domain d) (:resources (b bool)) (:morphism m :precondition {body} :effect (assign b true)))"
    _, res = check(tmp_path, text)
    assert res.exit_code == 1
    m = first_error(res.stdout)
    assert m["code"] == "E0104" and m["line"] == "1"


def test_nesting_ten_thousand_deep_in_a_fresh_process(tmp_path):
    body = "(not " * 10_000 + "b" + ")" * 10_000
    path = tmp_path / "deep.cat"
    path.write_text(
        f"(define (domain d) (:resources (b bool)) (:morphism m :precondition {body} :effect (assign b true)))"
    )
    res = run_catc_process("check", str(path), timeout=60)
    assert res.exit_code == 1, res.output
    assert "Traceback" not in res.output and "E0104" in res.stdout


def test_200000_digit_literal(tmp_path):
    digits = "9" * 200_000
    text = f"(define (domain d) (:requirements :numeric) (:resources (x real)) (:morphism m :effect (increase x {digits})))"
    _, res = check(tmp_path, text)
    assert res.exit_code == 1
    m = first_error(res.stdout)
    assert m["code"] == "E0105" and "200000 digits" in res.stdout


def test_huge_exponent_does_not_hang(tmp_path):
    text = "(define (domain d) (:requirements :numeric) (:resources (x real)) (:morphism m :effect (increase x 1e999999999)))"
    _, res = check(tmp_path, text)
    assert res.exit_code == 1 and first_error(res.stdout)["code"] == "E0105"


def test_unknown_section(tmp_path):
    _, res = check(tmp_path, "(define (domain d)\n  (:morphisms m))")
    assert res.exit_code == 1
    m = first_error(res.stdout)
    assert (m["code"], m["line"], m["col"]) == ("E0106", "2", "4")
    assert "did you mean ':morphism'" in res.stdout


def test_unknown_option(tmp_path):
    _, res = check(tmp_path, "(define (domain d)\n  (:morphism m :pre (x)))")
    m = first_error(res.stdout)
    assert m["code"] == "E0106" and "did you mean ':precondition'" in res.stdout


def test_stray_character(tmp_path):
    _, res = check(tmp_path, "(define (domain d) @)")
    assert first_error(res.stdout)["code"] == "E0107"


def test_duplicate_names(tmp_path):
    _, res = check(tmp_path, "(define (domain d) (:resources (x bool) (x bool)))")
    m = first_error(res.stdout)
    assert m["code"] == "E0201" and "previously declared here" in res.stdout


@pytest.mark.parametrize(
    "pre_or_effect, code, fragment",
    [
        (":precondition (member a x)", "E0303", "needs a set"),
        (":effect (add s 3)", "E0301", "cannot add an int to 's'"),
        (":precondition (= a x)", "E0301", "cannot compare a symbol of sort 'm' with a real"),
    ],
)
def test_type_mismatches(tmp_path, pre_or_effect, code, fragment):
    text = (
        "(define (domain d) (:requirements :numeric :sets) (:sorts m - symbol) (:constants a - m)\n"
        f" (:resources (x real) (s (set m)))\n (:morphism t {pre_or_effect}))"
    )
    _, res = check(tmp_path, text)
    assert res.exit_code == 1
    m = first_error(res.stdout)
    assert m["code"] == code and m["line"] == "3" and fragment in res.stdout


def test_two_assignments_to_one_resource(tmp_path):
    text = "(define (domain d) (:requirements :numeric) (:resources (x real))\n (:morphism t :effect (and (assign x 1) (assign x 2))))"
    _, res = check(tmp_path, text)
    m = first_error(res.stdout)
    assert m["code"] == "E0501" and m["line"] == "2" and "the assign is here" in res.stdout


def test_problem_naming_a_missing_domain(tmp_path):
    _, res = check(tmp_path, "(define (problem p) (:domain ghost) (:goal true))")
    assert res.exit_code == 1
    m = first_error(res.stdout)
    assert (m["code"], m["line"], m["col"]) == ("E0207", "1", "30")


def test_problem_finds_its_domain_in_its_folder(tmp_path):
    (tmp_path / "dom.cat").write_text(
        "(define (domain far) (:resources (b bool)) (:morphism m :effect (assign b true)))"
    )
    sub = tmp_path / "p.cat"
    sub.write_text("(define (problem p) (:domain far) (:goal b))")
    res = run_catc("check", str(sub))
    assert res.exit_code == 0, res.output


def test_unknown_import(tmp_path):
    _, res = check(tmp_path, "(define (domain d) (:import robot-bas))")
    m = first_error(res.stdout)
    assert m["code"] == "E0208" and "did you mean 'robot-base'" in res.stdout


def test_circular_import_across_files(tmp_path):
    (tmp_path / "a.cat").write_text("(define (domain a) (:import b))")
    (tmp_path / "b.cat").write_text("(define (domain b) (:import a))")
    res = run_catc("check", str(tmp_path / "a.cat"))
    assert res.exit_code == 1
    assert first_error(res.stdout)["code"] == "E0209"
    assert "a -> b -> a" in res.stdout


def test_self_import(tmp_path):
    _, res = check(tmp_path, "(define (domain a) (:import a))")
    assert first_error(res.stdout)["code"] == "E0209"


def test_all_errors_of_a_run_are_reported(tmp_path):
    text = (
        "(define (domain d) (:requirements :numeric)\n"
        " (:resources (x real) (x real))\n"
        " (:morphism m :precondition (>= y 1) :effect (assign z 1))\n"
        " (:morphism n :precondition (frob x) :effect (increase x true)))\n"
    )
    _, res = check(tmp_path, text)
    codes = [m["code"] for m in LOCATED.finditer(res.stdout)]
    assert sorted(codes) == ["E0201", "E0202", "E0202", "E0211", "E0301"], res.stdout


def test_error_excerpt_has_a_caret_under_the_culprit(tmp_path):
    _, res = check(
        tmp_path,
        "(define (domain d) (:requirements :numeric)\n (:resources (ram real))\n (:morphism m :precondition (>= rma 1)))",
    )
    lines = res.stdout.splitlines()
    i = next(i for i, l in enumerate(lines) if "error[E0202]" in l)
    assert lines[i + 2].endswith("(:morphism m :precondition (>= rma 1)))")
    caret = lines[i + 3]
    source_line = lines[i + 2]
    assert source_line.index("rma") == caret.index("^") and caret.count("~") == 2
    assert "did you mean 'ram'" in lines[i]


def test_bom_is_accepted(tmp_path):
    _, res = check(
        tmp_path,
        "\ufeff(define (domain d) (:resources (b bool)) (:morphism m :effect (assign b true)))".encode("utf-8"),
    )
    assert res.exit_code == 0, res.output


def test_usage_error_exits_2():
    res = run_catc("check", "--format", "xml", "x.cat")
    assert res.exit_code == 2
    res = run_catc("no-such-command")
    assert res.exit_code == 2


def test_syntax_error_names_what_was_expected(tmp_path):
    _, res = check(tmp_path, "(define (domain d)\n  (:resources (x real :bounds (1 2 3))))")
    m = first_error(res.stdout)
    assert (m["code"], m["line"], m["col"]) == ("E0101", "2", "36")
    assert "unexpected '3'; expected ')'" in res.stdout


def test_same_domain_defined_in_two_files_of_one_folder(tmp_path):
    (tmp_path / "a.cat").write_text(
        "(define (domain twin) (:resources (b bool)) (:morphism m :effect (assign b true)))"
    )
    (tmp_path / "b.cat").write_text(
        "(define (domain twin) (:resources (b bool)) (:morphism m :effect (assign b true)))"
    )
    res = run_catc("check", str(tmp_path))
    assert res.exit_code == 1
    assert first_error(res.stdout)["code"] == "E0210" and "also defined here" in res.stdout


def test_same_domain_name_in_two_folders_resolves_by_folder(tmp_path):
    for sub, res_name in (("one", "alpha"), ("two", "beta")):
        (tmp_path / sub).mkdir()
        (tmp_path / sub / "d.cat").write_text(
            f"(define (domain twin) (:resources ({res_name} bool)) (:morphism m :effect (assign {res_name} true)))"
        )
        (tmp_path / sub / "p.cat").write_text(f"(define (problem p) (:domain twin) (:goal {res_name}))")
    res = run_catc("check", str(tmp_path))
    assert res.exit_code == 0, res.output
    # A problem elsewhere cannot tell which one it means.
    (tmp_path / "three").mkdir()
    (tmp_path / "three" / "p.cat").write_text("(define (problem p) (:domain twin) (:goal alpha))")
    res = run_catc("check", str(tmp_path))
    assert res.exit_code == 1 and "defined in several folders" in res.stdout


def test_problem_without_domain_section(tmp_path):
    _, res = check(tmp_path, "(define (problem p) (:goal true))")
    assert first_error(res.stdout)["code"] == "E0206"


@pytest.mark.parametrize(
    "text, fragment, col",
    [
        ('(define (domain d) (:resources (x bool :doc "a \\")))', "unterminated string", 45),
        ("(define (domain d) (:morphism m :precondition (>= x 12abc)))", "malformed number '12abc'", 53),
    ],
)
def test_lexical_errors(tmp_path, text, fragment, col):
    _, res = check(tmp_path, text)
    m = first_error(res.stdout)
    assert m["code"] == "E0107" and int(m["col"]) == col and fragment in res.stdout


def test_negation_without_space(tmp_path):
    text = "(define (domain d) (:requirements :numeric) (:resources (x real)) (:morphism m :effect (assign x (-x))))"
    _, res = check(tmp_path, text)
    assert res.exit_code == 0, res.output


DETECTION = Path(__file__).resolve().parents[1] / "examples" / "detection"


@pytest.mark.parametrize(
    ("file", "ascii", "other"),
    [
        ("person.cat", "(:horizon 3)", "(:horizon ٣)"),  # ARABIC-INDIC DIGIT THREE
        ("person.cat", "(= ram 16)", "(= ram ١٦)"),
        ("person.cat", "(= ram 16)", "(= ram １６)"),  # FULLWIDTH DIGIT ONE
        ("person.cat", "(= ram 16)", "(= ram 1६)"),  # a DEVANAGARI DIGIT SIX after an ASCII 1
        ("person.cat", "(:horizon 3)", "(:horizon ³)"),  # SUPERSCRIPT THREE (str.isdigit)
        ("person.cat", "(:horizon 3)", "(:horizon Ⅲ)"),  # ROMAN NUMERAL THREE (str.isnumeric)
        ("domain.cat", ":uses 1", ":uses ١"),
    ],
)
def test_numbers_are_written_with_ascii_digits(tmp_path, file, ascii, other):
    """Issue 28, finding 5: Python's ``\\d`` took other scripts' digits for numbers, so
    ``(:horizon ٣)`` checked and solved.  Now the first such character is a located E0107
    that names it."""
    for name in ("domain.cat", "person.cat"):
        text = (DETECTION / name).read_text()
        if name == file:
            assert ascii in text
            text = text.replace(ascii, other, 1)
            bad = next(i for i, ch in enumerate(text) if not ch.isascii() and (ch.isdigit() or ch.isnumeric()))
            line, col = text.count("\n", 0, bad) + 1, bad - text.rfind("\n", 0, bad)
        (tmp_path / name).write_text(text)
    res = run_catc("check", str(tmp_path / file))
    assert res.exit_code == 1
    m = first_error(res.stdout)
    assert (m["code"], int(m["line"]), int(m["col"])) == ("E0107", line, col), res.stdout
    assert "ASCII digits 0-9" in res.stdout
