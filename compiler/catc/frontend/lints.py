"""Warnings a modeller wants (errors under ``catc check --strict``).

Domain lints look at one checked domain; instance lints use the problem's initial state
for a relaxed reachability analysis (delete relaxation over set memberships and bool
resources; numbers are assumed reachable) to find morphisms that can never apply.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence

from catc import ir
from catc.ir import SortKind
from catc.semantics.validate import initial_state
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics, Note
from catgrammar.span import Span


def _user(span: Span | None, is_user: Callable[[str], bool]) -> bool:
    return span is not None and is_user(span.file)


def lint_domain(
    domain: ir.Domain,
    diags: Diagnostics,
    is_user: Callable[[str], bool],
    problems: Sequence[ir.Problem] = (),
) -> None:
    """``problems`` are this domain's problems checked in the same run: a sort used only
    for their objects is used."""
    used_resources: set[str] = set()
    used_sorts: set[str] = {o.sort.name for p in problems for o in p.objects.values()}
    for m in domain.morphisms.values():
        used_resources |= m.reads | m.writes
        for p in m.params:
            used_sorts.add(_base(p.sort))
            if p.sort.kind is SortKind.REAL and (p.lower is None or p.upper is None) and _user(p.span, is_user):
                missing = (
                    "no bounds"
                    if p.lower is None and p.upper is None
                    else ("no lower bound" if p.lower is None else "no upper bound")
                )
                diags.report(
                    codes.UNBOUNDED_PARAMETER,
                    f"real parameter '{p.name}' of '{m.name}' has {missing}; "
                    f"optimisation over it may be unbounded and exports cannot grid it",
                    p.span,
                )
    for r in domain.resources.values():
        used_sorts.add(_base(r.sort))
        if r.name not in used_resources and _user(r.span, is_user):
            diags.report(codes.UNUSED_RESOURCE, f"resource '{r.name}' is never read or written by any morphism", r.span)
    for c in domain.constants.values():
        used_sorts.add(c.sort.name)
    for s in domain.sorts.values():
        if s.parent:
            used_sorts.add(s.parent)
    for s in domain.sorts.values():
        span = _sort_span(domain, s)
        if s.name not in used_sorts and span is not None and _user(span, is_user):
            diags.report(codes.UNUSED_SORT, f"sort '{s.name}' is never used", span)


def _base(sort: ir.Sort) -> str:
    return sort.element.name if sort.kind is SortKind.SET and sort.element else sort.name


def _sort_span(domain: ir.Domain, sort: ir.Sort) -> Span | None:
    return sort.span


# ---------------------------------------------------------------- instance lints


def lint_instance(inst: ir.Instance, diags: Diagnostics, is_user: Callable[[str], bool]) -> None:
    written: set[str] = set()
    for m in inst.morphisms.values():
        written |= m.writes
    for lit in inst.problem.goal:
        reads = ir.resources_in(lit.expr)
        if reads and not (reads & written) and _user(lit.span, is_user):
            names = ", ".join(f"'{r}'" for r in sorted(reads))
            diags.report(
                codes.UNWRITABLE_GOAL,
                f"this goal reads only {names}, which no morphism writes: the initial state alone decides it",
                lit.span,
            )
    for m, lit, why in unreachable_morphisms(inst):
        if _user(m.span, is_user):
            notes = [Note(why, lit.span)] if lit.span else []
            diags.report(codes.UNREACHABLE_MORPHISM, f"morphism '{m.name}' can never apply: {why}", m.span, *notes)


def unreachable_morphisms(inst: ir.Instance) -> Iterator[tuple[ir.Morphism, ir.Literal, str]]:
    """Morphisms whose preconditions can never hold under the delete relaxation, each with
    the first literal that cannot hold and why.

    Facts are ``(set-resource, element)`` memberships and ``(bool-resource, value)``; a
    literal that is not a plain membership or bool test is assumed satisfiable, so the
    analysis only ever under-reports."""
    facts = _Facts(inst)
    applied: set[str] = set()
    changed = True
    while changed:  # apply every morphism that can apply until nothing new holds
        changed = False
        for m in inst.morphisms.values():
            if m.name not in applied and all(facts.holds(lit)[0] for lit in m.pre):
                applied.add(m.name)
                facts.apply(m)
                changed = True
    for m in inst.morphisms.values():
        if m.name in applied:
            continue
        for lit in m.pre:
            ok, why = facts.holds(lit)
            if not ok:
                yield m, lit, why
                break


class _Facts:
    """What can ever hold, growing as morphisms apply (deletes ignored)."""

    def __init__(self, inst: ir.Instance) -> None:
        self.members: set[tuple[str, object]] = set()
        self.bools: set[tuple[str, bool]] = set()
        self.any_member: set[str] = set()  # sets a parameter may add anything to
        for hole in inst.domain.holes.values():  # a hole may write anything in its view
            view = inst.domain.views.get(hole.view) if hole.view else None
            for r in inst.resources.values():
                if view is None or r.name in view.kept:
                    if r.sort.kind is SortKind.SET:
                        self.any_member.add(r.name)
                    elif r.sort.kind is SortKind.BOOL:
                        self.bools |= {(r.name, True), (r.name, False)}
        for name, value in initial_state(inst).items():  # s₀, as the validator replays it
            if isinstance(value, frozenset):
                self.members |= {(name, e) for e in value}
            elif isinstance(value, bool):
                self.bools.add((name, value))

    def holds(self, lit: ir.Literal) -> tuple[bool, str]:
        """Whether ``lit`` can hold, and if not, why."""
        e = lit.expr
        positive = True
        if isinstance(e, ir.BoolOp) and e.op is ir.BoolOpKind.NOT and len(e.args) == 1:
            e, positive = e.args[0], False
        if isinstance(e, ir.Member) and positive and isinstance(e.set, ir.ResourceRef):
            s = e.set.name
            if isinstance(e.element, ir.Const):
                ok = (s, e.element.value) in self.members or s in self.any_member
                return ok, f"it needs '{e.element.value}' in '{s}', which the initial state lacks and no morphism adds"
            if isinstance(e.element, ir.ParamRef):
                ok = any(k == s for k, _ in self.members) or s in self.any_member
                return ok, f"it needs an element in '{s}', which starts empty and no morphism fills"
        if isinstance(e, ir.ResourceRef) and e.sort.kind is SortKind.BOOL:
            return (e.name, positive) in self.bools, (
                f"it needs '{e.name}' to be {'true' if positive else 'false'}, which it never becomes"
            )
        return True, ""

    def apply(self, m: ir.Morphism) -> None:
        """Add what ``m``'s effects make true."""
        for eff in m.effects:
            if eff.kind is ir.EffectKind.ADD:
                if isinstance(eff.value, ir.Const):
                    self.members.add((eff.resource, eff.value.value))
                else:
                    self.any_member.add(eff.resource)
            elif (
                eff.kind is ir.EffectKind.ASSIGN
                and isinstance(eff.value, ir.Const)
                and isinstance(eff.value.value, bool)
            ):
                self.bools.add((eff.resource, eff.value.value))
            elif eff.kind is ir.EffectKind.ASSIGN and eff.value.sort.kind is SortKind.BOOL:
                self.bools |= {(eff.resource, True), (eff.resource, False)}
