"""Run deadlines: how long one run of catc may take, and Ctrl-C (docs/limits.md).

These are limits of a *run*, not of the language: :mod:`catgrammar.limits` bounds what a
model may be (bytes, tokens, nesting, resources, horizon ...); this module bounds the time
a command spends on it.  It sits here, beside the reader, because it must be usable by every
stage from the reader up (catgrammar imports nothing of catc; catc and catrt import this).

:func:`deadline` gives a block a wall-clock limit (nested blocks keep the sooner one), every
long phase calls :func:`check_time` (the encoder per step, the validator per step, the PDDL
export per ground action), and a solver's checks get :func:`remaining`.  Ctrl-C is the same
kind of stop: :func:`interrupt` marks the running command, which then stops at its next check
and reports what it has, as at its time limit, but says "interrupted".
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TypeVar

T = TypeVar("T")


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


def call_within(phase: str, call: Callable[[], T]) -> T:
    """``call()`` — code that never looks at the clock (another library's parser) — within the
    command's time: it runs in a thread of its own and, should the time run out first,
    :class:`TimeLimitReached` (or :class:`Interrupted`) is raised here while the thread is left
    to finish on its own (a daemon: it does not keep the process alive).  Without a time
    limit, ``call()`` here."""
    c = _clock.get()
    if c is None or c.at is None:
        return call()
    import threading

    check_time(phase)
    outcome: list = []

    def run() -> None:
        try:
            outcome.append((True, call()))
        except BaseException as exc:  # handed to the caller below
            outcome.append((False, exc))

    worker = threading.Thread(target=run, name=f"catc-{phase}", daemon=True)
    worker.start()
    while not outcome:
        worker.join(min(0.05, max(0.0, c.at - time.perf_counter())))
        if not outcome:
            check_time(phase)  # raises once the time is up (or Ctrl-C)
    ok, value = outcome[0]
    if not ok:
        raise value
    return value
