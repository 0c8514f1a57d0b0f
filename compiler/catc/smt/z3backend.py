"""The Z3 backend: the only module of catc that imports ``z3``.

The encoder's script reaches Z3 as text (``from_string``: one C++ parse per batch, so the
incremental driver can grow the horizon step by step); the queries' terms
(:mod:`catc.smt.terms`) are built with Z3's API, numbers as exact ``RealVal`` s; values come
back as ``Fraction`` s and ``bool`` s, objective bounds as the three coefficients of
``a·∞ + b + c·ε`` (``Z3_optimize_get_lower/upper_as_vector``), cores as the assumed symbols.

Each backend works in its own Z3 context unless it shares another's (``share_with``):
Z3's term ids, and with them its search and the model it returns, depend on every term its
context has seen, so in the shared default context the same query could get a different
(equally valid) answer after other queries in one process — in the language server, the
lifelong loop, tests.  A fresh context costs about 1 ms when the previous one has been freed,
7–8 ms while others are alive (measured by hand); the first of a process initialises Z3 (the
"Z3 start" column of docs/benchmarks.md).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterator, Sequence
from fractions import Fraction
from typing import Any

import z3

from catc.ir.numbers import fraction_text, int_text, int_value
from catc.smt.backend import Backend, Bound, Capability, Check, kept
from catc.smt.script import Assertion, SmtSort, Symbol, commands_text
from catc.smt.terms import App, Interned, Term
from catgrammar import limits

_NO_LIMIT_MS = 4294967295  # Z3's largest timeout: none
_CANCELED = ("interrupted from keyboard", "canceled")

_OPS: dict[str, Callable[..., Any]] = {
    "and": z3.And,
    "or": z3.Or,
    "not": z3.Not,
    "=>": z3.Implies,
    "=": lambda a, b: a == b,
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
    "+": z3.Sum,
    "-": lambda a, *b: -a if not b else a - z3.Sum(*b),
    "*": z3.Product,
    "ite": z3.If,
    "to_real": z3.ToReal,
}


def to_fraction(v: z3.ExprRef) -> Fraction:
    """A numeral of Z3 as an exact number (read from its digits, however many)."""
    if z3.is_int_value(v):
        return Fraction(int_value(v.as_string()))
    if z3.is_rational_value(v):
        return Fraction(int_value(v.numerator().as_string()), int_value(v.denominator().as_string()))
    if z3.is_algebraic_value(v):
        raise ValueError(f"the solver returned an irrational value (≈{v.approx(12)}); no exact rational exists")
    raise ValueError(f"not a numeral: {v}")


def _weight_text(w: Fraction) -> str:
    """A soft constraint's weight as Z3 reads it, exactly ("7", "-1/3")."""
    if w.denominator == 1:
        return int_text(w.numerator)
    return f"{int_text(w.numerator)}/{w.denominator}"


#: About how many characters of SMT-LIB2 Z3 reads in one call (a few tenths of a second).
PART_CHARS = 1 << 20


def _parts(decls: list[Symbol], asserts: list[Assertion]) -> Iterator[str]:
    """The declarations and assertions as command strings of about :data:`PART_CHARS` each,
    the declarations first (Z3 keeps what one call declared for the next)."""
    part = [commands_text(decls, [])]
    size = len(part[0])
    for _, a in asserts:
        part.append(f"(assert {a})")
        size += len(part[-1])
        if size >= PART_CHARS:
            yield "".join(part)
            part, size = [], 0
    if size:
        yield "".join(part)


