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
registry (:mod:`catc.queries.registry`) over its checked instance — ``model.solve()``,
``model.optimize(...)``, ``model.diagnose()``, ... or ``model.query("relax", ...)`` — with
the query's keyword options; each returns the query's result, already replayed by the
independent validator where the query produces a composition (as the command line does
before printing), and :meth:`Model.to_json` turns any result into the command's documented
``--json`` document (docs/cli.md).  All numbers are exact (:class:`fractions.Fraction`).
The long queries (solve, optimize, diagnose, relax, recompose) take ``progress``, a function
called with a message as each phase starts (what the command line shows on its status
line).  Nothing here imports click.

Below the queries, the part of the API a program embedding catc relies on (the runtime,
catrt, uses nothing else of catc but the IR and :mod:`catc.semantics.plan`): the deploy
policy (:func:`deploy_query`), a query's outcome as data (:func:`composed`,
:func:`refuted`), plans read against a model (:func:`read_plan`), the independent validator
(:func:`validate`, :func:`initial_state`), the deployment artifacts of a composition and
their difference (:func:`deployment`, :func:`write_files`, :func:`diff_artifacts`), the
outline of a source — its definitions and sections, with offsets — (:func:`outline`) and
the language's tokens (:func:`tokens`), so that no program parses ``.cat`` text itself, and
a problem written as a formatted ``.cat`` file (:func:`problem_source`), so that no program
writes one.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from fractions import Fraction
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from catc import ir
    from catc.frontend.session import TextCache
    from catc.queries.base import Result
    from catc.queries.solve import WarmStart
    from catc.semantics.plan import Plan
    from catc.semantics.validate import Report
    from catc.targets.grounding.diff import GroundDiff
    from catgrammar.diagnostics import Diagnostic, Diagnostics
    from catgrammar.limits import Limits

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


def load(
    *paths: PathLike,
    view: str | None = None,
    problem_name: str | None = None,
    search_paths: Iterable[PathLike] = (),
    limits: Limits | None = None,
) -> Model:
    """Load and check ``load(PROBLEM)`` or ``load(DOMAIN, PROBLEM)``, in the order of
    ``catc solve [DOMAIN] PROBLEM``: with PROBLEM alone the domain is found by name next to
    the problem, in ``search_paths``, ``CATC_PATH`` and the standard library.  ``view``
    overrides the problem's ``(:view ...)``; ``problem_name`` picks one problem of a file
    defining several.  ``limits`` (default: the defaults with ``CATC_LIMIT_*`` applied;
    docs/limits.md) hold for loading and for every query of the model.  Raises
    :class:`CatError`.

    catc used to take ``load(PROBLEM, DOMAIN)``: two paths the other way round (the
    first file defines only problems, the second only domains) are still accepted, with a
    :class:`DeprecationWarning`."""
    from catc.frontend.session import load_checked
    from catc.interfaces.command import search_path
    from catgrammar import limits as limits_
    from catgrammar.diagnostics import Diagnostics

    if len(paths) not in (1, 2):
        raise TypeError(f"load() takes PROBLEM or DOMAIN, PROBLEM ({len(paths)} paths given)")
    domain, problem = (None, paths[0]) if len(paths) == 1 else paths
    if domain is not None and _swapped(domain, problem):
        import warnings

        warnings.warn(
            f"load({str(domain)!r}, {str(problem)!r}): the order is load(DOMAIN, PROBLEM), as on the command "
            "line; the old order load(PROBLEM, DOMAIN) is accepted for now",
            DeprecationWarning,
            stacklevel=2,
        )
        domain, problem = problem, domain
    diags = Diagnostics()
    found_paths = search_path([str(p) for p in search_paths])
    found = _limits(limits)
    with limits_.using(found):
        inst = load_checked(problem, domain, diags, view=view, problem_name=problem_name, search_paths=found_paths)
    if inst is None:
        raise CatError(diags)
    return Model(inst, found)


