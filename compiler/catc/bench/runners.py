"""One tool run, each as a fresh process: catc (``python -m catc QUERY ... --json``), ENHSP on
the exported PDDL files (its plan replayed by catc's validator and its value computed
exactly), SMTPlan+ when installed.  A problem is loaded and exported once, in process."""

from __future__ import annotations

import json
import re
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any

from catc.bench.problems import Grid, Problem
from catc.queries import registry

if TYPE_CHECKING:
    from catc import ir
    from catc.semantics.plan import Plan

CATC = [sys.executable, "-m", "catc"]

#: The queries given ``--timeout`` (they report the best composition found by then).
ANYTIME_QUERIES = ("optimize", "recompose")


@dataclass
class ToolRun:
    status: str  # sat | opt | subopt | unsat | timeout | error | invalid
    wall: float
    value: Fraction | None = None
    planning_ms: int | None = None
    detail: dict[str, Any] = field(default_factory=dict)


class BenchInputError(Exception):
    pass


def load(path: Path) -> ir.Instance:
    from catc.frontend.workspace import load_instance
    from catc.ir.views import apply_view
    from catgrammar.diagnostics import Diagnostics

    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    if inst is None or diags.has_errors:
        msgs = "; ".join(d.message for d in diags.sorted()[:3])
        raise BenchInputError(f"{path}: {msgs or 'cannot load'}")
    return apply_view(inst, None)


class Loaded:
    """One problem loaded and exported once (in process); ENHSP runs on the files."""

    def __init__(self, examples: Path, problem: Problem, workdir: Path, grid: Grid | None = None):
        from catc.targets.pddl import export_pddl

        self.path = examples / problem.file
        self.inst = load(self.path)
        self.grid = dict(problem.grid if grid is None else grid)
        start = time.perf_counter()
        self.export = export_pddl(self.inst, grid=self.grid)
        self.export_s = time.perf_counter() - start
        self.dir = workdir
        self.dir.mkdir(parents=True, exist_ok=True)
        self.domain_file, self.problem_file = self.dir / "domain.pddl", self.dir / "problem.pddl"
        self.domain_file.write_text(self.export.domain)
        self.problem_file.write_text(self.export.problem)

    @property
    def metric_exported(self) -> bool:
        return "(:metric" in self.export.problem

    def objective(self) -> ir.Objective | None:
        met = self.inst.problem.metric
        if met is None or not met.objectives:
            return None
        return met.objectives[0]

    @property
    def sense(self) -> str | None:
        obj = self.objective()
        return None if obj is None else obj.sense.value


#: How an ENHSP plan's value is computed: (loaded problem, plan, validated final state) → value.
ValueOf = Callable[[Loaded, "Plan", Any], "Fraction | None"]


def run_catc(path: Path, query: str, extra: Sequence[str], timeout: float) -> ToolRun:
    if query not in registry.names():
        raise ValueError(f"{query!r} is not a catc query ({', '.join(registry.names())})")
    cmd = [*CATC, query, str(path), "--json", *extra]
    if query in ANYTIME_QUERIES:
        cmd += ["--timeout", str(timeout)]
    start = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout + 30)
    except subprocess.TimeoutExpired:
        return ToolRun("timeout", time.perf_counter() - start)
    wall = time.perf_counter() - start
    try:
        doc = json.loads(proc.stdout)
    except json.JSONDecodeError:
        return ToolRun("error", wall, detail={"stderr": proc.stderr[-500:]})
    status = doc.get("status", "error")
    value = None
    if query == "recompose" and doc.get("churn") is not None:
        value = Fraction(str(doc["churn"]))
    elif doc.get("objectives"):
        v = doc["objectives"][0].get("value")
        value = None if v is None else Fraction(str(v))
    if status == "unknown":
        status = "timeout"
    return ToolRun(status, wall, value, detail=doc)


def enhsp_run(loaded: Loaded, planner: str, timeout: float, value_of: ValueOf | None = None) -> ToolRun:
    """ENHSP on the exported files; a plan is replayed by catc's validator and its objective
    value computed exactly from the validated final state."""
    from catc.semantics.validate import objective_value, validate
    from catc.targets.enhsp import run_enhsp

    res = run_enhsp(loaded.domain_file, loaded.problem_file, planner=planner, timeout=timeout)
    run = ToolRun(
        res.status, res.wall, planning_ms=res.planning_ms, detail={"metric": res.metric, "actions": list(res.actions)}
    )
    if res.status != "sat":
        if res.status == "error":
            run.detail["output"] = res.output[-1500:]
        return run
    try:
        plan = loaded.export.plan_from_actions(res.actions)
    except KeyError as exc:
        run.status = "invalid"
        run.detail["violations"] = [f"unknown action {exc}"]
        return run
    rep = validate(loaded.inst, plan, horizon=len(plan), sequential=True)
    if not rep.ok:
        run.status = "invalid"
        run.detail["violations"] = [str(v) for v in rep.violations[:5]]
        return run
    run.detail["plan"] = plan
    run.detail["final_state"] = rep.final_state
    if value_of is not None:
        run.value = value_of(loaded, plan, rep.final_state)
    else:
        obj = loaded.objective()
        if obj is not None:
            v = objective_value(loaded.inst, plan, obj.term, rep.final_state)
            run.value = None if v is None else Fraction(v)
    return run


def churn_of(loaded: Loaded, plan: Plan, final_state: Any) -> Fraction | None:
    from catc import ir
    from catc.semantics.validate import objective_value

    v = objective_value(loaded.inst, plan, ir.TotalChurn(), final_state)
    return None if v is None else Fraction(v)


def value_of(problem: Problem) -> ValueOf | None:
    """How an ENHSP plan's value is judged: its churn for recompose, else the objective."""
    return churn_of if problem.query == "recompose" else None


def smtplan_export(loaded: Loaded) -> Loaded:
    """``loaded`` exported again in the smtplan flavour (PDDL+), beside its ENHSP files."""
    from catc.targets.pddl import export_pddl

    sm = Loaded.__new__(Loaded)
    sm.__dict__.update(loaded.__dict__)
    sm.dir = loaded.dir.with_name(loaded.dir.name + "-smtplan")
    sm.dir.mkdir(parents=True, exist_ok=True)
    ex = export_pddl(loaded.inst, grid=loaded.grid, flavor="smtplan")
    sm.domain_file, sm.problem_file = sm.dir / "domain.pddl", sm.dir / "problem.pddl"
    sm.domain_file.write_text(ex.domain)
    sm.problem_file.write_text(ex.problem)
    return sm


def smtplan_run(loaded: Loaded, exe: str, timeout: float) -> ToolRun:
    """SMTPlan+ on the same files (only when the binary is installed).  A plan is recognised
    by ``time: (action)`` lines; anything else is reported as ERR with its output."""
    start = time.perf_counter()
    try:
        proc = subprocess.run(
            [exe, str(loaded.domain_file), str(loaded.problem_file)], capture_output=True, text=True, timeout=timeout
        )
    except subprocess.TimeoutExpired:
        return ToolRun("timeout", time.perf_counter() - start)
    wall = time.perf_counter() - start
    out = proc.stdout + proc.stderr
    if re.search(r"^\s*\d+(\.\d+)?\s*:\s*\(", out, re.M):
        return ToolRun("sat", wall)
    return ToolRun("error", wall, detail={"output": out[-500:]})
