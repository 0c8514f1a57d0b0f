"""What `catc solve` and `catc validate` show: human text (rich) and JSON documents.

Numbers are exact: an integer prints plainly, a terminating decimal as a decimal (``4.25``),
anything else as a fraction with an approximation (``1/3 (≈0.333333)``).  Fresh values from
the finite grounding are marked ``(fresh)``.  The JSON schemas are in docs/cli.md.
"""

from __future__ import annotations

from collections.abc import Mapping
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir.numbers import decimal_text
from catc.semantics.plan import Plan, value_to_json


def show_value(v: Any, fresh: Mapping[str, str] = {}, unit: str | None = None) -> str:
    if isinstance(v, bool):
        text = "true" if v else "false"
    elif isinstance(v, Fraction):
        dec = decimal_text(v)
        text = dec if not dec.startswith("≈") else f"{v.numerator}/{v.denominator} ({dec})"
    elif isinstance(v, frozenset):
        text = "{" + " ".join(f"{e} (fresh)" if e in fresh else e for e in sorted(v)) + "}"
    elif isinstance(v, str):
        text = f"{v} (fresh)" if v in fresh else v
    else:
        text = str(v)
    return f"{text} {unit}" if unit and isinstance(v, Fraction) else text


def params_text(params: Mapping[str, Any], fresh: Mapping[str, str]) -> str:
    return ", ".join(f"{k} = {show_value(v, fresh)}" for k, v in params.items())


def state_json(state: Mapping[str, Any]) -> dict:
    return {k: value_to_json(v) for k, v in state.items()}


def solve_json(inst: ir.Instance, result) -> dict:
    plan: Plan | None = result.plan
    doc: dict = {
        "schema": "catc.solve/1",
        "status": result.status.value,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "view": inst.view,
        "horizon": result.horizon,
        "sequential": result.sequential,
        "strategy": result.strategy,
        "steps": None,
        "fresh": None,
        "initial_state": None,
        "final_state": None,
        "unsat": None,
        "reason": result.reason,
        "timings": {k: round(v, 6) for k, v in result.timings.items()},
    }
    if plan is not None:
        doc["steps"] = [
            [
                {
                    "morphism": a.morphism,
                    "kind": inst.morphisms[a.morphism].kind.value,
                    "params": {k: value_to_json(v) for k, v in a.params.items()},
                }
                for a in step
            ]
            for step in plan.steps
        ]
        doc["fresh"] = dict(plan.fresh)
        if result.states:
            doc["initial_state"] = state_json(result.states[0])
            doc["final_state"] = state_json(result.states[-1])
    if result.status.value == "unsat":
        doc["unsat"] = {"final": result.final, "length_bound": result.length_bound}
    return doc


def unsat_sentence(inst: ir.Instance, result) -> str:
    k = result.horizon
    head = f"no composition within {k} step{'s' if k != 1 else ''}"
    if result.final:
        return (
            f"{head}; this is final: every morphism has a use limit, so no composition needs more than "
            f"{result.length_bound} step{'s' if result.length_bound != 1 else ''}"
        )
    if result.length_bound is not None:
        return f"{head} (not final: compositions may need up to {result.length_bound} steps; raise --horizon)"
    unlimited = [m.name for m in inst.morphisms.values() if m.uses is None]
    names = ", ".join(unlimited[:3]) + (", ..." if len(unlimited) > 3 else "")
    return (
        f"{head} (not final: {names} {'has' if len(unlimited) == 1 else 'have'} no use limit; try a larger --horizon)"
    )


class PlainConsole:
    """The subset of rich's Console used here, printing plain aligned text (for pipes and
    files: no colour codes, no rich import — it costs start-up time)."""

    def __init__(self, write) -> None:
        self.write = write

    def print(self, obj: object = "") -> None:
        if isinstance(obj, Table):
            self.write(obj.render())
        else:
            import re

            self.write(re.sub(r"\[/?[a-z ]*\]", "", str(obj)))


