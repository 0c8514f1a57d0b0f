"""The limits of one ``catc`` command as the executable enforces them (docs/limits.md).

* :func:`command_limits` — the limits in force: the defaults, then ``CATC_LIMIT_*`` (the
  environment is read here, at the edge), then ``--limit NAME=N`` and ``--memory MB``;
* :func:`limit_memory` — the memory limit on this process: its address space
  (``RLIMIT_AS``, soft, so that a planner started by ``export --run`` can lift it for itself)
  and the solver's own limit, so a run that needs more stops with error E1110 (exit 3)
  instead of exhausting the machine;
* :func:`stoppable` — Ctrl-C and the time limit while a command runs: the first Ctrl-C
  during a query asks it to stop and report what it has ("interrupted", exit 130), a second
  stops at once; and a watchdog that, should some phase not notice its time is up, stops the
  command :data:`GRACE` seconds past its ``--timeout`` (error E1109, exit 3), and ends the
  process :data:`LAST_GRACE` seconds after that whatever it is doing.
"""

from __future__ import annotations

import os
import signal
import sys
import threading
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from typing import Any

from catgrammar import codes, limits


class Process:
    """Whether this process is the ``catc`` executable (:func:`catc.interfaces.entry.main`
    started it): only then are the settings of the whole process made — its memory limit, and
    the watchdog's last resort of ending it.  A program or a test that runs a command in its
    own process (``main(argv)``) keeps its process as it is."""

    executable = False


#: How long past its time limit a command may take to notice it (it then stops with E1109) —
#: more than the time it has to finish an answer it found (limits.FINISH_GRACE) — and how
#: much longer before the process ends regardless.
GRACE = 2.0
LAST_GRACE = 2.0


class LimitArgumentError(ValueError):
    """A malformed ``--limit``, ``--memory`` or ``CATC_LIMIT_*`` value (E1111)."""

    code = codes.BAD_LIMIT


def command_limits(
    specs: Sequence[str] = (), memory: int | None = None, environ: Mapping[str, str] | None = None
) -> limits.Limits:
    """The defaults, then ``CATC_LIMIT_*`` of ``environ`` (default: the process's), then the
    ``--limit`` specs, then ``--memory``.  Raises :class:`LimitArgumentError`."""
    try:
        found = limits.from_environment(os.environ if environ is None else environ)
        found = limits.parse_specs(specs, found)
    except limits.LimitSpecError as exc:
        raise LimitArgumentError(str(exc)) from None
    if memory is not None:
        if memory < 0:
            raise LimitArgumentError(f"--memory must be a number of megabytes ≥ 0 (0: no limit), got {memory}")
        found = found.replace(memory=memory)
    return found


#: Memory set aside under ``--memory`` and given back when the limit is reached, so that the
#: E1110 report can still be written: without it, Python itself may run out while printing it
#: ("MemoryError ... lost sys.stderr", exit 1 — seen in CI's slow group under load).
RESERVE_BYTES = 8 * 1024 * 1024
#: The bound ``close`` of each reservation: at the limit even looking a method up allocates (a
#: bound-method object, perhaps a new 1 MB arena) and can raise MemoryError itself, so the
#: method is looked up while there is memory.
_reserve: list[Any] = []
#: The report of :func:`last_words`, rendered while there was memory: (stdout, stderr) bytes.
_last_words: list[bytes] = []


def release_reserve() -> None:
    """Give back the memory :func:`limit_memory` set aside (the limit was reached).  Looks
    nothing up and builds nothing: it must work when nothing more can be allocated."""
    while _reserve:
        _reserve[-1]()
        del _reserve[-1]


def out_of_memory_error(exc: BaseException) -> bool:
    """Whether ``exc`` means the memory limit was reached: a MemoryError, or — only under a
    limit this process set (``--memory``) — the SystemError "error return without exception
    set" that CPython 3.11 itself raises when an allocation fails where no MemoryError can be
    made (seen at 152 and 249 MB of address space, mid-encoding, in pure Python code)."""
    if isinstance(exc, MemoryError):
        return True
    return bool(_last_words) and isinstance(exc, SystemError) and "without exception set" in str(exc)


