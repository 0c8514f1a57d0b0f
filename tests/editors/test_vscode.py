"""The VS Code extension (editors/vscode): manifest, snippets, grammar tests, packaging.

The tests marked ``editors`` need node and ``npm ci`` in editors/vscode
(``.ci/install-editors.sh``); they run offline.
"""

from __future__ import annotations

import json
import re
import zipfile

import pytest

from catgrammar import Diagnostics, parse_text
from catgrammar.symbols import all_keywords

from ._tools import CONTEXTS, ROOT, VSCODE, explain, glued, node_bin, run, tool
from .test_keywords import TM_SCOPES

MANIFEST = json.loads((VSCODE / "package.json").read_text(encoding="utf-8"))


# ---------------------------------------------------------------- manifest (no tools)


def test_manifest_declares_the_language_grammar_and_snippets():
    contributes = MANIFEST["contributes"]
    [language] = contributes["languages"]
    assert language["id"] == "cat" and language["extensions"] == [".cat"]
    assert (VSCODE / language["configuration"]).is_file()
    [grammar] = contributes["grammars"]
    assert grammar == {"language": "cat", "scopeName": "source.cat", "path": "./syntaxes/cat.tmLanguage.json"}
    assert json.loads((VSCODE / grammar["path"]).read_text())["scopeName"] == "source.cat"
    [snippets] = contributes["snippets"]
    assert snippets["language"] == "cat" and (VSCODE / snippets["path"]).is_file()


def test_manifest_starts_the_language_server():
    # main is the bundle esbuild makes from extension.js before packaging (npm run bundle)
    assert MANIFEST["main"] == "./dist/extension.js" and "--outfile=dist/extension.js" in MANIFEST["scripts"]["bundle"]
    assert (
        "extension.js" in MANIFEST["scripts"]["bundle"].split() and "--external:vscode" in MANIFEST["scripts"]["bundle"]
    )
    assert MANIFEST["scripts"]["vscode:prepublish"] == "npm run bundle"
    assert "onLanguage:cat" in MANIFEST["activationEvents"]
    setting = MANIFEST["contributes"]["configuration"]["properties"]["catc.serverPath"]
    assert setting["type"] == "string" and setting["default"] == "catc"
    assert MANIFEST["contributes"]["configuration"]["properties"]["catc.serverArgs"]["default"] == ["lsp"]
    assert "vscode-languageclient" in MANIFEST["dependencies"]
    assert MANIFEST["devDependencies"] == {
        "@vscode/vsce": "3.9.2",
        "esbuild": "0.25.12",
        "vscode-tmgrammar-test": "0.1.3",
    }
    source = (VSCODE / "extension.js").read_text(encoding="utf-8")
    assert "require('vscode-languageclient/node')" in source
    assert "getConfiguration('catc')" in source and "'serverPath'" in source


QUERY_COMMANDS = {"catc.runSolve": "solve", "catc.runDiagnose": "diagnose", "catc.runRelax": "relax"}


def test_manifest_commands_are_the_extensions_commands():
    """Every contributed command is registered by extension.js and every registered one is
    contributed; the query commands ask the server for queries it serves and are offered in
    .cat editors only."""
    from catc.queries import registry

    source = (VSCODE / "extension.js").read_text(encoding="utf-8")
    contributed = {c["command"]: c for c in MANIFEST["contributes"]["commands"]}
    registered = set(re.findall(r"registerCommand\('([^']+)'", source))
    table = dict(re.findall(r"'(catc\.run\w+)': \{ query: '(catc\.\w+)'", source))
    assert set(table) == set(QUERY_COMMANDS)
    assert set(contributed) == registered | set(table)
    for command, query in QUERY_COMMANDS.items():
        assert table[command] == f"catc.{query}" and query in registry.names()
        assert contributed[command]["title"] == query.capitalize() and contributed[command]["category"] == "catc"
    palette = {m["command"]: m["when"] for m in MANIFEST["contributes"]["menus"]["commandPalette"]}
    assert palette == {c: "editorLangId == cat" for c in QUERY_COMMANDS}
    # the server's own command ids are registered by vscode-languageclient: never reused
    assert not {f"catc.{q}" for q in registry.names()} & set(contributed)


def test_language_configuration():
    config = json.loads((VSCODE / "language-configuration.json").read_text(encoding="utf-8"))
    assert config["comments"] == {"lineComment": ";"}
    assert ["(", ")"] in config["brackets"] and ["{", "}"] in config["brackets"]
    assert {"(", "{", '"'} <= {pair["open"] for pair in config["autoClosingPairs"]}
    word = re.compile(config["wordPattern"])
    assert word.fullmatch(":max-preconditions") and word.fullmatch("lidar-driver") and word.fullmatch("-1.5e3")


