"""What ``catc lsp`` accepts before pygls sees it: the base protocol's framing and the
URIs whose files it may read (issue 28, findings 1 and 6).  No pygls here.

pygls reads a header only when it is spelled ``Content-Length: N`` exactly; the base
protocol's header names are case-insensitive (as HTTP's), and a client writing
``content-length:`` left pygls reading bodies as headers for good — it then ignored
``shutdown`` and ``exit``.  :class:`CanonicalHeaders` wraps standard input and hands pygls
every ``Content-Length`` header in its one spelling.
"""

from __future__ import annotations

import re
from typing import BinaryIO
from urllib.parse import unquote, urlparse

_LENGTH = re.compile(rb"content-length[ \t]*:[ \t]*(\d+)[ \t]*\r?\n?", re.IGNORECASE)
_DIGITS = 12  # a longer length is no body anyone sends: left for pygls to ignore


class CanonicalHeaders:
    """Standard input for pygls's reader (``readline`` and ``read``), with each
    ``Content-Length`` header line rewritten as ``Content-Length: N\\r\\n`` whatever the
    case of its name and the spaces around its colon.  Other lines pass unchanged."""

    def __init__(self, stream: BinaryIO) -> None:
        self._stream = stream

    def readline(self, *args: int) -> bytes:
        line = self._stream.readline(*args)
        m = _LENGTH.fullmatch(line)
        if m is not None and len(m.group(1)) <= _DIGITS:
            return b"Content-Length: %d\r\n" % int(m.group(1))
        return line

    def read(self, *args: int) -> bytes:
        return self._stream.read(*args)

    def __getattr__(self, name: str) -> object:  # fileno, close, ...: the stream's own
        return getattr(self._stream, name)


def readable_path(uri: object, known: set[str], roots: list[str]) -> str | None:
    """The file a query may read for ``uri``: only a ``file:`` URI, of a document the
    client opened (``known``) or inside a workspace folder (``roots``), whose path has no
    NUL; else None.  (``untitled:Untitled-1`` is no file: before, its path was read as
    ``./Untitled-1``; ``file:///x/%00.cat`` raised "embedded null byte".)"""
    import os

    if not isinstance(uri, str):
        return None
    parsed = urlparse(uri)
    if parsed.scheme != "file" or parsed.netloc not in ("", "localhost"):
        return None
    path = unquote(parsed.path)
    if not path or "\0" in path:
        return None
    if uri in known:
        return path
    real = os.path.realpath(path)
    for root in filter(None, roots):
        base = os.path.realpath(root)
        if real == base or real.startswith(base.rstrip(os.sep) + os.sep):
            return path
    return None
