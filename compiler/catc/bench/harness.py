"""``catc bench``: catc and ENHSP side by side on the same problems, in one run (issue 5).

Every trial runs each tool as a fresh process (``python -m catc ...``; ``java -jar enhsp.jar``
through :func:`catc.targets.enhsp.run_enhsp`), interleaved problem by problem, so both pay
their process start-up and see the same machine load.  Wall times are summarised by the
median and the interquartile range; ENHSP's own ``Planning Time (msec)`` is reported beside
its wall time.

Outcome markers are judged against the hand-derived expectations in the examples'
``expect.toml`` (``status``, ``optimum``, ``recompose_*``), with exact rational arithmetic:

* ``SAT`` / ``UNSAT`` — a satisfaction answer (``✗`` appended when it contradicts expect.toml);
* ``OPT`` — a composition whose objective value *equals* the known optimum;
* ``SUBOPT`` — a valid composition whose objective value is worse (e.g. ENHSP on a grid that
  misses the optimum, or with no metric exported);
* ``BETTER ✗`` — a value better than the known optimum (a bug in a tool or in expect.toml);
* ``INVALID`` — an ENHSP plan catc's validator rejects; ``TIMEOUT``; ``ERR``.

ENHSP's plan is read back through the export's ground-action names and replayed by catc's
independent validator (sequential semantics); its objective value is computed from the
validated final state, so the marker does not depend on how (or whether) the export maps
the metric.

Tables: runtimes; one-edit perturbations with model-edit line counts; lifelong queries
(diagnose, relax by bisection for ENHSP, recompose); a capability line for SMTPlan+ (run only
when an ``SMTPlan`` binary is on PATH).
"""

from __future__ import annotations

import dataclasses
import difflib
import json
import os
import platform
import re
import shlex
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
import tomllib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path

import click

EXIT_OK, EXIT_INPUT = 0, 2

# ====================================================================== pure parts


def quartiles(xs: Sequence[float]) -> tuple[float, float, float]:
    """(median, lower quartile, upper quartile) of ``xs`` (the quartiles by linear
    interpolation between order statistics, ``statistics.quantiles(method='inclusive')``);
    with one value all three are that value."""
    if not xs:
        raise ValueError("no measurements")
    if len(xs) == 1:
        return xs[0], xs[0], xs[0]
    q = statistics.quantiles(xs, n=4, method="inclusive")
    return statistics.median(xs), q[0], q[2]


def judge(
    status: str,
    expected_status: str | None,
    value: Fraction | None = None,
    optimum: Fraction | None = None,
    sense: str | None = None,
) -> str:
    """The outcome marker of one answer.

    ``status`` is the tool's answer: ``sat``/``opt``/``subopt`` (a composition was found),
    ``unsat``, ``timeout``, ``error`` or ``invalid``.  ``value`` is the composition's objective
    value and ``optimum`` the known optimum (both exact), ``sense`` ``minimize`` or
    ``maximize``.  Returns SAT, UNSAT, OPT, SUBOPT, ``BETTER ✗``, TIMEOUT, ERR or INVALID;
    ``✗`` is appended to SAT/UNSAT when the answer contradicts ``expected_status``."""
    if status == "timeout":
        return "TIMEOUT"
    if status == "invalid":
        return "INVALID"
    if status not in ("sat", "opt", "subopt", "unsat"):
        return "ERR"
    if status == "unsat":
        return "UNSAT ✗" if expected_status == "sat" else "UNSAT"
    if expected_status == "unsat":
        return "SAT ✗"
    if optimum is None:
        return "SAT"
    if value is None:
        return "SAT"  # a composition without an objective value (should not happen)
    value, optimum = Fraction(value), Fraction(optimum)
    if value == optimum:
        return "OPT"
    better = value > optimum if sense == "maximize" else value < optimum
    return "BETTER ✗" if better else "SUBOPT"


def strip_comment(line: str) -> str:
    """``line`` without its ``;`` comment (a ``;`` inside a double-quoted string is text)."""
    in_string = False
    escaped = False
    for i, ch in enumerate(line):
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch == ";":
            return line[:i]
    return line


def _split_declarations(line: str) -> list[str]:
    """``(:predicates (a) (b x))`` → ``["(:predicates", "(a)", "(b x)", ")"]``: one declaration
    a line, as a hand-written PDDL file would have them (what follows the section's closing
    parenthesis stays one line)."""
    head, _, rest = line.partition(" ")
    items: list[str] = [head]
    depth, cur = 1, []
    for i, ch in enumerate(rest):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
        if depth >= 2 or (ch == ")" and depth == 1):
            cur.append(ch)
            if depth == 1:
                items.append("".join(cur))
                cur = []
        elif depth == 0:
            items.append(")")
            tail = rest[i + 1 :].strip()
            if tail:
                items.append(tail)
            return items
    return [line]  # unbalanced: leave it as written


def model_lines(text: str, *, pddl: bool = False) -> list[str]:
    """The lines of a model file that count as model content: comments removed, whitespace
    normalised (runs of blanks → one space, stripped), blank lines dropped.  For PDDL,
    ``(:predicates ...)`` and ``(:functions ...)`` written on one line are split into one
    declaration per line first (as a hand-maintained file would list them)."""
    out: list[str] = []
    for raw in text.splitlines():
        line = " ".join(strip_comment(raw).split())
        if not line:
            continue
        if pddl and (line.startswith("(:predicates ") or line.startswith("(:functions ")):
            out.extend(_split_declarations(line))
        else:
            out.append(line)
    return out


