"""Driving the runtime: events from standard input, a file, a spool folder or an MQTT topic;
the shell sensors when they are due; stop at the end of the events (standard input, a file),
or on SIGTERM/SIGINT (a spool folder, MQTT: the event being handled is finished first)."""

from __future__ import annotations

import errno
import io
import signal
import sys
import threading
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from catrt.config import Sensor
from catrt.events import read_lines
from catrt.mqtt import Subscriber, is_address
from catrt.runtime import Runtime
from catrt.spool import Watcher, file_lines, finish, pending


class _Sensors:
    def __init__(self, sensors: Sequence[Sensor]) -> None:
        self.sensors = list(sensors)
        self.due = {s.name: 0.0 for s in self.sensors}

    def poll(self, runtime: Runtime) -> None:
        now = time.monotonic()
        ready = [s for s in self.sensors if self.due[s.name] <= now]
        for s in ready:
            self.due[s.name] = now + s.every
        if ready:
            runtime.read_sensors(ready)

    def wait(self) -> float:
        if not self.sensors:
            return 3600.0
        return max(0.0, min(self.due.values()) - time.monotonic())


def loop(runtime: Runtime, source: str | None, *, once: bool, stop: threading.Event, sensors: Sequence[Sensor]) -> None:
    clock = _Sensors(sensors)
    if is_address(source):  # connected before anything is decided: no broker there changes nothing
        _mqtt(runtime, Subscriber.open(source, runtime.folder), clock, stop)
        return
    path = Path(source) if source not in (None, "-") else runtime.folder / "spool"
    if source not in (None, "-") and not path.exists():
        raise FileNotFoundError(f"no such file or folder: {source}")
    runtime.start()
    clock.poll(runtime)
    if source == "-":
        _lines(runtime, read_lines(stdin_text(), "<stdin>"), clock, stop)
        return
    if path.exists() and not path.is_dir():  # a file, a FIFO, <(…), /dev/stdin, /dev/null: a stream of lines
        # a regular file's lines never keep the loop waiting: the model files are written at
        # most every second during them, and at their end (a stream may wait: written each time)
        runtime.defer_model = path.is_file()
        _lines(runtime, file_lines(path), clock, stop)
        runtime.flush_model()
        return
    path.mkdir(parents=True, exist_ok=True)
    runtime.defer_model = True  # written before the spool is watched again
    _spool(runtime, path, clock, stop, once)


def stdin_text() -> Any:
    """Standard input as UTF-8 whatever the locale says, a byte that is not UTF-8 kept (as a
    surrogate) so that the event holding it is rejected where it is, not the whole run."""
    return io.TextIOWrapper(sys.stdin.buffer, encoding="utf-8", errors="surrogateescape")


def _lines(runtime: Runtime, lines: Iterator[tuple[str, str]], clock: _Sensors, stop: threading.Event) -> None:
    """Until the lines end, or SIGTERM/SIGINT (the event being handled is finished first)."""
    previous = _on_signals(stop)
    try:
        for where, line in lines:
            if stop.is_set():
                return
            handle(runtime, line, where, stop)
            clock.poll(runtime)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


#: Seconds to wait before each new try when the disk is full (E1016); after the last, the
#: loop stops with E1016 (the event not acknowledged: a spool file stays in the spool).
BACKOFF = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 30.0, 30.0, 30.0, 30.0)


def disk_full(exc: BaseException) -> bool:
    from catrt.store import StoreError

    return (isinstance(exc, StoreError) and exc.code == "E1016") or (
        isinstance(exc, OSError) and exc.errno == errno.ENOSPC
    )


def handle(runtime: Runtime, line: str, where: str, stop: threading.Event) -> None:
    """Hand one line to the runtime; on a full disk, back off and try again (an event whose
    transaction did not commit was not acknowledged; one that did is a duplicate the second
    time, and an enactment the full disk interrupted is finished first)."""
    for wait in (*BACKOFF, None):
        try:
            runtime.resume()
            runtime.handle_line(line, where)
            return
        except (OSError, RuntimeError) as exc:
            if wait is None or not disk_full(exc) or stop.is_set():
                raise
            runtime.say_disk_full(where, str(exc), wait)
            stop.wait(wait)


def _spool(runtime: Runtime, folder: Path, clock: _Sensors, stop: threading.Event, once: bool) -> None:
    previous = _on_signals(stop)
    watcher = Watcher(folder) if not once else None
    try:
        while not stop.is_set():
            for path in pending(folder):
                for where, line in file_lines(path, f"spool/{path.name}"):
                    if stop.is_set():
                        return
                    handle(runtime, line, where, stop)
                    clock.poll(runtime)
                finish(path)
            runtime.flush_model()
            if watcher is None:  # --once
                return
            watcher.wait(min(clock.wait(), 1.0), stop)
            clock.poll(runtime)
    finally:
        if watcher is not None:
            watcher.close()
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _mqtt(runtime: Runtime, subscriber: Subscriber, clock: _Sensors, stop: threading.Event) -> None:
    """paho's thread queues the messages; this thread hands each to the runtime, then
    acknowledges it (one handled but not acknowledged is delivered again: its id makes it a
    no-op)."""
    previous = _on_signals(stop)
    runtime.defer_model = True
    try:
        runtime.start()
        clock.poll(runtime)
        while not stop.is_set():
            message = subscriber.get(min(clock.wait(), 0.5))
            if message is None:  # nothing waiting: the model files catch up
                runtime.flush_model()
            else:  # a full disk: retried with back-off; acknowledged only once handled
                handle(runtime, message.text, message.where, stop)
                subscriber.ack(message)
            clock.poll(runtime)
    finally:
        subscriber.close()
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _on_signals(stop: threading.Event) -> dict[int, Any]:
    previous: dict[int, Any] = {}
    for sig in (signal.SIGTERM, signal.SIGINT):
        previous[sig] = signal.signal(sig, lambda *_: stop.set())
    return previous