class Table:
    """A minimal table that renders as aligned columns, or converts to a rich Table."""

    def __init__(self, *columns: str, right: tuple[int, ...] = ()) -> None:
        self.columns = columns
        self.right = right
        self.rows: list[tuple[str, ...]] = []

    def add_row(self, *cells: str) -> None:
        self.rows.append(cells)

    def render(self) -> str:
        widths = [max(len(r[i]) for r in [self.columns, *self.rows]) for i in range(len(self.columns))]
        out = []
        for row in [self.columns, *self.rows]:
            cells = [c.rjust(w) if i in self.right else c.ljust(w) for i, (c, w) in enumerate(zip(row, widths))]
            out.append("  ".join(cells).rstrip())
        return "\n".join(out)

    def __rich__(self):
        from rich.table import Table as RichTable

        table = RichTable(show_header=True, header_style="bold", box=None, pad_edge=False)
        for i, c in enumerate(self.columns):
            table.add_column(c, justify="right" if i in self.right else "left")
        for r in self.rows:
            table.add_row(*r)
        return table


def print_solve(console, inst: ir.Instance, result, *, timings: bool = True, header: bool = True) -> None:
    status = result.status.value.upper()
    colour = {"SAT": "green", "UNSAT": "red", "UNKNOWN": "yellow"}[status]
    where = f"problem [bold]{inst.problem.name}[/] of domain [bold]{inst.domain.name}[/]"
    if inst.view:
        where += f", view [bold]{inst.view}[/]"
    if result.status.value == "sat":
        plan = result.plan
        n = len(plan)
        if header:
            console.print(f"[bold {colour}]{status}[/]  composition of {n} step{'s' if n != 1 else ''} for {where}")
        table = Table("step", "morphism", "kind", "θ", right=(0,))
        for i, step in enumerate(plan.steps, 1):
            for j, a in enumerate(step):
                marker = str(i) if j == 0 else "⊗"
                kind = inst.morphisms[a.morphism].kind.value
                table.add_row(marker, a.morphism, kind, params_text(a.params, plan.fresh))
        console.print(table)
        if result.states:
            first, last = result.states[0], result.states[-1]
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
            acts = sum(len(s) for s in plan.steps)
            console.print(f"\n[green]✓[/] validated by independent replay: {n} steps, {acts} activations, goal holds")
    elif result.status.value == "unsat":
        console.print(f"[bold {colour}]{status}[/]  {unsat_sentence(inst, result)} ({where})")
    else:
        console.print(f"[bold {colour}]{status}[/]  the solver gave up ({result.reason}) for {where}")
    if timings and result.timings:
        t = result.timings
        start = f"Z3 start {t['start'] * 1000:.0f} ms, " if "start" in t else ""
        console.print(
            f"[dim]time: {start}encode {t.get('encode', 0) * 1000:.0f} ms, solve {t.get('solve', 0) * 1000:.0f} ms, "
            f"validate {t.get('validate', 0) * 1000:.0f} ms; horizons tried {result.horizons_tried}[/]"
        )


# ---------------------------------------------------------------- optimize


def _objective_rows(inst, result) -> list[tuple[str, str, str, str]]:
    from catc.ir.text import to_text

    rows = []
    for i, ov in enumerate(result.values, 1):
        term = to_text(ov.objective.term)
        if i == 1 and inst.problem.softs:
            term += " with soft penalties"
        if ov.bound is not None and not ov.attained:
            value = ov.bound + (f" (composition shown: {show_value(ov.value)})" if ov.value is not None else "")
        elif ov.value is None:
            value = "undefined"
        else:
            value = show_value(ov.value)
            if ov.value.denominator != 1:
                value += f"  [{ov.value.numerator}/{ov.value.denominator}]"
        rows.append((str(i), ov.objective.sense.value, term, value))
    return rows


