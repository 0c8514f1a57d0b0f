"""The lifelong-queries table: catc's diagnose, relax and recompose beside what ENHSP can do
instead — one unsolvable run for diagnose, a bisection over the initial budget for relax, a
plan whose churn catc computes for recompose."""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from catc.bench.problems import (
    LIFELONG_BUDGET_CUT,
    LIFELONG_CHEAPER_CAMERA,
    SAR_BUDGET_CUT,
    Expected,
    expected_for,
)
from catc.bench.runners import Loaded, ToolRun, churn_of, enhsp_run, run_catc
from catc.bench.session import Bench
from catc.bench.stats import consensus, fraction_text, judge, marker


@dataclass
class _Trials:
    """The runs of every trial, by tool and query."""

    diagnose: list[ToolRun] = field(default_factory=list)
    relax: list[ToolRun] = field(default_factory=list)  # relative to the deployed composition
    relax_none: list[ToolRun] = field(default_factory=list)  # of the whole problem
    recompose_stability: list[ToolRun] = field(default_factory=list)
    recompose_objective: list[ToolRun] = field(default_factory=list)
    enhsp_unsat: list[ToolRun] = field(default_factory=list)
    enhsp_bisect: list[dict[str, Any]] = field(default_factory=list)
    enhsp_recompose: list[ToolRun] = field(default_factory=list)


def query_rows(bench: Bench, include_sar: bool) -> list[dict[str, Any]]:
    """The rows of the lifelong-queries table (the search-and-rescue diagnose row with ``include_sar``)."""
    lf, cc = LIFELONG_BUDGET_CUT, LIFELONG_CHEAPER_CAMERA
    exp_bc = expected_for(bench.examples, lf)
    exp_cc = expected_for(bench.examples, cc)
    lb, lc = bench.load(lf), bench.load(cc)
    t = _run_trials(bench, lb, lc)
    rows = [diagnose_row(lf, t.diagnose, t.enhsp_unsat, exp_bc)]
    rows += _relax_rows(lf, t, exp_bc)
    rows += _recompose_rows(cc, t, exp_cc, lc)
    if include_sar:
        rows.append(_sar_diagnose_row(bench))
    return rows


def _run_trials(bench: Bench, lb: Loaded, lc: Loaded) -> _Trials:
    lf, cc = bench.examples / LIFELONG_BUDGET_CUT, bench.examples / LIFELONG_CHEAPER_CAMERA
    t = _Trials()
    for trial in range(bench.runs):
        bench.log(f"queries trial {trial + 1}/{bench.runs}")
        t.diagnose.append(run_catc(lf, "diagnose", (), bench.timeout))
        t.enhsp_unsat.append(enhsp_run(lb, "sat-hadd", bench.timeout))
        t.relax.append(run_catc(lf, "relax", (), bench.timeout))
        t.relax_none.append(run_catc(lf, "relax", ("--relative-to", "none"), bench.timeout))
        t.enhsp_bisect.append(bisect_budget(lb, bench.timeout))
        t.recompose_stability.append(run_catc(cc, "recompose", ("--priority", "stability"), bench.timeout))
        t.recompose_objective.append(run_catc(cc, "recompose", ("--priority", "objective"), bench.timeout))
        t.enhsp_recompose.append(enhsp_run(lc, "opt-hrmax", bench.timeout, value_of=churn_of))
    return t


def diagnose_row(
    problem: str, catc_runs: Sequence[ToolRun], enhsp_runs: Sequence[ToolRun], exp: Expected
) -> dict[str, Any]:
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


def _sar_diagnose_row(bench: Bench) -> dict[str, Any]:
    sf = SAR_BUDGET_CUT
    ls = bench.load(sf)
    sd, se = [], []
    for trial in range(bench.runs):
        bench.log(f"queries (SAR) trial {trial + 1}/{bench.runs}")
        sd.append(run_catc(bench.examples / sf, "diagnose", (), bench.timeout))
        se.append(enhsp_run(ls, "sat-hadd", bench.timeout))
    return diagnose_row(sf, sd, se, expected_for(bench.examples, sf))


# ---------------------------------------------------------------- relax


