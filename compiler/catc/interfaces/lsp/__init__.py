"""``catc lsp``: a language server for .cat files (pygls 2.x, over stdio).

Features: the diagnostics of ``catc check`` on open/change (computed from the editor's
in-memory text), Markdown hover (resources, morphisms, θ parameters, sorts, constants,
views, holes, options; from the last version that checked while the text does not),
go to definition, completion (keywords and names in scope), document symbols, references
and rename across a domain and its problems, formatting (``catc fmt``), quick fixes (the
diagnostics' structured fixes: did-you-mean, a missing requirement flag), semantic tokens,
unit inlay hints and signature help for a form's options (docs/editors.md has the table;
the parts that need no pygls are in :mod:`catc.interfaces.lsp.tools`).

Documents are checked in the background (one worker thread), so the server answers other
requests while a large document is checked; a newer text of a document makes the check of
the older one stale (dropped before it starts, abandoned while it parses or between phases,
never published).  Positions are in the encoding negotiated with the client (LSP 3.17
``general.positionEncodings``; UTF-16 unless the client offers UTF-8 or UTF-32 first), while
catc's spans count code points; every position crossing the wire is converted.  A request
whose parameters cannot be read (a position of -1 or 2³¹) is answered with an error.

The analysis (:func:`analyse`) does not depend on pygls; the server part imports pygls only
when the command runs, so the rest of catc works without the ``lsp`` extra.

Its parts: :mod:`.analysis` (definitions, positions, URIs), :mod:`.hover`, :mod:`.tools`
(references, rename, tokens, hints, signature help, formatting), :mod:`.server` (pygls),
:mod:`.commands` (queries and targets as ``workspace/executeCommand``).
"""

from __future__ import annotations

import sys

import click

from catc.interfaces.lsp.analysis import (
    MISSING,
    Analysis,
    Definition,
    analyse,
    client_column,
    code_units,
    definitions_of,
    lookup,
    names_in_scope,
    path_to_uri,
    server_column,
    uri_to_path,
    word_at,
)
from catc.interfaces.lsp.commands import run_query_on_file, run_target_on_file
from catc.interfaces.lsp.hover import hover_text
from catc.interfaces.lsp.server import Checks, Lines, build_server

__all__ = [
    "MISSING",
    "Analysis",
    "Checks",
    "Definition",
    "Lines",
    "analyse",
    "build_server",
    "client_column",
    "code_units",
    "definitions_of",
    "hover_text",
    "lookup",
    "lsp_command",
    "names_in_scope",
    "path_to_uri",
    "run_query_on_file",
    "run_target_on_file",
    "server_column",
    "uri_to_path",
    "word_at",
]


@click.command("lsp")
@click.option(
    "--stdio",
    is_flag=True,
    help="Talk over standard input/output (the default; accepted for editors).",
)
def lsp_command(stdio: bool) -> None:
    """Run the .cat language server over stdio (needs the 'lsp' extra).

    Diagnostics as `catc check`, hover, go to definition, completion, document symbols,
    references, rename, formatting, quick fixes, semantic tokens, unit hints and signature
    help.
    """
    try:
        import lsprotocol  # noqa: F401
        import pygls  # noqa: F401
    except ImportError:
        click.echo(MISSING, err=True)
        sys.exit(2)
    from catc.interfaces.lsp_framing import CanonicalHeaders

    build_server().start_io(CanonicalHeaders(sys.stdin.buffer))
