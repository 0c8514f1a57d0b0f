"""catc lsp: the real server over stdio, driven by pytest-lsp.

Needs the ``lsp`` extra (pygls 2, lsprotocol) and pytest-lsp; skipped without them."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from conftest import ROOT

try:
    import _lsp_session
    import pytest_asyncio  # (a pytest-lsp dependency)
    import pytest_lsp
    from lsprotocol import types
    from pygls.lsp.server import LanguageServer  # noqa: F401
    from pytest_lsp import ClientServerConfig, LanguageClient
except ImportError as exc:  # the lsp extra or pytest-lsp is missing
    MISSING = (
        f"the LSP tests need the 'lsp' extra and pytest-lsp ({exc.name or exc} is missing): "
        "pip install 'catc-lang[lsp]' pytest-lsp"
    )
    needs_lsp = pytest.mark.skip(reason=MISSING)
    LanguageClient = object  # only in annotations of skipped tests
else:
    MISSING = None
    needs_lsp = pytest.mark.asyncio(loop_scope="module")  # the module's server lives in the module's loop

EXAMPLE = ROOT / "tests" / "fixtures" / "lsp" / "detection"  # examples/detection, every resource its own
DOMAIN = EXAMPLE / "domain.cat"
PROBLEM = EXAMPLE / "person.cat"


if MISSING is None:
    # one server for the module's tests (issue 28), reset after each: tests/_lsp_session.py
    @pytest_lsp.fixture(config=ClientServerConfig(server_command=[sys.executable, "-m", "catc", "lsp"]), scope="module")
    async def server(lsp_client: LanguageClient):
        await lsp_client.initialize_session(
            types.InitializeParams(
                capabilities=pytest_lsp.client_capabilities("visual-studio-code"),
                root_uri=ROOT.as_uri(),
            )
        )
        yield
        await lsp_client.shutdown_session()

    @pytest_asyncio.fixture(loop_scope="module")
    async def client(server: LanguageClient):
        yield server
        await _lsp_session.reset(server)


def _open(client: LanguageClient, path: Path, text: str | None = None) -> str:
    uri = path.resolve().as_uri()
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(
            types.TextDocumentItem(
                uri=uri, language_id="cat", version=1, text=path.read_text() if text is None else text
            )
        )
    )
    return _lsp_session.opened(client, uri)


async def _diagnostics(client: LanguageClient, uri: str):
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return list(client.diagnostics[uri])


def _pos(text: str, needle: str, offset: int = 1) -> types.Position:
    i = text.index(needle) + offset
    line = text.count("\n", 0, i)
    return types.Position(line, i - (text.rfind("\n", 0, i) + 1))


@needs_lsp
async def test_clean_file_has_no_diagnostics(client: LanguageClient) -> None:
    uri = _open(client, PROBLEM)
    assert await _diagnostics(client, uri) == []


@needs_lsp
async def test_diagnostics_follow_the_in_memory_text(client: LanguageClient) -> None:
    text = PROBLEM.read_text()
    bad = text.replace("(member person detects)", "(member persn detects)")
    assert bad != text
    uri = _open(client, PROBLEM, bad)
    diags = await _diagnostics(client, uri)
    assert diags and all(d.source == "catc" for d in diags)
    assert any(d.severity == types.DiagnosticSeverity.Error for d in diags)
    assert any("persn" in d.message for d in diags)
    # the same as catc check on that text
    from catc.interfaces.lsp import analyse

    expected = {(d.code, d.message) for d in analyse(str(PROBLEM), bad).diagnostics}
    assert {(d.code, d.message) for d in diags} == expected
    # fixing the text in the editor clears them (nothing is read from disk)
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(uri=uri, version=2),
            [types.TextDocumentContentChangeWholeDocument(text=text)],
        )
    )
    assert await _diagnostics(client, uri) == []


@needs_lsp
async def test_syntax_error_is_located(client: LanguageClient) -> None:
    uri = _open(client, PROBLEM, "(define (problem p)\n  (:domain detection)\n  (:init (= ram 4)\n")
    diags = await _diagnostics(client, uri)
    assert len(diags) == 1 and diags[0].code.startswith("E01")


@needs_lsp
async def test_hover_resource_and_morphism(client: LanguageClient) -> None:
    text = DOMAIN.read_text()
    uri = _open(client, DOMAIN)
    await _diagnostics(client, uri)
    h = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(uri), _pos(text, "(>= ram", 5))
    )
    assert h is not None and "**resource** `ram`" in h.contents.value and "unit: GB (information)" in h.contents.value
    h = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(uri), _pos(text, "(:morphism camera-driver", 12))
    )
    value = h.contents.value
    assert "**morphism** `camera-driver`" in value
    assert "preconditions:" in value and "`(>= ram ram-req)`" in value
    assert "effects:" in value and "`(decrease ram ram-req)`" in value
    assert "parameters:" in value and "`ram-req` : real [GB] in (0.5 2)" in value


@needs_lsp
async def test_definition_across_files(client: LanguageClient) -> None:
    text = PROBLEM.read_text()
    uri = _open(client, PROBLEM)
    await _diagnostics(client, uri)
    # (:domain detection) → the domain file
    locs = await client.text_document_definition_async(
        types.DefinitionParams(types.TextDocumentIdentifier(uri), _pos(text, "(:domain detection", 10))
    )
    assert locs and Path(locs[0].uri.removeprefix("file://")).resolve() == DOMAIN.resolve()
    dom_text = DOMAIN.read_text()
    assert locs[0].range.start.line == dom_text.count("\n", 0, dom_text.index("(domain detection)"))
    # a resource used in the problem → its declaration in the domain
    await _definition_of_ram(client, uri, text, DOMAIN)


async def _definition_of_ram(client: LanguageClient, uri: str, text: str, declared: Path) -> None:
    locs = await client.text_document_definition_async(
        types.DefinitionParams(types.TextDocumentIdentifier(uri), _pos(text, "(= ram", 3))
    )
    assert locs and Path(locs[0].uri.removeprefix("file://")).resolve() == declared.resolve()
    line = declared.read_text().split("\n")[locs[0].range.start.line]
    assert line[locs[0].range.start.character :].startswith("ram")


@needs_lsp
async def test_definition_of_an_imported_standard_library_resource(client: LanguageClient) -> None:
    """examples/detection imports robot-base: its ram is declared in the stdlib's compute domain."""
    problem = ROOT / "examples" / "detection" / "person.cat"
    uri = _open(client, problem)
    await _diagnostics(client, uri)
    await _definition_of_ram(client, uri, problem.read_text(), ROOT / "stdlib_domains" / "compute.cat")