def _defines(path: PathLike) -> set[str]:
    """What a file defines: a subset of {'domain', 'problem'}, found by the language's
    tokenizer (comments and strings never count); empty when it cannot be read."""
    from catgrammar._lalr import UnexpectedCharacters
    from catgrammar.tokens import tokenize

    try:
        with open(path, encoding="utf-8") as fh:
            text = fh.read()
    except (OSError, UnicodeDecodeError):
        return set()
    kinds = {"_DOMAIN_WORD": "domain", "_PROBLEM_WORD": "problem"}
    found: set[str] = set()
    window = ("", "", "")
    try:
        for tok in tokenize(text):
            if window == ("LPAR", "_DEFINE_WORD", "LPAR") and tok.type in kinds:
                found.add(kinds[tok.type])
            window = (window[1], window[2], tok.type)
    except UnexpectedCharacters:
        pass
    return found


def _swapped(first: PathLike, second: PathLike) -> bool:
    """``load(PROBLEM, DOMAIN)``, the order catc used to take."""
    return _defines(first) == {"problem"} and _defines(second) == {"domain"}


def _limits(given: Limits | None) -> Limits:
    """``given``, or the defaults with the environment's ``CATC_LIMIT_*`` applied."""
    from catgrammar import limits

    return given if given is not None else limits.from_environment(os.environ)


def loads(
    sources: Mapping[str, str],
    problem: str,
    *,
    view: str | None = None,
    problem_name: str | None = None,
    search_paths: Iterable[PathLike] = (),
    limits: Limits | None = None,
    cache: TextCache | None = None,
) -> Model:
    """Load and check a model given as text: ``sources`` maps paths to ``.cat`` texts, and
    ``problem`` is the path of the one holding the problem.  ``cache`` (:func:`text_cache`):
    the files and domains of an earlier call, reused where their texts are unchanged.  A domain among the sources is
    found by name; imports that are not among them come from the disk (the folder of the
    importing path, ``search_paths``, ``CATC_PATH``, the standard library).  ``limits`` as
    for :func:`load`.  Raises :class:`CatError`, located in the given paths."""
    from catc.frontend.session import load_texts
    from catc.interfaces.command import search_path
    from catgrammar import limits as limits_
    from catgrammar.diagnostics import Diagnostics

    if problem not in sources:
        raise ValueError(f"{problem!r} is not among the sources")
    diags = Diagnostics()
    paths = search_path([str(p) for p in search_paths])
    found = _limits(limits)
    with limits_.using(found):
        inst = load_texts(
            sources, problem, diags, view=view, problem_name=problem_name, search_paths=paths, text_cache=cache
        )
    if inst is None:
        raise CatError(diags)
    return Model(inst, found)


