"""The language server (pygls, imported when it starts): document sync with background
checks, and the features registered on it."""

from __future__ import annotations

import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from catc.interfaces.lsp.analysis import (
    WORD,
    Analysis,
    analyse,
    client_column,
    code_units,
    lookup,
    names_in_scope,
    path_to_uri,
    same_name,
    server_column,
    uri_to_path,
    word_at,
)
from catc.interfaces.lsp.commands import register_commands
from catc.interfaces.lsp.hover import hover_text
from catgrammar.span import Source, Span

# ---------------------------------------------------------------- the server


class Lines:
    """Positions for the client: catc's spans (1-based, code points) in the negotiated
    encoding, reading each file's lines once (the document's text as analysed, the other
    files as read by the analysis)."""

    def __init__(self, encoding: str, texts: Mapping[str, str]) -> None:
        self.encoding = encoding
        self.texts = {os.path.normcase(os.path.abspath(k)): v for k, v in texts.items()}
        self._lines: dict[str, list[str] | None] = {}

    def line(self, path: str, line: int) -> str | None:
        """Line ``line`` (0-based) of ``path``, or None when it is not known."""
        key = os.path.normcase(os.path.abspath(path))
        if key not in self._lines:
            text = self.texts.get(key)
            self._lines[key] = text.split("\n") if text is not None else None
        lines = self._lines[key]
        return lines[line] if lines is not None and 0 <= line < len(lines) else None

    def position(self, types: Any, path: str, line: int, column: int) -> Any:
        """A 1-based line and code-point column → an LSP Position."""
        text = self.line(path, line - 1)
        character = column - 1 if text is None else client_column(text, column - 1, self.encoding)
        return types.Position(max(line - 1, 0), max(character, 0))

    def range(self, types: Any, span: Span | None) -> Any:
        if span is None:
            return types.Range(types.Position(0, 0), types.Position(0, 0))
        return types.Range(
            self.position(types, span.file, span.line, span.column),
            self.position(types, span.file, span.end_line, span.end_column),
        )


def _encoding(ls: Any) -> str:
    """The position encoding pygls negotiated with the client ("utf-16" by default)."""
    value = getattr(ls.workspace, "position_encoding", None)
    return str(getattr(value, "value", value) or "utf-16")


def _lines(ls: Any, a: Analysis) -> Lines:
    return Lines(_encoding(ls), {**a.sources, a.path: a.text})


class Checks:
    """The background checks of open documents: one worker thread, so that the server
    answers other requests meanwhile.  Each new text of a document starts a new generation;
    a check of an older generation is stale: dropped before it starts, abandoned while it
    parses or between its phases, and its result is never published."""

    def __init__(self) -> None:
        import threading
        from concurrent.futures import ThreadPoolExecutor

        self._lock = threading.Lock()
        self._generation: dict[str, int] = {}
        self.executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="catc-check")
        self.tasks: dict[str, Any] = {}  # uri → the asyncio task that checks its latest text

    def next(self, uri: str) -> int:
        with self._lock:
            self._generation[uri] = self._generation.get(uri, 0) + 1
            return self._generation[uri]

    def stale(self, uri: str, generation: int) -> bool:
        with self._lock:
            return self._generation.get(uri) != generation

    def run(
        self, uri: str, generation: int, path: str, text: str, search: tuple[str, ...], texts: Mapping[str, str]
    ) -> Analysis | None:
        """In the worker: the analysis (the other open documents read as their editors hold
        them), or None when it became stale."""
        from catgrammar.parser import Cancelled

        if self.stale(uri, generation):
            return None
        try:
            a = analyse(path, text, search, cancelled=lambda: self.stale(uri, generation), texts=texts)
        except Cancelled:
            return None
        return None if self.stale(uri, generation) else a


def build_server() -> Any:
    """The language server: document sync with diagnostics, navigation, symbols, and one
    ``workspace/executeCommand`` command per query (``catc.solve``, ``catc.diagnose``, ...) and
    per target (``catc.export.pddl``, ...)."""
    from lsprotocol import types
    from pygls.lsp.server import LanguageServer

    from catc import __version__

    server = LanguageServer(
        "catc",
        __version__,
        text_document_sync_kind=types.TextDocumentSyncKind.Full,
        protocol_cls=_protocol_class(),
    )
    server.analyses = {}  # type: ignore[attr-defined]  # catc's own: uri → Analysis (the last one)
    server.checks = Checks()  # type: ignore[attr-defined]
    _register_documents(server, types)
    _register_navigation(server, types)
    _register_symbols(server, types)
    register_commands(server, types)
    _register_editing(server, types)
    _register_fixes(server, types)
    _register_display(server, types)
    _register_signature_help(server, types)
    return server


