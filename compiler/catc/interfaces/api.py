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
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Iterable, Mapping
from fractions import Fraction
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from catc import ir
    from catc.queries.base import Result
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
) -> Model:
    """Load and check a model given as text: ``sources`` maps paths to ``.cat`` texts, and
    ``problem`` is the path of the one holding the problem.  A domain among the sources is
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
        inst = load_texts(sources, problem, diags, view=view, problem_name=problem_name, search_paths=paths)
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
        ``pddlplus``, ``smt2``, ``ground``) with its options, as ``catc export``/``compile``/
        ``ground`` make it; its JSON document: ``model.export_json(target, artifact)``.
        Raises :class:`catc.queries.base.InputError` when the model cannot be expressed."""
        from catc.targets import registry as targets
        from catgrammar import limits

        with limits.using(self.limits):
            return targets.get(target).run(self.instance, **options)

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
