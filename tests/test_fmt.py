"""catc fmt: a fixpoint on every repository file, the same checked IR before and after,
comments kept, a golden layout, and the --check exit codes.  Also the pre-commit hooks file."""

from __future__ import annotations

import dataclasses
import difflib
import re
import shutil
from enum import Enum
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import ROOT, repo_cat_files, run_catc

from catc.frontend.formatter import format_text
from catgrammar.diagnostics import Diagnostics

VALID = repo_cat_files()
ALL = VALID + repo_cat_files(invalid=True)

#: Valid files whose exact layout is a fixture of another test, and so not catc fmt's: none
#: since the editors indent as catc fmt does (editors/vim/test/sample.cat is in its layout).
LAYOUT_FIXTURES: set[str] = set()


def _id(p: Path) -> str:
    return p.relative_to(ROOT).as_posix()


CANONICAL = [p for p in VALID if _id(p) not in LAYOUT_FIXTURES]


def _comments(text: str) -> list[str]:
    # ';' never occurs inside the repository's strings; strip strings anyway
    text = re.sub(r'"(?:[^"\\\n]|\\.)*"', '""', text)
    return [m.group().rstrip() for m in re.finditer(r";[^\n]*", text)]


def _plain(obj, seen=None):
    """An IR object as nested tuples, without spans (positions change with the layout)."""
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        return (type(obj).__name__,) + tuple(
            (f.name, _plain(getattr(obj, f.name))) for f in dataclasses.fields(obj) if "span" not in f.name
        )
    if isinstance(obj, dict) or (hasattr(obj, "items") and hasattr(obj, "keys")):
        return tuple(sorted((k, _plain(v)) for k, v in obj.items()))
    if isinstance(obj, (frozenset, set)):
        return tuple(sorted(map(repr, obj)))
    if isinstance(obj, (list, tuple)):
        return tuple(_plain(x) for x in obj)
    if isinstance(obj, (Enum, Fraction, bool, int, str, float)) or obj is None:
        return repr(obj)
    return repr(obj)


def _check(path: Path):
    from catc.frontend.session import check_files

    diags = Diagnostics()
    domains, instances = check_files([str(path)], diags, [str(path.parent)])
    return (
        _plain(domains),
        _plain({k: v.problem for k, v in instances.items()}),
        sorted((d.code, d.message) for d in diags),
    )


