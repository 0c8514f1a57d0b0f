"""Issue 28, findings 1 and 6: ``catc lsp`` over its real stdio, message by message as bytes.

Each test writes every message (ending with ``shutdown`` and ``exit``) at once, closes
standard input and reads all the server wrote: no clock is raced.  A server that stops
reading (finding 1) never answers ``shutdown``, and its exit code is not 0."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from conftest import ROOT

pytest.importorskip("pygls")

PROBLEM = ROOT / "examples" / "detection" / "person.cat"


def frame(body: object, header: bytes = b"Content-Length") -> bytes:
    data = body if isinstance(body, bytes) else json.dumps(body).encode()
    return header + b": %d\r\n\r\n" % len(data) + data


def request(id_: int, method: str, params: object = None) -> dict:
    return {"jsonrpc": "2.0", "id": id_, "method": method, "params": params}


INIT = request(1, "initialize", {"processId": None, "rootUri": ROOT.as_uri(), "capabilities": {}})
INITIALIZED = {"jsonrpc": "2.0", "method": "initialized", "params": {}}
END = [request(99, "shutdown"), {"jsonrpc": "2.0", "method": "exit"}]


def talk(*frames: bytes, wait: tuple[object, ...] = ()) -> tuple[int, list[dict]]:
    """Run the server on ``frames``; once it has answered the ids ``wait`` (and published
    diagnostics, for the string "diagnostics" among them), send shutdown and exit.  Its exit
    code and everything it wrote.  (A timer kills a server that hangs: a guard, not a race.)"""
    proc = subprocess.Popen(
        [sys.executable, "-m", "catc", "lsp"], stdin=subprocess.PIPE, stdout=subprocess.PIPE, cwd=ROOT
    )
    guard = threading.Timer(300, proc.kill)
    guard.start()
    try:
        assert proc.stdin is not None and proc.stdout is not None
        proc.stdin.write(b"".join(frames))
        proc.stdin.flush()
        messages: list[dict] = []
        pending = set(wait)
        while pending:
            message = _read(proc.stdout)
            if message is None:
                break
            messages.append(message)
            pending.discard(message.get("id") if "method" not in message else None)
            if message.get("method") == "textDocument/publishDiagnostics":
                pending.discard("diagnostics")
        proc.stdin.write(b"".join(frame(m) for m in END))
        proc.stdin.close()
        while (message := _read(proc.stdout)) is not None:
            messages.append(message)
        return proc.wait(), messages
    finally:
        guard.cancel()
        proc.kill()
        proc.wait()


def _read(stream) -> dict | None:  # type: ignore[no-untyped-def]
    length = None
    while (line := stream.readline()) not in (b"\r\n", b""):
        name, _, value = line.partition(b":")
        if name.strip().lower() == b"content-length":
            length = int(value)
    return None if length is None else json.loads(stream.read(length))


def answer(messages: list[dict], id_: int) -> dict:
    found = [m for m in messages if m.get("id") == id_ and "method" not in m]
    assert len(found) == 1, messages
    return found[0]


HEADERS = [b"content-length", b"CONTENT-LENGTH", b"Content-length", b"content-length ", b"Content-Length"]


def test_a_header_name_in_any_case_is_read() -> None:
    """Header names are case-insensitive (the base protocol's headers are HTTP's); before,
    a lower-case one left the server reading bodies as headers, deaf to shutdown and exit.
    Each request after ``initialize`` names a method no server has: its error answer shows
    the frame was read."""
    asks = [frame(request(2 + i, "catc/none"), h) for i, h in enumerate(HEADERS)]
    code, messages = talk(frame(INIT, b"content-length"), frame(INITIALIZED), *asks, wait=(1, 2, 3, 4, 5, 6))
    assert answer(messages, 1)["result"]["serverInfo"]["name"] == "catc"
    assert [answer(messages, 2 + i)["error"]["code"] for i in range(len(HEADERS))] == [-32601] * len(HEADERS)
    assert answer(messages, 99)["result"] is None and code == 0


BODIES = [b"[]", b"null", b"1", b'"x"', b"{}", b"[1, 2]", b'{"jsonrpc": "2.0"}']


def test_a_body_that_is_no_message_is_answered_with_an_error() -> None:
    """JSON that is not a JSON-RPC message raised AttributeError in handle_message; now each
    is an Invalid Request error (id null) and the server goes on."""
    code, messages = talk(
        frame(INIT), frame(INITIALIZED), *map(frame, BODIES), frame(request(7, "catc/none")), wait=(1, 7)
    )
    errors = [m for m in messages if m.get("id") is None and "error" in m]
    assert [e["error"]["code"] for e in errors] == [-32600] * len(BODIES), messages
    assert answer(messages, 7)["error"]["code"] == -32601
    assert answer(messages, 99)["result"] is None and code == 0


def _command(id_: int, uri: str) -> dict:
    return request(id_, "workspace/executeCommand", {"command": "catc.solve", "arguments": [uri]})


def test_a_query_reads_only_files_of_the_workspace_or_opened(tmp_path: Path) -> None:
    """Finding 6: a query named any URI read its path.  Now: a ``file:`` URI inside the
    workspace (or of an opened document) only; ``untitled:``, other schemes, a path with
    %00 and a file outside the workspace are refused with a catc.error/1 document."""
    outside = tmp_path / "person.cat"  # a readable, valid model, but not the workspace's
    outside.write_text(PROBLEM.read_text().replace("(:domain detection)", "(:domain detection)"))
    uris = [
        PROBLEM.resolve().as_uri(),
        "untitled:Untitled-1",
        "file:///x/%00.cat",
        "https://example.org/person.cat",
        outside.as_uri(),
        "file://elsewhere" + str(PROBLEM.resolve()),
    ]
    code, messages = talk(
        frame(INIT),
        frame(INITIALIZED),
        *(frame(_command(10 + i, u)) for i, u in enumerate(uris)),
        wait=tuple(range(10, 10 + len(uris))),
    )
    results = [answer(messages, 10 + i)["result"] for i in range(len(uris))]
    assert results[0]["schema"] == "catc.solve/1" and results[0]["status"] == "sat"
    for r in results[1:]:
        assert r["schema"] == "catc.error/1" and "not a file: URI of an open document" in r["diagnostics"][0]["message"]
    assert code == 0


def test_an_opened_document_outside_the_workspace_may_be_queried(tmp_path: Path) -> None:
    domain, problem = tmp_path / "domain.cat", tmp_path / "person.cat"
    domain.write_text((ROOT / "examples" / "detection" / "domain.cat").read_text())
    problem.write_text(PROBLEM.read_text())
    opened = {
        "jsonrpc": "2.0",
        "method": "textDocument/didOpen",
        "params": {
            "textDocument": {"uri": problem.as_uri(), "languageId": "cat", "version": 1, "text": problem.read_text()}
        },
    }
    code, messages = talk(
        frame(INIT), frame(INITIALIZED), frame(opened), frame(_command(10, problem.as_uri())), wait=(10,)
    )
    assert answer(messages, 10)["result"]["status"] == "sat" and code == 0


def test_a_path_with_a_nul_is_no_traceback() -> None:
    """``file:///x/%00.cat`` opened: its check says what is wrong, no "embedded null byte"."""
    opened = {
        "jsonrpc": "2.0",
        "method": "textDocument/didOpen",
        "params": {"textDocument": {"uri": "file:///x/%00.cat", "languageId": "cat", "version": 1, "text": "(define"}},
    }
    hover = request(
        5, "textDocument/hover", {"textDocument": {"uri": "file:///x/%00.cat"}, "position": {"line": 0, "character": 1}}
    )
    code, messages = talk(frame(INIT), frame(INITIALIZED), frame(opened), frame(hover), wait=(5, "diagnostics"))
    answer(messages, 5)
    logs = [m["params"]["message"] for m in messages if m.get("method") == "window/logMessage"]
    assert not any("null byte" in text for text in logs), logs
    published = [m for m in messages if m.get("method") == "textDocument/publishDiagnostics"]
    assert published and published[-1]["params"]["diagnostics"], messages
    assert code == 0


