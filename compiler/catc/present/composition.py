"""A composition for people: its steps with θ, the resources that changed, the validation line."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from catc import ir
from catc.present.console import Console, Table, counted
from catc.present.values import params_text, show_value
from catc.semantics.plan import Plan


def where_text(inst: ir.Instance) -> str:
    """``problem P of domain D[, view V]``, with markup."""
    where = f"problem [bold]{inst.problem.name}[/] of domain [bold]{inst.domain.name}[/]"
    if inst.view:
        where += f", view [bold]{inst.view}[/]"
    return where


def print_composition(console: Console, inst: ir.Instance, plan: Plan, states: Sequence[Mapping[str, Any]]) -> None:
    """The steps (``⊗`` marks a morphism in parallel with the one above), the resources
    that changed from the first state to the last, and the validation line."""
    if not plan.steps:  # a table of no rows says nothing
        console.print("the goal holds in the initial state: nothing to compose (the empty composition)")
        if states:
            console.print("\n[green]✓[/] validated by independent replay: 0 steps, goal holds in the initial state")
        return
    table = Table("step", "morphism", "kind", "θ", right=(0,))
    for i, step in enumerate(plan.steps, 1):
        for j, a in enumerate(step):
            marker = str(i) if j == 0 else "⊗"
            m = inst.morphisms[a.morphism]
            units = {p.name: p.unit for p in m.params if p.unit}
            table.add_row(marker, a.morphism, m.kind.value, params_text(a.params, plan.fresh, units))
    console.print(table)
    if not states:
        return
    first, last = states[0], states[-1]
    changed = [r for r in inst.resources.values() if first.get(r.name) != last.get(r.name)]
    if changed:
        st = Table("resource", "initial", "final")
        for r in changed:
            st.add_row(
                r.name,
                show_value(first[r.name], plan.fresh, r.unit),
                show_value(last[r.name], plan.fresh, r.unit),
            )
        console.print()
        console.print("[bold]final state[/] (resources that changed)")
        console.print(st)
    n, acts = len(plan), sum(len(s) for s in plan.steps)
    console.print(
        f"\n[green]✓[/] validated by independent replay: {counted(n, 'step')}, {counted(acts, 'activation')}, goal holds"
    )
