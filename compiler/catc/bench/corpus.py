"""``catc bench --corpus wheel``: PDDL problems nobody here wrote, imported and solved by catc beside ENHSP.

The corpus is the PDDL shipped inside unified-planning's wheel (``unified_planning/test/pddl``)
plus two generated families for growth with instance size: *counters* (n counters that must end
strictly increasing, IPC numeric style; the shortest plan has n(n-1)/2 actions) and *sailing*
(one boat, p persons to save at fixed distances). For each problem:

1. ``catc import pddl`` (:func:`catc.interfaces.import_cli.import_pddl`) — imported, or refused
   with the reasons of its import report;
2. ENHSP (``sat-hadd``) on the original PDDL, then catc ``solve --sequential --strategy search``
   (the UP engine's route: the forward search where it applies, greedy then A* for the shortest
   plan; the SMT search elsewhere) on the imported ``.cat`` with ENHSP's plan length as the horizon (:data:`CAP` when
   ENHSP found none: then catc's UNSAT means "none within CAP steps" unless its relaxed
   reachability proves more);
3. where the PDDL has a metric: ENHSP ``opt-blind`` for the optimal cost, then catc
   ``optimize --sequential`` with the optimal plan's length as the horizon (enough: no plan is
   cheaper than a proven optimum, and one that cheap has that many steps);
4. every plan (ENHSP's and catc's) checked by unified-planning's sequential plan validator on
   the problem UP's reader read from the original PDDL — a validator catc did not write;
5. the round trip: ``catc export pddl`` of the imported instance, solved again by ENHSP.

Agreement: both SAT or both UNSAT; where both optimise, the same cost; catc's plan (the
shortest, sequential) no longer than ENHSP's — unless the time ran out before A* proved the
greedy plan shortest.
"""

from __future__ import annotations

import itertools
import os
import re
import time
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

CAP = 30  # the horizon when ENHSP found no plan

_STEP = re.compile(r"^\s*\d+(?:\.\d+)?\s*:\s*(\([^()]*\))", re.MULTILINE)


@dataclass
class Case:
    family: str
    name: str
    domain: Path
    problem: Path
    size: int | None = None  # the family's size parameter (counters: n; sailing: persons)

    @property
    def temporal(self) -> bool:
        text = self.domain.read_text(encoding="utf-8", errors="replace").lower()
        return ":durative-action" in text


@dataclass
class Row:
    case: Case
    imported: bool = False
    refused: list[tuple[str, str]] = field(default_factory=list)
    error: str | None = None
    morphisms: int | None = None
    metric: str | None = None
    enhsp: str = "-"  # sat | unsat | timeout | error
    enhsp_cost: Fraction | None = None
    enhsp_len: int | None = None
    enhsp_time: float | None = None
    enhsp_valid: bool | None = None
    catc: str = "-"
    catc_cost: Fraction | None = None
    catc_len: int | None = None
    catc_shortest: bool = True  # False: the forward search's greedy plan, not proven shortest
    catc_time: float | None = None
    catc_valid: bool | None = None
    roundtrip: str = "-"
    roundtrip_cost: Fraction | None = None
    roundtrip_valid: bool | None = None  # UP's validator on ENHSP's plan for the exported PDDL
    par: str = "-"  # catc with parallel steps (no --sequential), its plan linearised step by step
    par_steps: int | None = None
    par_len: int | None = None
    par_time: float | None = None
    par_valid: bool | None = None
    lpg: str = "-"  # LPG through up-lpg, where it is installed: solved | unsolvable | error | timeout
    lpg_len: int | None = None
    lpg_time: float | None = None
    lpg_valid: bool | None = None

    @property
    def agrees(self) -> bool | None:
        """None when there is nothing to compare (refused, or every catc run or ENHSP gave up).
        catc's sequential and parallel answers must both match ENHSP's where given, every plan
        must be valid, an optimal cost found by both must be equal, catc's shortest plan no
        longer than ENHSP's, and the round trip (where the export is whole) the same."""
        if not self.imported or self.enhsp not in ("sat", "unsat"):
            return None
        answers = [a for a in (self.catc, self.par) if a in ("sat", "unsat")]
        if not answers:
            return None
        valid = (self.catc_valid, self.par_valid, self.enhsp_valid, self.roundtrip_valid)
        if any(a != self.enhsp for a in answers) or False in valid:
            return False
        if self.enhsp == "sat":
            both_costs = None not in (self.enhsp_cost, self.catc_cost)
            if self.metric is not None and both_costs and self.catc_cost != self.enhsp_cost:
                return False
            longer = (self.catc_len or 0) > (self.enhsp_len or 0)
            if self.metric is None and self.catc == "sat" and self.catc_shortest and longer:
                return False
        if self.roundtrip not in ("sat", "unsat"):
            return True
        same_cost = None in (self.roundtrip_cost, self.enhsp_cost) or self.roundtrip_cost == self.enhsp_cost
        return self.roundtrip == self.enhsp and same_cost


