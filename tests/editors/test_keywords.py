"""Every highlighter knows every word of ``catgrammar.symbols.all_keywords()``.

These checks read each highlighter independently of ``editors/generate.py`` (which wrote
the lists): the Pygments lexer is run on every word in context; the TextMate grammar's
rules are compiled with Python's ``re`` and matched against every word in context; the
Vim syntax file's ``syntax keyword`` statements and the Emacs mode's ``cat-keywords``
are parsed.  The tests marked ``editors`` (test_vscode.py, test_vim.py, test_emacs.py)
run the same sweep through the real editors.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys

import pytest
from pygments.token import Name, Whitespace

from catgrammar.lexer import TOKEN_FOR_CATEGORY, CatLexer
from catgrammar.symbols import all_keywords

from ._tools import CONTEXTS, EDITORS, ROOT, glued

KEYWORDS = all_keywords()
WORDS = [(category, word) for category, words in KEYWORDS.items() for word in words]
GLUED = [(category, word, name) for category, word in WORDS for name in glued(word)]

TM_GRAMMAR = EDITORS / "vscode" / "syntaxes" / "cat.tmLanguage.json"
VIM_SYNTAX = EDITORS / "vim" / "syntax" / "cat.vim"
VIM_INDENT = EDITORS / "vim" / "indent" / "cat.vim"
EMACS_MODE = EDITORS / "emacs" / "cat-mode.el"

#: TextMate scope expected for each category (editors/vscode/README.md documents them).
TM_SCOPES = {
    "structure": "keyword.other.structure.cat",
    "section": "keyword.declaration.section.cat",
    "option": "entity.other.attribute-name.option.cat",
    "requirement": "keyword.other.requirement.cat",
    "operator": "keyword.operator.word.cat",
    "symbol-operator": "keyword.operator.symbol.cat",
    "type": "storage.type.cat",
    "constant": "constant.language.boolean.cat",
    "kind": "support.constant.kind.cat",
    "metric": "support.constant.metric.cat",
}


def test_every_category_has_a_context_and_a_highlight():
    categories = set(KEYWORDS)
    assert categories <= set(CONTEXTS), "tests/editors/_tools.py: no context for " + str(categories - set(CONTEXTS))
    assert categories <= set(TOKEN_FOR_CATEGORY), "catgrammar/lexer.py: no token for " + str(
        categories - set(TOKEN_FOR_CATEGORY)
    )
    assert categories <= set(TM_SCOPES)


def test_generated_files_are_up_to_date():
    result = subprocess.run(
        [sys.executable, str(EDITORS / "generate.py"), "--check"], cwd=ROOT, capture_output=True, text=True
    )
    assert result.returncode == 0, f"editors/generate.py --check failed:\n{result.stderr}"


def test_generate_check_detects_and_fixes_a_stale_file(tmp_path):
    """``--check`` fails on a hand-edited keyword list; a plain run restores it."""
    copy = tmp_path / "editors"
    shutil.copytree(EDITORS, copy, ignore=shutil.ignore_patterns("node_modules", "*.vsix"))
    syntax = copy / "vim" / "syntax" / "cat.vim"
    original = syntax.read_text(encoding="utf-8")
    edited = re.sub(r"^(syntax keyword catOperator .*) member\b", r"\1", original, count=1, flags=re.M)
    assert edited != original
    syntax.write_text(edited, encoding="utf-8")
    env = {"PYTHONPATH": str(ROOT)}
    command = [sys.executable, str(copy / "generate.py")]
    check = subprocess.run([*command, "--check"], capture_output=True, text=True, env=env)
    assert check.returncode == 1, check.stdout + check.stderr
    assert "stale: editors/vim/syntax/cat.vim" in check.stderr
    fix = subprocess.run(command, capture_output=True, text=True, env=env)
    assert fix.returncode == 0, fix.stderr
    assert syntax.read_text(encoding="utf-8") == original
    assert subprocess.run([*command, "--check"], capture_output=True, env=env).returncode == 0


# ---------------------------------------------------------------- Pygments


@pytest.mark.parametrize(("category", "word"), WORDS)
def test_pygments_highlights_every_word(category, word):
    text = CONTEXTS[category] % word
    toks = [(t, v) for t, v in CatLexer().get_tokens(text) if t not in Whitespace]
    found = [t for t, v in toks if v == word]
    assert found, f"{word!r} is not one token in {text!r}: {toks}"
    assert found[0] is TOKEN_FOR_CATEGORY[category], f"{category} {word!r} in {text!r}: {toks}"


@pytest.mark.parametrize(("category", "word", "name"), GLUED)
def test_pygments_does_not_highlight_a_word_inside_a_name(category, word, name):
    toks = [(t, v) for t, v in CatLexer().get_tokens(f"(x {name} y)") if t not in Whitespace]
    assert (Name, name) in toks, toks


# ---------------------------------------------------------------- TextMate


def _tm_grammar() -> dict:
    return json.loads(TM_GRAMMAR.read_text(encoding="utf-8"))


def _tm_rules_scoped(grammar: dict, scope: str) -> list[tuple[re.Pattern, int]]:
    """(compiled ``match``, group) of the rules reachable from the top-level patterns
    that give ``scope`` to the whole match (``name``) or to a capture group."""
    found = []
    repository = grammar["repository"]
    for include in grammar["patterns"]:
        rule = repository[include["include"].lstrip("#")] if "include" in include else include
        for sub in rule.get("patterns", [rule]):
            if "match" not in sub:
                continue
            groups = [0] if sub.get("name") == scope else []
            groups += [int(g) for g, c in sub.get("captures", {}).items() if c.get("name") == scope]
            for group in groups:
                found.append((re.compile(sub["match"]), group))
    return found


def _tm_highlights(grammar: dict, scope: str, text: str, word: str) -> bool:
    start = text.index(word)
    for pattern, group in _tm_rules_scoped(grammar, scope):
        for m in pattern.finditer(text):
            if m.start(group) == start and m.end(group) == start + len(word):
                return True
    return False


@pytest.mark.parametrize(("category", "word"), WORDS)
def test_textmate_grammar_highlights_every_word(category, word):
    text = CONTEXTS[category] % word
    assert _tm_highlights(_tm_grammar(), TM_SCOPES[category], text, word), (
        f"no rule of {TM_GRAMMAR.relative_to(ROOT)} gives {TM_SCOPES[category]} to {word!r} in {text!r}"
    )


@pytest.mark.parametrize(("category", "word", "name"), GLUED)
def test_textmate_grammar_does_not_highlight_a_word_inside_a_name(category, word, name):
    text = f"(x {name} y)"
    grammar = _tm_grammar()
    for scope in TM_SCOPES.values():
        for pattern, group in _tm_rules_scoped(grammar, scope):
            for m in pattern.finditer(text):
                assert not (3 <= m.start(group) < 3 + len(name)), f"{scope} matches {m.group(group)!r} in {text!r}"


def test_textmate_option_rule_comes_before_section_rule():
    """``:view`` outside ``(`` is an option: at one position the earlier rule wins."""
    includes = [p.get("include") for p in _tm_grammar()["patterns"]]
    assert includes.index("#section-head") < includes.index("#option") < includes.index("#section")
    assert includes.index("#number") < includes.index("#symbol-operator")


# ---------------------------------------------------------------- Vim


def _vim_keywords() -> dict[str, set[str]]:
    groups: dict[str, set[str]] = {}
    for line in VIM_SYNTAX.read_text(encoding="utf-8").splitlines():
        parts = line.split()
        if parts[:2] == ["syntax", "keyword"]:
            groups.setdefault(parts[2], set()).update(p for p in parts[3:] if p != "contained")
    return groups


def _vim_group(category: str) -> str:
    return "cat" + "".join(part.capitalize() for part in category.split("-"))


@pytest.mark.parametrize(("category", "word"), [(c, w) for c, w in WORDS if c != "symbol-operator"])
def test_vim_syntax_has_every_word(category, word):
    assert word in _vim_keywords().get(_vim_group(category), set()), (
        f"{VIM_SYNTAX.relative_to(ROOT)}: no 'syntax keyword {_vim_group(category)} ... {word}'"
    )


def test_vim_syntax_has_every_symbol_operator():
    match = re.search(r"^syntax match catSymbolOperator /(.*)/$", VIM_SYNTAX.read_text(encoding="utf-8"), re.M)
    assert match, "no catSymbolOperator match"
    alternation = re.search(r".*\\%\((.*)\\\)$", match.group(1))  # the last \%(...\)
    assert alternation, match.group(1)
    operators = {re.sub(r"\\(.)", r"\1", alt) for alt in alternation.group(1).split("\\|")}
    assert operators == set(KEYWORDS["symbol-operator"])


def test_vim_indent_knows_every_call_head():
    text = VIM_INDENT.read_text(encoding="utf-8")
    block = text[text.index("let s:call_heads = [") : text.index("]", text.index("let s:call_heads = ["))]
    heads = set(re.findall(r"'((?:[^']|'')*)'", block))
    assert {w for _, w in WORDS if not w.startswith(":")} <= heads


# ---------------------------------------------------------------- Emacs


def _emacs_keywords() -> dict[str, set[str]]:
    text = EMACS_MODE.read_text(encoding="utf-8")
    start = text.index("(defconst cat-keywords")
    block = text[start : text.index('"Words of the .cat language', start)]
    groups = {}
    for category, body in re.findall(r"\(([a-z-]+)((?:\s+\"(?:[^\"\\]|\\.)*\")+)\s*\)", block):
        groups[category] = {re.sub(r"\\(.)", r"\1", w) for w in re.findall(r"\"((?:[^\"\\]|\\.)*)\"", body)}
    return groups


@pytest.mark.parametrize(("category", "word"), WORDS)
def test_emacs_mode_has_every_word(category, word):
    assert word in _emacs_keywords().get(category, set()), (
        f"{EMACS_MODE.relative_to(ROOT)}: cat-keywords lacks {word!r} in ({category} ...)"
    )


def test_emacs_mode_has_no_unknown_category():
    assert set(_emacs_keywords()) == set(KEYWORDS)


def test_generated_lists_have_nothing_extra():
    """A word removed from symbols.py disappears from the editors too."""
    vim_words = set().union(*_vim_keywords().values()) - {"contained"}
    assert vim_words == {w for c, w in WORDS if c != "symbol-operator"}
    for category, words in _emacs_keywords().items():
        assert words == set(KEYWORDS[category]), category
