"""Interchangeable components in the examples: would symmetry breaking have anything to break?
(issue 16, "symmetry breaking between interchangeable components").

    python benchmarks/symmetry_classes.py [--catalog N,D]

Two components are interchangeable when renaming one into the other maps every composition to
a composition with the same answer: the same kind, parameters (names, sorts, bounds, fixed),
preconditions, effects, churn weight, use limit and cost, and both deployed or neither (churn),
and no objective, goal or soft constraint names either of them (``(uses m)``, a parameter's
value).  The script prints, for every problem of every example (and optionally one generated
catalog of ``benchmarks/catalogs.py``), how many components it has and its classes of two or
more interchangeable ones.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT / "compiler"), str(ROOT / "benchmarks")]


def classes(inst: object) -> list[list[str]]:
    from catc import ir
    from catc.ir.text import to_text

    deployed = set(inst.problem.deployed)  # type: ignore[attr-defined]
    named: set[str] = set()

    def walk(e: object) -> None:
        if isinstance(e, (ir.Uses, ir.ParamValue)):
            named.add(e.morphism)
        for child in getattr(e, "args", ()) or ():
            walk(child)
        for attr in ("left", "right", "cond", "then", "orelse", "element", "set", "expr", "term"):
            if hasattr(e, attr):
                walk(getattr(e, attr))

    problem = inst.problem  # type: ignore[attr-defined]
    objectives = problem.metric.objectives if problem.metric is not None else ()
    for part in (*problem.goal, *objectives, *problem.softs):
        walk(part)
    groups: dict[tuple, list[str]] = {}
    for m in inst.morphisms.values():  # type: ignore[attr-defined]
        if m.name in named:
            continue
        key = (
            m.kind,
            tuple((p.name, p.sort.name, p.lower, p.upper, p.fixed) for p in m.params),
            tuple(to_text(lit.expr) for lit in m.pre),
            tuple((e.kind, e.resource, to_text(e.value)) for e in m.effects),
            m.churn,
            m.uses,
            None if m.cost is None else to_text(m.cost),
            m.name in deployed,
        )
        groups.setdefault(key, []).append(m.name)
    return [g for g in groups.values() if len(g) > 1]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--catalog", default=None, help="also a generated catalog: N,D")
    args = ap.parse_args(argv)
    from catc.frontend.workspace import load_instance
    from catgrammar.diagnostics import Diagnostics

    rows = []
    for folder in sorted((ROOT / "examples").iterdir()):
        domain = folder / "domain.cat"
        for problem in sorted(folder.glob("*.cat")):
            if problem.name == "domain.cat":
                continue
            diags = Diagnostics()
            _, inst = load_instance(str(domain) if domain.exists() else None, str(problem), diags)
            if inst is None:
                continue  # deliberately broken files and problem-less domains
            rows.append((f"{folder.name}/{problem.name}", len(inst.morphisms), classes(inst)))
    if args.catalog:
        from catalogs import catalog

        from catc.api import loads

        n, d = (int(x) for x in args.catalog.split(","))
        inst = loads({"catalog.cat": catalog(n, d, "ram")[0]}, "catalog.cat").instance
        rows.append((f"catalog ram n={n} d={d}", len(inst.morphisms), classes(inst)))
    command = " ".join(["python benchmarks/symmetry_classes.py", *(sys.argv[1:] if argv is None else argv)])
    print(f"`{command}`\n")
    print("| problem | components | classes of interchangeable components |")
    print("|---|---:|---|")
    for name, count, groups in rows:
        shown = "; ".join("{" + ", ".join(g) + "}" for g in groups[:3]) + (" …" if len(groups) > 3 else "")
        print(f"| {name} | {count} | {len(groups)}{': ' + shown if groups else ''} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