def _protocol_class() -> Any:
    """pygls's protocol, answering a request whose parameters cannot be read (a position of
    -1 or 2³¹: LSP's uinteger ends at 2³¹−1) with its error; pygls only logs it, and the
    client would wait for ever."""
    from pygls.exceptions import JsonRpcException
    from pygls.exceptions import JsonRpcInvalidRequest as InvalidRequest
    from pygls.protocol import LanguageServerProtocol

    class Protocol(LanguageServerProtocol):
        def structure_message(self, data: dict[str, Any]) -> Any:
            try:
                return super().structure_message(data)
            except JsonRpcException as exc:
                if "method" in data and isinstance(data.get("id"), (int, str)):
                    self._send_response(data["id"], error=exc.to_response_error())
                    return _ANSWERED
                if "method" not in data and "id" not in data:
                    return object()  # neither request, notification nor response: no message
                raise

        def handle_message(self, message: Any) -> None:
            if message is _ANSWERED:
                return
            if not hasattr(message, "jsonrpc"):  # a body of [], null, 1, "x" or {}: no message
                self._send_response(None, error=InvalidRequest("not a JSON-RPC message").to_response_error())  # type: ignore[arg-type]  # id null
                return
            super().handle_message(message)

    return Protocol


_ANSWERED = object()  # a request already answered with an error while it was read


async def _refresh(ls: Any, types: Any, uri: str, generation: int, text: str, cascade: bool = True) -> None:
    """Check ``text``, the document's text of ``generation``, in the background and publish
    its diagnostics (unless a newer text came meanwhile); with ``cascade``, then check again
    the other open documents that read this one (a problem whose domain changed: its
    diagnostics must not go stale until it is edited itself)."""
    import asyncio

    from catc.interfaces.command import search_path

    loop = asyncio.get_running_loop()
    try:
        a = await loop.run_in_executor(
            ls.checks.executor,
            ls.checks.run,
            uri,
            generation,
            uri_to_path(uri),
            text,
            search_path(),
            _open_texts(ls),
        )
    except Exception as exc:  # never take the editor down with an internal error
        ls.window_log_message(types.LogMessageParams(types.MessageType.Error, f"catc: {exc!r}"))
        return
    if a is None or ls.checks.stale(uri, generation):
        return
    previous = ls.analyses.get(uri)
    if a.tree is None and previous is not None:  # keep symbols/definitions of the last good parse
        a.definitions = previous.definitions or a.definitions
        if not a.domains:
            a.domains = list(previous.domains)
            a.stale |= {id(d) for d in a.domains}
        a.tree = previous.tree
        a.sources = {**previous.sources, **a.sources}
    if previous is not None:
        _keep_last_good(a, previous)
    ls.analyses[uri] = a
    _publish(ls, types, uri, a)
    if cascade:
        for other in _dependents(ls, uri):
            _schedule(ls, types, other, cascade=False)


def _dependents(ls: Any, uri: str) -> list[str]:
    """The other open documents whose last check read ``uri``'s file, or that sit in its
    folder (a problem uses the domain beside it; a renamed name may newly break it)."""
    from catc.frontend.workspace import normalise_path

    path = normalise_path(uri_to_path(uri))
    out = []
    for other in list(ls.workspace.text_documents):
        if other == uri or not other.startswith("file:"):
            continue
        a = ls.analyses.get(other)
        read = {normalise_path(p) for p in a.sources} if a is not None else set()
        same_folder = normalise_path(str(Path(uri_to_path(other)).parent)) == normalise_path(str(Path(path).parent))
        if path in read or same_folder:
            out.append(other)
    return out


def _keep_last_good(a: Analysis, previous: Analysis) -> None:
    """A domain (or problem) of this document that does not check now keeps the checked
    model of its last version that did, marked stale: hover, semantic tokens and unit hints
    go on working while the text is being edited."""
    defined = {(d.kind, d.name) for d in a.definitions if same_name(d.span.file, a.path)}
    have = {x.name for x in a.domains}
    for dom in previous.domains:
        if dom.name not in have and ("domain", dom.name) in defined:
            a.domains.append(dom)
            a.stale.add(id(dom))
    have = {x.name for x in a.problems}
    for prob in previous.problems:
        if prob.name not in have and ("problem", prob.name) in defined:
            a.problems.append(prob)
            a.stale.add(id(prob))