class Model:
    """A checked instance (domain + problem, view applied) and the queries over it: one
    method per query of the registry, with that query's keyword options."""

    def __init__(self, instance: ir.Instance, limits: Limits | None = None) -> None:
        from catgrammar.limits import DEFAULT

        self.instance = instance
        self.limits = DEFAULT if limits is None else limits

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
    def query(self, name: str, /, *args: Any, **options: Any) -> Result:
        """Answer the query ``name`` (``solve``, ``optimize``, ...) with its options, as the
        command of that name does: ``model.query("relax", weights={"budget": 2})``."""
        from catc.queries import registry
        from catc.queries.base import Kind

        query = registry.get(name)
        for option in query.options:
            value = options.get(option.name)
            if option.kind is Kind.WEIGHTS and option.name in options:
                options[option.name] = {k: Fraction(v) for k, v in value.items()} if value else None
            elif option.kind is Kind.OBJECTIVES and value is not None:
                options[option.name] = list(value)
        from catgrammar import limits
        from catgrammar.diagnostics import Diagnostics

        with limits.using(self.limits):
            try:
                return query.run(self.instance, *args, **options)
            except limits.LimitExceeded as exc:  # the horizon, a universe: located
                diags = Diagnostics()
                diags.report(exc.code, exc.message, exc.span)
                raise CatError(diags) from None

    def __getattr__(self, name: str) -> Callable[..., Result]:
        from catc.queries import registry

        if name.startswith("_") or name not in registry.QUERIES:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        run = registry.get(name).run

        @functools.wraps(run)
        def answer(*args: Any, **options: Any) -> Result:
            return self.query(name, *args, **options)

        return answer

    def __dir__(self) -> list[str]:
        from catc.queries import registry

        return sorted(set(super().__dir__()) | set(registry.QUERIES))

    # ------------------------------------------------------------ targets
    def export(self, target: str, /, **options: Any) -> Any:
        """The artifact of the target ``target`` (:mod:`catc.targets.registry`: ``pddl``,
        ``pddlplus``, ``smt2``, ``cat``, ``ground``) with its options, as ``catc export``/``compile``/
        ``ground`` make it; its JSON document: ``model.export_json(target, artifact)``.
        Raises :class:`catc.queries.base.InputError` when the model cannot be expressed."""
        from catc.interfaces.layout import export as export_artifact
        from catc.targets import registry as targets
        from catgrammar import limits

        with limits.using(self.limits):
            return export_artifact(targets.get(target), self.instance, options)

    def export_json(self, target: str, artifact: Any) -> dict:
        from catc.targets import registry as targets

        return targets.get(target).to_json(self.instance, artifact)

    def ground(self, **options: Any) -> Any:
        """The artifacts a robot runs (:class:`catc.targets.ground.Grounding`): ``plan=`` a
        composition, else the problem solved first; ``horizon=``, ``timeout=``."""
        return self.export("ground", **options)

    # ------------------------------------------------------------ output
    def to_json(self, result: Any) -> dict:
        """The ``--json`` document of the command that gives ``result`` (docs/cli.md)."""
        from catc.queries import registry

        return registry.for_result(result).to_json(self.instance, result)


# ---------------------------------------------------------------- for programs embedding catc


def convert(value: Fraction, unit: str, to: str) -> Fraction:
    """``value`` ``unit`` in the unit ``to``, exactly, as a ``.cat`` literal with a unit is
    read (``2 GB`` in MB is 2000); ValueError naming both dimensions when they differ, or the
    unit that is not one."""
    from catc.frontend import units

    try:
        source, target = units.parse(unit), units.parse(to)
    except units.UnitError as exc:
        raise ValueError(str(exc)) from None
    if not source.same_dimension(target):
        raise ValueError(f"{unit} is {source.dimension}, not {target.dimension} ({to})")
    return value * units.factor(source, target)


def deploy_query(inst: ir.Instance) -> str:
    """The query that finds the composition to deploy: ``optimize`` when the problem says
    what is best (a metric or soft constraints), else ``solve``."""
    from catc.queries.registry import deploy_query as policy

    return policy(inst)


def read_plan(inst: ir.Instance, doc: Any) -> Plan:
    """A plan document (``catc.plan/1``, or an answer holding one) read against ``inst``;
    :class:`catc.semantics.plan.PlanFormatError` when it is malformed."""
    from catc.semantics.plan import read_plan as read

    return read(inst, doc)


def composed(result: Any) -> bool:
    """``result`` (of solve, optimize or recompose) holds a composition: satisfiable, an
    optimum, or the best found in the time limit."""
    from catc.queries.optimize import OptStatus
    from catc.queries.solve import SolveStatus

    found = (SolveStatus.SAT, OptStatus.OPT, OptStatus.SUBOPT)
    return getattr(result, "plan", None) is not None and result.status in found


def refuted(result: Any) -> bool:
    """``result`` proves that no composition exists (``unsat``)."""
    from catc.queries.optimize import OptStatus
    from catc.queries.solve import SolveStatus

    return bool(result.status in (SolveStatus.UNSAT, OptStatus.UNSAT))


def stopped_early(result: Any) -> bool:
    """``result`` holds the best composition found before the time limit, not one proven
    optimal (``subopt``)."""
    from catc.queries.optimize import OptStatus

    return bool(result.status is OptStatus.SUBOPT)


def text_cache() -> TextCache:
    """A cache for :func:`loads` (a program that checks one model again and again, each time
    with a small change: the runtime)."""
    from catc.frontend.session import new_text_cache

    return new_text_cache()