def _relax_rows(problem: str, t: _Trials, exp: Expected) -> list[dict[str, Any]]:
    """catc relative to the deployed composition (expect.toml), and of the whole problem
    (--relative-to none), which is what ENHSP's bisection can answer."""
    want = {k: Fraction(v) for k, v in exp.case.get("relax", {}).items()}
    b0 = t.enhsp_bisect[0]
    found = None if b0.get("found") is None else Fraction(b0["found"])
    deployed, whole = _relaxations(t.relax), _relaxations(t.relax_none)
    cannot = {
        "answer": "cannot express the deployed composition (not exported); see the next row",
        "calls": 0,
        "wall": [],
    }
    bisection = {
        "answer": b0["answer"],
        "calls": b0["calls"],
        "wall": [b["total"] for b in t.enhsp_bisect],
        "found": b0.get("found"),
        "tolerance": b0.get("tolerance"),
    }
    # no expect.toml entry for the whole problem: the tools are compared with each other
    whole_agrees = found is not None and whole.get("init/budget") == found
    return [
        _relax_row(
            "relax (relative to the deployed composition)", problem, t.relax, deployed, deployed == want, cannot
        ),
        _relax_row("relax (whole problem, --relative-to none)", problem, t.relax_none, whole, whole_agrees, bisection),
    ]


def _relaxations(runs: Sequence[ToolRun]) -> dict[str, Fraction]:
    return {x["label"]: Fraction(str(x["delta"])) for x in runs[0].detail.get("relaxations", [])}


def _relax_row(
    variant: str,
    problem: str,
    runs: Sequence[ToolRun],
    got: dict[str, Fraction],
    agrees: bool,
    enhsp: dict[str, Any],
) -> dict[str, Any]:
    return {
        "query": variant,
        "problem": problem,
        "catc": {
            "answer": ", ".join(f"{k} +{fraction_text(v)}" for k, v in got.items()) or runs[0].status,
            "agrees": agrees,
            "wall": [r.wall for r in runs],
        },
        "enhsp": enhsp,
    }


class _BudgetProbe:
    """ENHSP (sat-hadd) on the exported problem with the resource's initial value rewritten;
    counts the calls and their seconds."""

    def __init__(self, lb: Loaded, resource: str, pattern: re.Pattern[str], timeout: float) -> None:
        self.lb, self.resource, self.pattern, self.timeout = lb, resource, pattern, timeout
        self.dir = lb.dir.with_name(lb.dir.name + "-bisect")
        self.dir.mkdir(parents=True, exist_ok=True)
        self.calls = 0
        self.total = 0.0

    def solvable(self, value: Fraction) -> bool | None:
        from catc.targets.enhsp import run_enhsp
        from catc.targets.pddl import number, sanitize

        prob = self.dir / "problem.pddl"
        prob.write_text(
            self.pattern.sub(f"(= ({sanitize(self.resource)}) {number(value)})", self.lb.export.problem, count=1)
        )
        r = run_enhsp(self.lb.domain_file, prob, planner="sat-hadd", timeout=self.timeout)
        self.calls += 1
        self.total += r.wall
        return {"sat": True, "unsat": False}.get(r.status)

    def answer(self, text: str, **more: str) -> dict[str, Any]:
        return {"answer": text, "calls": self.calls, "total": self.total, **more}


def bisect_budget(
    lb: Loaded, timeout: float, resource: str = "budget", tolerance: Fraction = Fraction(1)
) -> dict[str, Any]:
    """ENHSP's workaround for relax: re-run it at candidate initial budgets (the problem
    text's init value rewritten), doubling until solvable, then bisecting to within
    ``tolerance``.  Returns calls, total seconds and the found least increase."""
    from catc.targets.pddl import sanitize

    fn = re.escape(sanitize(resource))
    pat = re.compile(rf"\(= \({fn}\) ([^()\s]+)\)")
    m = pat.search(lb.export.problem)
    if m is None:
        return {"answer": f"n/a (no init value of {resource} in the export)", "calls": 0, "total": 0.0}
    initial = Fraction(m.group(1))
    probe = _BudgetProbe(lb, resource, pat, timeout)
    first = probe.solvable(initial)
    if first is None:
        return probe.answer("ENHSP gave up")
    if first:
        return probe.answer("already solvable", found="0")
    lo, hi, why = _bracket(probe, initial)
    if hi is None:
        return probe.answer(why)
    narrowed = _bisect(probe, lo, hi, tolerance)
    if narrowed is None:
        return probe.answer("ENHSP gave up")
    lo, hi = narrowed
    found = hi - initial
    return probe.answer(
        f"{resource} +{fraction_text(found)} (least solvable within {fraction_text(tolerance)}: "
        f"{fraction_text(lo)} unsolvable, {fraction_text(hi)} solvable)",
        found=str(found),
        tolerance=str(tolerance),
    )


