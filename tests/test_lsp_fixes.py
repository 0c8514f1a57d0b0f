"""Structured fixes on diagnostics (the language server's code actions read them) and the
analysis helpers of catc.interfaces.lsp.tools; no pygls needed."""

from __future__ import annotations

import contextlib
import re
from pathlib import Path

import pytest
from conftest import ROOT, word_uses

from catc.interfaces.lsp import analyse
from catgrammar.span import Source

DETECTION = ROOT / "tests" / "fixtures" / "lsp" / "detection"  # examples/detection, every resource its own
INVALID = sorted((ROOT / "tests" / "fixtures" / "invalid").glob("*.cat"))

#: Broken texts, one per place that makes a did-you-mean: (text, misspelt word, suggestion).
TYPOS = [
    ("(define (domain d) (:requirements :numerc))", ":numerc", ":numeric"),
    ("(define (domain d) (:requirements :symbols) (:sorts a - symbl))", "symbl", "symbol"),
    ("(define (domain d) (:requirements :numeric) (:resources (x reall)))", "reall", "real"),
    (
        "(define (domain d) (:requirements :numeric :views) (:resources (battery real)) (:view v :keep (batery)))",
        "batery",
        "battery",
    ),
    ("(define (domain d) (:resources (x bool)) (:morphism m :kind sofware))", "sofware", "software"),
    (
        "(define (domain d) (:requirements :numeric) (:resources (x real)) (:morphism m :effect (increse x 1)))",
        "increse",
        "increase",
    ),
    (
        "(define (domain d) (:requirements :numeric) (:resources (battery real))"
        " (:morphism m :effect (increase batery 1)))",
        "batery",
        "battery",
    ),
    (
        "(define (domain d) (:requirements :numeric) (:resources (battery real))"
        " (:morphism m :precondition (>= batery 1)))",
        "batery",
        "battery",
    ),
    ("(define (domain d) (:resources (x bool)) (:morphism m :precondition (nott x)))", "nott", "not"),
    ("(define (domain d) (:resources (x bool)) (:morphism m :precondtion x))", ":precondtion", ":precondition"),
    ("(define (domain d) (:resources (x bool)) (:morphism m precondition x))", "precondition", ":precondition"),
    ("(define (domain d) (:import robot-bse))", "robot-bse", "robot-base"),
    ("(define (problem p) (:domain detection) (:init (= rm 8)))", "rm", "ram"),
    ("(define (problem p) (:domain detection) (:init (= ram 8)) (:goal (member persn detects)))", "persn", "person"),
    (
        "(define (domain d) (:requirements :grounding) (:resources (x bool))"
        ' (:morphism m :kind software :ground (sofware :image "a/b:1" :node n)))',
        "sofware",
        "software",
    ),
]


def _apply(text: str, fix) -> str:
    return text[: fix.span.start] + fix.text + text[fix.span.end :]


@pytest.mark.parametrize("text, word, best", TYPOS, ids=[t[1] for t in TYPOS])
def test_every_did_you_mean_carries_its_replacement(text: str, word: str, best: str, tmp_path) -> None:
    path = DETECTION / "typo.cat" if "(:domain detect" in text else tmp_path / "typo.cat"
    a = analyse(str(path), text)
    [d] = [d for d in a.diagnostics if f"did you mean '{best}'" in d.message]
    [fix] = d.fixes
    assert text[fix.span.start : fix.span.end] == word  # the fix replaces the misspelt word itself
    assert fix.text == best
    fixed = _apply(text, fix)
    assert not [x for x in analyse(str(path), fixed).diagnostics if f"'{word}'" in x.message]


@pytest.mark.parametrize("path", INVALID, ids=[p.stem for p in INVALID])
def test_every_did_you_mean_of_the_invalid_corpus_has_a_fix(path: Path) -> None:
    """Whatever made the suggestion, the diagnostic carries it as data (not only as text)."""
    a = analyse(str(path), path.read_text())
    for d in a.diagnostics:
        m = re.search(r"did you mean '([^']+)'", d.message)
        if m is None:
            continue
        assert d.fixes, d.message
        assert any(m.group(1) in f.text for f in d.fixes), (d.message, d.fixes)


def test_no_suggestion_no_fix() -> None:
    a = analyse("x.cat", "(define (domain d) (:requirements :numeric) (:resources (x qqqqqq)))")
    [d] = a.diagnostics
    assert "did you mean" not in d.message and d.fixes == ()