@dataclass(frozen=True)
class LineDiff:
    added: int
    removed: int
    changed: int  # edited lines: a replaced block of a old and b new lines counts max(a, b)

    def __add__(self, other: LineDiff) -> LineDiff:
        return LineDiff(self.added + other.added, self.removed + other.removed, self.changed + other.changed)

    def text(self) -> str:
        return f"{self.changed} (+{self.added} −{self.removed})"


def line_diff(old: Iterable[str], new: Iterable[str]) -> LineDiff:
    """Line-level difference of two normalised line lists (:func:`model_lines`), by difflib."""
    a, b = list(old), list(new)
    added = removed = changed = 0
    for tag, i1, i2, j1, j2 in difflib.SequenceMatcher(None, a, b, autojunk=False).get_opcodes():
        if tag == "equal":
            continue
        removed += i2 - i1
        added += j2 - j1
        changed += max(i2 - i1, j2 - j1)
    return LineDiff(added, removed, changed)


def text_diff(old: str, new: str, *, pddl: bool = False) -> LineDiff:
    return line_diff(model_lines(old, pddl=pddl), model_lines(new, pddl=pddl))


def fraction_text(v: Fraction | None) -> str:
    if v is None:
        return "—"
    from catc.ir.numbers import decimal_text

    return decimal_text(Fraction(v))


# ====================================================================== the curated problems

Grid = dict[str, Fraction]

#: Grids for the real θ of the examples (by parameter name), stated in every table.
GRID_DETECTION: Grid = {"ram-req": Fraction(1, 2)}
GRID_GPU: Grid = {"m": Fraction(1, 4)}
GRID_NAV: Grid = {"d": Fraction(1)}
GRID_SAR: Grid = {"ram-req": Fraction(1, 4), "d": Fraction(1), "mem": Fraction(1, 2)}


@dataclass(frozen=True)
class Problem:
    file: str  # relative to the examples folder
    query: str  # catc command: solve | optimize | recompose
    planner: str  # ENHSP -planner
    grid: Grid = field(default_factory=dict)
    catc_args: tuple[str, ...] = ()
    quick: bool = False

    @property
    def value_of(self) -> Callable | None:
        """How an ENHSP plan's value is judged: its churn for recompose, else the objective."""
        return churn_of if self.query == "recompose" else None


def _p(file, query, planner, grid=None, catc_args=(), quick=False) -> Problem:
    return Problem(file, query, planner, dict(grid or {}), tuple(catc_args), quick)


PROBLEMS: dict[str, Problem] = {
    p.file: p
    for p in [
        _p("detection/person.cat", "solve", "sat-hadd", GRID_DETECTION, quick=True),
        _p("detection/unmodeled-class.cat", "solve", "sat-hadd", GRID_DETECTION, quick=True),
        _p("navigation/farthest.cat", "optimize", "opt-hrmax", GRID_NAV),
        _p("navigation/precise.cat", "solve", "sat-hadd", GRID_NAV),
        _p("navigation/coarse.cat", "solve", "sat-hadd", GRID_NAV),
        _p("gpu-allocation/max-confidence.cat", "optimize", "opt-hrmax", GRID_GPU, quick=True),
        _p("gpu-allocation/upgrade.cat", "optimize", "opt-hrmax", GRID_GPU, quick=True),
        _p("gpu-allocation/retask.cat", "optimize", "opt-hrmax", GRID_GPU),
        _p("lifelong/budget-cut.cat", "solve", "sat-hadd", quick=True),
        _p("lifelong/cheaper-camera.cat", "recompose", "opt-hrmax"),
        _p("search-and-rescue/event1-fresh.cat", "solve", "sat-hadd", GRID_SAR),
        _p("search-and-rescue/event2-out-of-range.cat", "optimize", "opt-hrmax", GRID_SAR),
        _p("search-and-rescue/event4-dark.cat", "solve", "sat-hadd", GRID_SAR),
        _p("search-and-rescue/budget-cut.cat", "solve", "sat-hadd", GRID_SAR),
        _p("search-and-rescue/cheaper-camera.cat", "recompose", "opt-hrmax", GRID_SAR),
    ]
}

RUNTIME_ROWS = [
    "detection/person.cat",
    "navigation/farthest.cat",
    "navigation/precise.cat",
    "navigation/coarse.cat",
    "gpu-allocation/max-confidence.cat",
    "lifelong/budget-cut.cat",
    "search-and-rescue/event1-fresh.cat",
    "search-and-rescue/event2-out-of-range.cat",
    "search-and-rescue/event4-dark.cat",
    "search-and-rescue/budget-cut.cat",
]