def test_a_request_about_a_document_not_opened_reads_nothing() -> None:
    """Finding 6 for the document requests: each one about a document the client has not
    opened answers null with a line in the client's log -- it neither reads the file a
    ``file:`` URI names (the workspace's own model here, which would have symbols) nor
    ``./Untitled-1`` for ``untitled:Untitled-1`` (a FileNotFoundError before)."""
    at = {"line": 0, "character": 1}
    whole = {"start": {"line": 0, "character": 0}, "end": {"line": 0, "character": 1}}
    methods = {
        "textDocument/hover": {"position": at},
        "textDocument/definition": {"position": at},
        "textDocument/completion": {"position": at},
        "textDocument/documentSymbol": {},
        "textDocument/references": {"position": at, "context": {"includeDeclaration": True}},
        "textDocument/prepareRename": {"position": at},
        "textDocument/rename": {"position": at, "newName": "x"},
        "textDocument/formatting": {"options": {"tabSize": 2, "insertSpaces": True}},
        "textDocument/codeAction": {"range": whole, "context": {"diagnostics": []}},
        "textDocument/semanticTokens/full": {},
        "textDocument/inlayHint": {"range": whole},
        "textDocument/signatureHelp": {"position": at},
    }
    for uri in (PROBLEM.resolve().as_uri(), "untitled:Untitled-1"):
        asked = [request(20 + i, m, {"textDocument": {"uri": uri}, **p}) for i, (m, p) in enumerate(methods.items())]
        code, messages = talk(frame(INIT), frame(INITIALIZED), *map(frame, asked), wait=tuple(a["id"] for a in asked))
        for a in asked:
            assert answer(messages, a["id"]) == {"jsonrpc": "2.0", "id": a["id"], "result": None}, a["method"]
        logged = [m["params"]["message"] for m in messages if m.get("method") == "window/logMessage"]
        assert sum("not an open document" in line for line in logged) == len(methods), logged
        assert code == 0
