"""Feeding an encoding to Z3 through its Python API, and reading compositions back.

:class:`Z3Session` owns one ``z3.Solver``.  ``flush`` hands it the commands the encoder
added since the last call (``Solver.from_string``: one C++ parse per batch), so the
incremental driver can grow the horizon step by step; ``check`` asserts extra constraints
(the goal at the current state, the use limits) inside a push/pop scope.
"""

from __future__ import annotations

from fractions import Fraction

import z3

from catc import ir
from catc.ir import SortKind
from catc.semantics.plan import Activation, Plan
from catc.smt.encoder import Encoder


def to_fraction(v: z3.ExprRef) -> Fraction:
    if z3.is_int_value(v):
        return Fraction(v.as_long())
    if z3.is_rational_value(v):
        return Fraction(v.numerator_as_long(), v.denominator_as_long())
    if z3.is_algebraic_value(v):
        raise ValueError(f"the solver returned an irrational value (≈{v.approx(12)}); no exact rational exists")
    raise ValueError(f"not a numeral: {v}")


def _commands(decls, asserts) -> str:
    return "".join(f"(declare-fun {n} () {s})" for n, s in decls) + "".join(f"(assert {a})" for _, a in asserts)


class Z3Session:
    """``optimize=True`` drives a ``z3.Optimize`` instead of a ``z3.Solver``; ``logic`` (e.g.
    ``"QF_LRA"``) configures the solver for that logic (``z3.SolverFor``).

    A session works in its own Z3 context unless given one (``ctx``, for sessions whose
    terms meet): Z3's term ids, and with them its search and the model it returns, depend
    on every term its context has seen, so in the shared default context the same query
    could get a different (equally valid) answer after other queries in one process — in
    the language server, the lifelong loop, tests.  A fresh context costs about 1 ms when the
    previous one has been freed, 7–8 ms while others are alive (measured by hand); the first
    of a process initialises Z3 (the "Z3 start" column of docs/benchmarks.md)."""

    def __init__(
        self, enc: Encoder, *, optimize: bool = False, logic: str | None = None, ctx: z3.Context | None = None
    ):
        self.enc = enc
        self.ctx = ctx = z3.Context() if ctx is None else ctx
        if optimize:
            self.solver = z3.Optimize(ctx=ctx)
        else:
            self.solver = z3.SolverFor(logic, ctx=ctx) if logic else z3.Solver(ctx=ctx)

    def flush(self) -> None:
        decls, asserts = self.enc.script.take()
        text = _commands(decls, asserts)
        if text:
            self.solver.from_string(text)

    def set_timeout(self, seconds: float | None) -> None:
        """A per-check limit; None removes it."""
        self.solver.set("timeout", 4294967295 if seconds is None else max(1, int(seconds * 1000)))

    def check(self, extra: list[str], assumptions=()) -> z3.CheckSatResult:
        """Check with ``extra`` constraints in a scope the caller closes with :meth:`pop`;
        ``assumptions`` are names of Bool variables assumed true for this check only."""
        self.flush()
        self.solver.push()
        if extra:
            self.solver.from_string("".join(f"(assert {c})" for c in extra))
        return self.solver.check(*[z3.Bool(a[1:-1] if a.startswith("|") else a, self.ctx) for a in assumptions])

    def pop(self) -> None:
        self.solver.pop()

    def reason_unknown(self) -> str:
        return self.solver.reason_unknown()

    # ------------------------------------------------------------------ models
    def extract(self, steps: int) -> Plan:
        model = self.solver.model()
        enc = self.enc
        out = []
        fresh: dict[str, str] = {}
        for t in range(steps):
            step = []
            for m in enc.morphisms:
                if not z3.is_true(model.eval(z3.Bool(enc.act[t][m.name][1:-1], model.ctx), model_completion=True)):
                    continue
                params = {}
                for p in m.params:
                    name = enc.theta[t][(m.name, p.name)][1:-1]  # type: ignore[index]
                    params[p.name] = self._value(model, name, p.sort, fresh)
                step.append(Activation(m.name, params))
            if step:
                out.append(tuple(step))
        return Plan(tuple(out), fresh)

    def _value(self, model: z3.ModelRef, name: str, sort: ir.Sort, fresh: dict[str, str]):
        return value_in_model(model, name, sort, self.enc, fresh)

    def parse_term(self, text: str) -> z3.ExprRef:
        """An encoded term as a Z3 expression (for objectives and cores)."""
        self.flush()
        decls = "".join(f"(declare-fun {n} () {s})" for n, s in self.enc.script.decls)
        return z3.parse_smt2_string(f"{decls}(assert (= {text} {text}))", ctx=self.ctx)[0].arg(0)


def value_in_model(model: z3.ModelRef, name: str, sort: ir.Sort, enc: Encoder, fresh: dict[str, str]):
    """The value of variable ``name`` of IR sort ``sort`` (symbols decoded through the
    grounding; fresh values recorded in ``fresh``)."""
    if sort.kind is SortKind.BOOL:
        return z3.is_true(model.eval(z3.Bool(name, model.ctx), model_completion=True))
    if sort.kind is SortKind.REAL:
        return to_fraction(model.eval(z3.Real(name, model.ctx), model_completion=True))
    raw = model.eval(z3.Int(name, model.ctx), model_completion=True).as_long()
    if sort.kind is SortKind.INT:
        return Fraction(raw)
    u = enc.grounding.universe(sort)
    value = u.elements[raw]
    if value in u.fresh:
        fresh[value] = u.sort_of[value]
    return value
