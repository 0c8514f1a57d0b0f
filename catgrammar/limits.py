"""Limits: how much one run of catc may read, compute and spend (docs/limits.md).

Every limit is a row of :data:`LIMITS`: its name (``--limit NAME=N`` on the command line),
its default, the code of the error that reports it, its environment variable
(``CATC_LIMIT_NAME``) and what it bounds.  Each is checked where the quantity is made — the
reader (input bytes, tokens, nesting, literal digits), the constant folder, the checker
(resources, morphisms, the problem's horizon), the finite grounding (universe size), the
horizon of a query, the PDDL export (ground actions) — and crossing it is a located error
with its own code, never a crash or a hang.

The limits in force are a context variable, as :mod:`decimal`'s context is: :func:`using`
sets them for a block, :func:`current` reads them, and each thread starts with the defaults.
The library never reads the environment: the command line and the Python API build a
:class:`Limits` from ``--limit``, ``--memory`` and ``CATC_LIMIT_*`` (:func:`parse_specs`,
:func:`from_environment`) at the edge and run inside ``using(...)``.

Time is a limit of one command rather than of a model: :func:`deadline` gives a block a
wall-clock limit (nested blocks keep the sooner one), every long phase calls
:func:`check_time` (the encoder per step, the validator per step, the PDDL export per ground
action), and a solver's checks get :func:`remaining`.  Ctrl-C is the same kind of stop:
:func:`interrupt` marks the running command, which then stops at its next check and reports
what it has, as at its time limit, but says "interrupted".

This is the lowest stage that needs limits (the reader does), so it imports nothing of catc.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from functools import lru_cache

from catgrammar import codes
from catgrammar.record import Record, set_field
from catgrammar.span import Span

MIB = 1024 * 1024


class Limit(Record):
    """One limit: ``name`` as ``--limit`` spells it, the :class:`Limits` ``field``, the
    ``default``, the ``code`` of its error, the ``unit`` and ``what`` it bounds."""

    __slots__ = ("name", "field", "default", "code", "unit", "what")
    name: str
    field: str
    default: int
    code: str
    unit: str
    what: str

    def __init__(self, name: str, default: int, code: str, unit: str, what: str) -> None:
        set_field(self, "name", name)
        set_field(self, "field", name.replace("-", "_"))
        set_field(self, "default", default)
        set_field(self, "code", code)
        set_field(self, "unit", unit)
        set_field(self, "what", what)

    @property
    def env(self) -> str:
        """The environment variable that overrides the default."""
        return "CATC_LIMIT_" + self.field.upper()

    @property
    def how_to_raise(self) -> str:
        return f"raise it with --limit {self.name}=N or {self.env}"


#: Every limit, in the order of the pipeline.
LIMITS: tuple[Limit, ...] = (
    Limit("input-bytes", 16 * MIB, codes.INPUT_TOO_LARGE, "bytes", "the size of one input file"),
    Limit("tokens", 4_000_000, codes.TOO_MANY_TOKENS, "tokens", "the tokens of one input file"),
    Limit("nesting", 128, codes.TOO_DEEP, "levels", "how deep parentheses nest"),
    Limit("literal-digits", 4_000, codes.LITERAL_TOO_LONG, "digits", "the digits (and exponent) of a numeric literal"),
    Limit(
        "constant-digits",
        4_000,
        codes.CONSTANT_TOO_LARGE,
        "digits",
        "the digits of the numerator and of the denominator of every constant the checker folds",
    ),
    Limit("resources", 100_000, codes.TOO_MANY_RESOURCES, "resources", "the resources of a domain, imports included"),
    Limit("morphisms", 100_000, codes.TOO_MANY_MORPHISMS, "morphisms", "the morphisms of a domain, imports included"),
    Limit(
        "universe",
        10_000,
        codes.UNIVERSE_TOO_LARGE,
        "values",
        "the grounded values of one symbolic sort: its constants and the reserve values the horizon needs",
    ),
    Limit("horizon", 1_000, codes.HORIZON_TOO_LARGE, "steps", "the horizon of a query or export"),
    Limit("ground-actions", 200_000, codes.TOO_MANY_GROUND_ACTIONS, "actions", "the ground actions of a PDDL export"),
    Limit(
        "memory",
        8_192,
        codes.OUT_OF_MEMORY,
        "MB",
        "the memory of a catc process: the solver's own limit, and the process's address space (0: none)",
    ),
)

BY_NAME: dict[str, Limit] = {limit.name: limit for limit in LIMITS}


class Limits(Record):
    """The value of every limit (keywords: the fields of :data:`LIMITS`, default: theirs)."""

    __slots__ = (
        "input_bytes",
        "tokens",
        "nesting",
        "literal_digits",
        "constant_digits",
        "resources",
        "morphisms",
        "universe",
        "horizon",
        "ground_actions",
        "memory",
    )
    input_bytes: int
    tokens: int
    nesting: int
    literal_digits: int
    constant_digits: int
    resources: int
    morphisms: int
    universe: int
    horizon: int
    ground_actions: int
    memory: int

    def __init__(self, **values: int) -> None:
        for limit in LIMITS:
            set_field(self, limit.field, values.pop(limit.field, limit.default))
        if values:
            raise TypeError(f"unknown limit(s): {', '.join(sorted(values))}")

    def replace(self, **values: int) -> Limits:
        return Limits(**{**{limit.field: getattr(self, limit.field) for limit in LIMITS}, **values})


DEFAULT = Limits()

_current: ContextVar[Limits] = ContextVar("catc_limits", default=DEFAULT)


def current() -> Limits:
    """The limits in force (:data:`DEFAULT` unless a :func:`using` block says otherwise)."""
    return _current.get()


@contextmanager
def using(limits: Limits) -> Iterator[Limits]:
    """Run the block under ``limits``."""
    token = _current.set(limits)
    try:
        yield limits
    finally:
        _current.reset(token)


# ---------------------------------------------------------------- reading overrides


class LimitSpecError(ValueError):
    """A ``--limit`` or ``CATC_LIMIT_*`` value that is not a limit and a whole number."""


def _value(limit: Limit, text: str, where: str) -> int:
    text = text.strip().replace("_", "")
    lowest = 0 if limit.name == "memory" else 1
    if not (text.isascii() and text.isdigit()) or int(text[:30]) < lowest:
        least = "a whole number ≥ 0 (0: no limit)" if lowest == 0 else "a positive whole number"
        raise LimitSpecError(f"{where}: the {limit.name} limit must be {least}, got {text!r}")
    return int(text[:30])


def parse_specs(specs: Iterable[str], base: Limits | None = None) -> Limits:
    """``NAME=N`` specs (``--limit``) applied to ``base`` (default: the defaults)."""
    values: dict[str, int] = {}
    for spec in specs:
        name, equals, text = spec.partition("=")
        limit = BY_NAME.get(name.strip())
        if limit is None or not equals:
            known = ", ".join(BY_NAME)
            raise LimitSpecError(f"--limit expects NAME=N with NAME one of {known}; got {spec!r}")
        values[limit.field] = _value(limit, text, f"--limit {spec}")
    return (base or DEFAULT).replace(**values)


def from_environment(environ: Mapping[str, str], base: Limits | None = None) -> Limits:
    """``base`` with the ``CATC_LIMIT_*`` variables of ``environ`` applied."""
    values = {
        limit.field: _value(limit, environ[limit.env], limit.env) for limit in LIMITS if environ.get(limit.env, "")
    }
    return (base or DEFAULT).replace(**values)


# ---------------------------------------------------------------- crossing a limit


class LimitExceeded(Exception):
    """A limit crossed where no diagnostics collection is at hand (a query's horizon, the
    grounding, an export): the code, the message and where in the source."""

    def __init__(self, code: str, message: str, span: Span | None = None) -> None:
        super().__init__(message)
        self.code, self.message, self.span = code, message, span


@lru_cache(maxsize=8)
def _power_of_ten(digits: int) -> int:
    return 10**digits


def digits_over(n: int, digits: int) -> bool:
    """Whether the integer ``n`` has more than ``digits`` decimal digits (without writing it
    out: Python refuses to write integers of more than 4,300 digits)."""
    return abs(n) >= _power_of_ten(digits)


def count_text(n: int, noun: str = "") -> str:
    """``1,000,000,000,001``, or ``1 step``/``5,000 steps``: a count as messages write it."""
    return f"{n:,}" if not noun else f"{n:,} {noun}{'' if n == 1 else 's'}"


# ---------------------------------------------------------------- time


class Stopped(Exception):
    """A command stopped before its end: ``reason`` is "timeout" or "interrupted", ``phase``
    what it was doing (``"encoding"``, ``"validating"``, ...)."""

    reason = "stopped"

    def __init__(self, phase: str, seconds: float | None = None) -> None:
        super().__init__(f"{self.reason} while {phase}")
        self.phase, self.seconds = phase, seconds


class TimeLimitReached(Stopped):
    reason = "timeout"


class Interrupted(Stopped):
    reason = "interrupted"


class Clock:
    """The time limit of a block: ``at`` (``time.perf_counter()``; None: none) and ``limit``
    (the seconds it was given), the block it is nested in, and — on the outermost — whether
    the command was interrupted and the ``phase`` it is in."""

    __slots__ = ("at", "parent", "interrupted", "phase", "limit")

    def __init__(self, at: float | None, parent: Clock | None, limit: float | None) -> None:
        self.at, self.parent, self.limit = at, parent, limit
        self.interrupted = False
        self.phase = "starting"

    @property
    def root(self) -> Clock:
        clock = self
        while clock.parent is not None:
            clock = clock.parent
        return clock


_clock: ContextVar[Clock | None] = ContextVar("catc_clock", default=None)


def seconds_value(seconds: float | None, what: str = "timeout") -> float | None:
    """A time limit as given (None: none; ∞: none), or ValueError for NaN, 0 or less."""
    if seconds is None:
        return None
    if math.isnan(seconds) or seconds <= 0:
        raise ValueError(f"the {what} must be a positive number of seconds, got {seconds}")
    return None if math.isinf(seconds) else float(seconds)


@contextmanager
def deadline(seconds: float | None) -> Iterator[Clock]:
    """Within the block, the time limit is ``seconds`` from now (None or ∞: none of its own),
    or the enclosing block's when that comes first."""
    limit = seconds_value(seconds)
    parent = _clock.get()
    at = None if limit is None else time.perf_counter() + limit
    if parent is not None and parent.at is not None and (at is None or parent.at <= at):
        at, limit = parent.at, parent.limit  # the enclosing limit comes first
    clock = Clock(at, parent, limit)
    token = _clock.set(clock)
    try:
        yield clock
    finally:
        _clock.reset(token)