def print_optimize(console, inst: ir.Instance, result) -> None:
    from types import SimpleNamespace

    status = result.status.value.upper()
    colour = {"OPT": "green", "SUBOPT": "yellow", "UNSAT": "red", "UNKNOWN": "yellow", "UNBOUNDED": "red"}[status]
    where = f"problem [bold]{inst.problem.name}[/] of domain [bold]{inst.domain.name}[/]"
    if inst.view:
        where += f", view [bold]{inst.view}[/]"
    if result.status.value == "unsat":
        console.print(f"[bold {colour}]{status}[/]  no composition within {result.horizon} steps ({where})")
        return
    if result.plan is None:
        console.print(f"[bold {colour}]{status}[/]  the solver gave up ({result.reason}) for {where}")
        return
    what = {
        "OPT": "proven optimal",
        "SUBOPT": f"best found before the solver stopped ({result.reason})",
        "UNBOUNDED": "the objective is unbounded",
    }[status]
    console.print(f"[bold {colour}]{status}[/]  {what} for {where}")
    table = Table("#", "sense", "objective", "value", right=(0,))
    for row in _objective_rows(inst, result):
        table.add_row(*row)
    console.print(table)
    if result.softs:
        console.print()
        st = Table("soft constraint", "weight", "outcome")
        from catc.ir.text import to_text

        for o in result.softs:
            st.add_row(to_text(o.soft.expr), show_value(o.soft.weight), "violated" if o.violated else "satisfied")
        console.print(st)
    console.print()
    shim = SimpleNamespace(
        status=SimpleNamespace(value="sat"),
        plan=result.plan,
        states=result.states,
        timings=result.timings,
        horizons_tried=1,
    )
    print_solve(console, inst, shim, timings=False, header=False)
    t = result.timings
    console.print(
        f"[dim]time: encode {t.get('encode', 0) * 1000:.0f} ms, optimise {t.get('solve', 0) * 1000:.0f} ms, "
        f"validate {t.get('validate', 0) * 1000:.0f} ms; horizon {result.horizon}[/]"
    )


def optimize_json(inst: ir.Instance, result) -> dict:
    from catc.ir.text import to_text

    doc = {
        "schema": "catc.optimize/1",
        "status": result.status.value,
        "problem": inst.problem.name,
        "domain": inst.domain.name,
        "view": inst.view,
        "horizon": result.horizon,
        "objectives": [
            {
                "sense": ov.objective.sense.value,
                "term": to_text(ov.objective.term),
                "value": value_to_json(ov.value) if ov.value is not None else None,
                "decimal": decimal_text(ov.value) if ov.value is not None else None,
                "attained": ov.attained,
                "bound": ov.bound,
            }
            for ov in result.values
        ],
        "soft": [
            {
                "label": o.soft.label,
                "constraint": to_text(o.soft.expr),
                "weight": value_to_json(o.soft.weight),
                "violated": o.violated,
            }
            for o in result.softs
        ],
        "steps": None,
        "fresh": None,
        "final_state": None,
        "reason": result.reason,
        "timings": {k: round(v, 6) for k, v in result.timings.items()},
    }
    if result.plan is not None:
        doc["steps"] = [
            [
                {
                    "morphism": a.morphism,
                    "kind": inst.morphisms[a.morphism].kind.value,
                    "params": {k: value_to_json(v) for k, v in a.params.items()},
                }
                for a in step
            ]
            for step in result.plan.steps
        ]
        doc["fresh"] = dict(result.plan.fresh)
        if result.states:
            doc["final_state"] = state_json(result.states[-1])
    return doc


# ---------------------------------------------------------------- lifelong queries


def _where(info, sources=None) -> str:
    span = info.span
    return f"{span.file}:{span.line}:{span.column}" if span else "(no source location)"


def _describe_label(info) -> str:
    owner = (
        f" of {info.owner}"
        if info.owner and info.kind in ("precondition", "effect", "parameter bounds", "use limit")
        else ""
    )
    return f"{info.kind}{owner}  {info.text}"


def label_json(info) -> dict:
    span = info.span
    return {
        "label": info.label,
        "kind": info.kind,
        "text": info.text,
        "owner": info.owner,
        "location": None
        if span is None
        else {
            "file": span.file,
            "line": span.line,
            "column": span.column,
            "end_line": span.end_line,
            "end_column": span.end_column,
        },
    }


