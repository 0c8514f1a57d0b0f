"""Events: one JSON object per line, ``catrt.event/1`` (schemas/event-1.json, docs/runtime.md).

Reading an event checks its shape against the JSON schema (with ``jsonschema``) and keeps
every number exact: a JSON number is read as the decimal it is written as (``22.73`` is
2273/100, never a float), a string may hold a decimal or a fraction.  What an event *means*
for the model — a resource that exists, a value of its sort, a goal that type-checks — is
checked when it is applied (:mod:`catrt.apply`).  Nothing here touches the store.
"""

from __future__ import annotations

import json
import re
import uuid
from collections.abc import Iterator
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from fractions import Fraction
from functools import cache
from importlib import resources
from typing import Any

from catc.ir.numbers import ratio_text
from catrt.changes import registry as changes

SCHEMA = "catrt.event/1"
CHANGE_KEYS = changes.fields()  # set, goal, metric, softs, horizon, catalog, health
APPROVAL_KEYS = ("approve", "reject")
MAX_LINE = 1_000_000  # bytes: a longer line is rejected, read no further than this (read_lines)
MAX_DIGITS = 1000  # digits of a number's numerator or denominator (1e9999 is no measurement)

_NUMBER = re.compile(r"[+-]?(\d+(\.\d+)?|\.\d+)([eE][+-]?\d{1,4})?|[+-]?\d+/\d+", re.ASCII)
_SURROGATE = re.compile("[\ud800-\udfff]")


class EventError(ValueError):
    """A line that is not an event: ``where`` is ``SOURCE:LINE[:COL]``; ``event_id`` the id
    it gives, when it is JSON with one (so that the rejection can name it)."""

    def __init__(self, where: str, message: str, event_id: str = "") -> None:
        super().__init__(f"{where}: {message}")
        self.where, self.message, self.event_id = where, message, event_id


@dataclass(frozen=True)
class Event:
    """A well-formed event: ``body`` is canonical JSON (numbers as exact text); ``where``
    is where it was read (``events.jsonl:4``, ``spool/a.jsonl:1``, ``api``)."""

    id: str
    body: dict[str, Any]
    where: str
    given_id: bool = True

    @property
    def is_approval(self) -> bool:
        return any(k in self.body for k in APPROVAL_KEYS)

    def to_json(self) -> dict[str, Any]:
        return {"v": 1, "id": self.id, **{k: v for k, v in self.body.items() if k not in ("v", "id")}}


def exact(text: str) -> Fraction | None:
    """A decimal or fraction written as text, exactly; None when it is not one."""
    text = text.strip()
    if not _NUMBER.fullmatch(text):
        return None
    try:
        if "/" in text:
            n, d = text.split("/")
            if int(d) == 0 or max(len(n.lstrip("+-")), len(d)) > MAX_DIGITS:
                return None
            return Fraction(int(n), int(d))
        number = Decimal(text)
        return Fraction(number) if _fits(number) else None
    except (InvalidOperation, ValueError, ZeroDivisionError):
        return None


_QUANTITY = re.compile(r"\s*(\S+)\s+(\S.*?)\s*", re.ASCII)


def quantity(text: str) -> tuple[Fraction, str] | None:
    """``"2 GB"`` → (2, "GB"): a number and a unit, as a ``.cat`` file writes them; None when
    ``text`` is not a number followed by a unit's name (the unit is checked when applied)."""
    m = _QUANTITY.fullmatch(text)
    number = exact(m.group(1)) if m else None
    return None if m is None or number is None else (number, m.group(2))


def _fits(number: Decimal) -> bool:
    """``number`` is finite and, written as a fraction, has at most MAX_DIGITS digits above
    and below: checked on its exponent, before ``1e99999999`` is expanded."""
    if not number.is_finite():
        return False
    _, digits, exponent = number.as_tuple()
    assert isinstance(exponent, int)
    return len(digits) + max(exponent, 0) <= MAX_DIGITS and -exponent <= MAX_DIGITS


@cache
def schema() -> dict[str, Any]:
    return json.loads(resources.files("catrt").joinpath("schemas", "event-1.json").read_text(encoding="utf-8"))


@cache
def _validator() -> Any:
    try:
        from jsonschema import Draft202012Validator
    except ImportError as exc:  # pragma: no cover - the runtime extra brings it
        raise ImportError("catrt needs the 'runtime' extra: pip install 'catc-lang[runtime]'") from exc
    return Draft202012Validator(schema())


def _reject_constant(name: str) -> Any:
    raise ValueError(f"{name} is not a number an event can carry")


def _exact_text(value: Any) -> Any:
    """A sensed value as stored: a number as exact text, anything else as it is."""
    if isinstance(value, bool) or not isinstance(value, (int, Decimal)):
        return value
    return ratio_text(Fraction(value))