def test_missing_requirement_fix_appends_to_the_section(tmp_path) -> None:
    domain = (DETECTION / "domain.cat").read_text()
    text = domain.replace("(:requirements :numeric :sets :free-parameters :grounding)", "(:requirements :numeric)")
    assert text != domain
    path = tmp_path / "domain.cat"
    a = analyse(str(path), text)
    missing = [d for d in a.diagnostics if d.code == "E0401"]
    assert {re.search(r"requirement '([^']+)'", d.message).group(1) for d in missing} == {
        ":sets",
        ":symbols",  # (:sorts ...): implied by :sets, which is gone too
        ":free-parameters",
        ":grounding",
    }
    for d in missing:  # each adds its flag just before the section's ')'
        [fix] = d.fixes
        assert fix.span.start == fix.span.end == text.index("(:requirements :numeric)") + len("(:requirements :numeric")
    fixed = text
    for d in sorted(missing, key=lambda d: -d.fixes[0].span.start):
        fixed = _apply(fixed, d.fixes[0])
    flags = fixed.split("(:requirements", 1)[1].split(")", 1)[0].split()
    assert sorted(flags) == sorted([":numeric", ":sets", ":symbols", ":free-parameters", ":grounding"])
    assert analyse(str(path), fixed).diagnostics == []


def test_missing_requirement_fix_adds_a_section(tmp_path) -> None:
    text = "(define (domain d)\n  (:resources (x real))\n  (:morphism m :effect (increase x 1)))\n"
    a = analyse(str(tmp_path / "d.cat"), text)
    [d] = a.diagnostics
    assert d.code == "E0401" and ":numeric" in d.message
    [fix] = d.fixes
    fixed = _apply(text, fix)
    assert fixed == "(define (domain d)\n  (:requirements :numeric)" + text[len("(define (domain d)") :]
    assert analyse(str(tmp_path / "d.cat"), fixed).diagnostics == []


# ---------------------------------------------------------------- lsp_tools


def _span(path: Path, text: str, needle: str, shift: int = 0):
    i = text.index(needle) + shift
    m = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*").match(text, i)
    return m.group(), Source(str(path), text).span(i, m.end())


def test_references_of_a_resource_span_the_domain_and_its_problems() -> None:
    from catc.interfaces.lsp import tools as lsp_tools

    domain = DETECTION / "domain.cat"
    text = domain.read_text()
    a = analyse(str(domain), text)
    name, at = _span(domain, text, "(>= ram ram-req)", 4)
    assert name == "ram"
    files = lsp_tools.workspace_files(a, {})
    found = lsp_tools.references(a, name, at, files)
    by_file: dict[str, list[int]] = {}
    for s in found:
        by_file.setdefault(Path(s.file).resolve().name, []).append(s.start)
    expected = {p.name: word_uses(p.read_text(), "ram") for p in DETECTION.glob("*.cat")}
    expected = {k: v for k, v in expected.items() if v}
    assert by_file == expected
    assert set(expected) == {"domain.cat", "person.cat", "unmodeled-class.cat"}


def test_a_parameter_is_renamed_in_its_morphism_only(tmp_path) -> None:
    from catc.interfaces.lsp import tools as lsp_tools

    text = (
        "(define (domain d) (:requirements :numeric :free-parameters) (:resources (r real))\n"
        "  (:morphism a :parameters ((x real)) :precondition (>= r x) :effect (decrease r x))\n"
        "  (:morphism b :parameters ((x real)) :effect (increase r x)))\n"
    )
    path = tmp_path / "d.cat"
    path.write_text(text)
    a = analyse(str(path), text)
    name, at = _span(path, text, "(>= r x)", 6)
    edits = lsp_tools.rename_edits(a, name, at, "y", lsp_tools.workspace_files(a, {}))
    [spans] = edits.values()
    first = text.split("\n")[1]
    assert [s.line for s in spans] == [2, 2, 2] and [s.column - 1 for s in spans] == [
        m.start() for m in re.finditer(r"\bx\b", first)
    ]


@pytest.mark.parametrize(
    "word, new, why",
    [
        ("ram", "topics", "already the name of a resource"),
        ("ram", "camera-driver", "already the name of a morphism"),
        ("ram", "and", "keyword or built-in"),
        ("ram", "2x", "is not a name"),
        ("member", "x", "keyword or built-in"),
        ("real", "x", "keyword or built-in"),
    ],
)
def test_rename_refusals(word: str, new: str, why: str) -> None:
    from catc.interfaces.lsp import tools as lsp_tools

    domain = DETECTION / "domain.cat"
    text = domain.read_text()
    a = analyse(str(domain), text)
    at = re.search(rf"(?<![\w-]){word}(?![\w-])", text.split("(:morphism camera-driver")[1])
    offset = text.index("(:morphism camera-driver") + len("(:morphism camera-driver") + at.start()
    with pytest.raises(lsp_tools.RenameError, match=why):
        lsp_tools.check_rename(a, word, Source(str(domain), text).span(offset, offset + len(word)), new)


