"""A benchmark session: the problems loaded and exported once each (per grid), the interleaved
trials of catc and ENHSP, and the rows of the runtimes and perturbations tables."""

from __future__ import annotations

import dataclasses
import re
import shutil
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from catc.bench.lines import LineDiff, text_diff
from catc.bench.problems import (
    PROBLEMS,
    REFINE_FACTORS,
    REFINE_MAX_ACTIONS,
    Expected,
    Grid,
    Problem,
    expected_for,
    grid_text,
)
from catc.bench.runners import Loaded, ToolRun, enhsp_run, run_catc, smtplan_export, smtplan_run, value_of
from catc.bench.stats import consensus, marker


@dataclass
class Measured:
    problem: Problem
    expected: Expected
    catc: list[ToolRun] = field(default_factory=list)
    enhsp: list[ToolRun] = field(default_factory=list)
    actions: int = 0
    export_s: float = 0.0
    metric_exported: bool = False
    smtplan: str = "not installed"


def _reached(mk: str) -> bool:
    """Whether a marker is the expected answer (so no finer grid is needed)."""
    return mk.startswith("OPT") or mk in ("SAT", "UNSAT")


class Bench:
    def __init__(self, examples: Path, runs: int, timeout: float, workdir: Path, log: Callable[[str], None]):
        self.examples = examples
        self.runs = runs
        self.timeout = timeout
        self.workdir = workdir
        self.log = log
        self.loaded: dict[tuple[str, str], Loaded] = {}
        self.measured: dict[str, Measured] = {}
        self.smtplan = shutil.which("SMTPlan")

    def load(self, file: str, grid: Grid | None = None) -> Loaded:
        p = PROBLEMS[file]
        g = dict(p.grid if grid is None else grid)
        key = (file, grid_text(g))
        if key not in self.loaded:
            sub = self.workdir / re.sub(r"[^a-z0-9]+", "-", f"{file}-{grid_text(g)}".lower())
            self.loaded[key] = Loaded(self.examples, p, sub, g)
        return self.loaded[key]

    # ---- runtimes (and the perturbed problems), interleaved trials
    def measure(self, files: Sequence[str]) -> None:
        for f in files:
            p = PROBLEMS[f]
            ld = self.load(f)
            self.measured[f] = Measured(
                p,
                expected_for(self.examples, f, p.query, sense=ld.sense),
                actions=len(ld.export.actions),
                export_s=ld.export_s,
                metric_exported=ld.metric_exported,
            )
        for trial in range(self.runs):
            for f in files:
                p, m = PROBLEMS[f], self.measured[f]
                self.log(f"trial {trial + 1}/{self.runs}: {f}")
                m.catc.append(run_catc(self.examples / f, p.query, p.catc_args, self.timeout))
                m.enhsp.append(enhsp_run(self.load(f), p.planner, self.timeout, value_of=value_of(p)))
        if self.smtplan:
            for f in files:
                r = smtplan_run(smtplan_export(self.load(f)), self.smtplan, self.timeout)
                self.measured[f].smtplan = f"{marker(r, self.measured[f].expected)} {r.wall:.2f} s"

    def runtime_rows(self, files: Sequence[str]) -> list[dict[str, Any]]:
        return [self._runtime_row(f) for f in files]

    def _runtime_row(self, f: str) -> dict[str, Any]:
        m = self.measured[f]
        c, e = consensus(m.catc), consensus(m.enhsp)
        ms = [r.planning_ms for r in m.enhsp if r.planning_ms is not None]
        return {
            "problem": f,
            "query": m.problem.query,
            "grid": {k: str(v) for k, v in m.problem.grid.items()},
            "ground_actions": m.actions,
            "export_s": round(m.export_s, 4),
            "metric_exported": m.metric_exported,
            "expected": {
                "status": m.expected.status,
                "optimum": None if m.expected.optimum is None else str(m.expected.optimum),
            },
            "catc": {
                "marker": marker(c, m.expected),
                "value": None if c is None or c.value is None else str(c.value),
                "wall": [round(r.wall, 4) for r in m.catc],
            },
            "enhsp": {
                "planner": m.problem.planner,
                "marker": marker(e, m.expected),
                "value": None if e is None or e.value is None else str(e.value),
                "wall": [round(r.wall, 4) for r in m.enhsp],
                "planning_ms": ms,
                "error": None if e is None else e.detail.get("output") or e.detail.get("violations"),
            },
            "smtplan": m.smtplan,
        }

    # ---- perturbations
    def perturbation_rows(self, chosen: Sequence[tuple[str, str, str]]) -> list[dict[str, Any]]:
        return [self._perturbation_row(name, base, target) for name, base, target in chosen]

    def _perturbation_row(self, name: str, base: str, target: str) -> dict[str, Any]:
        pb, pt = PROBLEMS[base], PROBLEMS[target]
        edits = self._edit_lines(base, target)
        lb = self.load(base)
        lt = self.load(target, pb.grid)  # the base's grid
        exp = expected_for(self.examples, target, pt.query, sense=lt.sense)
        m = self.measured.get(target)
        if m is not None and m.problem.grid == pb.grid:
            c, e = consensus(m.catc), consensus(m.enhsp)
        else:
            c = run_catc(self.examples / target, pt.query, pt.catc_args, self.timeout)
            e = enhsp_run(lt, pt.planner, self.timeout, value_of=value_of(pt))
        cm, em = marker(c, exp), marker(e, exp)
        row = {
            "perturbation": name,
            "base": base,
            "perturbed": target,
            "grid": {k: str(v) for k, v in pb.grid.items()},
            "catc": cm,
            "enhsp": em,
            **edits,
            "recovery": None,
        }
        if not _reached(em):
            row["recovery"] = self.recover(base, target, lb, exp)
        return row

    def _edit_lines(self, base: str, target: str) -> dict[str, Any]:
        """The model-edit lines from base to perturbed: of the .cat files, and of the PDDL
        exported with the base's grid."""
        base_files, target_files = self.cat_files(base), self.cat_files(target)
        cat_dom = (
            text_diff(base_files[0].read_text(), target_files[0].read_text())
            if base_files[0] != target_files[0]
            else LineDiff(0, 0, 0)
        )
        cat_prob = text_diff(base_files[1].read_text(), target_files[1].read_text())
        lb = self.load(base)
        lt = self.load(target, PROBLEMS[base].grid)  # the base's grid
        pddl_dom = text_diff(lb.export.domain, lt.export.domain, pddl=True)
        pddl_prob = text_diff(lb.export.problem, lt.export.problem, pddl=True)
        return {
            "cat_lines": {"domain": dataclasses.asdict(cat_dom), "problem": dataclasses.asdict(cat_prob)},
            "pddl_lines": {"domain": dataclasses.asdict(pddl_dom), "problem": dataclasses.asdict(pddl_prob)},
        }

    def cat_files(self, file: str) -> tuple[Path, Path]:
        """(domain file, problem file) of an example: the folder's domain.cat and the problem."""
        folder = (self.examples / file).parent
        return folder / "domain.cat", self.examples / file

    def recover(self, base: str, target: str, lb: Loaded, exp: Expected) -> dict[str, Any]:
        """Re-export the perturbed problem with finer grids until ENHSP reaches the expected
        answer; the PDDL diff is then base (base grid) → perturbed (finer grid)."""
        why = self._no_grid_helps(base, target, exp)
        if why is not None:
            return {"found": False, "why": why}
        pt = PROBLEMS[target]
        tried = []
        for k in REFINE_FACTORS:
            grid = {name: step / k for name, step in pt.grid.items()}
            try:
                cand = self.load(target, grid)
            except Exception as exc:
                tried.append(f"{grid_text(grid)}: {exc}")
                continue
            if len(cand.export.actions) > REFINE_MAX_ACTIONS:
                tried.append(f"{grid_text(grid)}: {len(cand.export.actions)} actions, not tried")
                continue
            self.log(f"refine {target}: {grid_text(grid)}")
            r = enhsp_run(cand, pt.planner, self.timeout, value_of=value_of(pt))
            mk = marker(r, exp)
            tried.append(f"{grid_text(grid)}: {mk}")
            if _reached(mk):
                d = text_diff(lb.export.domain, cand.export.domain, pddl=True) + text_diff(
                    lb.export.problem, cand.export.problem, pddl=True
                )
                return {
                    "found": True,
                    "grid": {n: str(v) for n, v in grid.items()},
                    "enhsp": mk,
                    "actions": len(cand.export.actions),
                    "pddl_lines": dataclasses.asdict(d),
                    "tried": tried,
                }
        return {
            "found": False,
            "why": f"no finer grid among step/{', /'.join(map(str, REFINE_FACTORS))} reaches it within "
            f"{self.timeout:g} s",
            "tried": tried,
        }

    def _no_grid_helps(self, base: str, target: str, exp: Expected) -> str | None:
        """Why no finer grid can recover the perturbed problem's answer, or None to try."""
        pt = PROBLEMS[target]
        lt = self.load(target, PROBLEMS[base].grid)
        if exp.optimum is not None and not lt.metric_exported:
            reason = "; ".join(t for c, t in lt.export.report.items if c == "objective") or "no metric in the export"
            return f"no grid helps: the export writes no metric ({reason})"
        if not pt.grid:
            return "no real θ to refine"
        if pt.query == "recompose":  # judged on churn, which no grid changes
            return "no grid helps: churn against the deployed composition is not expressible in PDDL"
        return None
