"""catc lsp as a modelling tool, over stdio with pytest-lsp: references, rename,
formatting, code actions, semantic tokens, unit inlay hints, signature help, Markdown
hover, and no error answer for any request on a half-written text.

Needs the ``lsp`` extra (pygls 2, lsprotocol) and pytest-lsp; skipped without them."""

from __future__ import annotations

import random
import re
import shutil
import sys
from pathlib import Path

import pytest
from conftest import ROOT, word_uses

try:
    import _lsp_session
    import pytest_asyncio  # (a pytest-lsp dependency)
    import pytest_lsp
    from lsprotocol import types
    from pytest_lsp import ClientServerConfig, LanguageClient
except ImportError as exc:  # the lsp extra or pytest-lsp is missing
    MISSING = f"the LSP tests need the 'lsp' extra and pytest-lsp ({exc.name or exc} is missing)"
    needs_lsp = pytest.mark.skip(reason=MISSING)
    LanguageClient = object  # only in annotations of skipped tests
else:
    MISSING = None
    needs_lsp = pytest.mark.asyncio(loop_scope="module")  # the module's server lives in the module's loop

DETECTION = ROOT / "tests" / "fixtures" / "lsp" / "detection"  # examples/detection, every resource its own

if MISSING is None:
    # one server for the module's tests (issue 28), reset after each: tests/_lsp_session.py
    @pytest_lsp.fixture(config=ClientServerConfig(server_command=[sys.executable, "-m", "catc", "lsp"]), scope="module")
    async def server(lsp_client: LanguageClient):
        result = await lsp_client.initialize_session(
            types.InitializeParams(capabilities=pytest_lsp.client_capabilities("visual-studio-code"))
        )
        lsp_client.capabilities_of_server = result.capabilities  # type: ignore[attr-defined]
        yield
        await lsp_client.shutdown_session()

    @pytest_asyncio.fixture(loop_scope="module")
    async def client(server: LanguageClient):
        yield server
        await _lsp_session.reset(server)


@pytest.fixture
def model(tmp_path: Path) -> Path:
    """A copy of examples/detection (a domain and two problems that use it)."""
    folder = tmp_path / "detection"
    shutil.copytree(DETECTION, folder, ignore=shutil.ignore_patterns("*.json", "*.md"))
    return folder


def _open(client: LanguageClient, path: Path, text: str | None = None) -> str:
    uri = path.resolve().as_uri()
    text = path.read_text() if text is None else text
    client.text_document_did_open(
        types.DidOpenTextDocumentParams(types.TextDocumentItem(uri=uri, language_id="cat", version=1, text=text))
    )
    return _lsp_session.opened(client, uri)


def _change(client: LanguageClient, uri: str, version: int, text: str) -> None:
    client.text_document_did_change(
        types.DidChangeTextDocumentParams(
            types.VersionedTextDocumentIdentifier(uri=uri, version=version),
            [types.TextDocumentContentChangeWholeDocument(text=text)],
        )
    )


async def _diagnostics(client: LanguageClient, uri: str):
    await client.wait_for_notification(types.TEXT_DOCUMENT_PUBLISH_DIAGNOSTICS)
    return list(client.diagnostics[uri])


def _pos(text: str, needle: str, offset: int = 1) -> types.Position:
    i = text.index(needle) + offset
    line = text.count("\n", 0, i)
    return types.Position(line, i - (text.rfind("\n", 0, i) + 1))


def _offset(text: str, p: types.Position) -> int:
    lines = text.split("\n")
    return sum(len(x) + 1 for x in lines[: p.line]) + p.character  # ASCII texts: UTF-16 = code points


def _apply(text: str, edits) -> str:
    """TextEdits applied to ``text`` (last first, as LSP says they do not overlap)."""
    spans = sorted(
        ((_offset(text, e.range.start), _offset(text, e.range.end), e.new_text) for e in edits), reverse=True
    )
    for start, end, new in spans:
        text = text[:start] + new + text[end:]
    return text