def test_rename_refuses_the_standard_library() -> None:
    from catc.interfaces.lsp import tools as lsp_tools

    every = ROOT / "tests" / "fixtures" / "valid" / "every-construct.cat"
    text = every.read_text()
    a = analyse(str(every), text)
    i = text.index("budget")
    with pytest.raises(lsp_tools.RenameError, match="standard library"):
        lsp_tools.check_rename(a, "budget", Source(str(every), text).span(i, i + 6), "money")


def test_every_option_of_the_grammar_has_signature_help() -> None:
    from catc.interfaces.lsp.tools import OPTION_DOCS
    from catgrammar.symbols import HOLE_OPTIONS, MORPHISM_OPTIONS, PARAMETER_OPTIONS, RESOURCE_OPTIONS, VIEW_OPTIONS

    language = (ROOT / "docs" / "language.md").read_text()
    for options in (MORPHISM_OPTIONS, RESOURCE_OPTIONS, PARAMETER_OPTIONS, HOLE_OPTIONS, VIEW_OPTIONS):
        for o in options:
            assert o.value in OPTION_DOCS, o
            assert OPTION_DOCS[o.value][0].startswith(o.value)
            assert f"`{o.value}" in language, f"{o.value} is not documented in docs/language.md"


@pytest.mark.parametrize(
    "needle, shift, form, active",
    [
        ("    :kind software :uses 1\n    :parameters ((out", 25, "morphism", ":uses"),
        ("(ram-req real :unit GB :bounds (0.5 2))", 32, "parameter", ":bounds"),
        ("(ram real :group compute :unit GB", 33, "resource", ":unit"),
        ("(ram real :group compute", 9, "resource", None),
        ("(:morphism open-vocab-detector", 30, "morphism", None),
        ("(and (member in topics)", 10, "morphism", ":precondition"),
    ],
)
def test_signature_help_positions(needle: str, shift: int, form: str, active: str | None) -> None:
    from catc.interfaces.lsp.tools import signature_at

    text = (DETECTION / "domain.cat").read_text()
    sig = signature_at(text, text.index(needle) + shift)
    assert sig is not None and sig.doc == f"the options of a {form}"
    got = sig.options[sig.active].split()[0] if sig.active is not None else None
    assert got == active


def test_no_signature_outside_a_form() -> None:
    from catc.interfaces.lsp.tools import signature_at

    text = (DETECTION / "domain.cat").read_text()
    assert signature_at(text, text.index("(:sorts module") + 9) is None
    assert signature_at("", 0) is None and signature_at("(((", 3) is None and signature_at(")))", 2) is None


def test_grounding_key_and_template_hole_fixes(tmp_path) -> None:
    path = str(tmp_path / "g.cat")
    key = (
        "(define (domain d) (:requirements :grounding) (:resources (x bool))"
        ' (:morphism m :kind software :ground (software :imag "a/b:1" :node n)))'
    )
    [d] = [d for d in analyse(path, key).diagnostics if "did you mean ':image'" in d.message]
    [fix] = d.fixes
    assert key[fix.span.start : fix.span.end] == ":imag" and fix.text == ":image"  # the key, not its value
    hole = (
        "(define (domain d) (:requirements :grounding :free-parameters :symbols) (:sorts s - symbol)"
        " (:resources (x bool)) (:morphism m :kind hardware :parameters ((out s))"
        ' :ground (hardware :instruction "Mount {ot} now")))'
    )
    [d] = [d for d in analyse(path, hole).diagnostics if d.code == "E0508"]
    assert "did you mean 'out'" in d.message
    [fix] = d.fixes
    assert hole[fix.span.start : fix.span.end] == "{ot}" and fix.text == "{out}"
    assert [d.code for d in analyse(path, _apply(hole, fix)).diagnostics] == ["W0101"]  # x is unused, nothing else


def test_a_parameter_hides_the_resource_of_its_name(tmp_path) -> None:
    """References of resource r skip the uses inside a morphism whose θ is also called r
    (an error, E0204, but one a rename must not make worse while it is being fixed)."""
    from catc.interfaces.lsp import tools as lsp_tools

    text = (
        "(define (domain d) (:requirements :numeric :free-parameters) (:resources (r real :unit W))\n"
        "  (:morphism a :parameters ((r real)) :precondition (>= r 1))\n"
        "  (:morphism b :precondition (>= r 2) :effect (increase r 1)))\n"
    )
    path = tmp_path / "d.cat"
    path.write_text(text)
    a = analyse(str(path), text)
    name, at = _span(path, text, "(>= r 2)", 4)
    spans = lsp_tools.references(a, name, at, lsp_tools.workspace_files(a, {}))
    assert [(s.line, s.column) for s in spans] == [(1, 75), (3, 34), (3, 57)]
    assert [d.code for d in a.diagnostics] == ["E0204"]


