"""The Python API: the queries of the command line, for programs and notebooks.

    >>> from catc.api import load
    >>> model = load("examples/detection/person.cat")
    >>> answer = model.solve()
    >>> answer.status.value, [[a.morphism for a in step] for step in answer.plan.steps]
    ('sat', [['mount-rgb-camera'], ['camera-driver'], ['open-vocab-detector']])
    >>> model.to_json(answer)["schema"]
    'catc.solve/1'

:func:`load` checks the files as ``catc check`` does and raises :class:`CatError`, with the
located diagnostics, when they have errors.  A :class:`Model` answers every query of the
command line over its checked instance; each method returns the query's result object, already
replayed by the independent validator where the query produces a composition (as the
command line does before printing), and :meth:`Model.to_json` turns any result into the
command's documented ``--json`` document (docs/cli.md).  All numbers are exact
(:class:`fractions.Fraction`).  The long queries (optimize, diagnose, relax, recompose) take
``progress``, a function called with a message as each phase starts (what the command line
shows on its status line).  Nothing here imports click.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable, Mapping, Sequence
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from catc import ir
    from catc.semantics.plan import Plan
    from catgrammar.diagnostics import Diagnostic, Diagnostics

PathLike = str | os.PathLike[str]


class CatError(Exception):
    """Input with errors: ``diagnostics`` are the errors, located in the source;
    ``str()`` is their compiler-style text (``file:line:col: error[CODE]: ...``)."""

    def __init__(self, diagnostics: Diagnostics) -> None:
        from catgrammar.diagnostics import format_text

        self.diagnostics: list[Diagnostic] = list(diagnostics.sorted())
        super().__init__(format_text(diagnostics))

    @property
    def codes(self) -> list[str]:
        return [d.code for d in self.diagnostics if d.severity.value == "error"]


def load_checked(
    problem: PathLike,
    domain: PathLike | None,
    diags: Diagnostics,
    *,
    view: str | None = None,
    problem_name: str | None = None,
    search_paths: Iterable[PathLike] = (),
) -> ir.Instance | None:
    """Files → the checked instance with its view applied, or None with errors in ``diags``
    (the front end of every query, here and on the command line)."""
    from catc.frontend.workspace import load_instance
    from catc.ir.views import ViewError, apply_view

    paths = [str(problem)] if domain is None else [str(domain), str(problem)]
    for p in paths:
        if Path(p).is_dir():
            diags.report("E0001", f"cannot read '{p}': it is a folder; give a .cat file", None)
        elif not Path(p).is_file():
            diags.report("E0001", f"cannot read '{p}': no such file", None)
    if diags.has_errors:
        return None
    _, inst = load_instance(
        None if domain is None else str(domain), str(problem), diags, tuple(str(p) for p in search_paths), problem_name
    )
    if inst is None or diags.has_errors:
        return None
    try:
        return apply_view(inst, view)
    except ViewError as exc:
        diags.report("E0506", str(exc), exc.span)
        return None


def load(
    problem: PathLike,
    domain: PathLike | None = None,
    *,
    view: str | None = None,
    problem_name: str | None = None,
    search_paths: Iterable[PathLike] = (),
) -> Model:
    """Load and check PROBLEM (or DOMAIN and PROBLEM), as ``catc solve [DOMAIN] PROBLEM``:
    the domain is found by name next to the problem, in ``search_paths``, ``CATC_PATH`` and
    the standard library.  ``view`` overrides the problem's ``(:view ...)``; ``problem_name``
    picks one problem of a file defining several.  Raises :class:`CatError`."""
    from catgrammar.diagnostics import Diagnostics

    diags = Diagnostics()
    inst = load_checked(problem, domain, diags, view=view, problem_name=problem_name, search_paths=search_paths)
    if inst is None:
        raise CatError(diags)
    return Model(inst)


class Model:
    """A checked instance (domain + problem, view applied) and the queries over it."""

    def __init__(self, instance: ir.Instance) -> None:
        self.instance = instance

    def __repr__(self) -> str:
        view = f", view {self.instance.view}" if self.instance.view else ""
        return f"<catc Model: problem {self.instance.problem.name} of domain {self.instance.domain.name}{view}>"

    # ------------------------------------------------------------ objectives
    def minimize(self, term: str) -> ir.Objective:
        """An objective from its ``.cat`` text, e.g. ``model.minimize("(total-churn)")``."""
        return self._objective(term, "minimize")

    def maximize(self, term: str) -> ir.Objective:
        return self._objective(term, "maximize")

    def _objective(self, text: str, sense: str) -> ir.Objective:
        from catc import ir
        from catc.frontend.check import check_objective_text
        from catgrammar.diagnostics import Diagnostics

        diags = Diagnostics()
        term = check_objective_text(text, self.instance, diags, f"<{sense}>")
        if term is None or diags.has_errors:
            raise CatError(diags)
        return ir.Objective(ir.Sense(sense), term)

    # ------------------------------------------------------------ queries
    def solve(
        self,
        *,
        horizon: int | None = None,
        sequential: bool = False,
        timeout: float | None = None,
        strategy: str = "incremental",
        prune: bool = True,
    ):
        """The shortest composition (``catc solve``): a :class:`catc.queries.solve.SolveResult`."""
        from catc.queries.solve import solve

        return solve(
            self.instance, horizon=horizon, sequential=sequential, timeout=timeout, strategy=strategy, prune=prune
        )

    def optimize(
        self,
        objectives: Sequence[ir.Objective] | None = None,
        *,
        horizon: int | None = None,
        sequential: bool = False,
        timeout: float | None = None,
        strategy: str = "deepen",
        progress: Callable[[str], None] | None = None,
    ):
        """The best composition (``catc optimize``), lexicographic over ``objectives``
        (default: the problem's metric and soft constraints): a :class:`catc.queries.optimize.OptResult`."""
        from catc.queries.optimize import optimize

        return optimize(
            self.instance,
            None if objectives is None else list(objectives),
            horizon=horizon,
            sequential=sequential,
            timeout=timeout,
            strategy=strategy,
            progress=progress,
        )

    def pareto(
        self,
        objectives: Sequence[ir.Objective] | None = None,
        *,
        horizon: int | None = None,
        sequential: bool = False,
        max_points: int = 100,
        timeout: float | None = None,
    ):
        """Every non-dominated composition (``catc pareto``): a :class:`catc.queries.pareto.ParetoResult`."""
        from catc.queries.pareto import pareto

        return pareto(
            self.instance,
            None if objectives is None else list(objectives),
            horizon=horizon,
            sequential=sequential,
            max_points=max_points,
            timeout=timeout,
        )

    def diagnose(
        self,
        *,
        relative_to: Iterable[str] | None = None,
        all_cores: bool = False,
        max_cores: int = 5,
        horizon: int | None = None,
        sequential: bool = False,
        timeout: float | None = None,
        progress: Callable[[str], None] | None = None,
    ):
        """Why there is no composition (``catc diagnose``): irreducible cores of labelled
        requirements, a :class:`catc.queries.diagnose.Diagnosis`.  ``relative_to``: the composition
        to keep (default the problem's ``(:deployed ...)``; ``()`` for none)."""
        from catc.queries.diagnose import diagnose

        return diagnose(
            self.instance,
            horizon=horizon,
            sequential=sequential,
            relative_to=relative_to,
            all_cores=all_cores,
            max_cores=max_cores,
            timeout=timeout,
            progress=progress,
        )

    def relax(
        self,
        *,
        only: Iterable[str] = (),
        weights: Mapping[str, Fraction | int | str] | None = None,
        discrete: bool = False,
        relative_to: Iterable[str] | None = None,
        horizon: int | None = None,
        sequential: bool = False,
        timeout: float | None = None,
        progress: Callable[[str], None] | None = None,
    ):
        """The least weighted weakening that restores feasibility (``catc relax``): a
        :class:`catc.queries.relax.RelaxResult`.  ``weights`` map labels, label prefixes or
        resources to exact weights."""
        from catc.queries.relax import relax

        exact = None if weights is None else {k: Fraction(v) for k, v in weights.items()}
        return relax(
            self.instance,
            horizon=horizon,
            sequential=sequential,
            only=only,
            weights=exact,
            discrete=discrete,
            relative_to=relative_to,
            timeout=timeout,
            progress=progress,
        )

    def recompose(
        self,
        *,
        deployed: Iterable[str] | None = None,
        priority: str = "stability",
        objectives: Sequence[ir.Objective] | None = None,
        horizon: int | None = None,
        sequential: bool = False,
        timeout: float | None = None,
        progress: Callable[[str], None] | None = None,
    ):
        """A new composition with the least churn against the deployed one (``catc
        recompose``): a :class:`catc.queries.recompose.Recomposition`."""
        from catc.queries.recompose import recompose

        return recompose(
            self.instance,
            deployed=deployed,
            priority=priority,
            objectives=None if objectives is None else list(objectives),
            horizon=horizon,
            sequential=sequential,
            timeout=timeout,
            progress=progress,
        )

    def synthesize(
        self,
        hole: str | None = None,
        *,
        horizon: int | None = None,
        sequential: bool = False,
        timeout: float | None = None,
    ):
        """The weakest specification of a missing component (``catc synthesize``): a
        :class:`catc.queries.synthesize.Synthesis`."""
        from catc.queries.synthesize import synthesize

        return synthesize(self.instance, hole, horizon=horizon, sequential=sequential, timeout=timeout)

    def validate(self, plan: Plan | Mapping[str, Any], *, horizon: int | None = None, sequential: bool = False):
        """Replay a composition — a :class:`catc.semantics.plan.Plan` or a ``catc.plan/1`` document
        (``{"schema": "catc.plan/1", "steps": ...}``, the steps as any ``--json`` answer
        gives them) — and report every violation (``catc validate``):
        a :class:`catc.semantics.validate.Report`.  Raises :class:`catc.semantics.plan.PlanFormatError` for a
        malformed document."""
        from catc.semantics.plan import Plan, plan_from_json
        from catc.semantics.validate import validate

        if not isinstance(plan, Plan):
            sorts = {
                m.name: {p.name: (p.sort.kind.value if not p.sort.is_symbolic else "symbol") for p in m.params}
                for m in self.instance.morphisms.values()
            }
            plan = plan_from_json(plan, sorts)
        return validate(self.instance, plan, horizon=horizon, sequential=sequential)

    # ------------------------------------------------------------ output
    def to_json(self, result: Any) -> dict:
        """The ``--json`` document of the command that gives ``result`` (docs/cli.md)."""
        from catc.ir.labels import label_index
        from catc.present import report
        from catc.queries.diagnose import Diagnosis
        from catc.queries.optimize import OptResult
        from catc.queries.pareto import ParetoResult
        from catc.queries.recompose import Recomposition
        from catc.queries.relax import RelaxResult
        from catc.queries.solve import SolveResult
        from catc.queries.synthesize import Synthesis
        from catc.semantics.validate import Report

        inst = self.instance
        if isinstance(result, SolveResult):
            return report.solve_json(inst, result)
        if isinstance(result, OptResult):
            return report.optimize_json(inst, result)
        if isinstance(result, Recomposition):
            return report.recompose_json(inst, result)
        if isinstance(result, Diagnosis):
            return report.diagnosis_json(inst, result, label_index(inst))
        if isinstance(result, RelaxResult):
            return report.relax_json(inst, result, label_index(inst))
        if isinstance(result, ParetoResult):
            return report.pareto_json(inst, result)
        if isinstance(result, Synthesis):
            return report.synthesize_json(result)
        if isinstance(result, Report):
            return report.validate_json(result)
        raise TypeError(f"not a catc query result: {type(result).__name__}")
