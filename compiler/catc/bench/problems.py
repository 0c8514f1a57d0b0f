"""The benchmark problems: which examples are run, with which catc query and ENHSP planner,
on which grid for their real θ; and what each is expected to answer (examples/*/expect.toml)."""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

from catc.queries import registry

Grid = dict[str, Fraction]

#: Grids for the real θ of the examples (by parameter name), stated in every table.
GRID_DETECTION: Grid = {"ram-req": Fraction(1, 2)}
GRID_GPU: Grid = {"m": Fraction(1, 4)}
GRID_NAV: Grid = {"d": Fraction(1)}
GRID_SAR: Grid = {"ram-req": Fraction(1, 4), "d": Fraction(1), "mem": Fraction(1, 2)}


def fraction_text(v: Fraction | None) -> str:
    if v is None:
        return "—"
    from catc.ir.numbers import decimal_text

    return decimal_text(Fraction(v))


@dataclass(frozen=True)
class Problem:
    file: str  # relative to the examples folder
    query: str  # the catc query (a name of catc.queries.registry): solve | optimize | recompose
    planner: str  # ENHSP -planner
    grid: Grid = field(default_factory=dict)
    catc_args: tuple[str, ...] = ()
    quick: bool = False

    def __post_init__(self) -> None:
        if self.query not in registry.names():
            raise ValueError(f"{self.file}: {self.query!r} is not a catc query ({', '.join(registry.names())})")


def _p(
    file: str,
    query: str,
    planner: str,
    grid: Grid | None = None,
    catc_args: tuple[str, ...] = (),
    quick: bool = False,
) -> Problem:
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

#: The lifelong-queries table's problems: the unsolvable budget cut (diagnose, relax), the
#: cheaper camera (recompose), and the search-and-rescue budget cut (diagnose, not in --quick).
LIFELONG_BUDGET_CUT = "lifelong/budget-cut.cat"
LIFELONG_CHEAPER_CAMERA = "lifelong/cheaper-camera.cat"
SAR_BUDGET_CUT = "search-and-rescue/budget-cut.cat"

#: Finer grids tried (step / k) when the base grid loses the perturbed problem's answer.
REFINE_FACTORS = (2, 4, 5, 10, 20)
REFINE_MAX_ACTIONS = 25_000


def grid_text(grid: Grid) -> str:
    if not grid:
        return "—"
    return ", ".join(f"{k}={fraction_text(v)}" for k, v in sorted(grid.items()))


@dataclass
class Expected:
    status: str | None = None
    optimum: Fraction | None = None
    sense: str | None = None  # of the optimum
    case: dict[str, Any] = field(default_factory=dict)


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
