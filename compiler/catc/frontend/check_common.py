"""What the domain and the problem checkers share: requirements, options, numbers, bounds, units."""

from __future__ import annotations

from collections.abc import Iterable
from fractions import Fraction
from typing import Protocol, TypeVar

from catc import ir
from catc.frontend.typecheck import ExprChecker, describe
from catc.ir import Sort, SortKind
from catgrammar import ast, codes
from catgrammar.diagnostics import Diagnostics, Fix, Note, Suggestion
from catgrammar.span import Span
from catgrammar.symbols import (
    Option,
    Requirement,
    expand_requirements,
)


class DomainSource(Protocol):
    """Where the checkers get the domains a definition names (the workspace,
    :class:`catc.frontend.workspace.Workspace`; named by this protocol so the checkers do not
    import the workspace that imports them)."""

    def domain_ir(self, name: str, near: str | None, ref: Span | None, importing: bool = False) -> ir.Domain | None: ...


_REQUIREMENTS = {r.value: r for r in Requirement}
_KINDS = {k.value: k for k in ir.MorphismKind}


class _Requirements:
    """The declared requirement flags of one definition and the 'missing flag' reporter."""

    def __init__(
        self,
        decls: Iterable[ast.Requirements],
        diags: Diagnostics,
        extra: frozenset[str] = frozenset(),
        header: Span | None = None,
    ):
        self.diags = diags
        self.header = header  # the name of the definition (where a missing section is added)
        self.section: Span | None = None
        flags: set[Requirement] = {_REQUIREMENTS[f] for f in extra if f in _REQUIREMENTS}
        for decl in decls:
            self.section = self.section or decl.span
            for flag in decl.flags:
                if flag.text in _REQUIREMENTS:
                    flags.add(_REQUIREMENTS[flag.text])
                else:
                    hint = Suggestion(flag.text, _REQUIREMENTS, flag.span)
                    diags.report(
                        codes.UNKNOWN_REQUIREMENT,
                        f"unknown requirement '{flag.text}'{hint.hint}",
                        flag.span,
                        fixes=hint.fixes,
                    )
        self.flags = expand_requirements(flags)
        self._reported: set[Requirement] = set()

    @property
    def names(self) -> frozenset[str]:
        return frozenset(f.value for f in self.flags)

    def need(self, flag: Requirement, span: Span | None, what: str) -> None:
        if flag in self.flags or flag in self._reported:
            return
        self._reported.add(flag)
        notes = [Note("requirements are declared here", self.section)] if self.section else []
        self.diags.report(
            codes.MISSING_REQUIREMENT,
            f"{what} needs the requirement '{flag.value}'; add it to (:requirements ...)",
            span,
            *notes,
            fixes=self._add(flag.value),
        )

    def _add(self, flag: str) -> tuple[Fix, ...]:
        """The change that declares ``flag``: appended to the (first) requirements section, or
        a new section after the definition's ``(domain NAME)``/``(problem NAME)`` header."""
        anchor = self.section or self.header
        source = self.diags.sources.get(anchor.file) if anchor is not None else None
        if anchor is None or source is None:
            return ()
        text = source.text
        if self.section is not None:
            at = self.section.end - 1  # before the section's closing parenthesis
            if text[at : at + 1] != ")":
                return ()
            return (Fix(f"Add '{flag}' to (:requirements ...)", source.span(at, at), f" {flag}"),)
        close = text.find(")", anchor.end)
        if close < 0 or text[anchor.end : close].strip():
            return ()
        at = close + 1
        return (Fix(f"Add (:requirements {flag})", source.span(at, at), f"\n  (:requirements {flag})"),)


def _options(opts: Iterable[ast.Opt], allowed: Iterable[Option], owner: str, diags: Diagnostics) -> dict[str, ast.Opt]:
    """Options by key; duplicates reported (the grammar already rejects unknown keys)."""
    allowed_keys = {o.value for o in allowed}
    out: dict[str, ast.Opt] = {}
    for opt in opts:
        if opt.key not in allowed_keys:  # pragma: no cover - excluded by the grammar
            diags.report(codes.UNKNOWN_SECTION, f"option '{opt.key}' is not allowed in {owner}", opt.span)
        elif opt.key in out:
            diags.report(
                codes.DUPLICATE_OPTION,
                f"option '{opt.key}' is given twice in {owner}",
                opt.span,
                Note("first given here", out[opt.key].span),
            )
        else:
            out[opt.key] = opt
    return out


_V = TypeVar("_V")


def _value(opt: ast.Opt, kind: type[_V]) -> _V:
    """``opt.value`` (an ``object`` in the AST) as the kind of node the grammar gives its key."""
    value = opt.value
    assert isinstance(value, kind), (opt.key, value)
    return value


def _positive_int(num: ast.Num, what: str, diags: Diagnostics, *, allow_zero: bool = False) -> int | None:
    v = num.value
    if v.denominator != 1 or v < 0 or (v == 0 and not allow_zero):
        kind = "a non-negative" if allow_zero else "a positive"
        diags.report(codes.BAD_VALUE, f"{what} must be {kind} integer, got {num.text}", num.span)
        return None
    return int(v)


def _bounds(b: ast.Bounds, sort: Sort, diags: Diagnostics, what: str) -> tuple[Fraction | None, Fraction | None, bool]:
    lo = b.lower.value if b.lower else None
    hi = b.upper.value if b.upper else None
    ok = True
    if not sort.is_numeric:
        diags.report(codes.BAD_BOUNDS, f":bounds apply to numbers only, but {what} is {describe(sort)}", b.span)
        return None, None, False
    if sort.kind is SortKind.INT:
        for n in (b.lower, b.upper):
            if n is not None and n.value.denominator != 1:
                diags.report(
                    codes.BAD_BOUNDS, f"{what} is an int, so its bounds must be integers, got {n.text}", n.span
                )
                ok = False
    if b.lower is not None and b.upper is not None and lo is not None and hi is not None and lo > hi:
        diags.report(
            codes.BAD_BOUNDS, f"empty bounds for {what}: lower {b.lower.text} exceeds upper {b.upper.text}", b.span
        )
        ok = False
    return lo, hi, ok


def _unitless_target(
    checker: ExprChecker, res: ir.Resource, value: ir.Expr, node: ast.Expr, diags: Diagnostics
) -> None:
    """W0107 when a resource without :unit is given a quantity with one."""
    unit = checker.unit(value)
    if res.unit is None and unit is not None:
        diags.report(
            codes.UNITLESS_RESOURCE,
            f"resource '{res.name}' has no :unit but is given {unit.text} here, "
            f"so it is read in {unit.text}; declare its :unit",
            node.span,
        )
