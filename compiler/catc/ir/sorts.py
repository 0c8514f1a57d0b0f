"""Sorts of the IR: Booleans, numbers, symbols, enumerations and sets (re-exported by :mod:`catc.ir`)."""

from __future__ import annotations

from enum import Enum

from catgrammar.record import Record
from catgrammar.record import set_field as _set
from catgrammar.span import Span

# ---------------------------------------------------------------- sorts


class SortKind(str, Enum):
    BOOL = "bool"
    INT = "int"
    REAL = "real"
    SYMBOL = "symbol"  # open symbolic sort (grounded per problem, Proposition 1)
    ENUM = "enum"  # closed enumeration
    SET = "set"


class Sort(Record):
    __slots__ = ("kind", "name", "parent", "values", "element", "span")
    _compared = ("kind", "name", "parent", "values", "element")
    kind: SortKind
    name: str
    parent: str | None  # symbolic sorts: the declared super-sort
    values: tuple[str, ...]  # enumerations: the values, in order
    element: Sort | None  # sets: the element sort
    span: Span | None

    def __init__(
        self,
        kind: SortKind,
        name: str,
        parent: str | None = None,
        values: tuple[str, ...] = (),
        element: Sort | None = None,
        span: Span | None = None,
    ) -> None:
        _set(self, "kind", kind)
        _set(self, "name", name)
        _set(self, "parent", parent)
        _set(self, "values", values)
        _set(self, "element", element)
        _set(self, "span", span)

    @property
    def is_numeric(self) -> bool:
        return self.kind in (SortKind.INT, SortKind.REAL)

    @property
    def is_symbolic(self) -> bool:
        return self.kind in (SortKind.SYMBOL, SortKind.ENUM)

    def __str__(self) -> str:
        return f"(set {self.element})" if self.kind is SortKind.SET else self.name


BOOL = Sort(SortKind.BOOL, "bool")
INT = Sort(SortKind.INT, "int")
REAL = Sort(SortKind.REAL, "real")


def set_of(element: Sort) -> Sort:
    return Sort(SortKind.SET, f"(set {element.name})", element=element)