def print_diagnosis(console, inst: ir.Instance, diag, index, excerpt) -> None:
    if diag.status == "sat":
        console.print(f"[bold green]SAT[/]  nothing to diagnose: a composition exists within {diag.horizon} steps")
        return
    if diag.status != "unsat":
        console.print("[bold yellow]UNKNOWN[/]  the solver gave up before finding a core")
        return
    rel = ""
    if diag.relative_to:
        rel = f"\n       relative to the deployed composition: {', '.join(diag.relative_to)}"
    for n, core in enumerate(diag.cores, 1):
        head = f"core {n}: " if len(diag.cores) > 1 else ""
        console.print(
            f"[bold red]UNSAT[/]  {head}{len(core)} of {diag.total} labelled constraints conflict "
            f"(irreducible: dropping any one restores feasibility){rel if n == 1 else ''}"
        )
        for i, label in enumerate(core, 1):
            info = index[label]
            console.print(f"  {i}. {_describe_label(info)}")
            console.print(f"     {_where(info)}")
            for line in excerpt(info.span):
                console.print("     " + line)
    if len(diag.cores) > 1 or not diag.complete:
        more = "" if diag.complete else " (search stopped by --max or --timeout; more may exist)"
        console.print(f"{len(diag.cores)} distinct core{'s' if len(diag.cores) != 1 else ''}{more}")


def diagnosis_json(inst: ir.Instance, diag, index) -> dict:
    return {
        "schema": "catc.diagnose/1",
        "status": diag.status,
        "problem": inst.problem.name,
        "horizon": diag.horizon,
        "total": diag.total,
        "relative_to": list(diag.relative_to) if diag.relative_to else None,
        "cores": [[label_json(index[l]) for l in core] for core in diag.cores],
        "complete": diag.complete,
        "timings": {k: round(v, 6) for k, v in diag.timings.items()},
    }


def relaxation_text(inst: ir.Instance, rel, info) -> str:
    if rel.kind == "initial value":
        name = info.owner
        unit = inst.resources[name].unit if name in inst.resources else None
        sign = "+" if rel.delta > 0 else "-"
        old = inst.problem.init[name].value.value
        return (
            f"{name}: {sign}{show_value(abs(rel.delta))}{' ' + unit if unit else ''}"
            f"   (initial value {show_value(old)} → {show_value(old + rel.delta)})"
        )
    return f"{info.label}: weaken {info.text} by {show_value(rel.delta)}"


def print_relax(console, inst: ir.Instance, result, index) -> None:
    from types import SimpleNamespace

    if result.status == "sat":
        console.print("[bold green]SAT[/]  nothing to relax: the problem is feasible as it is")
        return
    if result.status == "unsat":
        console.print("[bold red]UNSAT[/]  no relaxation of the eligible requirements restores feasibility")
        return
    if result.status != "relaxed":
        console.print("[bold yellow]UNKNOWN[/]  the solver gave up")
        return
    if result.dropped:
        console.print(
            f"[bold yellow]RELAXED[/]  drop {len(result.dropped)} requirement"
            f"{'s' if len(result.dropped) != 1 else ''} (a minimum set whose removal restores feasibility):"
        )
        for label in result.dropped:
            info = index[label]
            console.print(f"  - {_describe_label(info)}   {_where(info)}")
        return
    what = (
        "the least restoration"
        if result.proven
        else "the best restoration found before the time limit (not proven least)"
    )
    console.print(
        f"[bold yellow]RELAXED[/]  {what} (weighted total {show_value(result.cost)}) "
        f"over {len(result.eligible)} eligible requirements:"
    )
    for rel in result.relaxations:
        info = index[rel.label]
        console.print(f"  {relaxation_text(inst, rel, info)}   {_where(info)}")
    if result.plan is not None:
        console.print("\nthe composition this makes possible:")
        shim = SimpleNamespace(
            status=SimpleNamespace(value="sat"),
            plan=result.plan,
            states=result.states,
            timings=result.timings,
            horizons_tried=1,
        )
        print_solve(console, result.relaxed_instance or inst, shim, timings=False, header=False)


