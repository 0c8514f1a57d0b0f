"""What an event's change fields share: the rejection of a field that cannot apply, the checks
of the text a field brings (one balanced expression, never closing the section it is put
in), and what a change kind is.  Adding a kind of change: one module in this package
defining ``CHANGE``, one line in :mod:`catrt.changes.registry`, and its field in the event
schema (``catrt/schemas/event-1.json``, published)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from typing import Any, NamedTuple

from catc import ir
from catc.api import Token, TokenError, tokens
from catrt.model import ModelState


class Rejection(ValueError):
    """Why an event cannot be applied: ``details`` are (field, line, column, code, message)
    — the field of the event an error points into, or ``model`` — each located within that
    field's text."""

    def __init__(self, message: str, details: list[dict[str, Any]] | None = None) -> None:
        super().__init__(message)
        self.message, self.details = message, details or []

    def to_json(self) -> dict[str, Any]:
        return {"message": self.message, "details": self.details}

    def text(self) -> str:
        lines = [self.message]
        for d in self.details:
            where = d.get("file") or d["field"]
            if d.get("line"):
                where += f":{d['line']}:{d['column']}"
            lines.append(f"  = {where}: {d['severity']}[{d['code']}]: {d['message']}")
        return "\n".join(lines)


#: (state, instance, the model's sources, the event's body, origins to fill) → the new state
Apply = Callable[[ModelState, ir.Instance, Mapping[str, str], Mapping[str, Any], dict[str, str]], ModelState]


class Change(NamedTuple):
    """A kind of change: the event fields it reads (``set``; ``catalog`` and ``health``,
    applied together) and how it changes the model state (Rejection when it cannot)."""

    fields: tuple[str, ...]
    apply: Apply


def json_text(value: Any) -> str:
    import json

    return json.dumps(value)


# ---------------------------------------------------------------- text fields


def balanced(text: str, what: str) -> list[Token]:
    """The tokens of ``text`` when it is balanced (never closes more than it opened, closes
    all it opens), else Rejection."""
    try:
        found = tokens(text)
    except TokenError as exc:
        column = exc.column
        raise Rejection(
            f"{what}: a character the language does not have" + (f" at column {column}" if column else "")
        ) from None
    depth = 0
    for tok in found:
        if tok.opens:
            depth += 1
        elif tok.closes:
            depth -= 1
            if depth < 0:
                raise Rejection(f"{what}: a ')' at {tok.line}:{tok.column} closes more than the text opened")
    if depth:
        raise Rejection(f"{what}: {depth} '(' never closed (the text ends at {found[-1].line}:{found[-1].column})")
    if not found:
        raise Rejection(f"{what}: empty")
    return found


def one_expression(text: str, what: str) -> None:
    depth, tops = 0, 0
    for tok in balanced(text, what):
        if depth == 0:
            tops += 1
        depth += tok.opens - tok.closes
    if tops != 1:
        raise Rejection(f"{what}: one condition is expected, {tops} were given (combine them with (and ...))")