@needs_lsp
async def test_completion_has_keywords_and_names(client: LanguageClient) -> None:
    uri = _open(client, PROBLEM)
    await _diagnostics(client, uri)
    res = await client.text_document_completion_async(
        types.CompletionParams(types.TextDocumentIdentifier(uri), types.Position(0, 0))
    )
    items = res.items if isinstance(res, types.CompletionList) else res
    labels = {i.label for i in items}
    assert {":morphism", ":precondition", "member"} <= labels
    assert {"ram", "camera-driver", "mounted"} <= labels


@needs_lsp
async def test_document_symbols(client: LanguageClient) -> None:
    uri = _open(client, DOMAIN)
    await _diagnostics(client, uri)
    syms = await client.text_document_document_symbol_async(
        types.DocumentSymbolParams(types.TextDocumentIdentifier(uri))
    )
    assert [s.name for s in syms] == ["detection"]
    children = {(c.name, c.detail) for c in syms[0].children}
    assert ("detects", "resource") in children and ("camera-driver", "morphism") in children


def test_missing_pygls_message() -> None:
    """Without pygls the command explains which extra to install and exits 2."""
    code = (
        "import sys, builtins\n"
        "real = builtins.__import__\n"
        "def fake(name, *a, **k):\n"
        "    if name.split('.')[0] in ('pygls', 'lsprotocol'):\n"
        "        raise ImportError(name)\n"
        "    return real(name, *a, **k)\n"
        "builtins.__import__ = fake\n"
        "from catc.interfaces.cli import main\n"
        "sys.argv = ['catc', 'lsp']\n"
        "main()\n"
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert "catc lsp needs the 'lsp' extra: pip install 'catc-lang[lsp]'" in proc.stderr


# ---------------------------------------------------------------- the analysis (no pygls needed)

EVERY = ROOT / "tests" / "fixtures" / "valid" / "every-construct.cat"


@pytest.mark.parametrize(
    "name, kind, declared",
    [
        ("every-construct", "domain", "(domain every-construct)"),
        ("every-construct-problem", "problem", "(problem every-construct-problem)"),
        ("thermal-class", "sort", "thermal-class - class"),
        ("bright", "enum value", "(enum bright dark)"),
        ("person", "constant", "person - class"),
        ("fire-extinguisher", "object", "fire-extinguisher - class"),
        ("confidence", "resource", "(confidence real"),
        ("detector", "morphism", "(:morphism detector"),
        ("software", "view", "(:view software :drop"),
        ("new-skill", "hole", "(:hole new-skill"),
    ],
)
def test_definitions(name: str, kind: str, declared: str) -> None:
    from catc.interfaces.lsp import analyse, lookup

    text = EVERY.read_text()
    a = analyse(str(EVERY), text)
    assert a.diagnostics == [] or all(d.severity.name != "ERROR" for d in a.diagnostics)
    defs = [d for d in lookup(a, name) if d.kind == kind]
    assert defs, f"no {kind} {name}"
    d = defs[0]
    assert text[d.span.start : d.span.end] == name
    assert text.index(declared) <= d.span.start < text.index(declared) + len(declared)


def test_imported_domain_definitions_and_hover() -> None:
    from catc.interfaces.lsp import analyse, hover_text, lookup, names_in_scope, word_at

    a = analyse(str(EVERY), EVERY.read_text())
    # robot-base (the standard library) is imported: its resources are in scope
    assert "budget" in names_in_scope(a)
    budget = lookup(a, "budget")
    assert budget and budget[0].span.file.endswith("external.cat")  # robot-base imports external
    assert "**resource** `budget`" in hover_text(a, "budget")
    assert "(enum bright dark)" in hover_text(a, "lighting")
    assert "**hole** `new-skill`" in hover_text(a, "new-skill")
    assert "**view** `perception`" in hover_text(a, "perception")
    assert word_at("  (:morphism mount-lidar\n", 0, 15) == "mount-lidar"
    assert word_at("  (:morphism mount-lidar\n", 0, 4) == ":morphism"


def test_diagnostics_use_the_given_text_not_the_file() -> None:
    from catc.interfaces.lsp import analyse

    text = EVERY.read_text().replace("(>= confidence 0.7)", "(>= confidenc 0.7)")
    a = analyse(str(EVERY), text)
    assert any("confidenc" in d.message for d in a.diagnostics)


@needs_lsp
async def test_every_query_is_a_server_command(client: LanguageClient) -> None:
    """workspace/executeCommand catc.<query> answers with the command line's --json document."""
    from catc.queries import registry

    result = await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="catc.solve", arguments=[PROBLEM.resolve().as_uri()])
    )
    assert result["schema"] == "catc.solve/1" and result["status"] == "sat"
    budget = (ROOT / "examples/lifelong/budget-cut.cat").resolve().as_uri()
    result = await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="catc.diagnose", arguments=[budget])
    )
    labels = {c["label"] for c in result["cores"][0]}
    assert result["schema"] == "catc.diagnose/1" and labels == {"init/budget", "pre/buy-lidar/1"}
    result = await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="catc.relax", arguments=[budget, {"discrete": True}])
    )
    assert result["schema"] == "catc.relax/1" and [d["label"] for d in result["dropped"]] == ["init/budget"]
    result = await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="catc.optimize", arguments=[PROBLEM.resolve().as_uri()])
    )
    assert result["schema"] == "catc.error/1" and "nothing to optimise" in result["diagnostics"][0]["message"]
    for name in registry.names():  # every query is a command; none crashes on a file it cannot answer
        result = await client.workspace_execute_command_async(
            types.ExecuteCommandParams(command=f"catc.{name}", arguments=[PROBLEM.resolve().as_uri()])
        )
        assert result["schema"] in (f"catc.{name}/1", "catc.error/1")
    plan = {"steps": [[{"morphism": "mount-rgb-camera"}]]}
    result = await client.workspace_execute_command_async(
        types.ExecuteCommandParams(command="catc.validate", arguments=[PROBLEM.resolve().as_uri(), {"plan": plan}])
    )
    assert result["schema"] == "catc.validate/1" and result["valid"] is False


