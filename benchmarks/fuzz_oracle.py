"""What one fuzz input must satisfy, from parse to export (issue 15, item 2).

:func:`examine` takes the bytes of one ``.cat`` file and runs the whole pipeline on it, in
this process: parse and check (``catc check``), ``catc fmt`` (idempotent, and the formatted
text checks to the same diagnostics and the same checked IR, positions aside), then, for
each problem that checks clean: solve (encode + Z3 + the independent validator, as ``catc
solve --timeout T`` does), a second replay of a SAT answer by the validator, and the PDDL
export in both flavours.  It returns the findings, each in one category of
:data:`CATEGORIES`; an input that reaches only a diagnostic has none.

Every stage runs under a watchdog (``signal.setitimer``): past ``timeout + GRACE`` seconds a
:class:`Hang` is raised in the stage's Python code and the stage counts as a hang; a stage
that finishes but took longer than that counts as a hang too (``catc solve --timeout 5``
must return within 6 s).  A hang inside C code that never returns to Python is left to the
process-level watchdog of ``benchmarks/fuzz.py``.

Used by ``benchmarks/fuzz.py`` (atheris) and by ``tests/test_fuzz_fixtures.py`` (the
minimised reproducers under ``tests/fixtures/fuzz/``).
"""

from __future__ import annotations

import signal
import sys
import time
import traceback
from collections.abc import Iterator, Mapping
from contextlib import contextmanager, nullcontext
from dataclasses import dataclass
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "compiler")]  # this tree's catc, also when run as a script

from catc import ir  # noqa: E402
from catc.frontend.formatter import format_file, format_text  # noqa: E402
from catc.frontend.session import check_files  # noqa: E402
from catc.ir.views import apply_view  # noqa: E402
from catc.queries.solve import SolveStatus, solve  # noqa: E402
from catc.semantics.horizon import default_horizon  # noqa: E402
from catc.semantics.validate import ValidationFailure, validate  # noqa: E402
from catc.targets.pddl import ExportError, export_pddl  # noqa: E402
from catgrammar import limits  # noqa: E402
from catgrammar.diagnostics import Diagnostics  # noqa: E402
from catgrammar.record import Record  # noqa: E402
from catgrammar.span import Span  # noqa: E402

INTERNAL = "internal errors"
HANG = "hangs past the timeout"
NOT_IDEMPOTENT = "fmt not idempotent"
MEANING = "fmt changed the meaning"
REJECTED = "SAT answers rejected by the validator"
DIED = "fuzzing process died (crash, out of memory, stuck in C code)"
CATEGORIES = (INTERNAL, HANG, NOT_IDEMPOTENT, MEANING, REJECTED, DIED)

#: Seconds a stage may run past its timeout before it counts as a hang (the issue's bar:
#: ``catc solve --timeout 5`` returns within 6 s).
GRACE = 1.0
#: How many problems of one file go through the solver and the export.
MAX_PROBLEMS = 2
#: What the command line reports as an answer rather than a bug: a refused export, a limit
#: crossed (docs/limits.md: a located error with its code), the time limit reached.
ANSWERS: tuple[type[BaseException], ...] = (ExportError, limits.LimitExceeded, limits.Stopped)


@dataclass(frozen=True)
class Finding:
    category: str
    stage: str
    detail: str


class Hang(BaseException):
    """Raised by the watchdog; a BaseException so that no ``except Exception`` swallows it."""


def _alarm(signum: int, frame: Any) -> None:
    raise Hang()


@contextmanager
def watchdog(seconds: float) -> Iterator[None]:
    """Raise :class:`Hang` in this thread's Python code after ``seconds``."""
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, previous)


def _where(exc: BaseException) -> str:
    """The innermost frames of catc's own code in a traceback, for a one-line detail."""
    frames = [
        f for f in traceback.extract_tb(exc.__traceback__) if "/catc/" in f.filename or "/catgrammar/" in f.filename
    ]
    return " < ".join(f"{Path(f.filename).name}:{f.lineno} {f.name}" for f in reversed(frames[-3:]))


