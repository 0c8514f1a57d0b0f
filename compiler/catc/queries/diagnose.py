"""diagnose: why there is no composition — an irreducible set of conflicting source constructs.

An irreducible unsatisfiable subset (paper eq. diagnose) of the labelled constructs
(:mod:`catc.smt.labelled`), shrunk by deletion until dropping any one member restores
feasibility.  ``all_cores`` explores further cores by excluding a member of each core found
(a hitting-set tree), bounded by count and time.

Most tests of a subset are settled without the solver: the relaxed reachability analysis
(:mod:`catc.semantics.relaxed`) proves many subsets infeasible in milliseconds, so a core
it can see is found by QuickXplain over the relaxation (Junker 2004: divide and conquer,
O(k log n) tests for a core of k among n) and the solver is asked only what the relaxation
cannot answer — above all that each deletion is feasible, which is what makes the core
irreducible.  ``presolve=False`` asks the solver everything (docs/benchmarks.md compares).

Diagnoses are *relative to the composition* when the problem has ``(:deployed ...)`` (or one
is given): the components used are then fixed to exactly the deployed ones, so the core
names what stops that composition rather than the whole causal chain.
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from typing import Any

from catc import ir
from catc.ir.labels import label_index
from catc.present.console import Console, counted, escape
from catc.present.labels import describe, excerpts, label_json, where
from catc.present.values import timings_json
from catc.queries.base import (
    ExitCode,
    Kind,
    Option,
    Progress,
    Query,
    Result,
    Status,
    backend_option,
    certificate_option,
    diagram_artifact,
    json_option,
    presolve_option,
    timeout_option,
    unknown_why,
)
from catc.queries.cores import AbstractCores, QuickCores, quickxplain
from catc.semantics.horizon import horizon_of
from catc.semantics.relaxed import RelaxedAnalysis
from catc.semantics.witness import witnessed
from catc.smt.backend import DEFAULT_BACKEND, Check
from catc.smt.encoder import Encoder
from catc.smt.labelled import HORIZON, LabelledModel, _extended_horizon
from catgrammar import limits


class DiagnoseStatus(Status):
    UNSAT = "unsat", ExitCode.OK  # cores found
    SAT = "sat", ExitCode.FAIL  # feasible: nothing to diagnose
    UNKNOWN = "unknown", ExitCode.UNKNOWN


@dataclass
class Diagnosis(Result):
    query = "diagnose"
    status: DiagnoseStatus
    cores: list[list[str]] = field(default_factory=list)
    total: int = 0  # labelled constraints considered
    relative_to: tuple[str, ...] | None = None
    horizon: int = 0
    checks: int = 0  # solver calls
    relaxed: int = 0  # subsets the relaxation proved infeasible without the solver
    witnessed: int = 0  # subsets shown feasible by a composition the validator accepted
    complete: bool = True  # --all: the search ended (not cut by count or time)
    timings: dict[str, float] = field(default_factory=dict)
    reason: str | None = None  # why it stopped early: "max", "timeout", "interrupted" (or unknown)
    #: unknown: the best core so far — unsat (a least-consumption refutation), not shown irreducible
    best: list[str] | None = None


class _Tests:
    """Infeasibility tests of label subsets: the relaxation first (when on), then the solver."""

    def __init__(self, model: LabelledModel, presolve: bool, quick: QuickCores | None = None) -> None:
        self.model = model
        self.quick = quick  # the h_max bound's tests, when there is no composition (issue 24)
        self.presolve = presolve
        self.components = model.components
        self.relaxed = 0  # subsets the relaxed analysis refuted
        self.witnessed = 0  # subsets a composition the validator accepted showed feasible
        self._analyses: dict[frozenset[str], RelaxedAnalysis] = {}
        self.abstract = AbstractCores(model)  # catalog-scale conflicts (issue 24)

    def refuted(self, labels: list[str]) -> bool:
        """The relaxed analysis proves ``labels`` infeasible (never a solver call)."""
        if not self.presolve:
            return False
        hit = self._analysis(labels).refutation is not None
        self.relaxed += hit
        return hit

    def _analysis(self, labels: list[str]) -> RelaxedAnalysis:
        """The relaxed fixpoint of ``labels`` (once per subset: the refutation and the
        witness's firing order both come from it)."""
        key = frozenset(labels)
        found = self._analyses.get(key)
        if found is None:
            limits.check_time("diagnosing")
            found = self._analyses[key] = RelaxedAnalysis(self.model.inst, key, self.components)
        return found

    def check(self, labels: list[str]) -> tuple[Check, list[str]]:
        if self.refuted(labels):
            return Check.UNSAT, labels
        if self.quick is not None and self.quick.bound.refuted(labels):
            return Check.UNSAT, labels
        if self.quick is not None and self.quick.feasible(labels):
            self.witnessed += 1
            return Check.SAT, []
        if self.presolve and (found := self.abstract.core(labels)) is not None:
            return Check.UNSAT, found
        if self.presolve and self.abstract.witnessed(labels, self.model.k, self.model.extended):
            self.witnessed += 1
            return Check.SAT, []
        if self.presolve and self._witnessed(labels):
            return Check.SAT, []
        return self.model.check(labels, _remaining(None))

    def _witnessed(self, labels: list[str]) -> bool:
        """A composition satisfying exactly ``labels``, accepted by the validator (no solver)."""
        limits.check_time("diagnosing")
        model, order = self.model, list(self._analysis(labels).fired)
        found = witnessed(model.inst, frozenset(labels), self.components, model.k, model.extended, order)
        self.witnessed += found
        return found

    def core(self, labels: list[str]) -> tuple[Check, list[str]]:
        """Whether ``labels`` are infeasible, with a core: QuickXplain over the relaxation
        when it refutes them (a core irreducible for the relaxation), else the solver's."""
        if not self.refuted(labels):
            if self.presolve and (found := self.abstract.core(labels)) is not None:
                return Check.UNSAT, found
            return self.model.check(labels, _remaining(None))
        return Check.UNSAT, quickxplain(labels, self.refuted)


def _shrink(tests: _Tests, core: list[str]) -> list[str] | None:
    """Deletion-based minimisation of an unsat core to an irreducible one: a member stays
    only when the solver finds the core without it feasible."""
    core = list(core)
    i = 0
    while i < len(core):
        trial = core[:i] + core[i + 1 :]
        r, smaller = tests.check(trial)
        if r is Check.UNSAT:
            keep = set(smaller)
            core = [l for l in trial if l in keep]
        elif r is Check.SAT:
            i += 1
        else:
            return None
    return core


def _remaining(deadline: float | None) -> float | None:
    """Time for the next check: up to the command's time limit (1 ms once interrupted)."""
    return limits.for_check(deadline)


def diagnose(
    inst: ir.Instance,  # relative_to: None = the problem's (:deployed ...); () = no composition
    *,
    horizon: int | None = None,
    sequential: bool = False,
    relative_to: Iterable[str] | None = None,
    all_cores: bool = False,
    max_cores: int = 5,
    timeout: float | None = None,
    progress: Progress | None = None,
    backend: str = DEFAULT_BACKEND,
    presolve: bool = True,
) -> Diagnosis:
    start = time.perf_counter()
    with limits.deadline(timeout):
        k = horizon_of(inst, horizon)
        components = (tuple(relative_to) or None) if relative_to is not None else (inst.problem.deployed or None)
        result = Diagnosis(DiagnoseStatus.UNKNOWN, relative_to=components, horizon=k)
        say = progress or (lambda message: None)
        start_core = None
        try:
            quick = None
            if presolve and components is None and not all_cores:  # the whole catalog (issue 24)
                quick, start_core = _quick(inst, k, result, say)
                if result.cores:
                    result.timings["total"] = time.perf_counter() - start
                    return result
            model = LabelledModel(inst, k, sequential=sequential, components=components, backend=backend)
            result.total = len(model.labels)
            result.timings["encode"] = time.perf_counter() - start
            tests = _Tests(model, presolve, quick)
            _cores(tests, result, max_cores if all_cores else 1, all_cores, say, start_core)
            result.checks, result.relaxed, result.witnessed = model.checks, tests.relaxed, tests.witnessed
        except limits.Stopped as stop:  # encoding when the time ran out
            result.complete, result.reason = False, stop.reason
        if result.status is DiagnoseStatus.UNKNOWN and start_core is not None:
            result.best = start_core
    result.timings["total"] = time.perf_counter() - start
    return result


def _quick(inst: ir.Instance, k: int, result: Diagnosis, say: Progress) -> tuple[QuickCores, list[str] | None]:
    """diagnose of the whole catalog without encoding it (issue 24): a core the h_max
    least-consumption bound refutes, shrunk by QuickXplain over the bound, each member shown
    needed by a composition the validator accepts (:class:`~catc.queries.cores.QuickCores`).
    Done, it is ``result``'s core; else the core to start the shrink from (None: the bound
    does not refute the problem)."""
    extended = _extended_horizon(inst, k)
    labels = [label for label in label_index(inst, k) if label != HORIZON or extended > k]
    # in the labelled model's order (its first step's), so that cores come out as they would there
    enc = Encoder(inst, 1, track=True)
    enc.unroll(1)
    first = [label for label, _ in enc.script.asserts if label is not None] + list(enc.indicators)
    position = {label: i for i, label in enumerate(dict.fromkeys(first))}
    labels.sort(key=lambda label: position.get(label, len(position)))
    quick = QuickCores(inst, k, extended)
    result.total = len(labels)
    say(f"checking {len(labels)} requirements together (least-consumption bound)")
    core = quick.core(labels)
    if core is None:
        return quick, None
    say(f"showing each of the {len(core)} requirements of a core needed")
    if quick.irreducible(core):
        result.cores, result.status = [core], DiagnoseStatus.UNSAT
        result.relaxed, result.witnessed = quick.bound.tests, quick.witnessed
        result.timings["encode"] = 0.0
    return quick, core


def _why_unknown(model: LabelledModel) -> str:
    """Why a check answered unknown: "interrupted", "timeout" — also when the solver's own
    timer, set to the time left, fired just before the command's clock said so (issue 28:
    the answer had no reason then) — or the solver's reason."""
    why = limits.stop_reason()
    if why is not None:
        return why
    solver = model.backend.reason_unknown()
    if limits.deadline_at() is not None and solver in ("timeout", "canceled"):
        return "timeout"
    return solver or "unknown"


def _cores(
    tests: _Tests, result: Diagnosis, wanted: int, all_cores: bool, say: Progress, start: list[str] | None = None
) -> None:
    """Irreducible cores, up to ``wanted``: a hitting-set tree, where every further core must
    avoid one member of each core found.  ``start``: a core of every label, known already."""
    labels = tests.model.labels
    say(f"checking {len(labels)} requirements together")
    known = set(tests.model.labels)
    if start is not None and known.issuperset(start):
        r, core = Check.UNSAT, start
    else:
        r, core = tests.core(labels)
    if r is not Check.UNSAT:
        result.status = DiagnoseStatus.SAT if r is Check.SAT else DiagnoseStatus.UNKNOWN
        result.reason = None if r is Check.SAT else _why_unknown(tests.model)
        return
    found: list[list[str]] = []
    frontier: list[frozenset[str]] = [frozenset()]
    seen: set[frozenset[str]] = set()
    while frontier and len(found) < wanted:
        if limits.expired():
            result.complete, result.reason = False, limits.stop_reason()
            break
        excluded = frontier.pop(0)
        if excluded in seen:
            continue
        seen.add(excluded)
        if excluded:  # the root is the whole set, checked above: its core is at hand
            r, core = tests.core([l for l in labels if l not in excluded])
            if r is not Check.UNSAT:
                continue
        say(f"{len(found)} core(s) found; shrinking a core of {len(core)} requirements")
        mus = _shrink(tests, core)
        if mus is None:
            result.complete, result.reason = False, _why_unknown(tests.model)
            break
        if sorted(mus) not in [sorted(c) for c in found]:
            found.append(mus)
        frontier.extend(excluded | {x} for x in mus)
    if all_cores and frontier and len(found) >= wanted:
        result.complete, result.reason = False, "max"
    result.cores = found
    result.status = DiagnoseStatus.UNSAT if found else DiagnoseStatus.UNKNOWN


# ====================================================================== output


def diagnosis_json(inst: ir.Instance, diag: Diagnosis) -> dict:
    index = label_index(inst, diag.horizon or None)
    doc = {
        "schema": "catc.diagnose/1",
        "status": diag.status.value,
        "problem": inst.problem.name,
        "horizon": diag.horizon,
        "total": diag.total,
        "relative_to": list(diag.relative_to) if diag.relative_to else None,
        "cores": [[label_json(index[label]) for label in core] for core in diag.cores],
        "complete": diag.complete,
        "timings": timings_json(diag.timings),
    }
    if diag.reason is not None:  # why the search stopped early
        doc["reason"] = diag.reason
    if diag.best is not None:  # unknown: the best core so far (unsat, not shown irreducible)
        doc["best_core"] = [label_json(index[label]) for label in diag.best]
    return doc


def render(console: Console, inst: ir.Instance, diag: Diagnosis, options: Mapping[str, Any] | None = None) -> None:
    _render_answer(console, inst, diag)
    t = diag.timings
    console.print(
        f"[dim]time: encode {t.get('encode', 0) * 1000:.0f} ms, "
        f"cores {(t.get('total', 0) - t.get('encode', 0)) * 1000:.0f} ms[/]"
    )


def _render_answer(console: Console, inst: ir.Instance, diag: Diagnosis) -> None:
    if diag.status is DiagnoseStatus.SAT:
        console.print(
            f"[bold green]SAT[/]  nothing to diagnose: a composition exists within {counted(diag.horizon, 'step')}"
        )
        return
    if diag.status is not DiagnoseStatus.UNSAT:
        why = "interrupted" if diag.reason == "interrupted" else unknown_why(diag.reason)
        if diag.best is None:
            console.print(f"[bold yellow]UNKNOWN[/]  {why} before finding a core")
            return
        console.print(
            f"[bold yellow]UNKNOWN[/]  {why} before showing a core irreducible; the best so far, "
            f"{len(diag.best)} of {diag.total} labelled constraints, conflict (a least-consumption bound):"
        )
        index = label_index(inst, diag.horizon or None)
        for i, label in enumerate(diag.best, 1):
            console.print(f"  {i}. {escape(describe(index[label]))}")
            console.print(f"     {escape(where(index[label]))}")
        return
    index, excerpt = label_index(inst, diag.horizon or None), excerpts()
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
            console.print(f"  {i}. {escape(describe(info))}")
            console.print(f"     {escape(where(info))}")
            for line in excerpt(info.span):
                console.print("     " + escape(line))
    if len(diag.cores) > 1 or not diag.complete:
        more = "" if diag.complete else f" ({_STOPPED.get(diag.reason or '', 'search stopped')}; more may exist)"
        console.print(f"{len(diag.cores)} distinct core{'s' if len(diag.cores) != 1 else ''}{more}")


_STOPPED = {
    "max": "search stopped by --max",
    "timeout": "search stopped by the time limit",
    "interrupted": "interrupted",
}


QUERY = Query(
    "diagnose",
    summary="Explain infeasibility: an irreducible set of conflicting source constructs.",
    description=(
        "Exit 0 when a core is found, 1 when the problem is feasible (nothing to diagnose), 2 input error, 3 unknown."
    ),
    options=(
        Option(
            "relative_to",
            ("--relative-to",),
            Kind.COMPONENTS,
            "Diagnose relative to this composition (comma-separated morphisms; default: the problem's "
            "(:deployed ...); 'none' for none).",
            metavar="COMPONENTS",
            none_word="none",
        ),
        Option(
            "all_cores",
            ("--all",),
            Kind.FLAG,
            "Enumerate several distinct cores (bounded by --max and --timeout).",
            default=False,
        ),
        Option("max_cores", ("--max",), Kind.POSITIVE, "The most cores --all reports.", default=5, show_default=True),
        timeout_option("Stop after this many seconds (exit 3 when no core is found by then)."),
        json_option("catc.diagnose/1"),
        backend_option(),
        presolve_option(),
        certificate_option(),
    ),
    run=diagnose,
    to_json=diagnosis_json,
    render=render,
    artifacts=diagram_artifact,
    progress=True,
)