def relax_weights(
    inst: ir.Instance,
    only: Iterable[str] = (),
    weights: Mapping[str, Fraction] | None = None,
    fixed: Iterable[str] = (),
) -> tuple[dict[str, Fraction], str | None]:
    """The weights ``relax`` uses by default, never adding unlike units at weight 1: (weights,
    None), or ({}, why not) when a requirement of another unit has no scale
    (:func:`catc.queries.relax.unit_safe_weights`; the runtime's ``[relax]`` policy)."""
    from catc.queries.registry import relax_weights as weigh

    return weigh(inst, only, weights, fixed)


def warm_start(literal_resources: Iterable[str] = ()) -> WarmStart:
    """What ``solve`` keeps from one call to the next (``model.solve(warm=...)``) to answer on
    the previous encoding when only initial values or the goal changed; the initial values
    of ``literal_resources`` (sensed, say) are kept behind literals from the start."""
    from catc.queries.solve import WarmStart

    return WarmStart(literal_resources)


def validate(inst: ir.Instance, plan: Plan) -> Report:
    """Replay ``plan`` on ``inst`` with the independent validator (no solver):
    ``report.ok``, ``report.violations``, ``report.states``."""
    from catc.semantics.validate import validate as replay

    return replay(inst, plan)


def initial_state(inst: ir.Instance) -> dict[str, object]:
    """The value of every resource before the first step."""
    from catc.semantics.validate import initial_state as initial

    return initial(inst)


def deployment(inst: ir.Instance, plan: Plan, model_sha256: str) -> tuple[dict[str, bytes], dict[str, Any]]:
    """The deployment artifacts of ``plan`` (valid in ``inst``) as ``catc ground`` writes
    them: file name → bytes, and the manifest naming them (with ``model_sha256``).
    ValueError when the composition cannot be grounded (a grounding conflict, a value no
    artifact can carry)."""
    from catc.semantics.validate import validate as replay
    from catc.targets.grounding.artifacts import artifacts, manifest
    from catc.targets.grounding.resolve import ground

    grounded = ground(inst, plan, replay(inst, plan).states)
    files = artifacts(grounded)
    return files, manifest(grounded, files, model_sha256, inst)


def diagram(inst: ir.Instance, plan: Plan, *, title: str | None = None) -> str:
    """``plan`` over ``inst`` drawn as a string diagram (what ``catc solve --diagram`` draws),
    with the states the validator replays tagged on the wires; the SVG document."""
    from catc.present.diagram import render_svg
    from catc.semantics.validate import validate as replay

    report = replay(inst, plan)
    states = report.states if report.ok else None
    return render_svg(inst, plan, states=states, title=title)


def write_files(folder: Path, files: dict[str, bytes], document: dict[str, Any], *, durable: bool = False) -> None:
    """Write ``files`` and the manifest ``document`` into ``folder`` as ``catc ground`` does
    (each file replaced atomically; ``durable``: synced to the disk)."""
    from catc.targets.grounding.artifacts import write

    write(folder, files, document, durable=durable)


def read_grounding(path: str) -> dict[str, bytes]:
    """The files of a grounding (a folder ``catc ground`` or the runtime wrote, or its
    manifest.json), each checked against the manifest's sha256; a ValueError
    (``NotAGrounding``) says what is wrong."""
    from catc.targets.grounding.diff import read_grounding as read

    return read(path)


def diff_artifacts(old: Mapping[str, bytes], new: Mapping[str, bytes]) -> GroundDiff:
    """What changes from one set of deployment artifacts to the next (services added,
    removed, restarted; the commands that do it)."""
    from catc.targets.grounding.diff import diff_artifacts as diff

    return diff(old, new)