def _shape_error(doc: Any) -> str | None:
    """The first way ``doc`` breaks the schema, in words."""
    if not isinstance(doc, dict):
        return f"an event is a JSON object, not {type(doc).__name__}"
    unknown = sorted(set(doc) - set(schema()["properties"]))
    if unknown:
        from catgrammar.diagnostics import did_you_mean

        hint = did_you_mean(unknown[0], list(schema()["properties"]))
        return f"unknown field '{unknown[0]}'{hint}; an event has {', '.join(schema()['properties'])}"
    changes = [k for k in CHANGE_KEYS if k in doc]
    approvals = [k for k in APPROVAL_KEYS if k in doc]
    if not changes and not approvals:
        return f"an event needs one of {', '.join(CHANGE_KEYS + APPROVAL_KEYS)}"
    if approvals and (changes or len(approvals) > 1):
        return f"'{approvals[0]}' is an event of its own: it cannot come with {', '.join([*changes, *approvals[1:]])}"
    errors = sorted(_validator().iter_errors(doc), key=lambda e: (len(list(e.absolute_path)), str(e.message)))
    if not errors:
        return None
    from jsonschema.exceptions import best_match

    e = best_match(errors)
    path = "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in e.absolute_path).lstrip(".")
    return f"{path or 'the event'}: {_short(e.message)}"


_PYTHON_REPR = re.compile(r"Decimal\('([^']*)'\)|\bNone\b|\bTrue\b|\bFalse\b")


def _short(message: str) -> str:
    """jsonschema's message in JSON's words (``Decimal('24.5')`` → 24.5, None → null), cut to 200."""
    json_words = {"None": "null", "True": "true", "False": "false"}
    message = _PYTHON_REPR.sub(lambda m: m.group(1) if m.group(1) is not None else json_words[m.group()], message)
    return message if len(message) <= 200 else message[:197] + "..."


def _unique_keys(pairs: list[tuple[str, Any]]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, value in pairs:
        if key in out:
            raise ValueError(f"the key '{key}' appears twice in one object")
        out[key] = value
    return out


def parse_event(line: str, where: str) -> Event:
    """One line → an Event, or EventError saying where and why (and naming its id)."""
    if len(line.encode("utf-8", "surrogatepass")) > MAX_LINE:
        raise EventError(where, f"the line is longer than {MAX_LINE} bytes")
    bad = _SURROGATE.search(line)
    if bad is not None:  # a byte that is not UTF-8, read with surrogateescape
        raise EventError(f"{where}:{bad.start() + 1}", f"not UTF-8 text: the byte {_byte(bad.group())}")
    try:
        doc = json.loads(line, parse_float=Decimal, parse_constant=_reject_constant, object_pairs_hook=_unique_keys)
    except json.JSONDecodeError as exc:
        raise EventError(f"{where}:{exc.colno}", f"not JSON: {exc.msg}") from None
    except (ValueError, RecursionError) as exc:
        raise EventError(where, f"not an event: {exc}") from None
    if _has_surrogate(doc):  # "\ud800": JSON can escape what no text holds
        raise EventError(where, "a string holds a lone surrogate (\\ud800-\\udfff): not text")
    try:
        return _event(doc, where)
    except EventError as exc:
        given = doc.get("id") if isinstance(doc, dict) else None
        exc.event_id = given if isinstance(given, str) and given.isprintable() and len(given) <= 200 else ""
        raise


def _event(doc: Any, where: str) -> Event:
    horizon = doc.get("horizon") if isinstance(doc, dict) else None
    if isinstance(horizon, Decimal) and _fits(horizon) and horizon == int(horizon):
        doc["horizon"] = int(doc["horizon"])  # 24.0: an integer written as a decimal
    problem = _shape_error(doc)
    if problem is not None:
        raise EventError(where, problem)
    for name, value in (doc.get("set") or {}).items():
        if isinstance(value, str) and value[:1] in "+-.0123456789" and exact(value) is None and quantity(value) is None:
            raise EventError(
                where,
                f"set.{name}: '{value}' is not a number (a decimal such as 22.73, or 1/3, of at most "
                f"{MAX_DIGITS} digits)",
            )
        if isinstance(value, (int, Decimal)) and not isinstance(value, bool) and not _fits(Decimal(value)):
            raise EventError(where, f"set.{name}: a number of more than {MAX_DIGITS} digits")
    body = dict(doc)
    if "set" in body:
        body["set"] = {name: _exact_text(value) for name, value in body["set"].items()}
    given = "id" in doc
    event_id = body.get("id") or f"auto-{uuid.uuid4().hex}"
    body.pop("id", None)
    body.pop("v", None)
    return Event(event_id, body, where, given)


def _byte(char: str) -> str:
    code = ord(char)
    return f"0x{code - 0xDC00:02x}" if 0xDC80 <= code <= 0xDCFF else f"U+{code:04X}"


def _has_surrogate(doc: Any) -> bool:
    todo = [doc]
    while todo:
        value = todo.pop()
        if isinstance(value, str) and _SURROGATE.search(value):
            return True
        if isinstance(value, dict):
            todo += [*value.keys(), *value.values()]
        elif isinstance(value, list):
            todo += value
    return False


def read_lines(stream: Any, source: str) -> Iterator[tuple[str, str]]:
    """(where, line) for each non-blank line of a text stream; a last line without its
    newline (a torn write) is still yielded, and rejected by :func:`parse_event` unless it
    is a whole event.  A line longer than MAX_LINE is read no further than that: its first
    MAX_LINE + 1 characters are yielded (and rejected as too long), the rest is skipped in
    chunks, so memory stays bounded whatever the line's length."""
    number = 0
    while True:
        line = stream.readline(MAX_LINE + 1)
        if not line:
            return
        number += 1
        if len(line) > MAX_LINE and not line.endswith("\n"):
            while True:  # the rest of the line, unread
                rest = stream.readline(1 << 16)
                if not rest or rest.endswith("\n"):
                    break
        text = line.rstrip("\n").rstrip("\r")
        if text.strip():
            yield f"{source}:{number}", text