def _bracket(probe: _BudgetProbe, initial: Fraction) -> tuple[Fraction, Fraction | None, str]:
    """(an unsolvable value, a solvable one above it or None, why none): doubling the step
    from the unsolvable initial value."""
    lo, step = initial, max(abs(initial), Fraction(1))
    for _ in range(40):
        cand = lo + step
        ok = probe.solvable(cand)
        if ok is None:
            return lo, None, "ENHSP gave up"
        if ok:
            return lo, cand, ""
        lo, step = cand, step * 2
    return lo, None, "no solvable budget found"


def _bisect(probe: _BudgetProbe, lo: Fraction, hi: Fraction, tolerance: Fraction) -> tuple[Fraction, Fraction] | None:
    """(unsolvable, solvable) values at most ``tolerance`` apart (on the tolerance grid from
    ``lo``), or None when ENHSP gives up."""
    while hi - lo > tolerance:
        k = ((hi - lo) / 2 / tolerance).__floor__()
        mid = lo + max(k, 1) * tolerance
        if mid >= hi:
            break
        ok = probe.solvable(mid)
        if ok is None:
            return None
        lo, hi = (lo, mid) if ok else (mid, hi)
    return lo, hi


# ---------------------------------------------------------------- recompose


def _recompose_rows(problem: str, t: _Trials, exp: Expected, lc: Loaded) -> list[dict[str, Any]]:
    """ENHSP's plan judged on the churn (stability first) and on the budget left (objective
    first) against expect.toml."""
    er = consensus(t.enhsp_recompose)
    budget_left = None
    if er is not None and "final_state" in er.detail:
        bl = er.detail["final_state"].get("budget")
        budget_left = None if bl is None else Fraction(bl)
    rows = []
    for prio, runs in (("stability", t.recompose_stability), ("objective", t.recompose_objective)):
        want = exp.case.get(f"recompose_{prio}", {})
        d = runs[0].detail
        churn = d.get("churn")
        obj = (d.get("objectives") or [{}])[0].get("value")
        agrees = (
            churn is not None
            and Fraction(str(churn)) == Fraction(want.get("churn", "-1"))
            and obj is not None
            and Fraction(str(obj)) == Fraction(want.get("objective", "-1"))
        )
        rows.append(
            {
                "query": f"recompose ({prio} first)",
                "problem": problem,
                "catc": {
                    "answer": f"churn {churn}, budget left {obj}",
                    "agrees": agrees,
                    "wall": [r.wall for r in runs],
                },
                "enhsp": {
                    "answer": _enhsp_recompose_answer(prio, want, er, budget_left, exp, lc),
                    "calls": 1,
                    "wall": [r.wall for r in t.enhsp_recompose],
                    "planning_ms": [r.planning_ms for r in t.enhsp_recompose if r.planning_ms is not None],
                },
            }
        )
    return rows


def _enhsp_recompose_answer(
    prio: str, want: dict[str, Any], er: ToolRun | None, budget_left: Fraction | None, exp: Expected, lc: Loaded
) -> str:
    if er is None or er.status != "sat":
        return marker(er, exp)
    if prio == "stability":
        mk = judge("sat", "sat", er.value, Fraction(want["churn"]), "minimize") if "churn" in want else "SAT"
    else:
        mk = judge("sat", "sat", budget_left, Fraction(want["objective"]), lc.sense) if "objective" in want else "SAT"
    return (
        f"{mk}: plan with churn {fraction_text(er.value)} (computed by catc against the deployed "
        f"composition; ENHSP has no notion of churn), budget left {fraction_text(budget_left)}"
        + ("" if lc.metric_exported else "; no metric exported (maximize)")
    )
