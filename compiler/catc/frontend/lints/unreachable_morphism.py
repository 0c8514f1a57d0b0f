"""W0103: a morphism that can never apply.  The problem's initial state feeds a relaxed
reachability analysis (delete relaxation over set memberships and bool resources; numbers
are assumed reachable) that finds morphisms whose preconditions can never hold."""

from __future__ import annotations

from collections.abc import Iterator

from catc import ir
from catc.frontend.lints.base import IsUser, Lint, Scope, user
from catc.ir import SortKind
from catc.semantics.validate import initial_state
from catgrammar import codes
from catgrammar.diagnostics import Diagnostics, Note


def run(inst: ir.Instance, diags: Diagnostics, is_user: IsUser) -> None:
    for m, lit, why in unreachable_morphisms(inst):
        if user(m.span, is_user):
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


LINT = Lint(codes.UNREACHABLE_MORPHISM, Scope.INSTANCE, run)
