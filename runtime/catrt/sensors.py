"""Shell sensors: the paper's shell-evaluated conditions, made safe enough to run on a robot.

A sensor is an argument list from the configuration — never a shell string, and nothing
from the model or an event is put into it.  It runs with no shell, no standard input, a
scrubbed environment (``PATH=/usr/bin:/bin``, ``LC_ALL=C.UTF-8``), the state folder as its
working directory, a timeout (the whole process group is killed), and at most 4 KiB of
output read.  The output must be exactly one value of the resource's sort: a number (an
exact decimal or a fraction), ``true``/``false``, a symbol, or symbols separated by spaces
for a set.  Anything else is a failure, journaled with what was printed, and changes
nothing.  The runtime refuses a configuration with sensors unless it was started with
``--allow-shell``.
"""

from __future__ import annotations

import contextlib
import os
import re
import signal
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from catc import ir
from catrt.config import Sensor
from catrt.events import exact

MAX_OUTPUT = 4096
_NAME = re.compile(r"[a-zA-Z_][a-zA-Z0-9_-]*")
ENVIRONMENT = {"PATH": "/usr/bin:/bin", "LC_ALL": "C.UTF-8", "LANG": "C.UTF-8"}


@dataclass
class Reading:
    sensor: str
    resource: str
    value: Any  # the event value (exact text, bool, symbol, or list), or None on failure
    error: str | None
    exit: int | None
    output: str
    seconds: float

    def to_json(self) -> dict[str, Any]:
        return {"sensor": self.sensor, "resource": self.resource, "value": self.value, "error": self.error,
                "exit": self.exit, "output": self.output, "seconds": round(self.seconds, 6)}  # fmt: skip


def run_sensor(sensor: Sensor, resource: ir.Resource | None, cwd: Path) -> Reading:
    start = time.perf_counter()
    fail = lambda why, code=None, out="": Reading(sensor.name, sensor.resource, None, why, code, out,  # noqa: E731
                                                  time.perf_counter() - start)  # fmt: skip
    if resource is None:
        return fail(f"the model has no resource '{sensor.resource}'")
    try:
        proc = subprocess.Popen(
            list(sensor.argv), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
            cwd=cwd, env=ENVIRONMENT, start_new_session=True, close_fds=True,
        )  # fmt: skip
    except OSError as exc:
        return fail(f"cannot run {sensor.argv[0]}: {exc.strerror or exc}")
    try:
        out, _ = _communicate(proc, sensor.timeout)
    except subprocess.TimeoutExpired:
        _kill(proc)
        return fail(f"timed out after {sensor.timeout:g} s")
    shown = out[:200].decode("utf-8", "replace")
    if len(out) > MAX_OUTPUT:
        return fail(f"printed more than {MAX_OUTPUT} bytes", proc.returncode, shown)
    if proc.returncode != 0:
        return fail(f"exited with status {proc.returncode}", proc.returncode, shown)
    try:
        text = out.decode("utf-8")
    except UnicodeDecodeError:
        return fail("printed bytes that are not UTF-8", proc.returncode, shown)
    value, why = parse_reading(text, resource)
    if why is not None:
        return fail(why, proc.returncode, shown)
    return Reading(sensor.name, sensor.resource, value, None, proc.returncode, shown, time.perf_counter() - start)


def _communicate(proc: subprocess.Popen[bytes], timeout: float) -> tuple[bytes, None]:
    """At most MAX_OUTPUT + 1 bytes of standard output, within ``timeout``."""
    assert proc.stdout is not None
    deadline = time.monotonic() + timeout
    chunks: list[bytes] = []
    size = 0
    os.set_blocking(proc.stdout.fileno(), False)
    while True:
        remaining = deadline - time.monotonic()
        if remaining <= 0:
            raise subprocess.TimeoutExpired(proc.args, timeout)
        try:
            chunk = proc.stdout.read(MAX_OUTPUT + 1 - size)
        except BlockingIOError:
            chunk = None
        if chunk:
            chunks.append(chunk)
            size += len(chunk)
            if size > MAX_OUTPUT:
                _kill(proc)
                return b"".join(chunks), None
            continue
        if chunk == b"":  # end of output
            proc.wait(timeout=max(remaining, 0.01))
            return b"".join(chunks), None
        time.sleep(min(0.01, remaining))


def _kill(proc: subprocess.Popen[bytes]) -> None:
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(proc.pid, signal.SIGKILL)
    proc.wait()


def parse_reading(text: str, resource: ir.Resource) -> tuple[Any, str | None]:
    """One value of ``resource``'s sort from a sensor's output, or (None, why not)."""
    body = text.strip()
    if "\n" in body or "\r" in body:
        return None, "printed more than one line"
    kind = resource.sort.kind
    if resource.sort.is_numeric:
        number = exact(body)
        if number is None:
            return None, f"{body[:40]!r} is not a number"
        if kind is ir.SortKind.INT and number.denominator != 1:
            return None, f"{body!r} is not an integer"
        from catc.ir.numbers import ratio_text

        return ratio_text(number), None
    if kind is ir.SortKind.BOOL:
        if body in ("true", "false"):
            return body == "true", None
        return None, f"{body[:40]!r} is not true or false"
    if kind is ir.SortKind.SET:
        names = body.split()
        bad = [n for n in names if not _NAME.fullmatch(n)]
        return (None, f"{bad[0][:40]!r} is not a symbol") if bad else (sorted(set(names)), None)
    if not _NAME.fullmatch(body):
        return None, f"{body[:40]!r} is not a symbol"
    return body, None