def last_words() -> None:
    """The last resort when the memory limit is reached and even the E1110 report cannot be
    made: give the reserve back, write the report prepared by :func:`limit_memory` (the
    ``catc.error/1`` document on stdout under ``--json``, the error line on stderr) with
    system calls only, and end the process with exit 3.  Never returns."""
    try:  # noqa: SIM105 - contextlib.suppress would allocate a context manager
        release_reserve()
    except MemoryError:  # pragma: no cover - nothing more can be done about it
        pass
    if _last_words:
        if _last_words[0]:
            os.write(1, _last_words[0])
        os.write(2, _last_words[1])
    else:  # pragma: no cover - no limit was set, yet memory ran out (the machine's own limit)
        os.write(2, b"catc: error[E1110]: out of memory\n")
    os._exit(3)


def limit_memory(megabytes: int, as_json: bool = False) -> None:
    """Cap this process at ``megabytes`` of address space (0: no cap) and the solver at as
    much.  The soft limit only: a child process may raise it again (a planner does:
    :func:`catc.targets.enhsp.lift_memory_limit`).  Only in the executable (:class:`Process`).
    ``as_json``: the command answers in JSON (the report of :func:`last_words`)."""
    if not Process.executable:
        return
    try:
        import resource
    except ImportError:  # pragma: no cover - not on POSIX: the solver's limit only
        resource = None  # type: ignore[assignment]
    if megabytes and not _reserve:
        import mmap

        _reserve.append(mmap.mmap(-1, RESERVE_BYTES).close)
        message = out_of_memory_message(None, megabytes)
        document = stopped_document(codes.OUT_OF_MEMORY, message) + "\n" if as_json else ""
        _last_words[:] = [document.encode(), f"catc: error[{codes.OUT_OF_MEMORY}]: {message}\n".encode()]
    if resource is not None:
        _, hard = resource.getrlimit(resource.RLIMIT_AS)
        soft = resource.RLIM_INFINITY if megabytes == 0 else megabytes * limits.MIB
        if hard != resource.RLIM_INFINITY and (soft == resource.RLIM_INFINITY or soft > hard):
            soft = hard
        resource.setrlimit(resource.RLIMIT_AS, (soft, hard))
    from catc.smt.backend import keep_solver_contexts, limit_solver_memory

    limit_solver_memory(megabytes)
    keep_solver_contexts()  # the executable ends with os._exit: its solver contexts need no freeing


def out_of_memory_message(phase: str | None = None, megabytes: int | None = None) -> str:
    most = limits.current().memory if megabytes is None else megabytes
    where = f" while {phase}" if phase else ""
    limit = limits.BY_NAME["memory"]
    return (
        f"out of memory{where}: the memory limit of {most:,} MB was reached; raise it with --memory MB or {limit.env}"
    )


def time_limit_message(seconds: float | None, phase: str | None) -> str:
    limit = f" of {seconds:g} s" if seconds is not None else ""
    where = f" while {phase}" if phase else ""
    return f"the time limit{limit} was reached{where}; no answer (--timeout)"


def clock_message(clock: limits.Clock) -> str:
    return time_limit_message(clock.root.limit, clock.root.phase)


# ---------------------------------------------------------------- Ctrl-C and the watchdog


class _Run:
    """What the signal handler and the watchdog know of the running command."""

    def __init__(self, clock: limits.Clock) -> None:
        self.clock = clock
        self.soft = False  # a query is running: the first Ctrl-C asks it to stop
        self.timed_out = False  # the watchdog stopped it
        self.as_json = False  # --json: the last resort also writes the catc.error/1 document
        self.done = threading.Event()


@contextmanager
def stoppable(clock: limits.Clock) -> Iterator[_Run]:
    """Within the block: Ctrl-C and the watchdog (main thread only; elsewhere, nothing)."""
    run = _Run(clock)
    if threading.current_thread() is not threading.main_thread():
        yield run
        return
    previous = signal.getsignal(signal.SIGINT)
    signal.signal(signal.SIGINT, lambda signum, frame: _on_sigint(run))
    unraisable, alarm = sys.unraisablehook, getattr(signal, "SIGALRM", None)
    alarm_handler = signal.getsignal(alarm) if alarm is not None else None
    if alarm is not None:
        sys.unraisablehook = _interrupt_again(run, unraisable)
    watcher = _watchdog(run)
    try:
        yield run
    finally:
        run.done.set()
        if watcher is not None:
            watcher.join(0.1)
        signal.signal(signal.SIGINT, previous)
        if alarm is not None:
            signal.setitimer(signal.ITIMER_REAL, 0)
            if alarm_handler is not None:
                signal.signal(alarm, alarm_handler)
        sys.unraisablehook = unraisable


