"""Every phase of a command honours ``--timeout`` (issue 28, finding 4: ``solve --sequential
--timeout 5`` of a 2.1 MB model ended at 7.6 s, ``export pddl --timeout 10`` at 13.4 s — the
reader, the encoder's steps, Z3's reading of a step and the export's parsers never looked at
the clock, so the watchdog stopped them seconds late).

No test here measures time.  A fake clock (:class:`Jump`) stands still until a given phase
has looked at it ``after`` times, then leaps past any limit: the phase must stop at its next
look, and the command says so by its exit code and a message that names the phase.  Jumping
only after the phase's first look shows the phase looks again *while it works*, not only at
its entry (the time a phase may run on past the limit is the time between two looks)."""

from __future__ import annotations

import json
import threading
import time

import pytest
from conftest import ROOT, run_catc

from catgrammar import deadlines, limits


class Jump:
    """The clock of :mod:`catgrammar.deadlines`: the real time of its making until ``phase``
    has read it more than ``after`` times, then a million seconds later."""

    def __init__(self, phase: str, after: int = 1) -> None:
        self.base = time.perf_counter()
        self.phase, self.after = phase, after
        self.looks = 0
        self.jumped = False

    def perf_counter(self) -> float:
        if not self.jumped:
            c = deadlines.clock()
            if c is not None and c.root.phase == self.phase:
                self.looks += 1
                self.jumped = self.looks > self.after
        return self.base + (1e6 if self.jumped else 0.0)


@pytest.fixture
def jump(monkeypatch):
    """``jump(phase, after)`` installs a :class:`Jump` as the deadlines' clock.  (The watchdog
    keeps the real clock: with ``--timeout 600`` it never acts within a test.)"""

    def install(phase: str, after: int = 1) -> Jump:
        clock = Jump(phase, after)
        monkeypatch.setattr(deadlines, "time", clock)
        return clock

    return install


def catalog(morphisms: int) -> str:
    """Many interchangeable components (about 40 tokens each) and a goal none reaches."""
    lines = ["(define (domain big) (:requirements :numeric :free-parameters)", "  (:resources (ram real) (done bool))"]
    lines += [
        f"  (:morphism m{i} :parameters ((r real :bounds (0 1))) :precondition (>= ram r) :effect (decrease ram r))"
        for i in range(morphisms)
    ]
    lines.append(")")
    lines.append("(define (problem p) (:domain big) (:init (= ram 8)) (:goal done) (:horizon 3))")
    return "\n".join(lines) + "\n"


@pytest.fixture
def model(tmp_path) -> str:
    path = tmp_path / "big.cat"
    path.write_text(catalog(300))  # ~9,000 tokens: the reader looks at the clock four times
    return str(path)


def time_limit(res, phase: str) -> None:
    assert res.exit_code == 3, res.output
    assert f"error[E1109]: the time limit of 600 s was reached while {phase}" in res.stderr, res.output
    assert "Traceback" not in res.output


@pytest.mark.parametrize(
    "phase",
    ["reading the model", "checking"],  # the reader: every 2,048 tokens; the checker: every morphism
)
def test_a_query_stops_where_its_time_runs_out_while_reading(jump, model, phase):
    clock = jump(phase)
    res = run_catc("solve", model, "--timeout", "600", "--json")
    time_limit(res, phase)
    assert clock.looks == 2  # stopped at the look after the jump
    doc = json.loads(res.stdout)
    assert doc["schema"] == "catc.error/1" and doc["reason"] == "timeout", doc


def test_the_reader_stops_at_the_end_of_its_grace(jump, model, monkeypatch):
    """Reading the model has FINISH_GRACE more (a query whose time is up still answers its
    UNKNOWN), but no more than that: the reader looked at no clock and ran on to the
    watchdog, two seconds past the limit."""
    monkeypatch.setattr(deadlines, "FINISH_GRACE", 1e5)  # less than the clock's leap
    jump("reading the model")
    time_limit(run_catc("solve", model, "--timeout", "600"), "reading the model")


def test_the_encoder_looks_at_the_clock_within_a_step(jump, model):
    """A step of thousands of morphisms took seconds: the encoder looked at the clock only
    between steps.  Here the time runs out at the first morphism of the only step."""
    clock = jump("encoding")
    res = run_catc("compile", model, "--timeout", "600", "--emit", "smt2", "--horizon", "1")
    time_limit(res, "encoding")
    assert clock.looks == 2


def test_a_query_stopped_while_encoding_answers_unknown_for_its_timeout(jump, model):
    jump("encoding")
    res = run_catc("solve", model, "--timeout", "600", "--no-presolve", "--json")
    assert res.exit_code == 3, res.output
    doc = json.loads(res.stdout)
    assert doc["status"] == "unknown" and doc["reason"] == "timeout", doc