def _lsp_diagnostic(types: Any, lines: Lines, d: Any) -> Any:
    from catgrammar.diagnostics import Severity

    severity = {
        Severity.ERROR: types.DiagnosticSeverity.Error,
        Severity.WARNING: types.DiagnosticSeverity.Warning,
    }
    related = [
        types.DiagnosticRelatedInformation(
            types.Location(path_to_uri(note.span.file), lines.range(types, note.span)),
            note.message,
        )
        for note in getattr(d, "notes", ()) or ()
        if getattr(note, "span", None) is not None
    ]
    return types.Diagnostic(
        range=lines.range(types, d.span),
        message=d.message,
        severity=severity.get(d.severity, types.DiagnosticSeverity.Information),
        code=d.code,
        source="catc",
        related_information=related or None,
    )


def _publish(ls: Any, types: Any, uri: str, a: Analysis) -> None:
    lines = _lines(ls, a)
    out = [_lsp_diagnostic(types, lines, d) for d in a.diagnostics]
    ls.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=out))


def _schedule(ls: Any, types: Any, uri: str, cascade: bool = True) -> None:
    """Start checking the document's current text: a new generation, so that every check
    of an older text is stale from now on."""
    import asyncio

    text = ls.workspace.get_text_document(uri).source
    generation = ls.checks.next(uri)
    ls.checks.tasks[uri] = asyncio.ensure_future(_refresh(ls, types, uri, generation, text, cascade))


def _request(server: Any, method: str, *options: Any) -> Any:
    """``server.feature(method, ...)`` for a request about one document: one the client has
    not opened gets no answer (null) and a line in the client's log, never a read of the path
    its URI names (``./Untitled-1`` for ``untitled:Untitled-1``, any file a URI names: issue 28,
    finding 6) or a traceback."""
    import functools

    def register(handler: Any) -> Any:
        @functools.wraps(handler)
        async def answer(ls: Any, params: Any) -> Any:
            uri = params.text_document.uri
            if uri not in ls.workspace.text_documents:
                from lsprotocol import types

                note = f"catc: {method} about {uri}, which is not an open document: no answer"
                ls.window_log_message(types.LogMessageParams(types.MessageType.Warning, note))
                return None
            return await handler(ls, params)

        return server.feature(method, *options)(answer)

    return register


def _opened_text(ls: Any, uri: str) -> str:
    """The text of the open document ``uri`` (a :func:`_request` handler's: opened)."""
    return str(ls.workspace.text_documents[uri].source)


async def _current(ls: Any, types: Any, uri: str) -> Analysis:
    """The document's latest analysis; until it has one, its check under way is waited for
    (a request that comes right after the document was opened)."""
    import asyncio

    while uri not in ls.analyses:
        task = ls.checks.tasks.get(uri)
        if task is None:
            _schedule(ls, types, uri)
            continue
        if task.done():
            break
        await asyncio.shield(task)
    return ls.analyses.get(uri) or Analysis(uri_to_path(uri), "")


async def _fresh(ls: Any, types: Any, uri: str) -> Analysis:
    """The analysis of the document's current text (its check under way is waited for):
    what an edit of the text (rename, code actions) must start from."""
    import asyncio

    task = ls.checks.tasks.get(uri)
    if task is not None and not task.done():
        await asyncio.shield(task)
    return await _current(ls, types, uri)


def _log(ls: Any, types: Any, message: str) -> None:
    ls.window_log_message(types.LogMessageParams(types.MessageType.Error, f"catc: {message}"))


def _word(ls: Any, a: Analysis, position: Any) -> tuple[str, Span] | None:
    """The name under an LSP position of the document's text, and its span (catc's)."""
    text = _doc_text(ls, a)
    lines = text.split("\n")
    if not 0 <= position.line < len(lines):
        return None
    line = lines[position.line]
    column = server_column(line, position.character, _encoding(ls))
    for m in WORD.finditer(line):
        if m.start() <= column <= m.end():
            offset = sum(len(x) + 1 for x in lines[: position.line]) + m.start()
            return m.group(), Source(a.path, text).span(offset, offset + len(m.group()))
    return None