def _interrupt_again(run: _Run, previous: Any) -> Any:
    """A Ctrl-C or the watchdog's SIGINT that lands in a finaliser (Z3's ``Solver.__del__``
    during garbage collection) cannot propagate: Python would print "Exception ignored in"
    with a traceback and carry on as if nothing happened.  Instead it is sent again, to be
    raised where it can be (should it land in a finaliser again, it is sent again)."""

    def hook(unraisable: Any) -> None:
        if unraisable.exc_type is not None and issubclass(unraisable.exc_type, KeyboardInterrupt):
            # in 1 ms, by the clock: a signal sent from here would be handled in here again
            signal.signal(signal.SIGALRM, lambda signum, frame: _on_sigint(run))
            signal.setitimer(signal.ITIMER_REAL, 0.001)
            return
        previous(unraisable)

    return hook


def _on_sigint(run: _Run) -> None:
    root = run.clock.root
    if run.timed_out and isinstance(sys.exc_info()[1], limits.Stopped):
        # the watchdog's SIGINT while the command already reports its time limit: it would
        # cut the report short and turn exit 3 into 130 (issue 28, finding 2)
        return
    if run.soft and not root.interrupted and not run.timed_out:
        root.interrupted = True  # the query stops at its next check and reports what it has
        return
    raise KeyboardInterrupt


def _watchdog(run: _Run) -> threading.Thread | None:
    import time

    at = run.clock.at
    if at is None or at - time.perf_counter() > 30 * 24 * 3600:  # none, or as good as none (1e308 s)
        return None

    def watch() -> None:
        if run.done.wait(max(0.0, at - time.perf_counter()) + GRACE):
            return
        run.timed_out = True  # the SIGINT below is the watchdog's, not the user's
        signal.pthread_kill(threading.main_thread().ident or 0, signal.SIGINT)
        if run.done.wait(LAST_GRACE) or not Process.executable:
            return
        message = clock_message(run.clock)
        if run.as_json:  # the document --json promises (docs/cli.md), on standard output
            os.write(1, (_error_document(message) + "\n").encode())
        os.write(2, f"catc: error[{codes.TIME_LIMIT}]: {message}\n".encode())
        os._exit(3)

    thread = threading.Thread(target=watch, name="catc-watchdog", daemon=True)
    thread.start()
    return thread


def stopped_exit(run: _Run | None, as_json: bool, echo: Any) -> int:
    """After a KeyboardInterrupt: report it (time limit or Ctrl-C) and return the exit code."""
    if run is not None and run.timed_out:
        return time_limit_exit(clock_message(run.clock), as_json, echo)
    echo("catc: interrupted", True)
    return 130


def time_limit_exit(message: str, as_json: bool, echo: Any) -> int:
    """E1109 (with ``--json`` also a catc.error/1 document); exit 3."""
    if as_json:
        echo(_error_document(message))
    echo(f"catc: error[{codes.TIME_LIMIT}]: {message}", True)
    return 3


#: The ``reason`` of the catc.error/1 document of a command stopped by a limit (status
#: "unknown", as every unknown answer has its reason — docs/cli.md), by its error code.
STOP_REASONS = {codes.TIME_LIMIT: "timeout", codes.OUT_OF_MEMORY: "memory"}


def _error_document(message: str) -> str:
    # (issue 28: the time ran out while reading the model, and the document had no reason)
    return stopped_document(codes.TIME_LIMIT, message)


def stopped_document(code: str, message: str) -> str:
    """The catc.error/1 document of a command stopped by its time (E1109) or memory (E1110)
    limit: status "unknown" with its reason (:data:`STOP_REASONS`)."""
    import json

    doc = {
        "schema": "catc.error/1",
        "status": "unknown",
        "reason": STOP_REASONS[code],
        "diagnostics": [_diag(code, message)],
    }
    return json.dumps(doc)


def _diag(code: str, message: str) -> dict:
    return {
        "code": code,
        "name": codes.CODES[code].name,
        "severity": "error",
        "message": message,
        "location": None,
        "notes": [],
    }