def clock() -> Clock | None:
    """The clock of the innermost :func:`deadline` block (None outside any)."""
    return _clock.get()


def deadline_at() -> float | None:
    """When the time is up (``time.perf_counter()``), or None."""
    c = _clock.get()
    return None if c is None else c.at


def interrupt() -> bool:
    """Mark the running command interrupted (Ctrl-C); False when none is running here."""
    c = _clock.get()
    if c is None:
        return False
    c.root.interrupted = True
    return True


def interrupted() -> bool:
    c = _clock.get()
    return c is not None and c.root.interrupted


def expired(slack: float = 0.0) -> bool:
    """Whether the command must stop: interrupted, or within ``slack`` seconds of its limit."""
    c = _clock.get()
    if c is None:
        return False
    return c.root.interrupted or (c.at is not None and time.perf_counter() >= c.at - slack)


def remaining(at: float | None = None) -> float | None:
    """Seconds left before the time limit, or before ``at`` if sooner (None: no limit);
    0 once the command must stop."""
    c = _clock.get()
    if c is not None and c.root.interrupted:
        return 0.0
    ends = [t for t in (at, None if c is None else c.at) if t is not None]
    return None if not ends else max(0.0, min(ends) - time.perf_counter())


def for_check(at: float | None = None) -> float | None:
    """The time a solver's next check may take: :func:`remaining`, but at least 1 ms (a
    solver given 0 would take it for "no limit"); None without a limit."""
    left = remaining(at)
    return None if left is None else max(0.001, left)


def stop_reason() -> str | None:
    """ "interrupted", "timeout" once the limit has passed, else None."""
    if interrupted():
        return "interrupted"
    return "timeout" if expired() else None


def note_phase(phase: str) -> None:
    """Note what the command is doing (for the message should its time run out there)."""
    c = _clock.get()
    if c is not None:
        c.root.phase = phase


#: How long past its time limit a command may go on finishing an answer it has (replaying it
#: in the validator to show it), and ignore a first Ctrl-C while it does.
FINISH_GRACE = 1.0


def check_time(phase: str, finishing: bool = False) -> None:
    """Note that the command is ``phase``; raise :class:`Interrupted` or
    :class:`TimeLimitReached` when it must stop.  A ``finishing`` phase, one the answer
    needs (reading the model; the validator's replay of an answer found in time), is not
    interrupted, and has :data:`FINISH_GRACE` seconds more."""
    c = _clock.get()
    if c is None:
        return
    c.root.phase = phase
    if c.root.interrupted and not finishing:
        raise Interrupted(phase)
    if c.at is not None and time.perf_counter() >= c.at + (FINISH_GRACE if finishing else 0.0):
        raise TimeLimitReached(phase, c.limit)