#: (name, base, perturbed): the perturbed problem is judged with the base's grid.
PERTURBATIONS = [
    ("GPU upgrade (+1 GB)", "gpu-allocation/max-confidence.cat", "gpu-allocation/upgrade.cat"),
    (
        "re-tasking (least footprint, confidence ≥ 0.7)",
        "gpu-allocation/max-confidence.cat",
        "gpu-allocation/retask.cat",
    ),
    ("increased precision (22.73 Wh, 9.65 m)", "navigation/farthest.cat", "navigation/precise.cat"),
    ("one-decimal reading (22.7 Wh)", "navigation/farthest.cat", "navigation/coarse.cat"),
    ("unmodeled class", "detection/person.cat", "detection/unmodeled-class.cat"),
    ("dark room (SAR event IV)", "search-and-rescue/event1-fresh.cat", "search-and-rescue/event4-dark.cat"),
    (
        "cheaper camera in the catalog (SAR, recompose)",
        "search-and-rescue/event1-fresh.cat",
        "search-and-rescue/cheaper-camera.cat",
    ),
]

QUICK_RUNTIME_ROWS = ["detection/person.cat", "gpu-allocation/max-confidence.cat", "lifelong/budget-cut.cat"]
QUICK_PERTURBATIONS = ["GPU upgrade (+1 GB)", "unmodeled class"]

#: Finer grids tried (step / k) when the base grid loses the perturbed problem's answer.
REFINE_FACTORS = (2, 4, 5, 10, 20)
REFINE_MAX_ACTIONS = 25_000

TABLES = ("runtimes", "perturbations", "queries")


# ====================================================================== expectations


@dataclass
class Expected:
    status: str | None = None
    optimum: Fraction | None = None
    sense: str | None = None  # of the optimum
    case: dict = field(default_factory=dict)


def expected_for(
    examples: Path, file: str, query: str = "solve", priority: str = "stability", sense: str | None = None
) -> Expected:
    """The expectation of ``file`` (relative to ``examples``) for a catc ``query``: its status,
    and the known optimum with its ``sense`` (the churn for ``recompose``, stability first)."""
    folder, name = file.split("/", 1)
    path = examples / folder / "expect.toml"
    if not path.is_file():
        return Expected()
    for case in tomllib.loads(path.read_text()).get("case", []):
        if case.get("file") == name:
            exp = Expected(case.get("status"), case=case)
            if query == "recompose":
                rec = case.get(f"recompose_{priority}")
                if rec is not None:
                    if priority == "stability":
                        exp.optimum, exp.sense = Fraction(rec["churn"]), "minimize"
                    else:
                        exp.optimum, exp.sense = Fraction(rec["objective"]), sense
            elif query == "optimize" and case.get("optimum"):
                exp.optimum, exp.sense = Fraction(case["optimum"][0]), sense
            return exp
    return Expected()


# ====================================================================== measurements


@dataclass
class ToolRun:
    status: str  # sat | opt | subopt | unsat | timeout | error | invalid
    wall: float
    value: Fraction | None = None
    planning_ms: int | None = None
    detail: dict = field(default_factory=dict)


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

    def objective(self):
        met = self.inst.problem.metric
        if met is None or not met.objectives:
            return None
        return met.objectives[0]

    @property
    def sense(self) -> str | None:
        obj = self.objective()
        return None if obj is None else obj.sense.value


class BenchInputError(Exception):
    pass


def load(path: Path):
    from catc.frontend.workspace import load_instance
    from catc.ir.views import apply_view
    from catgrammar.diagnostics import Diagnostics

    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    if inst is None or diags.has_errors:
        msgs = "; ".join(d.message for d in diags.sorted()[:3])
        raise BenchInputError(f"{path}: {msgs or 'cannot load'}")
    return apply_view(inst, None)


CATC = [sys.executable, "-m", "catc"]


def run_catc(path: Path, query: str, extra: Sequence[str], timeout: float) -> ToolRun:
    cmd = [*CATC, query, str(path), "--json", *extra]
    if query in ("optimize", "recompose"):
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


def enhsp_run(loaded: Loaded, planner: str, timeout: float, value_of: Callable | None = None) -> ToolRun:
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


def churn_of(loaded: Loaded, plan, final_state) -> Fraction | None:
    from catc import ir
    from catc.semantics.validate import objective_value

    v = objective_value(loaded.inst, plan, ir.TotalChurn(), final_state)
    return None if v is None else Fraction(v)


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


# ====================================================================== presentation


def _diagnose_row(problem: str, catc_runs: Sequence[ToolRun], enhsp_runs: Sequence[ToolRun], exp: Expected) -> dict:
    """A lifelong-queries row for diagnose: catc's core against expect.toml, ENHSP's bare
    "unsolvable"."""
    got = catc_runs[0].detail.get("cores") or []
    labels = sorted(x["label"] for x in got[0]) if got else []
    first = enhsp_runs[0]
    return {
        "query": "diagnose",
        "problem": problem,
        "catc": {
            "answer": ("core " + ", ".join(labels)) if labels else catc_runs[0].status,
            "agrees": labels == sorted(exp.case.get("diagnose", [])),
            "wall": [r.wall for r in catc_runs],
        },
        "enhsp": {
            "answer": first.status.upper() + ("; no cause given" if first.status == "unsat" else ""),
            "calls": 1,
            "wall": [r.wall for r in enhsp_runs],
            "planning_ms": [r.planning_ms for r in enhsp_runs if r.planning_ms is not None],
        },
    }


