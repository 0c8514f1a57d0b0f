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

Time is a limit of one run rather than of a model, and lives in :mod:`catgrammar.deadlines`;
its names (:func:`deadline`, :func:`check_time`, :class:`Stopped`, ...) are imported here too,
so ``limits.deadline(...)`` keeps working.

This is the lowest stage that needs limits (the reader does), so it imports nothing of catc.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from functools import lru_cache

from catgrammar import codes
from catgrammar.deadlines import (
    FINISH_GRACE,
    Clock,
    Interrupted,
    Stopped,
    TimeLimitReached,
    check_time,
    clock,
    deadline,
    deadline_at,
    expired,
    for_check,
    interrupt,
    interrupted,
    note_phase,
    remaining,
    seconds_value,
    stop_reason,
)
from catgrammar.record import Record, set_field
from catgrammar.span import Span

#: The size limits defined here, and the run-deadline names of :mod:`catgrammar.deadlines`.
__all__ = [
    "BY_NAME",
    "DEFAULT",
    "FINISH_GRACE",
    "LIMITS",
    "MIB",
    "Clock",
    "Interrupted",
    "Limit",
    "LimitExceeded",
    "LimitSpecError",
    "Limits",
    "Stopped",
    "TimeLimitReached",
    "check_time",
    "clock",
    "count_text",
    "current",
    "deadline",
    "deadline_at",
    "digits_over",
    "expired",
    "for_check",
    "from_environment",
    "interrupt",
    "interrupted",
    "note_phase",
    "parse_specs",
    "remaining",
    "seconds_value",
    "stop_reason",
    "using",
]

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