def wheel_dir() -> Path | None:
    """``unified_planning/test/pddl`` of the installed wheel, or None."""
    try:
        import unified_planning
    except ImportError:
        return None
    d = Path(os.path.dirname(unified_planning.__file__)) / "test" / "pddl"
    return d if d.is_dir() else None


def wheel_cases() -> list[Case]:
    """Every domain/problem pair shipped in unified-planning's wheel (temporal ones included)."""
    root = wheel_dir()
    if root is None:
        return []
    out = []
    for d in sorted(p for p in root.iterdir() if p.is_dir() and not p.name.startswith("__")):
        files = sorted(f for f in d.iterdir() if f.suffix in (".pddl", ".hddl"))
        doms = [f for f in files if f.stem in ("domain", "d")]
        if not doms:
            continue
        for prob in (f for f in files if f not in doms):
            name = d.name if prob.stem in ("problem", "p") else f"{d.name}/{prob.stem}"
            out.append(Case(d.name, name, doms[0], prob))
    return out


COUNTERS_DOMAIN = """(define (domain fn-counters)
  (:requirements :typing :numeric-fluents)
  (:types counter)
  (:functions (value ?c - counter) (max_int))
  (:action increment :parameters (?c - counter)
    :precondition (<= (+ (value ?c) 1) (max_int)) :effect (increase (value ?c) 1))
  (:action decrement :parameters (?c - counter)
    :precondition (>= (value ?c) 1) :effect (decrease (value ?c) 1)))
"""


def counters_problem(n: int) -> str:
    """n counters from 0, each below the next at the end; max_int = 2n (as the IPC instances)."""
    cs = [f"c{i}" for i in range(n)]
    init = " ".join(f"(= (value {c}) 0)" for c in cs)
    goal = " ".join(f"(<= (+ (value {a}) 1) (value {b}))" for a, b in itertools.pairwise(cs))
    return (
        f"(define (problem counters-{n}) (:domain fn-counters)\n  (:objects {' '.join(cs)} - counter)\n"
        f"  (:init (= (max_int) {2 * n}) {init})\n  (:goal (and {goal})))\n"
    )


def sailing_problem(persons: int) -> str:
    """One boat at the origin; person i at distance d = -(10 + 7 i) (UP's sailing domain)."""
    ps = [f"p{i}" for i in range(persons)]
    init = " ".join(f"(= (d {p}) {-(10 + 7 * i)})" for i, p in enumerate(ps))
    goal = " ".join(f"(saved {p})" for p in ps)
    return (
        f"(define (problem sailing-1-{persons}) (:domain sailing)\n  (:objects b0 - boat {' '.join(ps)} - person)\n"
        f"  (:init (= (x b0) 0) (= (y b0) 0) {init})\n  (:goal (and {goal})))\n"
    )


def family_cases(work: Path, counters: range = range(2, 7), sailing: range = range(1, 5)) -> list[Case]:
    """The generated families, written into ``work``."""
    root = wheel_dir()
    out = []
    fam = work / "families"
    fam.mkdir(parents=True, exist_ok=True)
    cdom = fam / "counters-domain.pddl"
    cdom.write_text(COUNTERS_DOMAIN)
    for n in counters:
        p = fam / f"counters-{n}.pddl"
        p.write_text(counters_problem(n))
        out.append(Case("counters", f"counters-{n}", cdom, p, n))
    if root is not None:
        for k in sailing:
            p = fam / f"sailing-1-{k}.pddl"
            p.write_text(sailing_problem(k))
            out.append(Case("sailing", f"sailing-1-{k}", root / "sailing" / "domain.pddl", p, k))
    return out


# ---------------------------------------------------------------- running one case


def _up_plan(up_problem: Any, steps: list[str]) -> Any:
    from unified_planning.io import PDDLReader

    return PDDLReader().parse_plan_string(up_problem, "\n".join(steps) + "\n")


