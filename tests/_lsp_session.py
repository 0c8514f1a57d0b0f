"""One ``catc lsp`` per test module, reset between tests (issue 28: a fresh server for each
test cost about 0.6 s of CPU to start — most of an LSP test's time).

The module's ``server`` fixture (pytest-lsp, ``scope="module"``) starts and initialises the
server once; its ``client`` fixture (per test) hands it to the test and then :func:`reset`
closes every document the test opened, so the next test meets a server with no open
document, no analysis kept (``_keep_last_good``) and no check whose diagnostics are still to
come.  Imported only by the LSP test modules, after they know pytest-lsp is installed."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from lsprotocol import types

# a small file no LSP test opens: the request on it is the reset's barrier (the server reads it
# from disk once and keeps its analysis; a file that does not exist would be an error answer)
BARRIER = (Path(__file__).resolve().parent / "fixtures" / "valid" / "two-conflicts.cat").as_uri()


def opened(client: Any, uri: str) -> str:
    """Note ``uri`` as opened by the running test (closed by :func:`reset`)."""
    if not hasattr(client, "catc_opened"):
        client.catc_opened = set()
    client.catc_opened.add(uri)
    return uri


async def reset(client: Any) -> None:
    """Close what the test opened, and wait until the server has handled the closes.

    The server publishes a document's empty diagnostics as it handles its close, and a check
    still under way for a closed document is stale and never published (server.py, did_close
    and _refresh).  The server starts handling messages in the order they came, so the answer
    to a request sent after the closes comes after every publication they caused: once it is
    in, nothing of this test is still on its way, and the client's record of diagnostics
    starts empty."""
    for uri in sorted(getattr(client, "catc_opened", ())):
        client.text_document_did_close(types.DidCloseTextDocumentParams(types.TextDocumentIdentifier(uri)))
    client.catc_opened = set()
    await client.text_document_document_symbol_async(types.DocumentSymbolParams(types.TextDocumentIdentifier(BARRIER)))
    client.diagnostics = {}