def test_hover_on_an_option_keyword() -> None:
    from catc.interfaces.lsp import hover_text

    a = analyse(str(DETECTION / "domain.cat"), (DETECTION / "domain.cat").read_text())
    assert hover_text(a, ":uses") == (
        "```cat\n:uses N\n```\n\n**option** `:uses`: at most N activations (default unlimited; 0 switches it off)"
    )
    assert hover_text(a, ":requirements") is None


_PIECES = [
    "(",
    ")",
    " ",
    "\n",
    "(define (domain d)",
    "(:requirements :numeric :free-parameters)",
    "(:resources (r real :unit W :bounds (0 *))",
    "(:morphism m",
    " :parameters ((x real))",
    " :precondition (>= r x)",
    " :effect (decrease r x)",
    ":uses",
    ' "{x}"',
    "r",
    "x",
    "😀",
    ";c\n",
    '"',
    "{",
]


def test_the_analysis_helpers_never_raise_on_random_text() -> None:
    """Texts glued from pieces of a model: every helper the server calls answers (a
    RenameError is an answer) whatever the text."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from catc.interfaces.lsp import hover_text
    from catc.interfaces.lsp import tools as lsp_tools

    @settings(max_examples=60, deadline=None, suppress_health_check=list(HealthCheck), database=None)
    @given(st.lists(st.sampled_from(_PIECES), max_size=30), st.integers(min_value=0, max_value=400))
    def check(pieces: list[str], at: int) -> None:
        text = "".join(pieces)
        a = analyse("/nonexistent/random.cat", text)
        lsp_tools.semantic_tokens(a)
        lsp_tools.unit_hints(a)
        lsp_tools.signature_at(text, min(at, len(text)))
        lsp_tools.formatted(text)
        files = {a.path: text}
        for w in list(lsp_tools.words(a.path, text))[:5]:
            hover_text(a, w.text, w.span)
            lsp_tools.references(a, w.text, w.span, files)
            with contextlib.suppress(lsp_tools.RenameError):  # a refusal is an answer
                lsp_tools.rename_edits(a, w.text, w.span, "fresh-name", files)

    check()


def test_a_morphism_used_as_a_number_gets_the_uses_fix_in_an_objective() -> None:
    problem = DETECTION / "typo.cat"
    head = "(define (problem p) (:domain detection) (:requirements :optimization) (:init (= ram 8))"
    text = head + " (:goal (member person detects)) (:metric minimize camera-driver))"
    [d] = [d for d in analyse(str(problem), text).diagnostics if "'camera-driver' is a morphism" in d.message]
    [fix] = d.fixes
    assert text[fix.span.start : fix.span.end] == "camera-driver" and fix.text == "(uses camera-driver)"
    assert analyse(str(problem), _apply(text, fix)).diagnostics == []
    # in a goal (uses ...) is not allowed either: no fix there
    goal = head + " (:goal (>= camera-driver 1)))"
    [d] = [d for d in analyse(str(problem), goal).diagnostics if "'camera-driver' is a morphism" in d.message]
    assert d.fixes == ()


def test_references_of_an_imported_standard_library_resource_reach_the_importers() -> None:
    """examples/detection imports robot-base, which imports compute, which declares ram: its
    references are the declaration and every use in the domain and both problems (the domain
    beside the problems is the importer itself, not a rival domain of that name)."""
    from catc.interfaces.lsp import tools as lsp_tools

    folder = ROOT / "examples" / "detection"
    domain = folder / "domain.cat"
    text = domain.read_text()
    a = analyse(str(domain), text)
    name, at = _span(domain, text, "(>= ram ram-req)", 4)
    found = lsp_tools.references(a, name, at, lsp_tools.workspace_files(a, {}))
    by_file: dict[str, list[int]] = {}
    for s in found:
        by_file.setdefault(Path(s.file).resolve().name, []).append(s.start)
    expected = {p.name: word_uses(p.read_text(), "ram") for p in folder.glob("*.cat")}
    compute = ROOT / "stdlib_domains" / "compute.cat"
    expected["compute.cat"] = word_uses(compute.read_text(), "ram")  # its declaration
    assert by_file == {k: v for k, v in expected.items() if v}
    assert set(by_file) == {"domain.cat", "person.cat", "unmodeled-class.cat", "compute.cat"}
