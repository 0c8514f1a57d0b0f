"""Nothing catc prints can drive the terminal (issue 15, Found 9): control characters in a
``:unit``, a ``:doc``, a comment or a path are shown as escapes in every human-readable
output, JSON escapes them itself, and rich markup in the user's text (``[bold]``, ``[/]``)
is shown as written — on a pipe and on a terminal."""

from __future__ import annotations

import io
import json

import pytest
from conftest import run_catc

from catc.api import load
from catc.queries import registry

OSC = "\x1b]0;PWNED\x07"  # retitles the terminal
CLEAR = "\x1b[2J"  # clears it
UNIT = f"u{OSC}{CLEAR}[bold]U[/bold][/]"
DOC = f"doc{OSC}[bold]B[/bold]"
MODEL = (
    "(define (domain d) (:requirements :numeric)\n"
    "  (:resources (x real :unit GB) (y real :unit GB))\n"
    f'  (:morphism inc :uses 1 :doc "{DOC}" :precondition (>= y 1) :effect (increase x 1)))\n'
    "; a comment that clears the screen " + CLEAR + "\n"
    "(define (problem p) (:domain d) (:init (= x 0) (= y 0)) (:goal (>= x 1)))\n"
)
BAD = ";" + OSC + '\n(define (domain e) (:resources (z rea :doc "' + OSC + '")))\n'


def hostile(text: str) -> None:
    """No byte of the user's sequences reaches the output raw."""
    for raw in ("\x07", "\x1b]", CLEAR):
        assert raw not in text, f"{raw!r} printed raw in:\n{text}"


def test_printable_shows_control_characters_as_escapes():
    from catgrammar.terminal import printable

    assert printable(f"a{OSC}b\tc\n") == "a\\x1b]0;PWNED\\x07b\tc\n"
    assert printable("\r\x7f\x9b\u202e") == "\\x0d\\x7f\\x9b\\u202e"
    assert printable("θ ⊗ → ✓ ≈") == "θ ⊗ → ✓ ≈"


@pytest.mark.parametrize("text", ["[bold]x[/]", "a\\", "\\[bold]", "[/bold]", "[link=x]y[/link]", "[1, 2]"])
def test_escaped_markup_shows_as_written(text):
    """As rich shows it (a trailing backslash is doubled so that it cannot escape a tag that
    follows: followed by one, it shows as written)."""
    from rich.text import Text

    from catc.present.console import escape, plain

    markup = f"[bold]{escape(text)}[/]"
    assert plain(markup) == text == Text.from_markup(markup).plain


@pytest.fixture
def model_path(tmp_path):
    path = tmp_path / "hostile.cat"
    path.write_text(MODEL)
    return path


@pytest.mark.parametrize("query", ["solve", "diagnose", "relax"])
def test_query_text_on_a_pipe(model_path, query):
    res = run_catc(query, model_path)
    assert res.exit_code in (0, 1), res.output
    hostile(res.output)
    if query == "relax":
        assert "GB" in res.stdout  # the unit (a unit is now checked: a hostile one is E0314, below)
    if query == "diagnose":
        assert "[bold]B[/bold]" in res.stdout and "\\x1b]0;PWNED\\x07" in res.stdout  # the doc in the excerpt


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


@pytest.mark.parametrize("query", ["diagnose", "relax"])
def test_query_text_on_a_terminal(model_path, query, monkeypatch):
    """On a terminal rich renders the markup: a '[/]' in a unit used to crash it (MarkupError,
    exit 70) and a '[bold]' to turn bold on.  The console is the one catc makes when standard
    output is a terminal."""
    from catc.interfaces import command

    model = load(model_path)
    result = getattr(model, query)()
    out = _Terminal()
    monkeypatch.setattr("sys.stdout", out)
    monkeypatch.delenv("NO_COLOR", raising=False)
    registry.get(query).render(command.console(), model.instance, result, {})
    text = out.getvalue()
    hostile(text)
    from rich.text import Text

    shown = Text.from_ansi(text).plain
    if query == "relax":
        assert "GB" in shown
    else:
        assert "[bold]B[/bold]" in shown


def test_plain_console_keeps_user_brackets():
    from catc.present.console import PlainConsole, escape

    lines: list[str] = []
    PlainConsole(lines.append).print(f"[bold green]SAT[/]  {escape(UNIT)}")
    assert lines == ["SAT  u\\x1b]0;PWNED\\x07\\x1b[2J[bold]U[/bold][/]"]


def test_json_stays_json(model_path):
    res = run_catc("relax", model_path, "--json")
    hostile(res.stdout)
    json.loads(res.stdout)


def test_diagnostics_show_control_characters_as_escapes(tmp_path):
    path = tmp_path / "bad.cat"
    path.write_text(BAD)
    for fmt in ("text", "github"):
        res = run_catc("check", path, "--format", fmt)
        assert res.exit_code == 1
        hostile(res.output)
    res = run_catc("check", path)
    assert "unknown sort 'rea'" in res.stdout
    # the caret still points at 'rea' with the escapes before it
    lines = res.stdout.splitlines()
    row = next(i for i, line in enumerate(lines) if "(z rea" in line)
    assert lines[row + 1].index("^") == lines[row].index("rea")


def test_a_path_with_control_characters(tmp_path):
    folder = tmp_path / f"dir{OSC}"
    folder.mkdir()
    path = folder / "bad.cat"
    path.write_text(BAD)
    res = run_catc("check", path)
    hostile(res.output)
    res = run_catc("solve", path)
    assert res.exit_code == 2
    hostile(res.output)


def test_fmt_diff_shows_control_characters_as_escapes(tmp_path):
    path = tmp_path / "m.cat"
    path.write_text(MODEL)
    res = run_catc("fmt", "--diff", path)
    assert res.exit_code == 1
    hostile(res.output)


def test_a_hostile_unit_is_refused_with_escapes(tmp_path):
    """Units are checked against the registry (docs/language.md, units): a :unit with control
    characters and markup is E0314, and the diagnostic shows it escaped, as written."""
    path = tmp_path / "unit.cat"
    path.write_text(f'(define (domain d) (:requirements :numeric) (:resources (x real :unit "{UNIT}")))\n')
    for fmt in ("text", "github"):
        res = run_catc("check", path, "--format", fmt)
        assert res.exit_code == 1 and "E0314" in res.output
        hostile(res.output)
    assert "u\\x1b]0;PWNED\\x07\\x1b[2J[bold]U[/bold][/]" in run_catc("check", path).stdout