class Z3Backend(Backend):
    name = "z3"
    capabilities = frozenset({Capability.MODELS, Capability.CORES, Capability.OPTIMIZE, Capability.LOGIC})

    def __init__(self, *, optimize: bool = False, logic: str | None = None, share_with: Backend | None = None):
        if share_with is not None and not isinstance(share_with, Z3Backend):
            raise TypeError("a Z3 backend can share its context only with another Z3 backend")
        self.ctx: z3.Context = z3.Context() if share_with is None else share_with.ctx
        self.solver: z3.Solver | z3.Optimize
        if optimize:
            self.solver = z3.Optimize(ctx=self.ctx)
        else:
            self.solver = z3.SolverFor(logic, ctx=self.ctx) if logic else z3.Solver(ctx=self.ctx)
        if share_with is None:
            kept((self.ctx, self.solver))  # the solver too: freeing it costs 1–5 ms as well
        self._decls: list[str] = []  # every declaration so far, for parsing terms
        self._decl_text: str | None = ""
        self._model: z3.ModelRef | None = None
        self._failure: str | None = None  # why the last check raised instead of answering
        self._max: dict[int, bool] = {}  # objective handle id → maximise
        self._timer: float | None = None  # the timeout of each check (seconds), or None

    # ------------------------------------------------------------ input
    def add(self, decls: Sequence[Symbol], asserts: Sequence[Assertion]) -> None:
        if decls:
            self._decls.extend(s.declaration() for s in decls)
            self._decl_text = None
        # Z3's reader of a script cannot be stopped (not even by Z3_interrupt): a large step
        # is handed over in parts, with a look at the clock between two (issue 28, finding 4).
        # An Optimize forgets one call's declarations by the next: each part repeats them all.
        again = "".join(self._decls) if isinstance(self.solver, z3.Optimize) else ""
        for part in _parts([] if again else list(decls), list(asserts)):
            limits.check_time("encoding")
            try:
                self.solver.from_string(again + part)
            except z3.Z3Exception as exc:
                if "out of memory" in str(exc):  # the process's memory limit (--memory)
                    raise MemoryError(f"the solver ran out of memory: {exc}") from None
                raise

    def assert_term(self, term: Term) -> None:
        self.solver.add(self.expr(term))

    def push(self) -> None:
        self.solver.push()

    def pop(self) -> None:
        self.solver.pop()

    # ------------------------------------------------------------ terms
    def intern(self, term: Term) -> Term:
        return Interned(term, self.expr(term), self)

    def expr(self, term: Term) -> Any:
        """A query term as a Z3 expression."""
        if isinstance(term, Interned):
            return term.native if term.owner is self else self.expr(term.term)
        if isinstance(term, bool):
            return z3.BoolVal(term, self.ctx)
        if isinstance(term, Symbol):
            return self._const(term)
        if isinstance(term, str):
            return self._parse(term)
        if isinstance(term, Fraction):
            return z3.RealVal(fraction_text(term), self.ctx)
        if isinstance(term, App):
            return _OPS[term.op](*(self.expr(a) for a in term.args))
        raise TypeError(f"not a term: {term!r}")

    def _const(self, s: Symbol) -> Any:
        if s.sort is SmtSort.BOOL:
            return z3.Bool(s.name, self.ctx)
        return z3.Int(s.name, self.ctx) if s.sort is SmtSort.INT else z3.Real(s.name, self.ctx)

    def _parse(self, text: str) -> Any:
        if self._decl_text is None:
            self._decl_text = "".join(self._decls)
        return z3.parse_smt2_string(f"{self._decl_text}(assert (= {text} {text}))", ctx=self.ctx)[0].arg(0)

    # ------------------------------------------------------------ checking
    def set_timeout(self, seconds: float | None) -> None:
        ms = _NO_LIMIT_MS if seconds is None or seconds * 1000 >= _NO_LIMIT_MS else max(1, int(seconds * 1000))
        self.solver.set("timeout", ms)
        self._timer = None if ms == _NO_LIMIT_MS else ms / 1000

    def check(self, assumptions: Sequence[Symbol] = ()) -> Check:
        self._model = None
        self._failure = None
        limits.note_phase("solving")
        started = time.perf_counter()
        memory = self.memory
        try:
            if memory:
                z3.set_param("memory_max_size", memory)
            r = self.solver.check(*[self._const(a) for a in assumptions])
        except z3.Z3Exception as exc:  # e.g. a logic's configuration refusing the formula
            if "out of memory" in str(exc):
                raise MemoryError(f"the solver ran out of memory: {exc}") from None
            self._failure = str(exc)
            return Check.UNKNOWN
        finally:
            if memory:
                z3.set_param("memory_max_size", 0)
        if r == z3.unknown:
            self._stopped(time.perf_counter() - started)
        return Check.SAT if r == z3.sat else Check.UNSAT if r == z3.unsat else Check.UNKNOWN

    def _stopped(self, took: float) -> None:
        """After an unknown: tell the command it was interrupted when Z3 caught a Ctrl-C (it
        handles SIGINT itself during a check, as "interrupted from keyboard" or "canceled",
        the reason it also gives for a timeout — so canceled well before the timer is Ctrl-C,
        and at the timer a timeout, reported as "timeout"), and say so when Z3 ran out of its
        memory (``max. memory exceeded``)."""
        reason = self.solver.reason_unknown()
        if reason in _CANCELED and (self._timer is None or took < self._timer - 0.05):
            limits.interrupt()
        elif reason in _CANCELED:
            self._failure = "timeout"
        elif "memory" in reason:
            raise MemoryError(f"the solver ran out of memory ({reason})")

    def reason_unknown(self) -> str:
        return self._failure if self._failure is not None else self.solver.reason_unknown()

    def core(self) -> list[Symbol]:
        names = {c.decl().name() for c in self.solver.unsat_core()}
        return [Symbol(n, SmtSort.BOOL) for n in sorted(names)]

    def has_model(self) -> bool:
        try:
            self._current_model()
        except z3.Z3Exception:
            return False
        return True

    def _current_model(self) -> z3.ModelRef:
        if self._model is None:
            self._model = self.solver.model()
        return self._model

    def value(self, term: Term) -> Fraction | bool:
        v = self._current_model().eval(self.expr(term), model_completion=True)
        if z3.is_bool(v):
            return bool(z3.is_true(v))
        return to_fraction(v)

    # ------------------------------------------------------------ optimisation
    def minimize(self, term: Term) -> Any:
        return self._objective(term, maximize=False)

    def maximize(self, term: Term) -> Any:
        return self._objective(term, maximize=True)

    def _objective(self, term: Term, maximize: bool) -> Any:
        opt = self.solver
        assert isinstance(opt, z3.Optimize)
        handle = opt.maximize(self.expr(term)) if maximize else opt.minimize(self.expr(term))
        self._max[id(handle)] = maximize
        return handle

    def add_soft(self, term: Term, weight: Fraction, group: str | None = None) -> Any:
        opt = self.solver
        assert isinstance(opt, z3.Optimize)
        handle = opt.add_soft(self.expr(term), _weight_text(weight), group)
        self._max[id(handle)] = False
        return handle

    def bound(self, handle: Any) -> Bound:
        vector = handle.upper_values() if self._max[id(handle)] else handle.lower_values()
        infinite, value, epsilon = (to_fraction(vector[i]) for i in range(3))
        return Bound(int(infinite), value, epsilon)


def answer_file(path: str, milliseconds: int) -> str:
    """Z3's own answer on the SMT-LIB2 script ``path`` (its parser on the text, a fresh
    context, at most ``milliseconds``): ``sat``, ``unsat`` or ``unknown`` — what ``catc
    certify`` asks of an independent checker (it reads the text, never catc's terms).  The
    script's assertions are checked once (its ``(check-sat)``)."""
    ctx = z3.Context()
    solver = z3.Solver(ctx=ctx)
    solver.set("timeout", max(1, milliseconds))
    solver.from_file(path)
    return str(solver.check())
