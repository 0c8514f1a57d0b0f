"""Event sources: standard input or a file (one event a line), and a spool folder.

A spool folder (``STATE/spool`` by default) takes files of events, ``*.jsonl``, processed in
name order.  Producers write a file under another name (``*.tmp``, or anywhere else on the
same file system) and rename it into the folder, so that a file appears whole; ``catrt
event`` does that.  A file is moved to ``spool/done/`` once all its lines were handled; if
the runtime dies first, the file is read again at the next start and the events it had
accepted are no-ops (their ids were accepted), so no event is lost and none is applied
twice.  New files are noticed with ``watchdog`` when it is installed, else by looking again
every half second.
"""

from __future__ import annotations

import os
import queue
import threading
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from catrt.events import read_lines

DONE = "done"
SUFFIX = ".jsonl"


def pending(folder: Path) -> list[Path]:
    return sorted(p for p in folder.iterdir() if p.is_file() and p.suffix == SUFFIX and not p.name.startswith("."))


def drop(folder: Path, lines: list[str], name: str | None = None) -> Path:
    """Put events into a spool folder as one file that appears whole (write, sync, rename)."""
    folder.mkdir(parents=True, exist_ok=True)
    stamp = name or f"{time.time_ns():020d}-{os.getpid()}"
    tmp = folder / f".{stamp}.tmp"
    with open(tmp, "w", encoding="utf-8") as fh:
        fh.write("".join(line.rstrip("\n") + "\n" for line in lines))
        fh.flush()
        os.fsync(fh.fileno())
    final = folder / f"{stamp}{SUFFIX}"
    os.rename(tmp, final)
    return final


def file_lines(path: Path, label: str | None = None) -> Iterator[tuple[str, str]]:
    with open(path, encoding="utf-8", errors="surrogateescape") as fh:
        yield from read_lines(fh, label or str(path))


def finish(path: Path) -> None:
    """Move a handled file to ``done/``; a name handled before keeps its file (``NAME.1``, ``NAME.2``, …)."""
    done = path.parent / DONE
    done.mkdir(exist_ok=True)
    target, n = done / path.name, 0
    while target.exists():
        n += 1
        target = done / f"{path.name}.{n}"
    os.replace(path, target)


class Watcher:
    """Wakes the loop when a file appears in the folder (watchdog), or after ``timeout``."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.wake: queue.Queue[None] = queue.Queue()
        self.observer: Any = None
        try:
            from watchdog.events import FileSystemEventHandler
            from watchdog.observers import Observer
        except ImportError:
            return
        wake = self.wake

        class Handler(FileSystemEventHandler):
            def on_any_event(self, event: Any) -> None:
                if str(getattr(event, "dest_path", "") or event.src_path).endswith(SUFFIX):
                    wake.put(None)

        self.observer = Observer()
        self.observer.schedule(Handler(), str(folder), recursive=False)
        self.observer.daemon = True
        self.observer.start()

    def wait(self, timeout: float, stop: threading.Event) -> None:
        deadline = time.monotonic() + timeout
        step = timeout if self.observer is not None else min(timeout, 0.5)
        while not stop.is_set():
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                return
            try:
                self.wake.get(timeout=min(step, remaining))
                return
            except queue.Empty:
                if self.observer is None and pending(self.folder):
                    return

    def close(self) -> None:
        if self.observer is not None:
            self.observer.stop()
            self.observer.join(timeout=2)