# ---------------------------------------------------------------- references and rename


@needs_lsp
async def test_references_across_domain_and_problems(client: LanguageClient, model: Path) -> None:
    problem = model / "person.cat"
    text = problem.read_text()
    uri = _open(client, problem)
    await _diagnostics(client, uri)
    locs = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=types.TextDocumentIdentifier(uri),
            position=_pos(text, "(= ram", 3),
            context=types.ReferenceContext(include_declaration=True),
        )
    )
    got: dict[str, list[int]] = {}
    for loc in locs:
        path = Path(loc.uri.removeprefix("file://"))
        got.setdefault(path.name, []).append(_offset(path.read_text(), loc.range.start))
    expected = {p.name: word_uses(p.read_text(), "ram") for p in model.glob("*.cat")}
    assert {k: sorted(v) for k, v in got.items()} == {k: v for k, v in expected.items() if v}
    assert {"domain.cat", "person.cat", "unmodeled-class.cat"} <= set(got)
    # without the declaration: one fewer, the one in (:resources ...)
    locs = await client.text_document_references_async(
        types.ReferenceParams(
            text_document=types.TextDocumentIdentifier(uri),
            position=_pos(text, "(= ram", 3),
            context=types.ReferenceContext(include_declaration=False),
        )
    )
    assert len(locs) == sum(len(v) for v in expected.values()) - 1


@needs_lsp
async def test_rename_a_resource_across_files(client: LanguageClient, model: Path) -> None:
    domain = model / "domain.cat"
    text = domain.read_text()
    uri = _open(client, domain)
    await _diagnostics(client, uri)
    at = _pos(text, "(>= ram ram-req)", 4)
    prepared = await client.text_document_prepare_rename_async(
        types.PrepareRenameParams(types.TextDocumentIdentifier(uri), at)
    )
    assert prepared.placeholder == "ram" and prepared.range.start == _pos(text, "(>= ram ram-req)", 4)
    edit = await client.text_document_rename_async(
        types.RenameParams(types.TextDocumentIdentifier(uri), at, new_name="memory")
    )
    assert {Path(u.removeprefix("file://")).name for u in edit.changes} == {
        "domain.cat",
        "person.cat",
        "unmodeled-class.cat",
    }
    from catc.interfaces.lsp import analyse

    for u, edits in edit.changes.items():
        path = Path(u.removeprefix("file://"))
        before = path.read_text()
        after = _apply(before, edits)
        # the same as replacing the whole word by hand, outside comments
        expected = before
        for i in reversed(word_uses(before, "ram")):
            expected = expected[:i] + "memory" + expected[i + 3 :]
        assert after == expected
        assert "ram-req" in after or path.name != "domain.cat"  # another name that contains it is kept
        path.write_text(after)
    for path in model.glob("*.cat"):  # the renamed model checks as cleanly as before
        errors = [d for d in analyse(str(path), path.read_text()).diagnostics if d.severity.name == "ERROR"]
        assert errors == [], (path.name, errors)


@needs_lsp
async def test_rename_onto_an_existing_name_is_refused(client: LanguageClient, model: Path) -> None:
    from pygls.exceptions import JsonRpcException

    domain = model / "domain.cat"
    text = domain.read_text()
    uri = _open(client, domain)
    await _diagnostics(client, uri)
    with pytest.raises(JsonRpcException) as err:
        await client.text_document_rename_async(
            types.RenameParams(types.TextDocumentIdentifier(uri), _pos(text, "(>= ram ram-req)", 4), new_name="topics")
        )
    assert err.value.code == -32803 and "'topics' is already the name of a resource" in err.value.message
    for needle, shift in (("(and (member", 2), ("(ram real", 6)):  # a keyword, a built-in sort
        with pytest.raises(JsonRpcException) as err:
            await client.text_document_prepare_rename_async(
                types.PrepareRenameParams(types.TextDocumentIdentifier(uri), _pos(text, needle, shift))
            )
        assert "keyword or built-in" in err.value.message