def up_validates(up_problem: Any, steps: list[str]) -> bool:
    """unified-planning's sequential plan validator on the PDDL plan ``steps`` ("(a x y)")."""
    from unified_planning.engines import ValidationResultStatus
    from unified_planning.engines.plan_validator import SequentialPlanValidator
    from unified_planning.exceptions import UPUsageError

    plan = _up_plan(up_problem, steps)
    validator = SequentialPlanValidator(environment=up_problem.environment)
    try:
        res = validator.validate(up_problem, plan)
    except UPUsageError:
        # UP's validator declines problems of some kinds without looking (undefined initial
        # values: tpp_metric); its simulation still replays the plan, and an undefined value
        # the plan reads makes it fail, not pass
        validator.skip_checks = True
        res = validator.validate(up_problem, plan)
    return bool(res.status is ValidationResultStatus.VALID)


def _fraction(x: float | None) -> Fraction | None:
    return None if x is None else Fraction(str(x)).limit_denominator(10**6)


def run_case(case: Case, work: Path, timeout: float = 60.0, *, roundtrip: bool = True) -> Row:
    """Import, ENHSP, catc, the validator and the round trip for one case (see the module)."""
    from catc.interfaces.import_cli import ImportFailed, import_pddl
    from catc.targets.enhsp import run_enhsp

    row = Row(case)
    out = work / case.name.replace("/", "-")
    try:
        res = import_pddl(case.domain, case.problem, out)
    except ImportFailed as exc:
        row.refused = exc.refused or [(exc.code, exc.message)]
        row.error = f"{exc.code}: {exc.message}" if not exc.refused else None
        return row
    row.imported, row.morphisms, row.metric = True, len(res.instance.domain.morphisms), res.optimal_metric
    from unified_planning.io import PDDLReader

    up_problem = PDDLReader().parse_problem(str(case.domain), str(case.problem))
    en = run_enhsp(case.domain, case.problem, planner="sat-hadd", timeout=timeout)
    row.enhsp, row.enhsp_time = en.status, en.wall
    if en.status == "sat":
        steps = _steps(en.output)
        row.enhsp_len = len(steps)
        row.enhsp_valid = up_validates(up_problem, steps)
    _run_catc(row, res, up_problem, row.enhsp_len if row.enhsp_len is not None else CAP, timeout, optimise=False)
    _run_parallel(row, res, up_problem, row.enhsp_len if row.enhsp_len is not None else CAP, timeout)
    if row.metric is not None and row.enhsp == "sat":  # the optimum: ENHSP's opt-blind, then catc's
        opt = run_enhsp(case.domain, case.problem, planner="opt-blind", timeout=timeout)
        row.enhsp_time = (row.enhsp_time or 0) + opt.wall
        if opt.status == "sat":
            steps = _steps(opt.output)
            row.enhsp_cost = _fraction(opt.metric)
            row.enhsp_len = len(steps)
            row.enhsp_valid = bool(row.enhsp_valid) and up_validates(up_problem, steps)
            _run_catc(row, res, up_problem, len(steps), timeout, optimise=True)
    if roundtrip:
        _roundtrip(row, res, out, "opt-blind" if row.enhsp_cost is not None else "sat-hadd", timeout)
    _run_lpg(row, up_problem, timeout)
    return row


def lpg_available() -> bool:
    """Whether LPG (PyPI ``up-lpg``: a UP engine wrapping the LPG-td binary) is installed."""
    import importlib.util

    return importlib.util.find_spec("up_lpg") is not None


def _run_lpg(row: Row, up_problem: Any, timeout: float) -> None:
    """LPG on the problem UP read (a satisficing planner for numeric PDDL); its plan checked by
    UP's validator like the others."""
    if not lpg_available():
        return
    import warnings

    from unified_planning.engines import PlanGenerationResultStatus as S
    from unified_planning.shortcuts import OneshotPlanner

    factory = up_problem.environment.factory  # UP knows "lpg" by name once up-lpg is installed
    if "lpg" not in factory.engines:  # pragma: no cover - an older UP
        factory.add_engine("lpg", "up_lpg.lpg_planner", "LPGEngine")
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            with OneshotPlanner(name="lpg") as planner:
                res = planner.solve(up_problem, timeout=timeout)
    except Exception as exc:  # the engine refuses the problem's kind, or the binary fails
        row.lpg, row.lpg_time = f"error: {type(exc).__name__}", time.perf_counter() - start
        return
    row.lpg_time = time.perf_counter() - start
    solved = (S.SOLVED_SATISFICING, S.SOLVED_OPTIMALLY)
    row.lpg = {S.UNSOLVABLE_PROVEN: "unsat", S.TIMEOUT: "timeout"}.get(
        res.status, "sat" if res.status in solved else "error"
    )
    if res.plan is not None and res.status in solved:
        from unified_planning.engines import ValidationResultStatus
        from unified_planning.engines.plan_validator import SequentialPlanValidator

        row.lpg_len = len(res.plan.actions)
        check = SequentialPlanValidator(environment=up_problem.environment).validate(up_problem, res.plan)
        row.lpg_valid = check.status is ValidationResultStatus.VALID


