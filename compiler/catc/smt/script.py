"""SMT-LIB2 scripts: symbols, labelled assertions, and the text of terms.

The encoder writes its formula as SMT-LIB2 text (:class:`Script`), because Z3's C++ parser
builds terms about seven times faster than its Python API (docs/benchmarks.md) and every
backend reads SMT-LIB2.  Two things keep the text honest:

* every constant is a :class:`Symbol`: its quoted SMT-LIB name *is* the string spliced into
  term text, and it carries its sort, so a model's value is read back by symbol — never by
  re-parsing printed names;
* every assertion is filed under the label of the source construct it comes from
  (``pre/m/i``, ``init/r``, ...), or ``None`` for structural constraints, so an unsat core
  maps back to source lines.

The helpers below build term text with the small simplifications the encoder relies on
(``true`` conjuncts and ``false`` disjuncts dropped).
"""

from __future__ import annotations

from collections.abc import Sequence
from enum import Enum
from fractions import Fraction

from catc.ir.numbers import int_text


class SmtSort(str, Enum):
    BOOL = "Bool"
    INT = "Int"
    REAL = "Real"


class Symbol(str):
    """A declared SMT constant.  The string itself is the quoted SMT-LIB name (``|b.a.0|``),
    ready to splice into term text; ``name`` is the bare name and ``sort`` its sort."""

    name: str
    sort: SmtSort

    def __new__(cls, name: str, sort: SmtSort) -> Symbol:
        obj = super().__new__(cls, f"|{name}|")
        obj.name = name
        obj.sort = sort
        return obj

    def __reduce__(self) -> tuple[type[Symbol], tuple[str, SmtSort]]:
        return Symbol, (self.name, self.sort)

    def declaration(self) -> str:
        return f"(declare-fun {self} () {self.sort.value})"


#: An assertion: the label of its source construct (None: structural) and its text.
Assertion = tuple[str | None, str]


class Script:
    """Declarations and labelled assertions, in order; :meth:`take` hands out what is new
    since the last call (the incremental backends are fed a step at a time)."""

    __slots__ = ("_assert_mark", "_decl_mark", "asserts", "decls")

    def __init__(self) -> None:
        self.decls: list[Symbol] = []
        self.asserts: list[Assertion] = []
        self._decl_mark = 0
        self._assert_mark = 0

    def declare(self, name: str, sort: SmtSort) -> Symbol:
        symbol = Symbol(name, sort)
        self.decls.append(symbol)
        return symbol

    def take(self) -> tuple[list[Symbol], list[Assertion]]:
        d, a = self.decls[self._decl_mark :], self.asserts[self._assert_mark :]
        self._decl_mark, self._assert_mark = len(self.decls), len(self.asserts)
        return d, a

    def labels(self) -> list[str]:
        return list(dict.fromkeys(label for label, _ in self.asserts if label is not None))


def commands_text(decls: list[Symbol], asserts: list[Assertion]) -> str:
    """Declarations and assertions as one SMT-LIB2 command string (labels dropped)."""
    return "".join(s.declaration() for s in decls) + "".join(f"(assert {a})" for _, a in asserts)


# ---------------------------------------------------------------- term text


def real_literal(v: Fraction) -> str:
    def pos(n: int) -> str:
        return f"{int_text(n)}.0"

    a = abs(v)
    text = pos(a.numerator) if a.denominator == 1 else f"(/ {pos(a.numerator)} {pos(a.denominator)})"
    return f"(- {text})" if v < 0 else text


def int_literal(n: int) -> str:
    return f"(- {int_text(-n)})" if n < 0 else int_text(n)


def quote(name: str) -> str:
    return f"|{name}|"


def and_text(parts: Sequence[str]) -> str:
    parts = [p for p in parts if p != "true"]
    if not parts:
        return "true"
    return parts[0] if len(parts) == 1 else f"(and {' '.join(parts)})"


def or_text(parts: Sequence[str]) -> str:
    parts = [p for p in parts if p != "false"]
    if not parts:
        return "false"
    return parts[0] if len(parts) == 1 else f"(or {' '.join(parts)})"


def at_most(bools: Sequence[str], n: int) -> str:
    """Σ ite(b, 1, 0) ≤ n — plain linear arithmetic, understood by every SMT solver."""
    if len(bools) <= n:
        return "true"
    if n == 0:  # none of them (no one-argument '+', which SMT-LIB does not allow)
        return f"(not {bools[0]})" if len(bools) == 1 else f"(not (or {' '.join(bools)}))"
    if n == 1 and len(bools) == 2:
        return f"(not (and {bools[0]} {bools[1]}))"
    return f"(<= (+ {' '.join(f'(ite {b} 1 0)' for b in bools)}) {n})"


def count_text(bools: Sequence[str]) -> str:
    """The number of true ``bools``, as an Int term."""
    return f"(+ 0 {' '.join(f'(ite {b} 1 0)' for b in bools)})"