def _offset(text: str, position: Any, encoding: str) -> int:
    """An LSP position → a character offset of ``text`` (clamped to the text)."""
    lines = text.split("\n")
    if position.line >= len(lines):
        return len(text)
    return sum(len(x) + 1 for x in lines[: position.line]) + server_column(
        lines[position.line], position.character, encoding
    )


def _end(types: Any, text: str, encoding: str) -> Any:
    lines = text.split("\n")
    return types.Position(len(lines) - 1, code_units(lines[-1], encoding))


def _open_texts(ls: Any) -> dict[str, str]:
    out = {}
    for uri, doc in list(ls.workspace.text_documents.items()):
        if uri.startswith("file:"):
            out[uri_to_path(uri)] = doc.source
    return out


def _request_failed(message: str) -> Exception:
    from pygls.exceptions import JsonRpcException

    class Failed(JsonRpcException):
        CODE = -32803  # LSP RequestFailed
        MESSAGE = "Request failed"

    return Failed(message=message)


def _register_documents(server: Any, types: Any) -> None:
    @server.feature(types.TEXT_DOCUMENT_DID_OPEN)
    async def did_open(ls: Any, params: Any) -> None:
        _schedule(ls, types, params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CHANGE)
    async def did_change(ls: Any, params: Any) -> None:
        _schedule(ls, types, params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_SAVE)
    async def did_save(ls: Any, params: Any) -> None:
        _schedule(ls, types, params.text_document.uri)

    @server.feature(types.TEXT_DOCUMENT_DID_CLOSE)
    async def did_close(ls: Any, params: Any) -> None:
        uri = params.text_document.uri
        ls.checks.next(uri)  # a check under way is stale
        ls.checks.tasks.pop(uri, None)
        ls.analyses.pop(uri, None)
        ls.text_document_publish_diagnostics(types.PublishDiagnosticsParams(uri=uri, diagnostics=[]))


_COMPLETION_KINDS = {
    "resource": "Variable",
    "morphism": "Function",
    "sort": "Class",
    "constant": "Constant",
    "object": "Constant",
    "enum value": "EnumMember",
    "view": "Interface",
    "hole": "Struct",
    "domain": "Module",
    "problem": "Module",
    "parameter": "TypeParameter",
}


def _register_navigation(server: Any, types: Any) -> None:
    from catgrammar.symbols import all_keywords

    async def name_at(ls: Any, params: Any) -> tuple[Analysis, str | None]:
        a = await _current(ls, types, params.text_document.uri)
        text = _opened_text(ls, params.text_document.uri)
        line, character = params.position.line, params.position.character
        lines = text.split("\n")
        if not 0 <= line < len(lines):
            return a, None
        return a, word_at(text, line, server_column(lines[line], character, _encoding(ls)))

    @_request(server, types.TEXT_DOCUMENT_HOVER)
    async def hover(ls: Any, params: Any) -> Any:
        a = await _current(ls, types, params.text_document.uri)
        found = _word(ls, a, params.position)
        if found is None:
            return None
        name, at = found
        try:
            text = hover_text(a, name, at)
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"hover: {exc!r}")
            return None
        if text is None:
            return None
        return types.Hover(contents=types.MarkupContent(kind=types.MarkupKind.Markdown, value=text))

    @_request(server, types.TEXT_DOCUMENT_DEFINITION)
    async def definition(ls: Any, params: Any) -> Any:
        a, name = await name_at(ls, params)
        defs = lookup(a, name) if name else []
        if not defs:
            return None
        lines = _lines(ls, a)
        return [types.Location(path_to_uri(d.span.file), lines.range(types, d.span)) for d in defs]

    @_request(
        server,
        types.TEXT_DOCUMENT_COMPLETION,
        types.CompletionOptions(trigger_characters=[":", "("]),
    )
    async def completion(ls: Any, params: Any) -> Any:
        a = await _current(ls, types, params.text_document.uri)
        kinds = {k: getattr(types.CompletionItemKind, v) for k, v in _COMPLETION_KINDS.items()}
        items = [
            types.CompletionItem(label=k, kind=types.CompletionItemKind.Keyword, detail="keyword")
            for k in sorted({w for words in all_keywords().values() for w in words})
        ]
        items += [
            types.CompletionItem(
                label=n,
                kind=kinds.get(kind, types.CompletionItemKind.Text),
                detail=kind,
            )
            for n, kind in sorted(names_in_scope(a).items())
        ]
        return types.CompletionList(is_incomplete=False, items=items)


