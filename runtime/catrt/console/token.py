"""The console's access token: generated at ``catrt init`` into the state folder (mode 0600),
or given to ``catrt serve --token``; compared in constant time."""

from __future__ import annotations

import hmac
import os
import secrets
from pathlib import Path

TOKEN_FILE = "console-token"


def write_token(folder: Path) -> str:
    """A new random token in ``folder``/console-token, readable by its owner only."""
    token = secrets.token_urlsafe(32)
    path = folder / TOKEN_FILE
    fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    with os.fdopen(fd, "w", encoding="ascii") as f:
        f.write(token + "\n")
    os.chmod(path, 0o600)
    return token


def read_token(folder: Path) -> str | None:
    try:
        return (folder / TOKEN_FILE).read_text(encoding="ascii").strip() or None
    except (OSError, UnicodeDecodeError):
        return None


def same(given: str | None, expected: str) -> bool:
    """``given`` is ``expected``, compared in constant time."""
    return given is not None and hmac.compare_digest(given.encode("utf-8", "surrogateescape"), expected.encode())


def csrf_for(secret: bytes, token: str) -> str:
    """The CSRF value of the approval form: bound to the token and to this server's secret."""
    return hmac.new(secret, b"csrf:" + token.encode(), "sha256").hexdigest()
