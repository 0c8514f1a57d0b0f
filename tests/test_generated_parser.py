"""The generated LALR tables (catgrammar/_lalr.py): fresh, equivalent to Lark, Lark-free.

``catc`` parses with tables that ``python -m catgrammar.build_parser`` computes from
``cat.lark`` with the real Lark, so that a run of ``catc`` never imports Lark.  These tests
fail when the tables are stale, when the driver builds anything different from what Lark
itself builds with the same callbacks, or when Lark creeps back into the start-up path.
Also here: the AST nodes, written out by hand for start-up speed, must still behave as the
frozen slotted dataclasses they replaced.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import os
import pickle
import subprocess
import sys

import pytest
from conftest import ROOT, repo_cat_files

from catgrammar import _lalr, ast, build_parser
from catgrammar.diagnostics import Diagnostics
from catgrammar.parser import _Builder, parse_text
from catgrammar.span import Source
from catgrammar.tokens import tokenize

GRAMMAR = build_parser.GRAMMAR_PATH.read_text(encoding="utf-8")
STALE = "catgrammar/_lalr.py is stale: run `python -m catgrammar.build_parser` after editing cat.lark"


# ---------------------------------------------------------------- freshness


def test_recorded_grammar_hash_matches_cat_lark():
    assert hashlib.sha256(GRAMMAR.encode("utf-8")).hexdigest() == _lalr.GRAMMAR_SHA256, STALE


def test_tables_are_what_build_parser_generates():
    current = build_parser.TABLES_PATH.read_text(encoding="utf-8")
    assert build_parser.regenerate(current, GRAMMAR) == current, STALE


def test_grammar_compiles_in_strict_mode():
    pytest.importorskip("interegular")  # Lark's strict mode needs it; it is in the test extra
    parser = build_parser.compile_grammar(GRAMMAR, strict=True)
    assert parser.options.strict


def test_generation_does_not_depend_on_the_hash_seed():
    for seed in ("1", "2"):
        proc = subprocess.run(
            [sys.executable, "-m", "catgrammar.build_parser", "--check"],
            cwd=ROOT,
            env={**os.environ, "PYTHONHASHSEED": seed},
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert proc.returncode == 0, proc.stdout + proc.stderr


def test_a_changed_grammar_is_detected(tmp_path):
    current = build_parser.TABLES_PATH.read_text(encoding="utf-8")
    changed = GRAMMAR.replace("goal: LPAR GOAL_KW expr RPAR", "goal: LPAR GOAL_KW expr* RPAR")
    assert changed != GRAMMAR
    assert build_parser.regenerate(current, changed) != current


# ---------------------------------------------------------------- no Lark at run time

_ISOLATION = """
import sys
import catgrammar.span, catgrammar.ast
assert "catgrammar.parser" not in sys.modules, "importing catgrammar.span/ast loads the parser"
import catc.interfaces.cli, catgrammar.parser
from catgrammar.diagnostics import Diagnostics
diags = Diagnostics()
src = catgrammar.parser.read_source("examples/detection/person.cat", diags)
assert catgrammar.parser.parse_source(src, diags) is not None, [d.message for d in diags]
try:
    catc.interfaces.cli.main(["solve", "examples/detection/person.cat"], standalone_mode=False)
except SystemExit:
    pass
loaded = sorted(m for m in sys.modules if m.split(".")[0] in ("lark", "interegular"))
assert not loaded, loaded
print("isolated")
"""


def test_parsing_and_solving_never_import_lark():
    proc = subprocess.run([sys.executable, "-c", _ISOLATION], cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0 and "isolated" in proc.stdout, proc.stdout + proc.stderr


# ---------------------------------------------------------------- same results as Lark


@pytest.fixture(scope="module")
def lark_reference():
    """Lark's own LALR parser over the same grammar, tokens and callbacks."""
    lark = pytest.importorskip("lark")
    from lark.lexer import Lexer

    class Tokens(Lexer):
        def __init__(self, lexer_conf) -> None:
            pass

        def lex(self, data):
            return tokenize(data)

    builder = _Builder()
    parser = lark.Lark(GRAMMAR, parser="lalr", lexer=Tokens, maybe_placeholders=False, transformer=builder)
    return parser, builder


def _outcome(parse, builder: _Builder, text: str):
    """The value built, or the syntax error's essentials, or the diagnostics reported."""
    builder.src, builder.diags = Source("t.cat", text), Diagnostics()
    try:
        value = parse(text)
    except Exception as exc:
        token = getattr(exc, "token", None)
        if token is not None:
            return ("unexpected token", token.type, str(token), token.start_pos, frozenset(exc.expected))
        return ("error", type(exc).__name__, getattr(exc, "pos_in_stream", None))
    return ("ok", value, tuple(d.message for d in builder.diags))