_SYMBOL_KINDS = {
    "resource": "Variable",
    "morphism": "Function",
    "view": "Interface",
    "hole": "Struct",
    "sort": "Class",
    "constant": "Constant",
    "object": "Constant",
}


def _register_symbols(server: Any, types: Any) -> None:
    @_request(server, types.TEXT_DOCUMENT_DOCUMENT_SYMBOL)
    async def document_symbol(ls: Any, params: Any) -> Any:
        a = await _current(ls, types, params.text_document.uri)
        lines = _lines(ls, a)
        sk = types.SymbolKind
        top: list = []
        by_owner: dict[str, list] = {}
        for d in a.definitions:
            if not same_name(d.span.file, a.path):
                continue
            if d.kind in ("domain", "problem"):
                children: list = []
                by_owner[d.name] = children
                kind = sk.Module if d.kind == "domain" else sk.Namespace
                top.append(
                    types.DocumentSymbol(
                        name=d.name,
                        detail=d.kind,
                        kind=kind,
                        range=lines.range(types, d.whole),
                        selection_range=lines.range(types, d.span),
                        children=children,
                    )
                )
            elif d.kind in _SYMBOL_KINDS and d.owner in by_owner:
                by_owner[d.owner].append(
                    types.DocumentSymbol(
                        name=d.name,
                        detail=d.kind,
                        kind=getattr(sk, _SYMBOL_KINDS[d.kind]),
                        range=lines.range(types, d.whole),
                        selection_range=lines.range(types, d.span),
                    )
                )
        return top