# ---------------------------------------------------------------- formatting


@needs_lsp
async def test_formatting_is_catc_fmt(client: LanguageClient, model: Path) -> None:
    domain = model / "domain.cat"
    canonical = domain.read_text()  # the examples are formatted (test_fmt checks it)
    messy = re.sub(r"\n[ \t]+", "\n      ", canonical).replace("(:morphism", "   (:morphism")
    assert messy != canonical
    uri = _open(client, domain, messy)
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(types.TextDocumentIdentifier(uri), types.FormattingOptions(2, True))
    )
    assert _apply(messy, edits) == canonical
    _change(client, uri, 2, canonical)
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(types.TextDocumentIdentifier(uri), types.FormattingOptions(2, True))
    )
    assert edits is not None and len(edits) == 0
    _change(client, uri, 3, canonical.replace("(:morphism camera-driver", "(:morphism camera-driver ("))
    edits = await client.text_document_formatting_async(
        types.DocumentFormattingParams(types.TextDocumentIdentifier(uri), types.FormattingOptions(2, True))
    )
    assert edits is not None and len(edits) == 0  # a syntax error: no edits, and no error


# ---------------------------------------------------------------- code actions


async def _actions(client: LanguageClient, uri: str, diag) -> list:
    return await client.text_document_code_action_async(
        types.CodeActionParams(types.TextDocumentIdentifier(uri), diag.range, types.CodeActionContext([diag]))
    )


@needs_lsp
async def test_code_action_applies_a_did_you_mean(client: LanguageClient, model: Path) -> None:
    problem = model / "person.cat"
    text = problem.read_text().replace("(member person detects)", "(member persn detects)")
    uri = _open(client, problem, text)
    [diag] = await _diagnostics(client, uri)
    assert "did you mean 'person'" in diag.message
    [action] = await _actions(client, uri, diag)
    assert action.kind == types.CodeActionKind.QuickFix and action.title == "Replace with 'person'"
    [edits] = action.edit.changes.values()
    fixed = _apply(text, edits)
    assert fixed == problem.read_text()
    _change(client, uri, 2, fixed)
    assert await _diagnostics(client, uri) == []


@needs_lsp
async def test_code_action_adds_a_missing_requirement(client: LanguageClient, model: Path) -> None:
    domain = model / "domain.cat"
    text = domain.read_text().replace(" :free-parameters", "")
    uri = _open(client, domain, text)
    diags = await _diagnostics(client, uri)
    [diag] = [d for d in diags if d.code == "E0401"]
    assert "':free-parameters'" in diag.message
    [action] = await _actions(client, uri, diag)
    assert action.title == "Add ':free-parameters' to (:requirements ...)"
    fixed = _apply(text, next(iter(action.edit.changes.values())))
    assert "(:requirements :numeric :sets :grounding :free-parameters)" in fixed
    _change(client, uri, 2, fixed)
    assert await _diagnostics(client, uri) == []


@needs_lsp
async def test_no_code_action_without_a_fix(client: LanguageClient, model: Path) -> None:
    problem = model / "person.cat"
    text = problem.read_text().replace("(member person detects)", "(member qqqqqqqq detects)")
    uri = _open(client, problem, text)
    [diag] = await _diagnostics(client, uri)
    assert not await _actions(client, uri, diag)


# ---------------------------------------------------------------- display


def _decode(data: list[int], legend) -> list[tuple[int, int, int, str, set[str]]]:
    out, line, start = [], 0, 0
    for i in range(0, len(data), 5):
        dl, ds, length, kind, mods = data[i : i + 5]
        line += dl
        start = start + ds if dl == 0 else ds
        names = {m for b, m in enumerate(legend.token_modifiers) if mods >> b & 1}
        out.append((line, start, length, legend.token_types[kind], names))
    return out