def problem_source(inst: ir.Instance, *, header: str | None = None) -> str:
    """The problem of the checked instance ``inst`` as a ``.cat`` file in ``catc fmt``'s
    layout — the problem file of the ``cat`` target (``catc export cat``,
    ``Model.export("cat")``), laid out as every interface lays it out
    (:mod:`catc.interfaces.layout`) — with ``header`` as a comment on top; it names
    ``inst``'s domain and reads back as the same problem.  Raises
    :class:`catc.queries.base.InputError` when the model cannot be written as ``.cat`` (as
    ``Model.export("cat")`` does)."""
    from catc.interfaces.layout import export
    from catc.targets import registry as targets

    return str(export(targets.get("cat"), inst, {"header": header}).problem)


@dataclass(frozen=True)
class Section:
    """A section of a definition: ``keyword`` (``morphism``, ``goal``, ``soft``, ``metric``,
    ``requirements``, ``objects``, ...), its ``name`` when it declares one (a morphism's),
    its offsets in the text (``start``, ``end``) and those of its ``body`` — the condition
    of a goal or a soft constraint — when it has one."""

    keyword: str
    name: str | None
    start: int
    end: int
    body: tuple[int, int] | None = None


@dataclass(frozen=True)
class Definition:
    """``(define (domain NAME) ...)`` or ``(define (problem NAME) ...)`` in a source:
    ``kind`` is ``domain`` or ``problem``; offsets in the text; its sections in order."""

    kind: str
    name: str
    start: int
    end: int
    sections: tuple[Section, ...]


def outline(text: str, path: str = "<string>") -> list[Definition]:
    """The definitions of a ``.cat`` source and their sections, located by offset — for
    programs that cut and splice sources without parsing them.  Raises :class:`CatError`
    when the text does not parse (nothing is checked beyond the syntax)."""
    from catgrammar import ast
    from catgrammar.diagnostics import Diagnostics
    from catgrammar.parser import parse_text

    diags = Diagnostics()
    tree = parse_text(text, path, diags)
    if tree is None or diags.has_errors:
        raise CatError(diags)
    keywords = {ast.MorphismDecl: "morphism", ast.HoleDecl: "hole", ast.Requirements: "requirements",
                ast.Objects: "objects", ast.Goal: "goal", ast.Soft: "soft", ast.Metric: "metric",
                ast.Horizon: "horizon", ast.Init: "init", ast.Deployed: "deployed", ast.DomainRef: "domain"}  # fmt: skip
    out: list[Definition] = []
    for d in tree.definitions:
        if not isinstance(d, (ast.Domain, ast.Problem)):
            continue
        sections = []
        for s in d.sections:
            name = getattr(s, "name", None)
            condition = getattr(s, "condition", None)
            sections.append(
                Section(
                    keywords.get(type(s), type(s).__name__.lower()),
                    name.text if isinstance(name, ast.Name) else None,
                    s.span.start,
                    s.span.end,
                    (condition.span.start, condition.span.end) if condition is not None else None,
                )
            )
        kind = "domain" if isinstance(d, ast.Domain) else "problem"
        out.append(Definition(kind, d.name.text, d.span.start, d.span.end, tuple(sections)))
    return out


@dataclass(frozen=True)
class Token:
    """A token of the language: its ``text``, offsets, line and column (from 1)."""

    text: str
    start: int
    end: int
    line: int
    column: int

    @property
    def opens(self) -> bool:
        return self.text == "("

    @property
    def closes(self) -> bool:
        return self.text == ")"


class TokenError(ValueError):
    """A character the language does not have, at ``line``:``column`` (None when unknown)."""

    def __init__(self, message: str, line: int | None, column: int | None) -> None:
        super().__init__(message)
        self.line, self.column = line, column


def tokens(text: str) -> list[Token]:
    """The tokens of ``text`` (comments and white space dropped); :class:`TokenError` at a
    character the language does not have."""
    from catgrammar._lalr import UnexpectedInput
    from catgrammar.tokens import tokenize

    try:
        return [Token(t.value, t.start_pos or 0, t.end_pos or 0, t.line or 0, t.column or 0) for t in tokenize(text)]
    except UnexpectedInput as exc:
        column = getattr(exc, "column", None)
        raise TokenError(f"unexpected character at column {column}", getattr(exc, "line", None), column) from None
