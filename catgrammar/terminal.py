"""Text made safe to print on a terminal.

A ``.cat`` file may hold any character in its comments and strings (``:unit``, ``:doc``,
grounding data), and a path any character but ``/``: printed raw, an escape sequence in one
of them could retitle, clear or reprogram the user's terminal, and a carriage return or a
bidirectional override could hide text.  :func:`printable` shows every such character as an
escape instead; every human-readable output of catc goes through it (diagnostics, query
answers, messages), while JSON output escapes them itself.
"""

from __future__ import annotations

import re

#: C0 controls but tab and newline, DEL, C1 controls, and the bidirectional formatting
#: characters (embeddings, overrides, isolates, marks).
_UNSAFE = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069]")


def _escape(m: re.Match[str]) -> str:
    code = ord(m.group())
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def printable(text: str) -> str:
    """``text`` with each character that could drive a terminal shown as ``\\x1b`` or
    ``\\u202e``; newlines and tabs are kept."""
    return _UNSAFE.sub(_escape, text)