@pytest.mark.parametrize("path", ALL, ids=_id)
def test_fixpoint_and_comments(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    once = format_text(text)
    assert format_text(once) == once
    assert _comments(once) == _comments(text)


def test_layout_fixtures_exist() -> None:
    assert LAYOUT_FIXTURES.issubset(_id(p) for p in VALID)


@pytest.mark.parametrize("path", CANONICAL, ids=_id)
def test_repository_file_is_formatted(path: Path) -> None:
    """Every .cat file of the repository (but the broken ones and LAYOUT_FIXTURES) is in the
    canonical layout; CI runs `catc fmt --check` on them too.  Fix with `catc fmt FILE`."""
    text = path.read_text(encoding="utf-8")
    formatted = format_text(text)
    if formatted != text:
        diff = difflib.unified_diff(
            text.splitlines(keepends=True), formatted.splitlines(keepends=True), f"a/{_id(path)}", f"b/{_id(path)}"
        )
        pytest.fail(f"{_id(path)} is not formatted (run `catc fmt {_id(path)}`):\n{''.join(diff)}", pytrace=False)


@pytest.mark.parametrize("path", VALID, ids=_id)
def test_same_ir_after_formatting(path: Path, tmp_path: Path) -> None:
    # the domain files a problem imports stay in their folder: copy the folder
    folder = tmp_path / "m"
    shutil.copytree(path.parent, folder, ignore=shutil.ignore_patterns("*.toml", "*.md"))
    before = _check(folder / path.name)
    target = folder / path.name
    target.write_text(format_text(target.read_text(encoding="utf-8")), encoding="utf-8")
    after = _check(target)
    assert before[0] == after[0]
    assert before[1] == after[1]
    assert before[2] == after[2]


def test_ir_comparison_sees_changes() -> None:
    """The IR comparison above is not vacuous: a changed number changes it."""
    src = ROOT / "tests/fixtures/valid/every-construct.cat"
    text = src.read_text()
    a = _plain(_parse_check(text))
    b = _plain(_parse_check(text.replace(":cost 20000", ":cost 20001")))
    assert a != b and a == _plain(_parse_check(format_text(text)))


def _parse_check(text: str):
    import tempfile

    from catc.frontend.session import check_files

    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "x.cat"
        p.write_text(text)
        domains, instances = check_files([str(p)], Diagnostics())
        return domains, {k: v.problem for k, v in instances.items()}


GOLDEN_IN = """\
; header comment
(define (domain g) (:requirements :numeric :symbols)
 (:sorts a b - symbol c - a)   ; sorts
  (:resources (x int :bounds (0 10)) (y real))
  ; the only morphism

  (:morphism m :kind software :churn 0.50 :uses 2 :cost 1e2
     :precondition (and (>= x 1) (<= y 3.0) (>= x 2) (<= y 4) (>= x 3) (<= y 5) (>= x 4) (<= y 6) (>= x 5) (<= y 7))
     :effect (increase x 1)))
(define (problem p) (:domain g) (:init (= x 0) (= y -1.5)) (:goal (>= x 2)))
; trailing
"""

GOLDEN_OUT = """\
; header comment
(define (domain g)
  (:requirements :numeric :symbols)
  (:sorts a b - symbol  c - a) ; sorts
  (:resources
    (x int :bounds (0 10))
    (y real))
  ; the only morphism

  (:morphism m
    :kind software :churn 0.50 :uses 2 :cost 1e2
    :precondition (and (>= x 1)
                       (<= y 3.0)
                       (>= x 2)
                       (<= y 4)
                       (>= x 3)
                       (<= y 5)
                       (>= x 4)
                       (<= y 6)
                       (>= x 5)
                       (<= y 7))
    :effect (increase x 1)))

(define (problem p)
  (:domain g)
  (:init (= x 0) (= y -1.5))
  (:goal (>= x 2)))
; trailing
"""


def test_golden() -> None:
    assert format_text(GOLDEN_IN) == GOLDEN_OUT
    assert format_text(GOLDEN_OUT) == GOLDEN_OUT


# ---------------------------------------------------------------- layout rules, one by one
# Each expected layout is written by hand; each is also a fixpoint.


def _formats_to(before: str, after: str) -> None:
    assert format_text(before) == after
    assert format_text(after) == after


def test_width_counts_the_closing_brackets() -> None:
    # the (and ...) ends at column 100, and the ")" of its morphism comes after it
    line = "    :effect (and (decrease budget 20000) (decrease slots 1) (decrease power 12) (add mounted lidar)))"
    assert len(line) == 101
    _formats_to(
        "(define (domain d)\n  (:morphism m\n" + line + "\n  (:morphism n))\n",
        """\
(define (domain d)
  (:morphism m
    :effect (and (decrease budget 20000)
                 (decrease slots 1)
                 (decrease power 12)
                 (add mounted lidar)))
  (:morphism n))
""",
    )
    # one column less fits
    short = line.replace("lidar", "lida")
    _formats_to(
        "(define (domain d)\n  (:morphism m\n" + short + "\n  (:morphism n))\n",
        "(define (domain d)\n  (:morphism m\n" + short + "\n  (:morphism n))\n",
    )


def test_long_lists_are_filled_under_their_first_item() -> None:
    _formats_to(
        """\
(define (domain d)
  (:requirements :numeric :sets :symbols :free-parameters :views :holes :optimization :recomposition))
(define (problem p)
  (:domain d)
  (:init (= slots 6) (= power 20) (= ram 64) (= disk 1000) (= budget 25000) (= ambient bright) (= range-to-base 4))
  (:deployed mount-lidar lidar-driver slam explore mount-rgb-camera rgb-driver open-vocab-detector tracker))
""",
        """\
(define (domain d)
  (:requirements :numeric :sets :symbols :free-parameters :views :holes :optimization
                 :recomposition))

(define (problem p)
  (:domain d)
  (:init (= slots 6) (= power 20) (= ram 64) (= disk 1000) (= budget 25000) (= ambient bright)
         (= range-to-base 4))
  (:deployed mount-lidar lidar-driver slam explore mount-rgb-camera rgb-driver open-vocab-detector
             tracker))
""",
    )


def test_a_filled_item_that_breaks_has_its_lines_to_itself() -> None:
    _formats_to(
        "(define (problem p) (:domain d) (:init (= x 1) (= mounted {alpha-one beta-two gamma-three "
        "delta-four epsilon-five zeta-six eta-seven theta-eight iota-nine}) (= y 2)))\n",
        """\
(define (problem p)
  (:domain d)
  (:init (= x 1)
         (= mounted
            {alpha-one beta-two gamma-three delta-four epsilon-five zeta-six eta-seven theta-eight
             iota-nine})
         (= y 2)))
""",
    )


def test_name_lists_are_filled_not_one_per_line() -> None:
    # :keep/:drop names, {set} literals and (enum ...) values: lists of like items
    _formats_to(
        """\
(define (domain d)
  (:sorts level - (enum very-low low medium-low medium medium-high high very-high extreme off unknown broken))
  (:view behavior :keep (slam-running tracking speech-in speech-out scene-understanding explored at-victim interacted)))
(define (problem p) (:domain d) (:init (= seen {north-east north-west south-east south-west centre dock-a dock-b dock-c dock-d dock-e dock-f dock-g dock-h})))
""",
        """\
(define (domain d)
  (:sorts
    level - (enum very-low low medium-low medium medium-high high very-high extreme off unknown
                  broken))
  (:view behavior :keep (slam-running tracking speech-in speech-out scene-understanding explored
                         at-victim interacted)))

(define (problem p)
  (:domain d)
  (:init (= seen
            {north-east north-west south-east south-west centre dock-a dock-b dock-c dock-d dock-e
             dock-f dock-g dock-h})))
""",
    )


def test_a_long_typed_group_is_filled_and_keeps_its_sort() -> None:
    _formats_to(
        """\
(define (domain d)
  (:constants rgb-camera rgb-camera-lite thermal-camera lidar speaker-mic external-battery long-range-radio - module
              scan - topic))
""",
        """\
(define (domain d)
  (:constants
    rgb-camera rgb-camera-lite thermal-camera lidar speaker-mic external-battery
      long-range-radio - module
    scan - topic))
""",
    )


def test_short_morphism_options_share_a_line() -> None:
    # :kind :churn :uses :cost with a plain value; :doc and expressions get a line each
    _formats_to(
        """\
(define (domain d)
  (:morphism m :kind hardware :churn 1 :uses 1 :cost 150 :doc "a camera" :precondition ok
     :effect (assign ok true))
  (:morphism n :cost (* 2 x) :kind software :uses 2))
""",
        """\
(define (domain d)
  (:morphism m
    :kind hardware :churn 1 :uses 1 :cost 150
    :doc "a camera"
    :precondition ok
    :effect (assign ok true))
  (:morphism n
    :cost (* 2 x)
    :kind software :uses 2))
""",
    )


def test_comments_in_a_filled_list_stay_put() -> None:
    _formats_to(
        """\
(define (problem p) (:domain d)
  (:init (= a 1) ; the first
         ; before b
         (= b 2) (= c 3)))
""",
        """\
(define (problem p)
  (:domain d)
  (:init (= a 1) ; the first
         ; before b
         (= b 2) (= c 3)))
""",
    )


def test_awkward_comments_are_kept() -> None:
    text = """(define (domain d) ; after the head
  (:requirements ; inside
     :numeric)
  (:resources (x ; after x
     int))
  (:morphism m :precondition ; before the value
     (>= x 1) ; after the value
     :effect (and (increase x 1) ; last effect
     ) ; after and
  ; before the close
  ))
"""
    once = format_text(text)
    assert format_text(once) == once
    assert _comments(once) == _comments(text)


def test_check_exit_codes(tmp_path: Path) -> None:
    good = tmp_path / "good.cat"
    good.write_text(GOLDEN_OUT)
    bad = tmp_path / "bad.cat"
    bad.write_text(GOLDEN_IN)
    res = run_catc("fmt", "--check", good)
    assert res.exit_code == 0, res.output
    res = run_catc("fmt", "--check", good, bad)
    assert res.exit_code == 1
    assert str(bad) in res.stdout and str(good) not in res.stdout
    assert bad.read_text() == GOLDEN_IN  # --check writes nothing
    res = run_catc("fmt", bad)
    assert res.exit_code == 0
    assert bad.read_text() == GOLDEN_OUT
    assert run_catc("fmt", "--check", tmp_path).exit_code == 0


def test_diff_prints_a_unified_diff_and_writes_nothing(tmp_path: Path) -> None:
    good = tmp_path / "good.cat"
    good.write_text(GOLDEN_OUT)
    bad = tmp_path / "bad.cat"
    bad.write_text(GOLDEN_IN)
    res = run_catc("fmt", "--diff", good)
    assert (res.exit_code, res.stdout) == (0, "")
    res = run_catc("fmt", "--check", good)
    assert (res.exit_code, res.stdout) == (0, "")
    res = run_catc("fmt", "--diff", good, bad)
    assert res.exit_code == 1
    assert bad.read_text() == GOLDEN_IN  # --diff writes nothing
    expected = difflib.unified_diff(
        GOLDEN_IN.splitlines(keepends=True), GOLDEN_OUT.splitlines(keepends=True), f"a/{bad}", f"b/{bad}"
    )
    assert res.stdout == "".join(expected)
    assert res.stdout.startswith(f"--- a/{bad}\n+++ b/{bad}\n@@ ")
    assert str(good) not in res.stdout
    assert "1 file(s) would be reformatted" in res.stderr
    # applying the diff's + side gives the formatted file
    plus = [ln[1:] for ln in res.stdout.splitlines(keepends=True)[2:] if ln[:1] in " +"]
    assert "".join(plus) == GOLDEN_OUT


def test_bad_input_exits_2(tmp_path: Path) -> None:
    broken = tmp_path / "broken.cat"
    broken.write_text("(define (domain d)\n  (:resources (x int))\n")
    res = run_catc("fmt", broken)
    assert res.exit_code == 2
    assert "error[" in res.output
    assert broken.read_text() == "(define (domain d)\n  (:resources (x int))\n"
    assert run_catc("fmt", "--check", tmp_path / "missing.cat").exit_code == 2


# ---------------------------------------------------------------- pre-commit hooks


def _hooks() -> list[dict]:
    path = ROOT / ".pre-commit-hooks.yaml"
    text = path.read_text()
    try:
        import yaml
    except ImportError:  # a tiny reader for this flat list of mappings
        hooks: list[dict] = []
        for line in text.splitlines():
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            m = re.match(r"^(- )?\s*([\w-]+):\s*(.*)$", line.strip())
            if not m:
                continue
            if line.startswith("-"):
                hooks.append({})
            value = m.group(3).strip()
            if value.startswith("[") and value.endswith("]"):
                value = [v.strip().strip("'\"") for v in value[1:-1].split(",") if v.strip()]
            elif value.startswith(("'", '"')):
                value = value[1:-1]
            hooks[-1][m.group(2)] = value
        return hooks
    return yaml.safe_load(text)


def test_pre_commit_hooks_name_real_commands() -> None:
    import shlex

    from catc.interfaces.cli import main

    hooks = {h["id"]: h for h in _hooks()}
    assert set(hooks) == {"catc-check", "catc-fmt"}
    for hook in hooks.values():
        assert {"id", "name", "entry", "language", "files"} <= set(hook)
        argv = shlex.split(hook["entry"]) + list(hook.get("args", []))
        assert argv[0] == "catc"
        assert argv[1] in main.list_commands(None)  # a real command
        assert re.search(hook["files"], "examples/detection/domain.cat")
        assert not re.search(hook["files"], "README.md")
        # the options are real options of that command
        res = run_catc(*argv[1:], "--help")
        assert res.exit_code == 0
        for opt in [a for a in argv[2:] if a.startswith("--")]:
            assert opt in res.stdout
    assert "--strict" in hooks["catc-check"]["entry"] + " ".join(hooks["catc-check"].get("args", []))
    assert "--check" in hooks["catc-fmt"]["entry"] + " ".join(hooks["catc-fmt"].get("args", []))


def test_comments_anywhere_are_a_fixpoint() -> None:
    """Comments and line breaks dropped between random tokens of the corpus: the result is
    a fixpoint, parses, and keeps the tokens and the comments in order (format_text checks)."""
    import random

    from catgrammar.parser import parse_text
    from catgrammar.tokens import tokenize

    rng = random.Random(7)
    done = 0
    for _ in range(120):
        text = rng.choice(VALID).read_text(encoding="utf-8")
        out, pos = [], 0
        for tok in tokenize(text):
            gap = text[pos : tok.start_pos]
            r = rng.random()
            if r < 0.1:
                gap += f" ; c{rng.randint(0, 99)}\n"
            elif r < 0.15:
                gap = "\n\n; x y\n\n" + gap
            elif r < 0.25 and ";" not in gap:
                gap = gap.replace("\n", " ")
            elif r < 0.3:
                gap += "\n   "
            out += [gap, tok.value]
            pos = tok.end_pos
        mangled = "".join(out) + text[pos:] + ("; end\n" if rng.random() < 0.3 else "")
        if parse_text(mangled, diags=Diagnostics()) is None:
            continue
        once = format_text(mangled)
        assert format_text(once) == once
        assert parse_text(once, diags=Diagnostics()) is not None
        assert _comments(once) == _comments(mangled)
        done += 1
    assert done > 50


# ---------------------------------------------------------------- the editors' indentation rule


@pytest.mark.parametrize("path", CANONICAL, ids=_id)
def test_the_line_by_line_rule_restores_every_file(path):
    """catc.frontend.indent states fmt's layout one line at a time, as an editor indents (the
    Vim and Emacs indenters implement the same rule: tests/editors): every line of every file
    gets back its column from the lines above it, with every line flushed left."""
    from catc.frontend.indent import reindent

    text = path.read_text(encoding="utf-8")
    assert reindent("\n".join(line.strip() for line in text.split("\n"))) == text
    assert reindent(text) == text


def test_the_line_by_line_rule_on_hand_made_cases():
    from catc.frontend.indent import indent_of

    def col(text: str) -> int:
        lines = text.split("\n")
        return indent_of(lines, len(lines) - 1)

    assert col("(define (domain d)\nx") == 2  # a section: the body two in
    assert col("  (:init (= a 1)\nx") == 9  # filled: under the first item
    assert col("  (:init\nx") == 4
    assert col("  (:metric pareto\nx") == 4  # not under 'pareto'
    assert col("    (and (a)\nx") == 9  # a call: under the first argument
    assert col("    (and\nx") == 6
    assert col("    (and ; why\nx") == 9  # as if the argument followed the head
    assert col("    (ram real\nx") == 9  # any atom head is a call
    assert col("  (:constants\n    a b c\nx") == 6  # a typed group continued
    assert col("  (:constants\n    a b - t\nx") == 4  # a new group
    assert col("  (:constants\n    a - (enum p q)\nx") == 4
    assert col("  :keep (a b\nx") == 9  # a list of names: under the first
    assert col("  {a b\nx") == 3
    assert col("  ((a b)\nx") == 3
    assert col("  ( ; c\nx") == 3
    assert col('  (x "(" ; (\n     y)\nz') == 0  # brackets in strings and comments do not count
    assert col('  (x "(" ; (\ny') == 5


def test_fmt_has_the_limits_of_check(tmp_path, monkeypatch):
    """Issue 28, finding 7: ``catc fmt`` took no --limit or --memory (a 2.1 MB model took
    9.5 s of CPU with no way to bound it).  Now check's limits hold: a file past the token
    limit is E1102, exit 2, and is left as it was; the environment's limit too."""

    path = tmp_path / "person.cat"
    text = (ROOT / "examples" / "detection" / "person.cat").read_text().replace("(:horizon 3)", "(:horizon   3)")
    path.write_text(text)
    res = run_catc("fmt", str(path), "--limit", "tokens=10")
    assert res.exit_code == 2 and "error[E1102]" in res.output, res.output
    assert path.read_text() == text
    res = run_catc("fmt", "--check", str(path), "--memory", "0")
    assert res.exit_code == 1 and "would reformat" in res.output, res.output
    monkeypatch.setenv("CATC_LIMIT_TOKENS", "10")
    res = run_catc("fmt", "--check", str(path))
    assert res.exit_code == 2 and "error[E1102]" in res.output, res.output