def relax_json(inst: ir.Instance, result, index) -> dict:
    return {
        "schema": "catc.relax/1",
        "status": result.status,
        "problem": inst.problem.name,
        "cost": value_to_json(result.cost) if result.cost is not None else None,
        "proven": result.proven,
        "relaxations": [
            {**label_json(index[r.label]), "delta": value_to_json(r.delta), "weight": value_to_json(r.weight)}
            for r in result.relaxations
        ],
        "dropped": [label_json(index[l]) for l in result.dropped],
        "steps": None
        if result.plan is None
        else [
            [{"morphism": a.morphism, "params": {k: value_to_json(v) for k, v in a.params.items()}} for a in step]
            for step in result.plan.steps
        ],
        "timings": {k: round(v, 6) for k, v in result.timings.items()},
    }


def print_recompose(console, inst: ir.Instance, rec) -> None:
    res = rec.result
    if res.plan is None:
        print_optimize(console, inst, res)
        return
    first = (
        "stability first (least churn, then the mission objective)"
        if rec.priority == "stability"
        else "objective first (the mission objective, then least churn)"
    )
    status = res.status.value.upper()
    console.print(
        f"[bold green]{status}[/]  {first}: churn {show_value(rec.churn)} against the deployed "
        f"composition of {len(rec.deployed)} components"
    )
    if rec.items:
        table = Table("change", "component", "churn weight")
        for item in rec.items:
            table.add_row("+ added" if item.change == "added" else "- removed", item.morphism, show_value(item.weight))
        console.print(table)
    else:
        console.print("  no component changes")
    console.print()
    print_optimize(console, inst, res)


def recompose_json(inst: ir.Instance, rec) -> dict:
    doc = optimize_json(inst, rec.result)
    doc["schema"] = "catc.recompose/1"
    doc["priority"] = rec.priority
    doc["deployed"] = list(rec.deployed)
    doc["churn"] = value_to_json(rec.churn) if rec.churn is not None else None
    doc["changes"] = [
        {"morphism": i.morphism, "change": i.change, "weight": value_to_json(i.weight)} for i in rec.items
    ]
    return doc


def pareto_json(inst: ir.Instance, result) -> dict:
    from catc.ir.text import to_text

    return {
        "schema": "catc.pareto/1",
        "status": result.status,
        "complete": result.complete,
        "objectives": [{"sense": o.sense.value, "term": to_text(o.term)} for o in result.objectives],
        "points": [
            {
                "values": [value_to_json(v) for v in p.values],
                "decimals": [decimal_text(v) for v in p.values],
                "components": sorted(p.plan.components),
                "steps": [
                    [
                        {"morphism": a.morphism, "params": {k: value_to_json(v) for k, v in a.params.items()}}
                        for a in step
                    ]
                    for step in p.plan.steps
                ],
            }
            for p in result.points
        ],
        "timings": {k: round(v, 6) for k, v in result.timings.items()},
    }


def synthesize_json(result) -> dict:
    from catc.ir.text import effect_text, to_text
    from catc.queries.synthesize import to_cat

    m = result.morphism
    return {
        "schema": "catc.synthesize/1",
        "status": result.status,
        "hole": result.hole.name,
        "view": result.hole.view,
        "effects": [effect_text(e) for e in m.effects] if m else None,
        "preconditions": [to_text(l.expr) for l in m.pre] if m else None,
        "applied_at_step": result.step,
        "skeleton": to_cat(m, result.hole) if m is not None else None,
    }


def validate_json(report) -> dict:
    return {
        "schema": "catc.validate/1",
        "valid": report.ok,
        "violations": [
            {"kind": v.kind, "message": v.message, "step": v.step, "morphism": v.morphism, "label": v.label}
            for v in report.violations
        ],
        "final_state": state_json(report.states[-1]) if report.ok and report.states else None,
    }