def test_hover_says_what_a_morphism_is_grounded_as() -> None:
    from catc.interfaces.lsp import analyse, hover_text

    path = ROOT / "examples" / "search-and-rescue" / "domain.cat"
    a = analyse(str(path), path.read_text())
    driver = hover_text(a, "rgb-driver")  # the file: :image "ghcr.io/catc-examples/usb-cam-driver:1.0" :node rgb_camera
    assert driver is not None
    assert "grounded as ROS 2 node `rgb_camera` in image `ghcr.io/catc-examples/usb-cam-driver:1.0`" in driver
    lidar = hover_text(a, "mount-lidar")
    assert lidar is not None and "grounded as a hardware step" in lidar
    every = analyse(str(EVERY), EVERY.read_text())
    some = next(name for dom in every.domains for name in dom.morphisms)
    assert "no grounding" in (hover_text(every, some) or "")


# ---------------------------------------------------------------- hardening (issue 15, Found 8)

EMOJI = (
    "(define (domain faces) (:requirements :numeric)\n"
    '  (:resources (mood real :doc "🤖🤖") (battery real))\n'  # two characters beyond the BMP first
    '  (:morphism smile :doc "😀" :precondition (>= batery 1) :effect (increase battery 1)))\n'
)


def _utf16(line: str, code_points: int) -> int:
    return len(line[:code_points].encode("utf-16-le")) // 2