def _expand(body: list[str]) -> str:
    """A snippet body with every placeholder at its default (first choice) value."""
    text = "\n".join(body)
    text = re.sub(r"\$\{\d+\|([^,|}]*)[^}]*\|\}", r"\1", text)  # ${1|a,b|} -> a
    while re.search(r"\$\{\d+:([^{}]*)\}", text):
        text = re.sub(r"\$\{\d+:([^{}]*)\}", r"\1", text)  # ${1:default} -> default
    return re.sub(r"\$\d+", "", text)


SNIPPETS = json.loads((VSCODE / "snippets" / "cat.json").read_text(encoding="utf-8"))
#: How each snippet is embedded to make a whole file (``%s`` is the expanded snippet).
SNIPPET_HOSTS = {
    "Domain": "%s",
    "Problem": "%s",
    "Morphism": "(define (domain d) %s)",
    "Resources": "(define (domain d) %s)",
    "Resource": "(define (domain d) (:resources %s))",
    "View": "(define (domain d) %s)",
    "Hole": "(define (domain d) %s)",
}


def test_required_snippets_exist():
    prefixes = {p for s in SNIPPETS.values() for p in s["prefix"]}
    assert {"domain", "problem", "morphism", "resource", "view", "hole"} <= prefixes
    assert set(SNIPPETS) == set(SNIPPET_HOSTS)


@pytest.mark.parametrize("name", sorted(SNIPPETS))
def test_snippet_expands_to_valid_cat(name):
    text = SNIPPET_HOSTS[name] % _expand(SNIPPETS[name]["body"])
    assert "$" not in text, text
    diags = Diagnostics()
    tree = parse_text(text, f"<snippet {name}>", diags)
    assert tree is not None and not diags.has_errors, f"{text}\n{[d.message for d in diags]}"


# ---------------------------------------------------------------- with node


def _grammar_test(*patterns: str):
    binary = node_bin("vscode-tmgrammar-test")
    return run([binary, *patterns], cwd=VSCODE)


@pytest.mark.editors
def test_grammar_tests_pass():
    tests = sorted(VSCODE.glob("tests/*.cat.test"))
    assert len(tests) >= 3
    result = _grammar_test("tests/*.cat.test")
    assert result.returncode == 0, explain(result)
    for test in tests:
        assert f"{test.relative_to(VSCODE)} run successfuly" in result.stdout, explain(result)


def keyword_syntax_test() -> str:
    """A vscode-tmgrammar-test file checking every word of all_keywords()."""
    lines = ['; SYNTAX TEST "source.cat" "every word of catgrammar.symbols.all_keywords()"']
    all_scopes = " ".join(TM_SCOPES.values())
    for category, words in all_keywords().items():
        for word in words:
            text = CONTEXTS[category] % word
            column = text.index(word)
            lines += [text, ";" + " " * (column - 1) + "^" * len(word) + " " + TM_SCOPES[category]]
            for name in glued(word):
                lines += [f"(x {name} y)", ";  " + "^" * len(name) + " source.cat - " + all_scopes]
    return "\n".join(lines) + "\n"


@pytest.mark.editors
def test_grammar_highlights_every_keyword(tmp_path):
    path = tmp_path / "keywords.cat.test"
    path.write_text(keyword_syntax_test(), encoding="utf-8")
    result = _grammar_test(str(path))
    assert result.returncode == 0, explain(result)
    assert "run successfuly" in result.stdout, explain(result)


@pytest.mark.editors
def test_grammar_tests_can_fail(tmp_path):
    """A wrong assertion is reported (so a passing run means something)."""
    path = tmp_path / "wrong.cat.test"
    path.write_text('; SYNTAX TEST "source.cat"\n(and-gate x)\n;^^^ keyword.operator.word.cat\n', encoding="utf-8")
    result = _grammar_test(str(path))
    assert result.returncode != 0, explain(result)
    assert "missing required scopes: keyword.operator.word.cat" in result.stdout, explain(result)