def _register_editing(server: Any, types: Any) -> None:
    """References and rename (with prepareRename)."""
    import asyncio

    import catc.interfaces.lsp.tools as tools

    @_request(server, types.TEXT_DOCUMENT_REFERENCES)
    async def references(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        found = _word(ls, a, params.position)
        if found is None:
            return []
        try:
            files = await asyncio.to_thread(tools.workspace_files, a, _open_texts(ls))
            spans = await asyncio.to_thread(tools.references, a, *found, files, params.context.include_declaration)
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"references: {exc!r}")
            return []
        lines = Lines(_encoding(ls), files)
        return [types.Location(path_to_uri(s.file), lines.range(types, s)) for s in spans]

    @_request(server, types.TEXT_DOCUMENT_PREPARE_RENAME)
    async def prepare_rename(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        found = _word(ls, a, params.position)
        if found is None:
            raise _request_failed("there is no name here to rename")
        try:
            tools.check_rename(a, *found)
        except tools.RenameError as exc:
            raise _request_failed(str(exc)) from None
        lines = Lines(_encoding(ls), {a.path: _doc_text(ls, a)})
        return types.PrepareRenamePlaceholder(range=lines.range(types, found[1]), placeholder=found[0])

    @_request(server, types.TEXT_DOCUMENT_RENAME, types.RenameOptions(prepare_provider=True))
    async def rename(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        found = _word(ls, a, params.position)
        if found is None:
            raise _request_failed("there is no name here to rename")
        try:
            files = await asyncio.to_thread(tools.workspace_files, a, _open_texts(ls))
            edits = await asyncio.to_thread(tools.rename_edits, a, *found, params.new_name, files)
        except tools.RenameError as exc:
            raise _request_failed(str(exc)) from None
        lines = Lines(_encoding(ls), files)
        return types.WorkspaceEdit(
            changes={
                path_to_uri(path): [types.TextEdit(lines.range(types, s), params.new_name) for s in spans]
                for path, spans in edits.items()
            }
        )


def _register_fixes(server: Any, types: Any) -> None:
    """Formatting and code actions."""
    import asyncio

    import catc.interfaces.lsp.tools as tools

    @_request(server, types.TEXT_DOCUMENT_FORMATTING)
    async def formatting(ls: Any, params: Any) -> Any:
        text = _opened_text(ls, params.text_document.uri)
        try:
            new = await asyncio.to_thread(tools.formatted, text)  # seconds for a huge file: off the loop
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"formatting: {exc!r}")
            return []
        if new is None or new == text:
            return []  # a file that does not parse is left alone
        return [types.TextEdit(types.Range(types.Position(0, 0), _end(types, text, _encoding(ls))), new)]

    @_request(
        server,
        types.TEXT_DOCUMENT_CODE_ACTION,
        types.CodeActionOptions(code_action_kinds=[types.CodeActionKind.QuickFix]),
    )
    async def code_action(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        lines = _lines(ls, a)
        want = params.range
        out = []
        for d in a.diagnostics:
            fixes = getattr(d, "fixes", ())
            if not fixes or d.span is None:
                continue
            diag = _lsp_diagnostic(types, lines, d)
            r = diag.range
            if (r.end.line, r.end.character) < (
                want.start.line,
                want.start.character,
            ) or ((want.end.line, want.end.character) < (r.start.line, r.start.character)):
                continue
            for fix in fixes:
                edit = types.TextEdit(lines.range(types, fix.span), fix.text)
                out.append(
                    types.CodeAction(
                        title=fix.title,
                        kind=types.CodeActionKind.QuickFix,
                        diagnostics=[diag],
                        is_preferred=len(fixes) == 1,
                        edit=types.WorkspaceEdit(changes={path_to_uri(fix.span.file): [edit]}),
                    )
                )
        return out


def _doc_text(ls: Any, a: Analysis) -> str:
    try:
        return ls.workspace.get_text_document(path_to_uri(a.path)).source
    except Exception:  # pragma: no cover
        return a.text


def _register_display(server: Any, types: Any) -> None:
    """Semantic tokens and unit inlay hints (in a thread: a large document takes a second)."""
    import asyncio

    import catc.interfaces.lsp.tools as tools

    legend = types.SemanticTokensLegend(
        token_types=list(tools.TOKEN_TYPES), token_modifiers=list(tools.TOKEN_MODIFIERS)
    )

    @_request(
        server,
        types.TEXT_DOCUMENT_SEMANTIC_TOKENS_FULL,
        types.SemanticTokensRegistrationOptions(legend=legend, full=True),
    )
    async def semantic_tokens(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        encoding = _encoding(ls)
        lines = a.text.split("\n")
        data: list[int] = []
        last_line = last_start = 0
        try:
            found = await asyncio.to_thread(tools.semantic_tokens, a)
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"semantic tokens: {exc!r}")
            found = []
        for span, kind, mods in found:
            line = span.line - 1
            text = lines[line] if line < len(lines) else ""
            start = client_column(text, span.column - 1, encoding)
            length = code_units(text[span.column - 1 : span.end_column - 1], encoding)
            bits = sum(1 << tools.TOKEN_MODIFIERS.index(m) for m in mods)
            delta_start = start - last_start if line == last_line else start
            data += [
                line - last_line,
                delta_start,
                length,
                tools.TOKEN_TYPES.index(kind),
                bits,
            ]
            last_line, last_start = line, start
        return types.SemanticTokens(data=data)

    @_request(server, types.TEXT_DOCUMENT_INLAY_HINT)
    async def inlay_hints(ls: Any, params: Any) -> Any:
        a = await _fresh(ls, types, params.text_document.uri)
        lines = _lines(ls, a)
        r = params.range
        out = []
        try:
            hints = await asyncio.to_thread(tools.unit_hints, a)
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"inlay hints: {exc!r}")
            hints = []
        for span, unit, resource in hints:
            end = lines.position(types, span.file, span.end_line, span.end_column)
            if not ((r.start.line, r.start.character) <= (end.line, end.character) <= (r.end.line, r.end.character)):
                continue
            out.append(
                types.InlayHint(
                    position=end,
                    label=unit,
                    kind=types.InlayHintKind.Type,
                    tooltip=f"unit of resource {resource}",
                    padding_left=True,
                )
            )
        return out


def _register_signature_help(server: Any, types: Any) -> None:
    """The options of the form under the cursor."""
    import catc.interfaces.lsp.tools as tools

    @_request(
        server,
        types.TEXT_DOCUMENT_SIGNATURE_HELP,
        types.SignatureHelpOptions(trigger_characters=[":", " ", "("], retrigger_characters=[" "]),
    )
    async def signature_help(ls: Any, params: Any) -> Any:
        text = _opened_text(ls, params.text_document.uri)
        try:
            sig = tools.signature_at(text, _offset(text, params.position, _encoding(ls)))
        except Exception as exc:  # never a traceback for a half-written model
            _log(ls, types, f"signature help: {exc!r}")
            return None
        if sig is None:
            return None
        info = types.SignatureInformation(
            label=sig.label,
            documentation=types.MarkupContent(kind=types.MarkupKind.Markdown, value=sig.doc),
            parameters=[
                types.ParameterInformation(label=o, documentation=d) for o, d in zip(sig.options, sig.option_docs)
            ],
        )
        return types.SignatureHelp(signatures=[info], active_signature=0, active_parameter=sig.active)