def _steps(output: str) -> list[str]:
    return [s.lower() for s in _STEP.findall(output)]


def _run_catc(row: Row, res: Any, up_problem: Any, horizon: int, timeout: float, *, optimise: bool) -> None:
    """catc on the imported instance: ``solve --sequential`` (shortest plan) or, with
    ``optimise``, ``optimize --sequential``; its plan checked by UP's validator."""
    from catc.queries.optimize import OptStatus, optimize
    from catc.queries.solve import SolveStatus, solve

    start = time.perf_counter()
    if optimise:
        o = optimize(res.instance, horizon=horizon, sequential=True, timeout=timeout)
        if o.status in (OptStatus.OPT, OptStatus.UNSAT) or row.catc not in ("sat", "unsat"):
            row.catc = {OptStatus.OPT: "sat", OptStatus.UNSAT: "unsat"}.get(o.status, o.status.value)
        plan = o.plan if o.status is OptStatus.OPT else None
        if plan is not None and o.values:
            row.catc_cost = o.values[0].value
    else:
        # the engine's route: forward search (greedy, then A* for the proof), SMT where it cannot
        s = solve(res.instance, horizon=horizon, sequential=True, timeout=timeout, strategy="search")
        row.catc_shortest = s.shortest
        row.catc = {SolveStatus.SAT: "sat", SolveStatus.UNSAT: "unsat"}.get(s.status, s.status.value)
        plan = s.plan if s.status is SolveStatus.SAT else None
    row.catc_time = (row.catc_time or 0) + time.perf_counter() - start
    if plan is not None:
        steps = [res.actions[a.morphism] for step in plan.steps for a in step]
        row.catc_len = len(steps)
        row.catc_valid = (row.catc_valid is not False) and up_validates(up_problem, steps)


def _run_parallel(row: Row, res: Any, up_problem: Any, horizon: int, timeout: float) -> None:
    """catc ``solve`` with parallel steps: a step's activations do not interfere (none reads or
    assigns what another writes), so any order of them is a sequential plan; the steps are
    written out in catc's order and UP's validator judges the sequence."""
    from catc.queries.solve import SolveStatus, solve

    start = time.perf_counter()
    s = solve(res.instance, horizon=horizon, sequential=False, timeout=timeout)
    row.par_time = time.perf_counter() - start
    row.par = {SolveStatus.SAT: "sat", SolveStatus.UNSAT: "unsat"}.get(s.status, s.status.value)
    if s.status is SolveStatus.SAT and s.plan is not None:
        steps = [res.actions[a.morphism] for step in s.plan.steps for a in step]
        row.par_steps = sum(1 for step in s.plan.steps if step)
        row.par_len = len(steps)
        row.par_valid = up_validates(up_problem, steps)


def _roundtrip(row: Row, res: Any, out: Path, planner: str, timeout: float) -> None:
    from catc.targets.enhsp import run_enhsp
    from catc.targets.pddl import ExportError, export_pddl

    try:
        ex = export_pddl(res.instance)
    except ExportError as exc:
        row.roundtrip = f"export refused: {exc}"
        return
    lossy = [t for c, t in ex.report.items if c == "components"]
    if lossy:  # a partial domain: ENHSP's answer on it is not the problem's answer
        row.roundtrip = f"not comparable: the export leaves out {len(lossy)} morphisms ({lossy[0].split(': ', 1)[-1]})"
        return
    d = out / "export"
    d.mkdir(exist_ok=True)
    (d / "domain.pddl").write_text(ex.domain)
    (d / "problem.pddl").write_text(ex.problem)
    en = run_enhsp(d / "domain.pddl", d / "problem.pddl", planner=planner, timeout=timeout)
    row.roundtrip = en.status
    if en.status == "sat" and planner == "opt-blind":  # an optimum, comparable with the original's
        row.roundtrip_cost = _fraction(en.metric)
    if en.status == "sat":  # ENHSP's plan for catc's export, checked by UP on the exported files
        from unified_planning.io import PDDLReader

        exported = PDDLReader().parse_problem(str(d / "domain.pddl"), str(d / "problem.pddl"))
        row.roundtrip_valid = up_validates(exported, _steps(en.output))


# ---------------------------------------------------------------- the table