def summary(runs: Sequence[ToolRun]) -> str:
    walls = [r.wall for r in runs]
    if not walls:
        return "—"
    m, lo, hi = quartiles(walls)
    return f"{m:.2f} ({lo:.2f}–{hi:.2f})"


def consensus(runs: Sequence[ToolRun]) -> ToolRun | None:
    """The most common answer of the trials (the first run with it)."""
    if not runs:
        return None
    keys = [(r.status, r.value) for r in runs]
    best = max(set(keys), key=keys.count)
    return runs[keys.index(best)]


def marker(run: ToolRun | None, exp: Expected) -> str:
    if run is None:
        return "—"
    m = judge(run.status, exp.status, run.value, exp.optimum, exp.sense)
    if run.value is not None and m in ("OPT", "SUBOPT", "BETTER ✗"):
        m += f" {fraction_text(run.value)}"
    return m


def grid_text(grid: Grid) -> str:
    if not grid:
        return "—"
    return ", ".join(f"{k}={fraction_text(v)}" for k, v in sorted(grid.items()))


def cpu_text() -> str:
    """The processor model, the core count and the Python version (also used by the scripts
    in benchmarks/)."""
    model = platform.machine()
    try:
        with open("/proc/cpuinfo") as fh:
            model = next(l.split(":", 1)[1].strip() for l in fh if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    return f"{model}, {os.cpu_count()} cores, Python {platform.python_version()}"


def machine() -> str:
    java = "?"
    exe = shutil.which("java")
    if exe:
        try:
            out = subprocess.run([exe, "-version"], capture_output=True, text=True, timeout=30)
            java = (out.stderr or out.stdout).splitlines()[0]
        except (OSError, subprocess.SubprocessError, IndexError):
            pass
    try:
        from importlib.metadata import version

        enhsp = f"up-enhsp {version('up-enhsp')}"
    except Exception:
        enhsp = "up-enhsp ?"
    return f"{cpu_text()}, {java}, {enhsp}"


# ====================================================================== the benchmark


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
                m.enhsp.append(enhsp_run(self.load(f), p.planner, self.timeout, value_of=p.value_of))
        if self.smtplan:
            for f in files:
                from catc.targets.pddl import export_pddl

                ld = self.load(f)
                sm = Loaded.__new__(Loaded)
                sm.__dict__.update(ld.__dict__)
                sm.dir = ld.dir.with_name(ld.dir.name + "-smtplan")
                sm.dir.mkdir(parents=True, exist_ok=True)
                ex = export_pddl(ld.inst, grid=ld.grid, flavor="smtplan")
                sm.domain_file, sm.problem_file = sm.dir / "domain.pddl", sm.dir / "problem.pddl"
                sm.domain_file.write_text(ex.domain)
                sm.problem_file.write_text(ex.problem)
                r = smtplan_run(sm, self.smtplan, self.timeout)
                self.measured[f].smtplan = f"{marker(r, self.measured[f].expected)} {r.wall:.2f} s"

    def runtime_rows(self, files: Sequence[str]) -> list[dict]:
        rows = []
        for f in files:
            m = self.measured[f]
            c, e = consensus(m.catc), consensus(m.enhsp)
            ms = [r.planning_ms for r in m.enhsp if r.planning_ms is not None]
            rows.append(
                {
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
            )
        return rows

    # ---- perturbations
    def perturbation_rows(self, chosen: Sequence[tuple[str, str, str]]) -> list[dict]:
        rows = []
        for name, base, target in chosen:
            pb, pt = PROBLEMS[base], PROBLEMS[target]
            base_files, target_files = self.cat_files(base), self.cat_files(target)
            cat_dom = (
                text_diff(base_files[0].read_text(), target_files[0].read_text())
                if base_files[0] != target_files[0]
                else LineDiff(0, 0, 0)
            )
            cat_prob = text_diff(base_files[1].read_text(), target_files[1].read_text())
            lb = self.load(base)
            lt = self.load(target, pb.grid)  # the base's grid
            pddl_dom = text_diff(lb.export.domain, lt.export.domain, pddl=True)
            pddl_prob = text_diff(lb.export.problem, lt.export.problem, pddl=True)
            exp = expected_for(self.examples, target, pt.query, sense=lt.sense)
            m = self.measured.get(target)
            if m is not None and m.problem.grid == pb.grid:
                c, e = consensus(m.catc), consensus(m.enhsp)
            else:
                c = run_catc(self.examples / target, pt.query, pt.catc_args, self.timeout)
                e = enhsp_run(lt, pt.planner, self.timeout, value_of=pt.value_of)
            cm, em = marker(c, exp), marker(e, exp)
            row = {
                "perturbation": name,
                "base": base,
                "perturbed": target,
                "grid": {k: str(v) for k, v in pb.grid.items()},
                "catc": cm,
                "enhsp": em,
                "cat_lines": {"domain": dataclasses.asdict(cat_dom), "problem": dataclasses.asdict(cat_prob)},
                "pddl_lines": {"domain": dataclasses.asdict(pddl_dom), "problem": dataclasses.asdict(pddl_prob)},
                "recovery": None,
            }
            if not (em.startswith("OPT") or em in ("SAT", "UNSAT")):
                row["recovery"] = self.recover(base, target, lb, exp)
            rows.append(row)
        return rows

    def cat_files(self, file: str) -> tuple[Path, Path]:
        """(domain file, problem file) of an example: the folder's domain.cat and the problem."""
        folder = (self.examples / file).parent
        return folder / "domain.cat", self.examples / file

    def recover(self, base: str, target: str, lb: Loaded, exp: Expected) -> dict:
        """Re-export the perturbed problem with finer grids until ENHSP reaches the expected
        answer; the PDDL diff is then base (base grid) → perturbed (finer grid)."""
        pt = PROBLEMS[target]
        lt = self.load(target, PROBLEMS[base].grid)
        if exp.optimum is not None and not lt.metric_exported:
            reason = "; ".join(t for c, t in lt.export.report.items if c == "objective") or "no metric in the export"
            return {"found": False, "why": f"no grid helps: the export writes no metric ({reason})"}
        if not pt.grid:
            return {"found": False, "why": "no real θ to refine"}
        if pt.query == "recompose":  # judged on churn, which no grid changes
            return {
                "found": False,
                "why": "no grid helps: churn against the deployed composition is not expressible in PDDL",
            }
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
            r = enhsp_run(cand, pt.planner, self.timeout, value_of=pt.value_of)
            mk = marker(r, exp)
            tried.append(f"{grid_text(grid)}: {mk}")
            if mk.startswith("OPT") or mk in ("SAT", "UNSAT"):
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

    # ---- lifelong queries
    def queries(self, include_sar: bool) -> list[dict]:
        rows = []
        lf = "lifelong/budget-cut.cat"
        cc = "lifelong/cheaper-camera.cat"
        exp_bc = expected_for(self.examples, lf)
        exp_cc = expected_for(self.examples, cc)
        lb, lc = self.load(lf), self.load(cc)
        diag, relax, relax_none, rec_s, rec_o = [], [], [], [], []
        e_unsat, e_bis, e_rec = [], [], []
        for trial in range(self.runs):
            self.log(f"queries trial {trial + 1}/{self.runs}")
            diag.append(run_catc(self.examples / lf, "diagnose", (), self.timeout))
            e_unsat.append(enhsp_run(lb, "sat-hadd", self.timeout))
            relax.append(run_catc(self.examples / lf, "relax", (), self.timeout))
            relax_none.append(run_catc(self.examples / lf, "relax", ("--relative-to", "none"), self.timeout))
            e_bis.append(self.bisect_budget(lb))
            rec_s.append(run_catc(self.examples / cc, "recompose", ("--priority", "stability"), self.timeout))
            rec_o.append(run_catc(self.examples / cc, "recompose", ("--priority", "objective"), self.timeout))
            e_rec.append(enhsp_run(lc, "opt-hrmax", self.timeout, value_of=churn_of))
        rows.append(_diagnose_row(lf, diag, e_unsat, exp_bc))
        # relax: catc relative to the deployed composition (expect.toml), and of the whole
        # problem (--relative-to none), which is what ENHSP's bisection can answer
        want_relax = {k: Fraction(v) for k, v in exp_bc.case.get("relax", {}).items()}
        b0 = e_bis[0]
        found = None if b0.get("found") is None else Fraction(b0["found"])
        for variant, runs_ in (
            ("relax (relative to the deployed composition)", relax),
            ("relax (whole problem, --relative-to none)", relax_none),
        ):
            d0 = runs_[0].detail
            got_relax = {x["label"]: Fraction(str(x["delta"])) for x in d0.get("relaxations", [])}
            if runs_ is relax:
                agrees = got_relax == want_relax
                enhsp = {
                    "answer": "cannot express the deployed composition (not exported); see the next row",
                    "calls": 0,
                    "wall": [],
                }
            else:
                # no expect.toml entry: the tools are compared with each other
                agrees = found is not None and got_relax.get("init/budget") == found
                enhsp = {
                    "answer": b0["answer"],
                    "calls": b0["calls"],
                    "wall": [b["total"] for b in e_bis],
                    "found": b0.get("found"),
                    "tolerance": b0.get("tolerance"),
                }
            rows.append(
                {
                    "query": variant,
                    "problem": lf,
                    "catc": {
                        "answer": ", ".join(f"{k} +{fraction_text(v)}" for k, v in got_relax.items())
                        or runs_[0].status,
                        "agrees": agrees,
                        "wall": [r.wall for r in runs_],
                    },
                    "enhsp": enhsp,
                }
            )
        # recompose: ENHSP's plan judged on the churn (stability first) and on the budget left
        # (objective first) against expect.toml
        er = consensus(e_rec)
        budget_left = None
        if er is not None and "final_state" in er.detail:
            bl = er.detail["final_state"].get("budget")
            budget_left = None if bl is None else Fraction(bl)
        for prio, runs_ in (("stability", rec_s), ("objective", rec_o)):
            want = exp_cc.case.get(f"recompose_{prio}", {})
            d = runs_[0].detail
            churn = d.get("churn")
            obj = (d.get("objectives") or [{}])[0].get("value")
            agrees = (
                churn is not None
                and Fraction(str(churn)) == Fraction(want.get("churn", "-1"))
                and obj is not None
                and Fraction(str(obj)) == Fraction(want.get("objective", "-1"))
            )
            if er is not None and er.status == "sat":
                if prio == "stability":
                    mk = (
                        judge("sat", "sat", er.value, Fraction(want["churn"]), "minimize") if "churn" in want else "SAT"
                    )
                else:
                    mk = (
                        judge("sat", "sat", budget_left, Fraction(want["objective"]), lc.sense)
                        if "objective" in want
                        else "SAT"
                    )
                answer = (
                    f"{mk}: plan with churn {fraction_text(er.value)} (computed by catc against the deployed "
                    f"composition; ENHSP has no notion of churn), budget left {fraction_text(budget_left)}"
                    + ("" if lc.metric_exported else "; no metric exported (maximize)")
                )
            else:
                answer = marker(er, exp_cc)
            rows.append(
                {
                    "query": f"recompose ({prio} first)",
                    "problem": cc,
                    "catc": {
                        "answer": f"churn {churn}, budget left {obj}",
                        "agrees": agrees,
                        "wall": [r.wall for r in runs_],
                    },
                    "enhsp": {
                        "answer": answer,
                        "calls": 1,
                        "wall": [r.wall for r in e_rec],
                        "planning_ms": [r.planning_ms for r in e_rec if r.planning_ms is not None],
                    },
                }
            )
        if include_sar:
            sf = "search-and-rescue/budget-cut.cat"
            ls = self.load(sf)
            sd, se = [], []
            for trial in range(self.runs):
                self.log(f"queries (SAR) trial {trial + 1}/{self.runs}")
                sd.append(run_catc(self.examples / sf, "diagnose", (), self.timeout))
                se.append(enhsp_run(ls, "sat-hadd", self.timeout))
            rows.append(_diagnose_row(sf, sd, se, expected_for(self.examples, sf)))
        return rows

    def bisect_budget(self, lb: Loaded, resource: str = "budget", tolerance: Fraction = Fraction(1)) -> dict:
        """ENHSP's workaround for relax: re-run it at candidate initial budgets (the problem
        text's init value rewritten), doubling until solvable, then bisecting to within
        ``tolerance``.  Returns calls, total seconds and the found least increase."""
        from catc.targets.enhsp import run_enhsp
        from catc.targets.pddl import sanitize

        fn = re.escape(sanitize(resource))
        pat = re.compile(rf"\(= \({fn}\) ([^()\s]+)\)")
        m = pat.search(lb.export.problem)
        if m is None:
            return {"answer": f"n/a (no init value of {resource} in the export)", "calls": 0, "total": 0.0}
        initial = Fraction(m.group(1))
        d = lb.dir.with_name(lb.dir.name + "-bisect")
        d.mkdir(parents=True, exist_ok=True)
        calls = 0
        total = 0.0

        def solvable(value: Fraction) -> bool | None:
            nonlocal calls, total
            from catc.targets.pddl import number

            prob = d / "problem.pddl"
            prob.write_text(pat.sub(f"(= ({sanitize(resource)}) {number(value)})", lb.export.problem, count=1))
            r = run_enhsp(lb.domain_file, prob, planner="sat-hadd", timeout=self.timeout)
            calls += 1
            total += r.wall
            return {"sat": True, "unsat": False}.get(r.status)

        first = solvable(initial)
        if first is None:
            return {"answer": "ENHSP gave up", "calls": calls, "total": total}
        if first:
            return {"answer": "already solvable", "calls": calls, "total": total, "found": "0"}
        lo, step = initial, max(abs(initial), Fraction(1))
        hi = None
        for _ in range(40):
            cand = lo + step
            ok = solvable(cand)
            if ok is None:
                return {"answer": "ENHSP gave up", "calls": calls, "total": total}
            if ok:
                hi = cand
                break
            lo, step = cand, step * 2
        if hi is None:
            return {"answer": "no solvable budget found", "calls": calls, "total": total}
        while hi - lo > tolerance:
            k = ((hi - lo) / 2 / tolerance).__floor__()
            mid = lo + max(k, 1) * tolerance
            if mid >= hi:
                break
            ok = solvable(mid)
            if ok is None:
                return {"answer": "ENHSP gave up", "calls": calls, "total": total}
            lo, hi = (lo, mid) if ok else (mid, hi)
        found = hi - initial
        return {
            "answer": f"{resource} +{fraction_text(found)} (least solvable within {fraction_text(tolerance)}: "
            f"{fraction_text(lo)} unsolvable, {fraction_text(hi)} solvable)",
            "calls": calls,
            "total": total,
            "found": str(found),
            "tolerance": str(tolerance),
        }


# ====================================================================== Markdown


def _wall(xs: Sequence[float]) -> str:
    if not xs:
        return "—"
    m, lo, hi = quartiles(list(xs))
    return f"{m:.2f} ({lo:.2f}–{hi:.2f})"


def _ms(xs: Sequence[int]) -> str:
    return "—" if not xs else f"{statistics.median(xs):.0f}"


def markdown(doc: dict) -> str:
    out = ["```text", f"command: {doc['command']}", f"machine: {doc['machine']}", f"date: {doc['date']}", "```", ""]
    n = doc["runs"]
    if doc.get("runtimes") is not None:
        sm = doc["smtplan"]
        out += [
            "### Runtimes",
            "",
            f"Wall seconds including process start, median (interquartile range) of {n} interleaved trial(s); "
            "ENHSP's own Planning Time (msec) is the median it printed.",
            "",
            "| problem | catc query | catc answer | catc wall (s) | grid | ground actions | ENHSP planner | ENHSP answer | ENHSP wall (s) | ENHSP planning (ms) | SMTPlan+ |",
            "|---|---|---|---:|---|---:|---|---|---:|---:|---|",
        ]
        for r in doc["runtimes"]:
            metric = "" if r["metric_exported"] or r["expected"]["optimum"] is None else " (no metric exported)"
            out.append(
                f"| {r['problem']} | {r['query']} | {r['catc']['marker']} | {_wall(r['catc']['wall'])} | "
                f"{grid_text({k: Fraction(v) for k, v in r['grid'].items()})} | {r['ground_actions']} | {r['enhsp']['planner']} | "
                f"{r['enhsp']['marker']}{metric} | {_wall(r['enhsp']['wall'])} | {_ms(r['enhsp']['planning_ms'])} | "
                f"{r['smtplan'] if sm != 'not installed' else 'not installed'} |"
            )
        out += [""]
    if doc.get("perturbations") is not None:
        out += [
            "### One-edit perturbations",
            "",
            "Model-edit lines: changed non-comment, non-blank lines between the base and the perturbed model "
            "(difflib on whitespace-normalised lines; a block of a old and b new lines counts max(a, b); "
            "+added −removed in brackets). `.cat`: domain + problem files as written. PDDL: the exported "
            "domain.pddl + problem.pddl (generated by `catc export pddl`, one predicate/function declaration "
            "a line), base vs perturbed with the base's grid — the edits a maintainer of a hand-written PDDL "
            "encoding would have to make.",
            "",
            "| perturbation | base → perturbed | grid | catc | ENHSP | `.cat` lines (domain + problem) | PDDL lines (domain + problem) | ENHSP with a finer grid |",
            "|---|---|---|---|---|---|---|---|",
        ]
        for r in doc["perturbations"]:
            cd, cp = LineDiff(**r["cat_lines"]["domain"]), LineDiff(**r["cat_lines"]["problem"])
            pd, pp = LineDiff(**r["pddl_lines"]["domain"]), LineDiff(**r["pddl_lines"]["problem"])
            rec = r["recovery"]
            if rec is None:
                rtext = "not needed"
            elif rec["found"]:
                rtext = (
                    f"{grid_text({k: Fraction(v) for k, v in rec['grid'].items()})}: {rec['enhsp']}, "
                    f"{rec['actions']} actions, PDDL lines {LineDiff(**rec['pddl_lines']).text()}"
                )
            else:
                rtext = rec["why"] + (f" (tried {'; '.join(rec['tried'])})" if rec.get("tried") else "")
            out.append(
                f"| {r['perturbation']} | {r['base']} → {Path(r['perturbed']).name} | "
                f"{grid_text({k: Fraction(v) for k, v in r['grid'].items()})} | {r['catc']} | {r['enhsp']} | "
                f"{cd.changed} + {cp.changed} = {(cd + cp).text()} | {pd.changed} + {pp.changed} = {(pd + pp).text()} | {rtext} |"
            )
        out += [""]
    if doc.get("queries") is not None:
        out += [
            "### Lifelong queries",
            "",
            "ENHSP has no diagnose, relax or churn: diagnose is one unsolvable run; relax is a bisection over "
            "the initial budget (the exported problem's init value rewritten, ENHSP sat-hadd at each "
            "candidate: doubling until solvable, then bisection to 1 USD); recompose is opt-hrmax on the "
            "cheaper-camera problem, its plan's churn computed by catc against the deployed composition.",
            "",
            "| query | problem | catc answer | catc agrees¹ | catc wall (s) | ENHSP workaround | ENHSP calls | ENHSP wall (s, total) |",
            "|---|---|---|---|---:|---|---:|---:|",
        ]
        for r in doc["queries"]:
            out.append(
                f"| {r['query']} | {r['problem']} | {r['catc']['answer']} | {'yes' if r['catc']['agrees'] else 'NO'} | "
                f"{_wall(r['catc']['wall'])} | {r['enhsp']['answer']} | {r['enhsp']['calls']} | {_wall(r['enhsp']['wall'])} |"
            )
        out += [
            "",
            "¹ with expect.toml; for the whole-problem relaxation (no expect.toml entry), with ENHSP's bisection.",
            "",
        ]
    out += [f"SMTPlan+: {doc['smtplan']}.", ""]
    return "\n".join(out)


def _jsonable(x):
    if isinstance(x, Fraction):
        return str(x)
    if isinstance(x, dict):
        return {k: _jsonable(v) for k, v in x.items() if k not in ("plan", "final_state")}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, float):
        return round(x, 4)
    return x


# ====================================================================== CLI


def byte_compile() -> None:
    """Byte-compile catc's packages first, as ``pip install .`` does, so that the catc
    processes' start-up matches an installed catc whatever PYTHONDONTWRITEBYTECODE says."""
    import importlib

    dirs = []
    for name in ("catc", "catgrammar", "stdlib_domains"):
        try:
            mod = importlib.import_module(name)
        except ImportError:
            continue
        if getattr(mod, "__file__", None):
            dirs.append(str(Path(mod.__file__).parent))
    if dirs:
        subprocess.run([sys.executable, "-m", "compileall", "-q", *dirs], capture_output=True, check=False)


def default_examples() -> Path:
    return Path(__file__).resolve().parents[3] / "examples"


@click.command(name="bench")
@click.option(
    "--runs", "-n", type=click.IntRange(min=1), default=5, show_default=True, help="Trials per problem (interleaved)."
)
@click.option(
    "--quick",
    is_flag=True,
    help="A small subset: detection, GPU max-confidence, lifelong budget cut; two perturbations.",
)
@click.option(
    "--only",
    "only",
    multiple=True,
    metavar="TEXT",
    help="Keep the problems whose path contains TEXT (repeatable), e.g. --only gpu --only detection.",
)
@click.option(
    "--table",
    "tables",
    multiple=True,
    type=click.Choice(TABLES),
    help="Print only these tables (repeatable; default all).",
)
@click.option(
    "--timeout",
    type=click.FloatRange(min=0, min_open=True),
    default=120.0,
    show_default=True,
    help="Seconds per tool run.",
)
@click.option(
    "--examples",
    "examples_dir",
    type=click.Path(file_okay=False),
    help="The examples folder (default: the checkout's).",
)
@click.option("--json", "as_json", is_flag=True, help="Print a catc.bench/1 JSON document instead of Markdown.")
@click.option(
    "--no-compile", is_flag=True, help="Do not byte-compile catc first (by default it is, as `pip install .` does)."
)
@click.option(
    "--save-json", "save_json", type=click.Path(dir_okay=False), help="Also write the JSON document to this file."
)
@click.option(
    "--keep", "keep_dir", type=click.Path(file_okay=False), help="Keep the exported PDDL files in this folder."
)
def bench_command(runs, quick, only, tables, timeout, examples_dir, as_json, no_compile, save_json, keep_dir) -> None:
    """Run catc and ENHSP on the same example problems and print the comparison tables.

    Needs the baselines extra (up-enhsp) and Java 17.  Markers are judged against the
    examples' expect.toml.
    """
    from catc.targets.enhsp import BaselineMissing, enhsp_jar, java
    from catc.targets.pddl import ExportError

    try:
        java()
        enhsp_jar()
    except BaselineMissing as exc:
        click.echo(f"error: {exc}", err=True)
        sys.exit(EXIT_INPUT)
    examples = Path(examples_dir) if examples_dir else default_examples()
    if not examples.is_dir():
        click.echo(f"error: examples folder not found: {examples} (pass --examples DIR)", err=True)
        sys.exit(EXIT_INPUT)
    tables = tuple(tables) or TABLES
    if not no_compile:
        byte_compile()

    def keep(f: str) -> bool:
        return not only or any(t in f for t in only)

    rt_files = [f for f in (QUICK_RUNTIME_ROWS if quick else RUNTIME_ROWS) if keep(f)]
    perts = [p for p in PERTURBATIONS if (not quick or p[0] in QUICK_PERTURBATIONS) and (keep(p[1]) or keep(p[2]))]
    want_q = "queries" in tables and keep("lifelong/budget-cut.cat")
    measure = list(rt_files) if "runtimes" in tables else []
    if "perturbations" in tables:
        measure += [t for _, b, t in perts for t in (b, t) if t not in measure]
    argv = (
        ["catc", "bench"] + sys.argv[2:]
        if len(sys.argv) > 1 and sys.argv[1] == "bench"
        else ["catc", "bench", f"--runs {runs}"]
    )
    command = " ".join(shlex.quote(a) if " " not in a else a for a in argv)

    def log(msg: str) -> None:
        click.echo(f"[bench] {msg}", err=True)

    tmp = None
    if keep_dir:
        work = Path(keep_dir)
        work.mkdir(parents=True, exist_ok=True)
    else:
        tmp = tempfile.TemporaryDirectory(prefix="catc-bench-")
        work = Path(tmp.name)
    try:
        bench = Bench(examples, runs, timeout, work, log)
        try:
            bench.measure(measure)
            doc = {
                "schema": "catc.bench/1",
                "command": command,
                "machine": machine(),
                "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
                "runs": runs,
                "smtplan": bench.smtplan or "not installed",
                "runtimes": bench.runtime_rows(rt_files) if "runtimes" in tables else None,
                "perturbations": bench.perturbation_rows(perts) if "perturbations" in tables else None,
                "queries": bench.queries(include_sar=not quick and keep("search-and-rescue/budget-cut.cat"))
                if want_q
                else None,
            }
        except (BenchInputError, ExportError, OSError) as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(EXIT_INPUT)
        except BaselineMissing as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(EXIT_INPUT)
    finally:
        if tmp is not None:
            tmp.cleanup()
    text = json.dumps(_jsonable(doc), indent=1, ensure_ascii=False)
    if save_json:
        Path(save_json).write_text(text + "\n")
    if as_json:
        click.echo(text)
    else:
        click.echo(markdown(doc))