class _Run:
    """The findings of one input, stage by stage."""

    def __init__(self, timeout: float | None) -> None:
        self.timeout = timeout
        self.findings: list[Finding] = []
        self.reached: list[str] = []  # "checked clean", "solved sat", "exported", ...

    def add(self, category: str, stage: str, detail: str) -> None:
        self.findings.append(Finding(category, stage, detail))

    def stage(self, name: str, call: Any, *args: Any, expected: tuple[type[BaseException], ...] = (), **kw: Any) -> Any:
        """``call(*args, **kw)`` under the watchdog: its value, or None after a finding (or
        after one of the ``expected`` exceptions, which are answers, not findings)."""
        limit = None if self.timeout is None else self.timeout + GRACE
        t0 = time.perf_counter()
        try:  # the stage runs as a command with --timeout does: one deadline over all of it
            with watchdog(limit + 2.0) if limit is not None else nullcontext(), limits.deadline(self.timeout):
                value = call(*args, **kw)
        except Hang as exc:
            self.add(HANG, name, f"stopped after {time.perf_counter() - t0:.1f} s in {_where(exc)}")
            return None
        except ValidationFailure as exc:
            self.add(REJECTED, name, str(exc)[:300])
            return None
        except (*ANSWERS, *expected):
            return None
        except Exception as exc:
            self.add(INTERNAL, name, f"{type(exc).__name__}: {str(exc)[:200]} at {_where(exc)}")
            return None
        elapsed = time.perf_counter() - t0
        if limit is not None and elapsed > limit:
            self.add(HANG, name, f"returned after {elapsed:.1f} s (timeout {self.timeout} s)")
        return value


# ---------------------------------------------------------------- positions aside


def shape(value: Any, memo: dict[int, Any] | None = None) -> Any:
    """``value`` (IR records, containers, atoms) with every source position dropped: two
    checks of texts that differ only in layout give equal shapes."""
    memo = {} if memo is None else memo
    key = id(value)
    if key in memo:
        return memo[key]
    out: Any
    if isinstance(value, Span):
        out = None
    elif isinstance(value, Record):
        out = (type(value).__name__, *(shape(getattr(value, f), memo) for f in value._fields if f != "span"))
    elif isinstance(value, Mapping):
        out = ("dict", *((shape(k, memo), shape(v, memo)) for k, v in value.items()))
    elif isinstance(value, (list, tuple)):
        out = (type(value).__name__, *(shape(v, memo) for v in value))
    elif isinstance(value, (set, frozenset)):
        out = ("set", *sorted(repr(shape(v, memo)) for v in value))
    else:
        out = value
    memo[key] = out
    return out


def _diagnostic_codes(diags: Diagnostics) -> list[tuple[str, str]]:
    return sorted((d.severity.value, d.code) for d in diags)


def _checked(path: Path) -> tuple[Diagnostics, dict[str, ir.Domain], dict[str, ir.Instance]]:
    diags = Diagnostics()
    domains, instances = check_files([str(path)], diags)
    return diags, domains, instances


# ---------------------------------------------------------------- the stages


def _check_stage(run: _Run, path: Path) -> tuple[Diagnostics, dict[str, ir.Domain], dict[str, ir.Instance]] | None:
    checked = run.stage("check", _checked, path)
    if checked is None:
        return None
    for d in checked[0]:
        if not d.message.strip():
            run.add(INTERNAL, "check", f"an empty message for {d.code}")
        if d.span is not None and (d.span.line < 1 or d.span.column < 1):
            run.add(INTERNAL, "check", f"{d.code} located at line {d.span.line}, column {d.span.column}")
    return checked