def test_z3_reads_a_large_step_in_parts_with_a_look_at_the_clock_between(monkeypatch):
    """Z3's reader of a script cannot be stopped (Z3_interrupt does not reach it): a step of a
    2 MB model took 16 s in one call.  Given in parts, the time can run out between two."""
    from catc.smt import z3backend
    from catc.smt.script import SmtSort, Symbol

    monkeypatch.setattr(z3backend, "PART_CHARS", 200)
    xs = [Symbol(f"x{i}", SmtSort.INT) for i in range(100)]
    asserts = [(None, f"(> {x} {i})") for i, x in enumerate(xs)]  # ~15 characters each
    whole = z3backend.Z3Backend()
    whole.add(xs, asserts)  # no time limit: every part, as one call gave
    assert len(whole.solver.assertions()) == 100

    backend = z3backend.Z3Backend()
    calls: list[int] = []
    clock = Jump("encoding", after=10**9)

    class Reader:  # the solver, whose reading of the first part takes "all the time"
        def __init__(self, solver):
            self.solver = solver

        def from_string(self, text: str) -> None:
            calls.append(len(text))
            self.solver.from_string(text)
            clock.jumped = True

    backend.solver = Reader(backend.solver)  # type: ignore[assignment]
    monkeypatch.setattr(deadlines, "time", clock)
    with limits.deadline(600), pytest.raises(limits.TimeLimitReached) as stop:
        backend.add(xs, asserts)
    assert stop.value.phase == "encoding" and len(calls) == 1 and calls[0] >= 200


@pytest.fixture
def pddl_model(tmp_path) -> str:
    path = tmp_path / "grid.cat"
    path.write_text(catalog(300).replace(" :parameters ((r real :bounds (0 1)))", "").replace(" r)", " 1)"))
    return str(path)


def test_the_export_looks_at_the_clock_at_every_ground_action(jump, pddl_model, tmp_path):
    clock = jump("exporting")
    time_limit(run_catc("export", "pddl", pddl_model, "-o", tmp_path / "out", "--timeout", "600"), "exporting")
    assert clock.looks == 2 and not (tmp_path / "out" / "domain.pddl").exists()


def test_the_exports_parsers_run_within_the_time_left(jump, pddl_model, tmp_path, monkeypatch):
    """The parsers that read the export back (another library's code, ~25 s for 56,000
    ground actions) never look at catc's clock: they run beside the command, which stops
    when its time is up.  Here a parser that would never finish."""
    pytest.importorskip("pddl_plus_parser")
    from catc.targets import pddl_target

    release = threading.Event()
    started = threading.Event()

    def stuck(*args, **kwargs):
        started.set()
        release.wait(60)
        return []

    monkeypatch.setattr(pddl_target, "check_pddl", stuck)
    jump("parsing the export")
    try:
        res = run_catc("export", "pddl", pddl_model, "-o", tmp_path / "out", "--timeout", "600")
    finally:
        release.set()
    time_limit(res, "parsing the export")
    assert started.is_set() and (tmp_path / "out" / "domain.pddl").exists()


def test_a_call_within_the_time_gives_its_value_or_its_exception():
    with limits.deadline(600):
        assert deadlines.call_within("parsing", lambda: 42) == 42
        with pytest.raises(KeyError):
            deadlines.call_within("parsing", lambda: {}["x"])
    assert deadlines.call_within("parsing", lambda: 7) == 7  # no limit: called here


def test_the_documented_grace_is_the_finish_grace():
    """docs/limits.md states how long past --timeout a command may run; it must say what the
    code does."""
    doc = (ROOT / "docs" / "limits.md").read_text()
    assert f"`FINISH_GRACE`, {deadlines.FINISH_GRACE:g} s" in doc
    from catc.interfaces import guard

    assert f"{guard.GRACE:g} s past the limit" in doc and f"{guard.LAST_GRACE:g} s after that" in doc


@pytest.mark.parametrize("optimize", [False, True])
def test_a_step_read_in_parts_keeps_its_declarations(monkeypatch, optimize):
    """relax at 200 components (issue 24) ended in an internal error, "unknown constant":
    a Z3 Optimize, unlike a Solver, forgets what one from_string declared by the next, so the
    second part of a large step named undeclared constants.  Every part of either kind (and a
    later add naming earlier declarations) reads, and the assertions all count."""
    from catc.smt import z3backend
    from catc.smt.backend import Check
    from catc.smt.script import SmtSort, Symbol

    monkeypatch.setattr(z3backend, "PART_CHARS", 40)
    b = z3backend.Z3Backend(optimize=optimize)
    xs = [Symbol(f"x{i}", SmtSort.INT) for i in range(20)]
    b.add(xs, [(None, f"(> x{i} {i})") for i in range(20)])  # many parts
    b.add([], [(None, "(< (+ x0 x19) 21)")])  # a later call: x0 > 0 and x19 > 19 leave no room
    assert b.check() is Check.UNSAT


class _CanceledSolver:
    """A Z3 solver whose check ends unknown with the reason Z3 gives its own timer at times."""

    def __init__(self, took: float) -> None:
        self.took = took

    def check(self, *assumptions):
        import time

        import z3

        time.sleep(self.took)  # not a race: the test reads which side of the timer it ended
        return z3.unknown

    def reason_unknown(self) -> str:
        return "canceled"

    def set(self, *args) -> None:
        pass


def test_a_check_stopped_by_z3s_timer_says_timeout_not_canceled():
    """Z3 names a stop by its own per-check timer "canceled" at times (counters-tight-4
    imported with -k 60: "the solver gave up (canceled)"): a check that ran to its timer
    reports "timeout"; one canceled well before its timer is Ctrl-C (Z3's own SIGINT handler),
    as before."""
    from catc.smt import z3backend
    from catc.smt.backend import Check
    from catgrammar import limits

    b = z3backend.Z3Backend()
    b.set_timeout(0.001)
    b.solver = _CanceledSolver(0.002)
    assert b.check() is Check.UNKNOWN and b.reason_unknown() == "timeout"
    b = z3backend.Z3Backend()
    b.set_timeout(30)
    b.solver = _CanceledSolver(0)
    with limits.deadline(None):
        assert b.check() is Check.UNKNOWN
        assert limits.stop_reason() == "interrupted"
