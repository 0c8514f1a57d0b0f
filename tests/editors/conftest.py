"""Editor-support tests (Pygments lexer, VS Code, Vim, Emacs).

Tests marked ``editors`` run the real tools -- node with the npm packages of
``editors/vscode``, ``vim`` and ``emacs`` -- which ``.ci/install-editors.sh`` installs.
The project's pytest configuration deselects them by default; run them with::

    python3 -m pytest tests/editors -m editors      # only the tool-driven tests
    python3 -m pytest tests/editors -m ''          # everything in this folder

A missing tool fails the test with a hint to run the install script, unless
``CATC_SKIP_EDITOR_TOOLS=1`` is set, which turns those failures into skips.
"""

from __future__ import annotations


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "editors: editor integrations needing vim/emacs/node (installed by .ci/install-editors.sh)",
    )