@needs_lsp
async def test_semantic_tokens_colour_names_by_kind(client: LanguageClient, model: Path) -> None:
    domain = model / "domain.cat"
    text = domain.read_text()
    uri = _open(client, domain)
    await _diagnostics(client, uri)
    legend = client.capabilities_of_server.semantic_tokens_provider.legend
    result = await client.text_document_semantic_tokens_full_async(
        types.SemanticTokensParams(types.TextDocumentIdentifier(uri))
    )
    lines = text.split("\n")
    tokens = {}
    for line, start, length, kind, mods in _decode(result.data, legend):
        tokens.setdefault(lines[line][start : start + length], set()).add((kind, frozenset(mods)))

    def kinds(word: str) -> set[str]:
        return {k for k, _ in tokens[word]}

    assert kinds("ram") == {"variable"} and kinds("topics") == {"variable"}
    assert kinds("camera-driver") == {"function"} and kinds("open-vocab-detector") == {"function"}
    assert kinds("ram-req") == {"parameter"} and kinds("target") == {"parameter"}
    assert kinds("rgb-camera") == {"enumMember"} and kinds("person") == {"enumMember"}
    assert kinds("module") == {"type"} and kinds("detection") == {"namespace"}
    assert ("variable", frozenset({"declaration"})) in tokens["ram"]
    assert ("type", frozenset({"defaultLibrary"})) in tokens["symbol"]
    # a comment, a keyword and a string hold no token
    assert not ({"Detection", "and", "member", "software", "usb_cam"} & set(tokens))
    n_ram = len(word_uses(text, "ram"))
    assert sum(1 for w in _decode(result.data, legend) if lines[w[0]][w[1] : w[1] + w[2]] == "ram") == n_ram


@needs_lsp
async def test_inlay_hints_show_units_afterword_uses(client: LanguageClient, model: Path) -> None:
    domain = model / "domain.cat"
    text = domain.read_text()
    uri = _open(client, domain)
    await _diagnostics(client, uri)
    lines = text.split("\n")
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(
            types.TextDocumentIdentifier(uri), types.Range(types.Position(0, 0), types.Position(len(lines), 0))
        )
    )
    ends = sorted(_offset(text, h.position) for h in hints)
    declared = text.index("(ram real") + 1
    assert ends == [i + 3 for i in word_uses(text, "ram") if i != declared]  # every use, not the declaration
    assert all(h.label == "GB" for h in hints)
    # a range holding only the first use
    first = _pos(text, "(>= ram ram-req)", 4)
    hints = await client.text_document_inlay_hint_async(
        types.InlayHintParams(
            types.TextDocumentIdentifier(uri), types.Range(first, types.Position(first.line, first.character + 3))
        )
    )
    assert [h.position for h in hints] == [types.Position(first.line, first.character + 3)]


@needs_lsp
async def test_signature_help_in_a_morphism(client: LanguageClient, model: Path) -> None:
    domain = model / "domain.cat"
    text = domain.read_text()
    uri = _open(client, domain)
    await _diagnostics(client, uri)
    help = await client.text_document_signature_help_async(
        types.SignatureHelpParams(types.TextDocumentIdentifier(uri), _pos(text, "(and (member in topics)", 10))
    )
    [sig] = help.signatures
    labels = [p.label for p in sig.parameters]
    assert sig.label.startswith("(:morphism NAME :kind")
    assert [lab.split()[0] for lab in labels] == [
        ":kind",
        ":churn",
        ":uses",
        ":cost",
        ":parameters",
        ":precondition",
        ":effect",
        ":doc",
        ":ground",
    ]
    assert all(lab in sig.label for lab in labels)
    assert labels[help.active_parameter].startswith(":precondition")
    help = await client.text_document_signature_help_async(
        types.SignatureHelpParams(types.TextDocumentIdentifier(uri), _pos(text, "(ram real :group compute :unit", 31))
    )
    assert help.signatures[0].label.startswith("(NAME SORT :group")
    assert help.signatures[0].parameters[help.active_parameter].label.startswith(":unit")


