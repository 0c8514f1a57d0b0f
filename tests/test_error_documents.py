"""Every ``catc.error/1`` document says what docs/cli.md promises: ``"status": "error"`` with
its diagnostics for bad input, and ``"status": "unknown"`` with its ``reason`` when a limit
stopped the command — as every unknown answer has its reason (issue 28: the document of a
command stopped by its memory limit had none).

The producers are found by reading the source, so a new one fails here until it is listed
and checked below."""

from __future__ import annotations

import json
import re

import pytest
from conftest import ROOT

from catgrammar import codes

#: Each place that writes a catc.error/1 document, and the test below that makes it.
PRODUCERS = {
    "compiler/catc/interfaces/command.py": "input_errors",
    "compiler/catc/interfaces/guard.py": "stopped_document",
    "compiler/catc/interfaces/lsp/commands.py": "_error",
}


def test_every_producer_of_an_error_document_is_checked_here():
    found = {
        str(path.relative_to(ROOT))
        for tree in ("compiler", "runtime", "catgrammar")
        for path in (ROOT / tree).rglob("*.py")
        if re.search(r"""["']schema["']\s*:\s*["']catc\.error/1["']""", path.read_text(encoding="utf-8"))
    }
    assert found == set(PRODUCERS), found


def said(call, *args) -> dict:
    lines: list[str] = []
    from catc.interfaces import command

    echo = command.echo
    command.echo = lambda text, err=False: None if err else lines.append(text)  # type: ignore[assignment]
    try:
        with pytest.raises(SystemExit) as exit_:
            call(*args)
    finally:
        command.echo = echo  # type: ignore[assignment]
    (doc,) = [json.loads(line) for line in lines]
    doc["exit"] = exit_.value.code
    return doc


def test_input_errors_are_status_error_with_their_diagnostics():
    from catc.interfaces import command
    from catgrammar.diagnostics import Diagnostics

    diags = Diagnostics()
    diags.report(codes.BAD_ARGUMENT, "a bad argument", None)
    doc = said(command.input_errors, diags, True)
    assert doc["schema"] == "catc.error/1" and doc["status"] == "error" and doc["exit"] == 2
    assert [d["code"] for d in doc["diagnostics"]] == [codes.BAD_ARGUMENT]


def test_the_memory_limit_is_status_unknown_with_its_reason():
    from catc.interfaces import command

    doc = said(command.out_of_memory, "encoding", True)
    assert doc["schema"] == "catc.error/1" and doc["exit"] == 3
    assert doc["status"] == "unknown" and doc["reason"] == "memory", doc
    (diag,) = doc["diagnostics"]
    assert diag["code"] == codes.OUT_OF_MEMORY and diag["name"] == "out-of-memory" and "encoding" in diag["message"]


def test_the_time_limit_is_status_unknown_with_its_reason():
    from catc.interfaces import guard

    lines: list[str] = []
    assert guard.time_limit_exit("the time limit of 5 s was reached", True, lambda t, err=False: lines.append(t)) == 3
    doc = json.loads(lines[0])
    assert doc["status"] == "unknown" and doc["reason"] == "timeout"
    assert doc["diagnostics"][0]["code"] == codes.TIME_LIMIT and doc["diagnostics"][0]["name"] == "time-limit"


def test_the_lsp_answers_status_error():
    from catc.interfaces.lsp.commands import _error

    doc = _error([{"message": "not a file"}])
    assert doc["schema"] == "catc.error/1" and doc["status"] == "error" and doc["diagnostics"]


def test_the_reasons_are_documented():
    from catc.interfaces import guard

    text = (ROOT / "docs" / "cli.md").read_text()
    for code, reason in guard.STOP_REASONS.items():
        assert f'`"reason": "{reason}"` (`{code}`' in text, (code, reason)