@pytest.mark.editors
def test_vsix_package(tmp_path):
    vsce = node_bin("vsce")
    vsix = tmp_path / "cat-language.vsix"
    result = run([vsce, "package", "--allow-missing-repository", "--out", str(vsix)], cwd=VSCODE)
    assert result.returncode == 0, explain(result)
    assert "WARNING" not in result.stdout + result.stderr, explain(result)  # e.g. "N unbundled files"
    assert vsix.is_file() and zipfile.is_zipfile(vsix)
    with zipfile.ZipFile(vsix) as archive:
        names = set(archive.namelist())
        manifest = json.loads(archive.read("extension/package.json"))
        archive.extractall(tmp_path / "unpacked")
    assert {
        "extension/package.json",
        "extension/dist/extension.js",
        "extension/language-configuration.json",
        "extension/syntaxes/cat.tmLanguage.json",
        "extension/snippets/cat.json",
        "extension.vsixmanifest",
    } <= names
    # one bundled file: no node_modules, no unbundled sources
    assert not [n for n in names if "/node_modules/" in n] and "extension/extension.js" not in names
    assert len(names) < 15, sorted(names)
    assert manifest["name"] == MANIFEST["name"] and manifest["version"] == MANIFEST["version"]
    # Neither the tests nor the development tools are shipped.
    assert not [n for n in names if n.startswith("extension/tests/")]
    assert not [n for n in names if "/node_modules/@vscode/vsce/" in n or "vscode-tmgrammar-test" in n]
    # The packaged extension loads with what it ships (vscode-languageclient included).
    node = tool("node")
    loaded = run([node, str(VSCODE / "tests" / "load-extension.js"), str(tmp_path / "unpacked" / "extension")])
    assert loaded.returncode == 0, explain(loaded)
    assert "loaded catc.cat-language@" in loaded.stdout and "./dist/extension.js" in loaded.stdout


def _run_query_commands(tmp_path, answer: dict) -> dict:
    answer_file = tmp_path / "answer.json"
    answer_file.write_text(json.dumps(answer), encoding="utf-8")
    problem = ROOT / "examples" / "detection" / "person.cat"
    script = VSCODE / "tests" / "run-query-commands.js"
    result = run([tool("node"), str(script), str(VSCODE / "extension.js"), str(problem), str(answer_file)])
    assert result.returncode == 0, explain(result)
    return json.loads(result.stdout)


@pytest.mark.editors
def test_query_commands_ask_the_server_and_show_the_answer(tmp_path):
    """extension.js run with stand-ins for VS Code and the language client: each query
    command saves the file, sends workspace/executeCommand catc.<query> with its URI and
    writes the answer (a real `catc solve --json` document) to the "catc answers" channel."""
    import subprocess
    import sys

    problem = ROOT / "examples" / "detection" / "person.cat"
    solved = subprocess.run(
        [sys.executable, "-m", "catc", "solve", "--json", str(problem)], capture_output=True, text=True, check=True
    )
    answer = json.loads(solved.stdout)
    out = _run_query_commands(tmp_path, answer)
    assert set(QUERY_COMMANDS) <= set(out["registered"])
    assert out["requests"] == [
        {"method": "workspace/executeCommand", "params": {"command": f"catc.{q}", "arguments": [problem.as_uri()]}}
        for q in QUERY_COMMANDS.values()
    ]
    assert out["saved"] == 1  # the dirty document is saved before the first query
    shown = "\n".join(out["channels"]["catc answers"])
    assert "Solve examples/detection/person.cat\nschema catc.solve/1, status sat\n{" in shown
    assert json.loads(out["results"]["catc.runSolve"].split("\n", 2)[2]) == answer
    assert "Diagnose examples/detection/person.cat" in shown and "Relax examples/detection/person.cat" in shown


@pytest.mark.editors
def test_query_commands_show_input_errors(tmp_path):
    from catc.interfaces.lsp import run_query_on_file

    broken = tmp_path / "broken.cat"
    broken.write_text("(define (problem p) (:domain nowhere-to-be-found))\n", encoding="utf-8")
    answer = run_query_on_file("solve", broken.as_uri())
    assert answer["schema"] == "catc.error/1"
    out = _run_query_commands(tmp_path, answer)
    text = out["results"]["catc.runSolve"]
    assert "error: the query could not run" in text
    assert f"{broken}:1:30: [E0207] domain 'nowhere-to-be-found' not found" in text


def test_keyword_syntax_test_covers_every_word():
    text = keyword_syntax_test()
    for category, words in all_keywords().items():
        for word in words:
            assert (CONTEXTS[category] % word) + "\n" in text


def test_grammar_test_files_are_not_cat_files():
    """The grammar tests hold fragments, not programs: they must not join the corpus of
    .cat files that the repository's own tests check."""
    assert not list(VSCODE.glob("tests/**/*.cat"))
