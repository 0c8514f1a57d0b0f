"""Conveniences a compiler's users expect: ``catc init`` (a starter model) and ``catc explain``
(the long explanation of a diagnostic code).

The explanations come from docs/errors.md: each code's row is :data:`catgrammar.codes.CODES`
(name, severity, meaning) and the prose of its section is :mod:`catc.interfaces.errors_doc`,
generated from docs/errors.md by ``python -m catc.interfaces.docgen`` (a test checks they
agree), so the text ships inside the package.
"""

from __future__ import annotations

import difflib
import sys
from pathlib import Path

import click

from catc.interfaces.command import EXIT_INPUT, echo
from catgrammar import codes

#: ``catc init``'s starter domain: checks clean under --strict, and with :data:`STARTER_PROBLEM`
#: solves in 3 steps (tests/test_paper_cuts.py).
STARTER_DOMAIN = """\
; A starter domain, written by `catc init`.  The language: docs/language.md.
;
; A domain declares what a robot is made of (resources) and the components that change it
; (morphisms).  A problem (problem.cat) says where the robot starts and what it must reach;
; `catc solve domain.cat problem.cat` finds the shortest composition of components that gets
; there, and replays it with an independent validator before printing it.
(define (domain starter)
  ; :numeric for numbers, :sets for set resources, :free-parameters for parameters (θ)
  ; that the solver chooses.
  (:requirements :numeric :sets :free-parameters)

  ; Symbols come in sorts; the constants are the symbols the model knows by name.
  (:sorts module topic class - symbol)
  (:constants camera - module  image - topic  person - class)

  ; Resources: the state of the robot.  A numeric resource may carry a unit and bounds
  ; that no step may leave; a set resource starts empty unless the problem says otherwise.
  (:resources
    (mounted (set module) :doc "modules on the robot")
    (ram real :unit GB :bounds (0 *) :doc "free memory")
    (topics (set topic) :doc "published topics")
    (detects (set class) :doc "classes a running detector reports"))

  ; A morphism applies when its precondition holds and changes resources by its effect.
  ; :uses 1 means at most once in a composition.
  (:morphism mount-camera
    :kind hardware :uses 1
    :precondition (not (member camera mounted))
    :effect (add mounted camera))

  ; A parameter is chosen by the solver within its bounds: here, how much memory the
  ; driver reserves (at least 0.5 GB).
  (:morphism camera-driver
    :kind software :uses 1
    :parameters ((out topic) (mem real :bounds (0.5 2)))
    :precondition (and (member camera mounted) (>= ram mem))
    :effect (and (add topics out) (decrease ram mem)))

  (:morphism detector
    :kind software :uses 1
    :parameters ((in topic) (target class))
    :precondition (and (member in topics) (>= ram 4))
    :effect (and (add detects target) (decrease ram 4))))
"""

STARTER_PROBLEM = """\
; A starter problem, written by `catc init`: the robot starts with 8 GB free and nothing
; mounted, and must detect a person.  Try:
;   catc check domain.cat problem.cat
;   catc solve domain.cat problem.cat
;   catc optimize domain.cat problem.cat --maximize ram   (keep the most memory free)
(define (problem find-a-person)
  (:domain starter)
  ; resources not given here start at their defaults: sets empty, Booleans false
  (:init (= ram 8))
  (:goal (member person detects))
  ; the most steps a composition may take
  (:horizon 3))
"""


@click.command(name="init")
@click.argument("directory", default=".", type=click.Path(file_okay=False))
def init_command(directory: str) -> None:
    """Write a starter model, domain.cat and problem.cat, with comments, into DIRECTORY
    (default: the current folder; made if missing).

    The model checks clean and solves: try `catc solve DIRECTORY/domain.cat
    DIRECTORY/problem.cat`.  Refuses (exit 2, E0708) when either file exists: nothing is
    overwritten.
    """
    folder = Path(directory)
    files = {folder / "domain.cat": STARTER_DOMAIN, folder / "problem.cat": STARTER_PROBLEM}
    existing = [str(p) for p in files if p.exists()]
    if existing:
        echo(
            f"catc: error[{codes.WOULD_OVERWRITE}]: {' and '.join(existing)} already exist"
            f"{'s' if len(existing) == 1 else ''}; nothing written (choose another folder, or move "
            f"{'it' if len(existing) == 1 else 'them'} away)",
            err=True,
        )
        sys.exit(EXIT_INPUT)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        for path, text in files.items():
            with open(path, "x", encoding="utf-8") as fh:  # "x": never overwrite, even in a race
                fh.write(text)
    except OSError as exc:
        echo(f"catc: error[{codes.CANNOT_WRITE}]: cannot write the starter model: {exc}", err=True)
        sys.exit(EXIT_INPUT)
    dom, prob = (str(p) for p in files)
    echo(f"wrote {dom} and {prob}")
    echo(f"next: catc check {dom} {prob}")
    echo(f"      catc solve {dom} {prob}")


def explanation(code: str) -> str | None:
    """The long explanation of ``code`` (``E0202``, ``e0202`` or its name ``unknown-name``),
    or None when it is not a code."""
    from catc.interfaces.errors_doc import EXPLANATIONS, SECTIONS

    info = codes.CODES.get(code.upper())
    if info is None:
        info = next((c for c in codes.CODES.values() if c.name == code.lower()), None)
    if info is None:
        return None
    severity = getattr(info.severity, "value", info.severity)
    lines = [f"{info.code} ({info.name}, {severity})", "", info.summary]
    section = SECTIONS.get(info.code[:3])
    if section is not None:
        title, prose = section
        lines[0] += f" — {title}"
        if prose:
            lines += ["", prose]
    if info.code in EXPLANATIONS:
        lines += ["", EXPLANATIONS[info.code]]
    lines += ["", "Every code: docs/errors.md, or `catc explain` with no code."]
    return "\n".join(lines)


@click.command(name="explain")
@click.argument("code", required=False)
def explain_command(code: str | None) -> None:
    """Explain a diagnostic code: what it means and how to fix it.

    CODE is a code such as E0202 (any case) or its name (unknown-name); with no CODE, every
    code and its meaning.  Exit 2 (E0707) for something that is not a code.
    """
    if code is None:
        for info in codes.CODES.values():
            echo(f"{info.code}  {info.name:<28} {info.summary}")
        return
    text = explanation(code)
    if text is None:
        known = [*codes.CODES, *(c.name for c in codes.CODES.values())]
        close = difflib.get_close_matches(
            code.upper() if code[:1].isalpha() and code[1:].isdigit() else code, known, n=1
        )
        hint = f"; did you mean {close[0]}?" if close else "; `catc explain` lists every code"
        echo(f"catc: error[{codes.UNKNOWN_CODE}]: {code!r} is not a diagnostic code{hint}", err=True)
        sys.exit(EXIT_INPUT)
    echo(text)