@needs_lsp
async def test_positions_are_utf16_after_characters_beyond_the_bmp(client: LanguageClient, tmp_path) -> None:
    """The server speaks UTF-16 to a client that offers nothing else: a diagnostic after an
    emoji starts one unit further right than its code-point column, a hover there finds the
    name and a definition after two emoji is two units further (the server used to count code
    points both ways: wrong columns and dead hovers)."""
    path = tmp_path / "faces.cat"
    path.write_text(EMOJI)
    uri = _open(client, path)
    diags = await _diagnostics(client, uri)
    resources, smile = EMOJI.split("\n")[1:3]
    (error,) = [d for d in diags if "batery" in d.message]
    start = smile.index("batery")
    assert (error.range.start.line, error.range.start.character) == (2, _utf16(smile, start))
    assert error.range.end.character == _utf16(smile, start + len("batery"))
    at = types.Position(2, _utf16(smile, smile.index("battery 1") + 2))
    h = await client.text_document_hover_async(types.HoverParams(types.TextDocumentIdentifier(uri), at))
    assert h is not None and "**resource** `battery`" in h.contents.value
    locs = await client.text_document_definition_async(types.DefinitionParams(types.TextDocumentIdentifier(uri), at))
    assert locs and locs[0].range.start == types.Position(1, _utf16(resources, resources.index("battery")))


if MISSING is None:

    @pytest_lsp.fixture(
        config=ClientServerConfig(server_command=[sys.executable, "-m", "catc", "lsp"]), loop_scope="module"
    )
    async def client_utf8(lsp_client: LanguageClient):
        capabilities = pytest_lsp.client_capabilities("visual-studio-code")
        capabilities.general.position_encodings = [types.PositionEncodingKind.Utf8, types.PositionEncodingKind.Utf16]
        result = await lsp_client.initialize_session(types.InitializeParams(capabilities=capabilities))
        assert result.capabilities.position_encoding == types.PositionEncodingKind.Utf8
        yield
        await lsp_client.shutdown_session()


@needs_lsp
async def test_positions_follow_the_negotiated_encoding(client_utf8: LanguageClient, tmp_path) -> None:
    """A client that prefers UTF-8 (LSP 3.17 general.positionEncodings) gets byte columns."""
    path = tmp_path / "faces.cat"
    path.write_text(EMOJI)
    uri = _open(client_utf8, path)
    diags = await _diagnostics(client_utf8, uri)
    smile = EMOJI.split("\n")[2]
    (error,) = [d for d in diags if "batery" in d.message]
    assert error.range.start.character == len(smile[: smile.index("batery")].encode())


@needs_lsp
@pytest.mark.parametrize(
    "position", [(-1, 0), (2**31, 0), (0, -1), (0, 2**31), (2**31 - 1, 0), (0, 2**31 - 1), (10**6, 10**6)]
)
async def test_every_request_is_answered_whatever_its_position(client: LanguageClient, position) -> None:
    """An invalid position (LSP's uinteger is 0 … 2³¹−1) gets an error response, a valid one
    past the end of the text an empty result; before, neither got any reply and the client
    waited for ever (the wait below is only a guard against that)."""
    import asyncio

    from pygls.exceptions import JsonRpcException

    uri = _open(client, PROBLEM)
    await _diagnostics(client, uri)
    line, character = position
    valid = 0 <= line < 2**31 and 0 <= character < 2**31
    at = types.Position(0, 0)
    object.__setattr__(at, "line", line)  # past lsprotocol's validators: what a buggy client may send
    object.__setattr__(at, "character", character)
    for method, kind in (
        (types.TEXT_DOCUMENT_HOVER, types.HoverParams),
        (types.TEXT_DOCUMENT_DEFINITION, types.DefinitionParams),
    ):
        params = kind(types.TextDocumentIdentifier(uri), at)
        try:
            result = await asyncio.wait_for(client.protocol.send_request_async(method, params), timeout=120)
        except JsonRpcException as exc:
            assert not valid and exc.code == -32602  # invalid params
        else:
            assert valid and result in (None, [])