def _fmt_stage(
    run: _Run, path: Path, checked: tuple[Diagnostics, dict[str, ir.Domain], dict[str, ir.Instance]]
) -> None:
    # a FormatError is the formatter's own alarm (it changed a token or a comment): a bug
    pair = run.stage("fmt", format_file, str(path), Diagnostics())
    if pair is None:  # the file does not parse: nothing to format
        return
    formatted = pair[1]
    again = run.stage("fmt", format_text, formatted)
    if again is not None and again != formatted:
        run.add(NOT_IDEMPOTENT, "fmt", "formatting the formatted text changes it again")
    path.write_text(formatted, encoding="utf-8")  # the same path: the IR may name its file
    after = run.stage("check", _checked, path)
    if after is None:
        return
    before_codes, after_codes = _diagnostic_codes(checked[0]), _diagnostic_codes(after[0])
    if before_codes != after_codes:
        run.add(MEANING, "fmt", f"diagnostics {before_codes} became {after_codes}")
    elif shape((checked[1], checked[2])) != shape((after[1], after[2])):
        run.add(MEANING, "fmt", "the checked IR differs after formatting")


def _solve_stage(run: _Run, inst: ir.Instance, flavors: tuple[str, ...]) -> None:
    viewed = run.stage("view", apply_view, inst, None)
    if viewed is None:
        return
    k = default_horizon(viewed)
    result = run.stage("solve", solve, viewed, timeout=run.timeout)
    if result is not None:
        run.reached.append(f"answered {result.status.value}")
    if result is not None and result.status is SolveStatus.SAT:
        report = run.stage("validate", validate, viewed, result.plan, horizon=k)
        if report is not None and not report.ok:
            run.add(REJECTED, "validate", "; ".join(v.message for v in report.violations[:3]))
    for flavor in flavors:
        if run.stage(f"export {flavor}", export_pddl, viewed, flavor=flavor) is not None:
            run.reached.append(f"exported ({flavor})")


def examine(
    data: bytes,
    workdir: Path,
    *,
    timeout: float | None = 2.0,
    reached: list[str] | None = None,
    flavors: tuple[str, ...] = ("enhsp", "smtplan"),
) -> list[Finding]:
    """Every finding of the pipeline on ``data`` (the bytes of one .cat file), run in
    ``workdir`` (an empty folder of its own: the loader looks beside the file).  With
    ``timeout=None`` nothing is timed: no watchdog, no deadline for the solver, no hangs
    (what the tests use: they assert no time).  The
    stages the input reached ("checked clean", "answered sat", ...) are appended to
    ``reached``."""
    run = _Run(timeout)
    if reached is not None:
        run.reached = reached
    path = workdir / "fuzz.cat"
    path.write_bytes(data)
    checked = _check_stage(run, path)
    if checked is None:
        return run.findings
    _fmt_stage(run, path, checked)
    diags, _, instances = checked
    if not diags.has_errors and instances:
        run.reached.append("checked clean")
        for name in sorted(instances)[:MAX_PROBLEMS]:
            _solve_stage(run, instances[name], flavors)
    return run.findings


# ---------------------------------------------------------------- replay in a clean process


def main() -> None:
    """``python benchmarks/fuzz_oracle.py FILE... [--timeout T]``: the findings on each file,
    one JSON object a line, in this (uninstrumented) process; exit 1 when there are any.
    benchmarks/fuzz.py replays every hang this way before it counts it."""
    import argparse
    import json
    import tempfile

    ap = argparse.ArgumentParser(description=main.__doc__)
    ap.add_argument("files", nargs="+")
    ap.add_argument("--timeout", type=float, default=2.0)
    args = ap.parse_args()
    found = False
    for name in args.files:
        with tempfile.TemporaryDirectory() as work:
            for f in examine(Path(name).read_bytes(), Path(work), timeout=args.timeout):
                found = True
                print(json.dumps({"file": name, "category": f.category, "stage": f.stage, "detail": f.detail}))
    raise SystemExit(1 if found else 0)


if __name__ == "__main__":
    main()
