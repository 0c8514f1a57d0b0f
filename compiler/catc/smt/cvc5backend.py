"""The cvc5 backend, through cvc5's Python API (PyPI ``cvc5``; ``pip install 'catc-lang[cvc5]'``).

The script reaches cvc5 as text through its own SMT-LIB2 parser (``cvc5.InputParser``, one
string input per batch; its symbol manager keeps the declarations from batch to batch);
query terms are built with the term manager; values come back as exact rationals.  cvc5
checks under assumptions and gives cores over them, but does not optimise: ``catc solve
--backend cvc5`` and the queries built on plain satisfiability can use it.
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from catc.ir.numbers import fraction_text, int_value
from catc.smt.backend import Backend, BackendError, Capability, Check
from catc.smt.script import Assertion, SmtSort, Symbol, commands_text
from catc.smt.terms import App, Interned, Term

try:
    import cvc5
except ImportError as exc:  # pragma: no cover - depends on the environment
    raise BackendError("the cvc5 backend needs the cvc5 package: pip install 'catc-lang[cvc5]'") from exc

_K = cvc5.Kind
_OPS: dict[str, Any] = {
    "and": _K.AND,
    "or": _K.OR,
    "not": _K.NOT,
    "=>": _K.IMPLIES,
    "=": _K.EQUAL,
    "<": _K.LT,
    "<=": _K.LEQ,
    ">": _K.GT,
    ">=": _K.GEQ,
    "+": _K.ADD,
    "-": _K.SUB,
    "*": _K.MULT,
    "ite": _K.ITE,
    "to_real": _K.TO_REAL,
}


class Cvc5Backend(Backend):
    name = "cvc5"
    capabilities = frozenset({Capability.MODELS, Capability.CORES})

    def __init__(self, *, optimize: bool = False, logic: str | None = None, share_with: Backend | None = None):
        if optimize or logic:
            raise BackendError("the cvc5 backend does not optimise and is not configured by logic")
        if share_with is not None:
            raise BackendError("cvc5 backends do not share terms")
        self.tm = cvc5.TermManager()
        self.solver = cvc5.Solver(self.tm)
        for option, value in (
            ("incremental", "true"),
            ("produce-models", "true"),
            ("produce-unsat-assumptions", "true"),
        ):
            self.solver.setOption(option, value)
        self.solver.setLogic("ALL")
        self.symbols = cvc5.SymbolManager(self.tm)
        self.parser = cvc5.InputParser(self.solver, self.symbols)
        self._consts: dict[str, Any] = {}
        self._result: Any = None

    # ------------------------------------------------------------ input
    def add(self, decls: Sequence[Symbol], asserts: Sequence[Assertion]) -> None:
        text = commands_text(list(decls), list(asserts))
        if not text:
            return
        self.parser.setStringInput(cvc5.InputLanguage.SMT_LIB_2_6, text, "catc")
        while True:
            command = self.parser.nextCommand()
            if command.isNull():
                break
            command.invoke(self.solver, self.symbols)
        if decls:
            self._consts = {}

    def assert_term(self, term: Term) -> None:
        self.solver.assertFormula(self.term(term))

    def intern(self, term: Term) -> Term:
        return Interned(term, self.term(term), self)

    def push(self) -> None:
        self.solver.push()

    def pop(self) -> None:
        self.solver.pop()

    # ------------------------------------------------------------ terms
    def term(self, term: Term) -> Any:
        """A query term as a cvc5 term."""
        if isinstance(term, Interned):
            return term.native if term.owner is self else self.term(term.term)
        if isinstance(term, bool):
            return self.tm.mkBoolean(term)
        if isinstance(term, Symbol):
            return self._const(term)
        if isinstance(term, str):
            self.parser.setStringInput(cvc5.InputLanguage.SMT_LIB_2_6, term, "catc")
            return self.parser.nextTerm()
        if isinstance(term, Fraction):
            return self.tm.mkReal(fraction_text(term))
        if isinstance(term, App):
            args = [self.term(a) for a in term.args]
            if term.op == "and" and len(args) == 1:  # cvc5 wants two or more conjuncts
                return args[0]
            if term.op == "or" and len(args) == 1:
                return args[0]
            if term.op in ("and", "or") and not args:
                return self.tm.mkBoolean(term.op == "and")
            return self.tm.mkTerm(_OPS[term.op], *args)
        raise TypeError(f"not a term: {term!r}")

    def _const(self, s: Symbol) -> Any:
        if not self._consts:
            self._consts = {t.getSymbol(): t for t in self.symbols.getDeclaredTerms()}
        return self._consts[s.name]

    # ------------------------------------------------------------ checking
    def set_timeout(self, seconds: float | None) -> None:
        ms = 0 if seconds is None or seconds >= 2**53 / 1000 else max(1, int(seconds * 1000))  # 0: no limit
        self.solver.setOption("tlimit-per", str(ms))

    def check(self, assumptions: Sequence[Symbol] = ()) -> Check:
        terms = [self._const(a) for a in assumptions]
        self._result = self.solver.checkSatAssuming(*terms) if terms else self.solver.checkSat()
        if self._result.isSat():
            return Check.SAT
        return Check.UNSAT if self._result.isUnsat() else Check.UNKNOWN

    def reason_unknown(self) -> str:
        if self._result is None:
            return "no check yet"
        why = str(self._result.getUnknownExplanation())
        return "timeout" if "TIMEOUT" in why else why.rsplit(".", 1)[-1].lower()

    def core(self) -> list[Symbol]:
        by_name = {t.getSymbol(): t for t in self.solver.getUnsatAssumptions()}
        return [Symbol(n, _sort_of(t)) for n, t in sorted(by_name.items())]

    def has_model(self) -> bool:
        return self._result is not None and self._result.isSat()

    def value(self, term: Term) -> Fraction | bool:
        v = self.solver.getValue(self.term(term))
        if v.getSort().isBoolean():
            return bool(v.getBooleanValue())
        try:
            if v.isIntegerValue():
                return Fraction(v.getIntegerValue())
            if v.isRealValue():
                return Fraction(v.getRealValue())
        except ValueError:  # more digits than Python's int(str) reads: from cvc5's text
            return _numeral(str(v))
        raise ValueError(f"not a number: {v}")


def _numeral(text: str) -> Fraction:
    """An SMT-LIB numeral as cvc5 prints it (``12``, ``(- 12)``, ``(/ 1 3)``, ``2.5``)."""
    negative, parts = False, []
    for token in text.replace("(", " ").replace(")", " ").split():
        if token == "-":
            negative = not negative
        elif token != "/":
            whole, _, decimals = token.partition(".")
            parts.append(Fraction(int_value(whole + decimals), 10 ** len(decimals)))
    value = parts[0] / parts[1] if len(parts) == 2 else parts[0]
    return -value if negative else value


def _sort_of(t: Any) -> SmtSort:
    sort = t.getSort()
    return SmtSort.BOOL if sort.isBoolean() else SmtSort.INT if sort.isInteger() else SmtSort.REAL


def answer_file(path: str, milliseconds: int, manager: Any = None) -> str:
    """cvc5's own answer on the SMT-LIB2 script ``path`` (its parser, a fresh solver, at most
    ``milliseconds`` per query): ``sat``, ``unsat`` or ``unknown`` — what ``catc certify``
    asks of an independent checker (it reads the text, never catc's terms); ``error`` when
    the script has no answer.  ``manager``: a ``cvc5.TermManager`` to share between calls."""
    tm = manager if manager is not None else cvc5.TermManager()
    slv = cvc5.Solver(tm)
    slv.setOption("tlimit-per", str(max(1, milliseconds)))
    sm = cvc5.SymbolManager(tm)
    parser = cvc5.InputParser(slv, sm)
    parser.setFileInput(cvc5.InputLanguage.SMT_LIB_2_6, path)
    answer = "error"
    while True:
        cmd = parser.nextCommand()
        if cmd.isNull():
            return answer
        said = cmd.invoke(slv, sm).split()  # "unknown (TIMEOUT)": the first word
        if said and said[0] in ("sat", "unsat", "unknown"):
            answer = said[0]


def term_manager() -> Any:
    """A ``cvc5.TermManager`` for :func:`answer_file`."""
    return cvc5.TermManager()