@needs_lsp
async def test_hover_is_markdown_that_renders(client: LanguageClient, model: Path) -> None:
    domain = model / "domain.cat"
    text = domain.read_text()
    uri = _open(client, domain)
    await _diagnostics(client, uri)

    async def hover(at: types.Position) -> str:
        h = await client.text_document_hover_async(types.HoverParams(types.TextDocumentIdentifier(uri), at))
        assert h is not None and h.contents.kind == types.MarkupKind.Markdown
        return h.contents.value

    value = await hover(_pos(text, "(:morphism camera-driver", 12))
    paragraphs = value.split("\n\n")
    assert paragraphs[0].startswith("```cat\n(:morphism camera-driver") and paragraphs[0].endswith("\n```")
    assert paragraphs[1] == "**morphism** `camera-driver` (software)"
    assert "preconditions:" in paragraphs and "effects:" in paragraphs
    pre = paragraphs[paragraphs.index("preconditions:") + 1]
    assert pre.split("\n") == ["- `(member rgb-camera mounted)`", "- `(>= ram ram-req)`"]  # a list, one item a line
    assert not any(p.startswith("\n") or p.endswith("\n") for p in paragraphs[1:])
    value = await hover(_pos(text, "(>= ram ram-req)", 9))  # a θ parameter
    assert "**parameter** `ram-req` : real [GB (information)] in (0.5 2)" in value.split("\n\n")
    # an error elsewhere in the file: the hover is as full as before, from the last check
    broken = text.replace("(>= ram 4)", "(>= rom 4)")
    _change(client, uri, 2, broken)
    diags = await _diagnostics(client, uri)
    assert any("'rom'" in d.message for d in diags)
    value = await hover(_pos(broken, "(>= ram ram-req)", 4))
    blocks = value.split("\n\n")
    assert blocks[0] == "```cat\n(ram real :group compute :unit GB :bounds (0 *))\n```"
    assert blocks[1] == "**resource** `ram` : real"
    assert blocks[2].split("\n") == ["- unit: GB (information)", "- group: compute", "- bounds: (0 *)"]
    assert "as it last checked" in blocks[-1]


@needs_lsp
async def test_hover_of_a_file_that_never_checked(client: LanguageClient, model: Path) -> None:
    domain = model / "domain.cat"
    broken = domain.read_text().replace("(>= ram 4)", "(>= rom 4)")
    uri = _open(client, domain, broken)
    await _diagnostics(client, uri)
    h = await client.text_document_hover_async(
        types.HoverParams(types.TextDocumentIdentifier(uri), _pos(broken, "(>= ram ram-req)", 4))
    )
    blocks = h.contents.value.split("\n\n")
    assert blocks[0] == "```cat\n(ram real :group compute :unit GB :bounds (0 *))\n```"
    assert blocks[1] == "**resource** `ram` (in `detection`)"


@needs_lsp
async def test_capabilities_are_announced(client: LanguageClient) -> None:
    caps = client.capabilities_of_server
    assert caps.references_provider and caps.document_formatting_provider and caps.inlay_hint_provider
    assert caps.rename_provider.prepare_provider is True
    assert types.CodeActionKind.QuickFix in caps.code_action_provider.code_action_kinds
    assert caps.semantic_tokens_provider.full is True
    assert set(caps.semantic_tokens_provider.legend.token_types) >= {"variable", "function", "parameter", "type"}
    assert ":" in caps.signature_help_provider.trigger_characters


# ---------------------------------------------------------------- broken input