def _big_domain(morphisms: int) -> str:
    body = "\n".join(
        f"  (:morphism m{i} :uses 1 :precondition (>= x {i}) :effect (and (increase x 1) (decrease y 2)))"
        for i in range(morphisms)
    )
    return f"(define (domain big) (:requirements :numeric)\n  (:resources (x real) (y real))\n{body}\n  (:morphism bad :effect (increase z 1)))\n"


class _Published(dict):
    """client.diagnostics that also keeps every publication, in order."""

    def __init__(self) -> None:
        super().__init__()
        self.log: list[tuple[str, list]] = []

    def __setitem__(self, uri, diagnostics) -> None:
        self.log.append((uri, list(diagnostics)))
        super().__setitem__(uri, diagnostics)


@needs_lsp
async def test_a_large_document_is_checked_in_the_background(client: LanguageClient, tmp_path) -> None:
    """While a large document is being checked, a hover on another document is answered (it
    used to wait for the whole check: 169 s for 5.9 MB).  The order of the events is the
    assertion: the hover's answer comes before the large document's diagnostics."""
    client.diagnostics = _Published()
    small = _open(client, DOMAIN)
    await _diagnostics(client, small)
    big = _open(client, tmp_path / "big.cat", _big_domain(6000))  # about half a megabyte: seconds to check
    text = DOMAIN.read_text()
    h = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(small), _pos(text, "(>= ram", 5))
    )
    assert h is not None and "**resource** `ram`" in h.contents.value
    assert big not in client.diagnostics, "the hover waited for the large document's check"
    diags = await _diagnostics(client, big)
    assert any("'z'" in d.message for d in diags)


@needs_lsp
async def test_a_newer_text_makes_the_older_check_stale(client: LanguageClient, tmp_path) -> None:
    """Edits in a row: the check of a text that has been replaced is never published (it
    used to run to the end and publish diagnostics of a text the editor no longer has)."""
    client.diagnostics = _Published()
    path = tmp_path / "big.cat"
    uri = _open(client, path, _big_domain(6000))

    def change(version: int, text: str) -> None:
        client.text_document_did_change(
            types.DidChangeTextDocumentParams(
                types.VersionedTextDocumentIdentifier(uri=uri, version=version),
                [types.TextDocumentContentChangeWholeDocument(text=text)],
            )
        )

    change(2, DOMAIN.read_text().replace("(domain detection)", "(domain clean)"))
    await _diagnostics(client, uri)
    change(3, "(define (domain late) (:resources (w rea)))\n")
    await _diagnostics(client, uri)
    published = [[d.message for d in diags] for u, diags in client.diagnostics.log if u == uri]
    assert not any("'z'" in m for messages in published for m in messages), published
    assert len(published) == 2 and "unknown sort 'rea'" in published[1][0]


async def _until(client: LanguageClient, uri: str, pred, notifications: int = 20):
    """Wait for diagnostics of ``uri`` that satisfy ``pred`` (each publication, of any
    document, is one step; a bounded number of them, no clock)."""
    for _ in range(notifications):
        if pred(list(client.diagnostics.get(uri, []))):
            return list(client.diagnostics[uri])
        await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return list(client.diagnostics.get(uri, []))


@needs_lsp
async def test_a_problem_is_checked_again_when_its_open_domain_changes(client: LanguageClient, tmp_path) -> None:
    """Issue 29: with domain and problem open, renaming a resource in the (unsaved) domain left
    the problem at 0 diagnostics until the problem itself was edited."""
    import shutil

    folder = tmp_path / "detection"
    shutil.copytree(EXAMPLE, folder)
    domain_text = (folder / "domain.cat").read_text()
    problem_uri = _open(client, folder / "person.cat")
    assert await _until(client, problem_uri, lambda d: problem_uri in client.diagnostics) == []
    domain_uri = _open(client, folder / "domain.cat")
    renamed = domain_text.replace("(detects (set class)", "(found (set class)").replace("detects", "found")
    assert renamed != domain_text
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(uri=domain_uri, version=2),
            [types.TextDocumentContentChangeWholeDocument(text=renamed)],
        )
    )
    diags = await _until(client, problem_uri, lambda d: any("detects" in x.message for x in d))
    assert any("detects" in d.message and d.severity == types.DiagnosticSeverity.Error for d in diags), diags
    # renamed back: the problem is clean again, still without being edited
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(uri=domain_uri, version=3),
            [types.TextDocumentContentChangeWholeDocument(text=domain_text)],
        )
    )
    assert await _until(client, problem_uri, lambda d: d == []) == []