def _num(x: Fraction | None) -> str:
    if x is None:
        return "-"
    return str(x.numerator) if x.denominator == 1 else f"{float(x):.4g}"


def _t(x: float | None) -> str:
    return "-" if x is None else f"{x:.2f}"


def _ok(x: bool | None) -> str:
    return "-" if x is None else ("valid" if x else "INVALID")


def markdown(rows: list[Row], command: str) -> str:
    lines = [f"Produced by `{command}`.", ""]
    lpg = any(r.lpg != "-" for r in rows)
    lines.append(
        "| problem | import | morphisms | metric | ENHSP | cost/len | s | UP validator | catc | cost/len | s | "
        "UP validator | catc parallel steps/len/s/validator | round trip (ENHSP on catc's export) | agree |"
        + (" LPG (up-lpg) len/s/validator |" if lpg else "")
    )
    lines.append("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|" + ("---|" if lpg else ""))
    for r in rows:
        if not r.imported:
            why = "; ".join(w for w, _ in r.refused)
            lines.append(f"| {r.case.name} | refused: {why} | | | | | | | | | | | | | |" + (" |" if lpg else ""))
            continue
        ec = f"{_num(r.enhsp_cost)}/{r.enhsp_len}" if r.enhsp_len is not None else "-"
        cc = f"{_num(r.catc_cost)}/{r.catc_len}" if r.catc_len is not None else "-"
        rt = r.roundtrip + (f" {_num(r.roundtrip_cost)}" if r.roundtrip_cost is not None else "")
        rt += f" ({_ok(r.roundtrip_valid)})" if r.roundtrip_valid is not None else ""
        agree = {None: "-", True: "yes", False: "NO"}[r.agrees]
        par = r.par
        if r.par_len is not None:
            par += f" {r.par_steps}/{r.par_len}/{_t(r.par_time)}/{_ok(r.par_valid)}"
        elif r.par_time is not None:
            par += f" -/-/{_t(r.par_time)}/-"
        lines.append(
            f"| {r.case.name} | ok | {r.morphisms} | {r.metric or '-'} | {r.enhsp} | {ec} | {_t(r.enhsp_time)} | "
            f"{_ok(r.enhsp_valid)} | {r.catc} | {cc} | {_t(r.catc_time)} | {_ok(r.catc_valid)} | {par} | {rt} | {agree} |"
            + (
                f" {r.lpg} {r.lpg_len if r.lpg_len is not None else '-'}/{_t(r.lpg_time)}/{_ok(r.lpg_valid)} |"
                if lpg
                else ""
            )
        )
    return "\n".join(lines) + "\n"


def growth_markdown(rows: list[Row]) -> str:
    """Runtime against the family's size parameter (counters: n; sailing: persons)."""
    lines = [
        "| family | size | morphisms | plan length (catc/ENHSP) | catc s | catc parallel steps/len | catc parallel s | ENHSP s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        if r.case.size is None or not r.imported:
            continue
        lines.append(
            f"| {r.case.family} | {r.case.size} | {r.morphisms} | {r.catc_len if r.catc_len is not None else '-'}/"
            f"{r.enhsp_len if r.enhsp_len is not None else '-'} | {_t(r.catc_time)} | "
            f"{r.par_steps if r.par_steps is not None else '-'}/{r.par_len if r.par_len is not None else '-'} | "
            f"{_t(r.par_time)} | {_t(r.enhsp_time)} |"
        )
    return "\n".join(lines) + "\n"


def run_corpus(
    work: Path,
    timeout: float,
    only: tuple[str, ...] = (),
    *,
    families: bool = True,
    log: Any = None,
) -> tuple[list[Row], str]:
    """Every case of the wheel (temporal ones too: they are refused, by kind) and the families;
    the rows and the Markdown (the corpus table, then growth with size)."""
    import shlex
    import sys

    cases = wheel_cases() + (family_cases(work) if families else [])
    cases = [c for c in cases if not only or any(t in c.name for t in only)]
    rows = []
    for c in cases:
        if log is not None:
            log(f"corpus: {c.name}")
        rows.append(run_case(c, work, timeout))
    argv = (
        ["catc", "bench"] + sys.argv[2:]
        if len(sys.argv) > 1 and sys.argv[1] == "bench"
        else ["catc", "bench", "--corpus"]
    )
    command = " ".join(shlex.quote(a) for a in argv)
    text = "## The PDDL corpus\n\n" + markdown(rows, command)
    if any(r.case.size is not None for r in rows):
        text += "\n## Growth with instance size\n\n" + growth_markdown(rows)
    return rows, text