def _mutations(text: str, n: int, seed: int) -> list[str]:
    """Random edits of ``text``: cut a piece, duplicate one, insert a parenthesis, a quote,
    a keyword or a character beyond the BMP (deterministic: seeded)."""
    rng = random.Random(seed)
    out = []
    for _ in range(n):
        i = rng.randrange(len(text))
        j = min(len(text), i + rng.randrange(1, 40))
        choice = rng.randrange(5)
        if choice == 0:
            t = text[:i] + text[j:]
        elif choice == 1:
            t = text[:i] + text[i:j] + text[i:]
        elif choice == 2:
            t = text[:i] + rng.choice('()"{};') + text[i:]
        elif choice == 3:
            t = text[:i] + rng.choice([":morphism ", ":uses ", "(and ", ":unit ", "ram-req "]) + text[i:]
        else:
            t = text[:i] + "😀" + text[j:]
        out.append(t)
        text = t if rng.random() < 0.5 else text
    return out


@needs_lsp
async def test_no_request_fails_on_a_half_written_text(client: LanguageClient, model: Path) -> None:
    """Random edits of the domain, and every request at a few places of each: each is
    answered with a result, never an error (a traceback would come back as one), and no
    handler had to swallow an exception (it would have logged it)."""
    logged = len(client.log_messages)  # the module's server: what earlier tests logged is not this test's
    domain = model / "domain.cat"
    uri = _open(client, domain)
    await _diagnostics(client, uri)
    doc = types.TextDocumentIdentifier(uri)
    rng = random.Random(17)
    for version, text in enumerate(_mutations(domain.read_text(), 24, seed=5), start=2):
        _change(client, uri, version, text)
        await _diagnostics(client, uri)
        lines = text.split("\n")
        end = types.Position(len(lines), 0)
        await client.text_document_formatting_async(
            types.DocumentFormattingParams(doc, types.FormattingOptions(2, True))
        )
        await client.text_document_semantic_tokens_full_async(types.SemanticTokensParams(doc))
        await client.text_document_inlay_hint_async(types.InlayHintParams(doc, types.Range(types.Position(0, 0), end)))
        await client.text_document_code_action_async(
            types.CodeActionParams(doc, types.Range(types.Position(0, 0), end), types.CodeActionContext([]))
        )
        for _ in range(3):
            line = rng.randrange(len(lines))
            at = types.Position(line, rng.randrange(len(lines[line]) + 1))
            await client.text_document_hover_async(types.HoverParams(doc, at))
            await client.text_document_signature_help_async(types.SignatureHelpParams(doc, at))
            await client.text_document_references_async(
                types.ReferenceParams(
                    text_document=doc, position=at, context=types.ReferenceContext(include_declaration=True)
                )
            )
            await client.text_document_completion_async(types.CompletionParams(doc, at))
            await client.text_document_definition_async(types.DefinitionParams(doc, at))
    # the handlers catch what they did not foresee and log it: nothing was logged
    assert [m.message for m in client.log_messages[logged:] if m.type == types.MessageType.Error] == []


@pytest.mark.skipif(MISSING is not None, reason=str(MISSING))
def test_docs_list_every_feature_the_server_serves() -> None:
    """docs/editors.md has a row for every LSP method the server registers (and names no
    method it does not), and every server command."""
    from catc.interfaces.lsp import build_server

    server = build_server()
    served = set(server.protocol.fm.features)
    docs = (ROOT / "docs" / "editors.md").read_text()
    table = docs.split("## What the server does", 1)[1].split("\n## ", 1)[0]
    named = set(re.findall(r"`((?:textDocument|workspace)/[A-Za-z/]+)`", table))
    notifications = {"textDocument/didOpen", "textDocument/didChange", "textDocument/didSave"}
    assert served - {"textDocument/didClose"} <= named | notifications
    assert named - {"textDocument/publishDiagnostics", "workspace/executeCommand"} <= served
    for command in ("catc.solve", "catc.diagnose", "catc.relax"):
        assert command in server.protocol.fm.commands and f"`{command}`" in table