def _variants(text: str):
    """The text, then the text with each token (a sample of them) deleted or doubled."""
    yield text
    tokens = list(tokenize(text))
    step = max(1, len(tokens) // 40)
    for tok in tokens[::step]:
        yield text[: tok.start_pos] + text[tok.end_pos :]
        yield text[: tok.end_pos] + " " + str(tok) + text[tok.end_pos :]


CORPUS = [p for p in repo_cat_files() + repo_cat_files(invalid=True) if "editors" not in p.parts]


@pytest.mark.parametrize("path", CORPUS, ids=lambda p: str(p.relative_to(ROOT)))
def test_same_values_and_errors_as_lark(path, lark_reference):
    lark_parser, lark_builder = lark_reference
    ours_builder = _Builder()
    ours = _lalr.Parser(ours_builder)
    try:
        text = path.read_text(encoding="utf-8")
    except UnicodeDecodeError:
        pytest.skip("not UTF-8 (rejected before parsing)")
    for variant in _variants(text):
        expected = _outcome(lark_parser.parse, lark_builder, variant)
        actual = _outcome(lambda t: ours.parse(tokenize(t)), ours_builder, variant)
        assert actual == expected, variant


def test_end_of_input_is_an_unexpected_token_with_lark_expectations(lark_reference):
    lark_parser, lark_builder = lark_reference
    ours = _lalr.Parser(_Builder())
    for text in ["(define (domain d)", "(define (domain d) (:morphism m :cost", ""]:
        ours.builder.src, ours.builder.diags = Source("t.cat", text), Diagnostics()
        lark_builder.src, lark_builder.diags = ours.builder.src, ours.builder.diags
        if not text:
            assert ours.parse(tokenize(text)) == lark_parser.parse(text) == ()
            continue
        with pytest.raises(_lalr.UnexpectedToken) as ours_exc:
            ours.parse(tokenize(text))
        with pytest.raises(Exception) as lark_exc:
            lark_parser.parse(text)
        assert ours_exc.value.token.type == lark_exc.value.token.type == "$END"
        assert ours_exc.value.expected == set(lark_exc.value.expected)


def test_a_builder_without_a_callback_is_refused():
    with pytest.raises(TypeError, match="no callback"):
        _lalr.Parser(object())


def test_parses_share_no_state():
    """Each parse makes its own builder and parser (no module-level builder to lock): two
    parses interleaved by threads build exactly what each would alone."""
    import threading

    texts = [path.read_text(encoding="utf-8") for path in repo_cat_files()[:6]]
    alone = [parse_text(t, f"t{i}.cat") for i, t in enumerate(texts)]
    together: dict[int, object] = {}

    def parse(i: int) -> None:
        for _ in range(5):
            together[i] = parse_text(texts[i], f"t{i}.cat")

    threads = [threading.Thread(target=parse, args=(i,)) for i in range(len(texts))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert [together[i] for i in range(len(texts))] == alone


# ---------------------------------------------------------------- AST nodes = frozen dataclasses


NODES = [
    cls for cls in vars(ast).values() if isinstance(cls, type) and issubclass(cls, ast._Node) and cls is not ast._Node
]


def _reference(cls):
    """The frozen slotted dataclass the node class used to be."""
    hints = {name: eval(cls.__annotations__[name], vars(ast)) for name in cls.__slots__}  # the node's own fields
    return dataclasses.make_dataclass(
        cls.__name__, [(name, hints[name]) for name in cls.__slots__], frozen=True, slots=True
    )


def test_every_node_class_is_checked():
    assert len(NODES) >= 35
    assert {"Name", "Call", "MorphismDecl", "Domain", "Problem", "SourceFile"} <= {c.__name__ for c in NODES}


@pytest.mark.parametrize("cls", NODES, ids=lambda c: c.__name__)
def test_nodes_behave_like_frozen_slotted_dataclasses(cls):
    ref = _reference(cls)
    names = tuple(f.name for f in dataclasses.fields(ref))
    assert tuple(f.name for f in dataclasses.fields(cls)) == names == cls.__match_args__ == ref.__match_args__
    assert dataclasses.is_dataclass(cls)

    values = [f"v{i}" for i in range(len(names))]
    node, twin, other = cls(*values), cls(**dict(zip(names, values))), cls(*values[:-1], "different")
    expected = ref(*values)
    assert node == twin and node != other and hash(node) == hash(twin) == hash(expected)
    assert (node == expected) is False  # different classes never compare equal, as dataclasses
    assert repr(node) == repr(expected).replace(ref.__qualname__, cls.__qualname__, 1)
    assert [getattr(node, n) for n in names] == values
    assert not hasattr(node, "__dict__")
    for act in (
        lambda: setattr(node, names[0], "x"),
        lambda: delattr(node, names[0]),
        lambda: setattr(node, "extra", 1),
    ):
        with pytest.raises(dataclasses.FrozenInstanceError):
            act()
    assert pickle.loads(pickle.dumps(node)) == node
    assert copy.deepcopy(node) == node and copy.copy(node) == node
    assert dataclasses.replace(node, **{names[-1]: "different"}) == other
    assert dataclasses.asdict(node) == dict(zip(names, values))
    match node:
        case cls(first):  # positional patterns use __match_args__
            assert first == values[0]
        case _:
            pytest.fail("no match")


def test_parsed_nodes_hash_and_compare_by_value():
    from catgrammar.parser import parse_text

    text = (ROOT / "examples" / "detection" / "person.cat").read_text()
    a, b = parse_text(text, "p.cat"), parse_text(text, "p.cat")
    assert a is not None and a == b and hash(a.definitions) == hash(b.definitions)
