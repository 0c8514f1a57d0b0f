"""What every query is made of: a status that carries its exit code, a result, options, and
the :class:`Query` record that the command line, the Python API, the language server and the
benchmarks read.

A query module defines its result type, a ``run`` function over a checked instance, its
``--json`` document, its text rendering, and one ``QUERY = Query(...)`` naming all of them;
:mod:`catc.queries.registry` lists the modules.  Nothing else needs to change to add a query:
the command line builds its command from the options, the API its method, the language
server its command.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from enum import Enum, IntEnum
from typing import Any, ClassVar

from catc import ir
from catgrammar import codes
from catgrammar.record import Record, set_field


class ExitCode(IntEnum):
    """The exit codes of every command (docs/cli.md)."""

    OK = 0  # success: SAT, an optimum, a core found, a valid plan
    FAIL = 1  # the answer is negative: UNSAT, infeasible, invalid; model errors for check
    INPUT = 2  # usage or input errors
    UNKNOWN = 3  # the solver gave up, or stopped early with a best-so-far answer
    INTERNAL = 70  # a bug in catc (EX_SOFTWARE)
    INTERRUPTED = 130  # stopped by Ctrl-C (128 + SIGINT)


class Status(str, Enum):
    """A query's outcome.  Each query declares its own statuses as ``NAME = "json value",
    ExitCode``; the value is what ``--json`` prints, the exit code what the command returns."""

    exit_code: ExitCode

    def __new__(cls, value: str, exit_code: ExitCode = ExitCode.OK) -> Status:
        obj = str.__new__(cls, value)
        obj._value_ = value
        obj.exit_code = exit_code
        return obj


class Result:
    """The base of every query's result: ``status``, ``timings`` (seconds by phase) and
    whether the answer is ``settled`` (proven, complete).  A positive answer that is not
    settled — a best-so-far relaxation, an incomplete Pareto front — exits with UNKNOWN."""

    __slots__ = ()
    query: ClassVar[str] = ""  # the registry name of the query that gives this result
    status: Status
    timings: dict[str, float]

    @property
    def settled(self) -> bool:
        return True

    @property
    def exit_code(self) -> ExitCode:
        code = self.status.exit_code
        return ExitCode.UNKNOWN if code is ExitCode.OK and not self.settled else code


#: ``progress(message)``: told what a long query is doing as each phase starts.
Progress = Callable[[str], None]


class InputError(ValueError):
    """A query cannot run on these arguments (reported as an input error, exit 2)."""

    def __init__(self, message: str, code: str = codes.BAD_ARGUMENT) -> None:
        super().__init__(message)
        self.code = code


# ====================================================================== options


class Kind(str, Enum):
    """How an option is spelled on the command line and what value it gives ``run``."""

    FLAG = "flag"  # --x: True
    NO_FLAG = "no-flag"  # --no-x: the option (default True) becomes False
    COUNT = "count"  # an integer ≥ 0
    POSITIVE = "positive"  # an integer ≥ 1
    SECONDS = "seconds"  # a number of seconds > 0
    NAME = "name"  # a word
    CHOICE = "choice"  # one of ``choices``
    TEXTS = "texts"  # repeatable words: a tuple
    FOLDERS = "folders"  # repeatable folders: a tuple
    OBJECTIVES = "objectives"  # --minimize/--maximize EXPR, repeatable, in order: ir.Objective list
    COMPONENTS = "components"  # a,b,c: morphism names (``none_word`` for the empty list)
    WEIGHTS = "weights"  # repeatable KEY=W: a dict of exact weights
    OUTPUT_FILE = "output-file"  # a file to write
    OUTPUT_FOLDER = "output-folder"  # a folder to write into
    INPUT_FILE = "input-file"  # a file to read
    FILE_PAIR = "file-pair"  # two files to read: a tuple of two
    PLAN_FILE = "plan-file"  # a positional catc.plan/1 file: a Plan
    DOCUMENT_FILE = "document-file"  # a positional file after PATHS, its path (the query reads it)


class Use(str, Enum):
    """Who consumes an option: the loader, the query's ``run``, or the output."""

    LOAD = "load"
    RUN = "run"
    OUTPUT = "output"


class Option(Record):
    """One option of a query: its keyword (``run``'s and the API's), its command-line
    spellings, its kind, help and default."""

    __slots__ = (
        "name",
        "flags",
        "kind",
        "help",
        "default",
        "choices",
        "metavar",
        "show_default",
        "use",
        "none_word",
        "required",
    )
    name: str
    flags: tuple[str, ...]
    kind: Kind
    help: str
    default: Any
    choices: tuple[str, ...]
    metavar: str | None
    show_default: bool
    use: Use
    none_word: str | None
    required: bool

    def __init__(
        self,
        name: str,
        flags: tuple[str, ...],
        kind: Kind,
        help: str = "",
        *,
        default: Any = None,
        choices: tuple[str, ...] = (),
        metavar: str | None = None,
        show_default: bool = False,
        use: Use = Use.RUN,
        none_word: str | None = None,
        required: bool = False,
    ) -> None:
        set_field(self, "name", name)
        set_field(self, "flags", flags)
        set_field(self, "kind", kind)
        set_field(self, "help", help)
        if default is None and kind in (Kind.FLAG, Kind.NO_FLAG):
            default = kind is Kind.NO_FLAG  # a flag is off unless given; a --no-x flag is on
        set_field(self, "default", default)
        set_field(self, "choices", choices)
        set_field(self, "metavar", metavar)
        set_field(self, "show_default", show_default)
        set_field(self, "use", use)
        set_field(self, "none_word", none_word)
        set_field(self, "required", required)


def common_options() -> tuple[Option, ...]:
    """The options of every query: the horizon, the view, sequential steps, where to find
    domains, and which problem of the file."""
    view, path, problem = load_options("Solve in this view (overrides the problem's (:view ...)).")
    return (
        Option(
            "horizon",
            ("--horizon", "-k"),
            Kind.COUNT,
            "Most steps a composition may take (default: the problem's (:horizon), else the sum of use limits, "
            "else 10).",
        ),
        view,
        Option(
            "sequential",
            ("--sequential",),
            Kind.FLAG,
            "One morphism per step (default: parallel steps with non-interference).",
            default=False,
        ),
        path,
        problem,
        *limit_options(),
    )


def load_options(view_help: str, path_help: str = "Extra folder to search for domains.") -> tuple[Option, ...]:
    """``--view``, ``--path`` and ``--problem``: which model a command reads (every query's,
    every target's, ``catc check``'s ``--path``)."""
    return (
        Option("view", ("--view",), Kind.NAME, view_help, use=Use.LOAD),
        Option("search_paths", ("--path",), Kind.FOLDERS, path_help, default=(), use=Use.LOAD),
        Option(
            "problem_name", ("--problem",), Kind.NAME, "The problem to use when the file defines several.", use=Use.LOAD
        ),
    )


def limit_options() -> tuple[Option, ...]:
    """``--limit NAME=N`` and ``--memory MB`` (docs/limits.md): read by the command line
    before loading, never passed to ``run``."""
    return (
        Option(
            "limits",
            ("--limit",),
            Kind.TEXTS,
            "Set a limit: NAME=N, e.g. horizon=5000 (repeatable; the limits and their defaults: docs/limits.md).",
            default=(),
            metavar="NAME=N",
            use=Use.LOAD,
        ),
        Option(
            "memory",
            ("--memory",),
            Kind.COUNT,
            "The most memory the command may use, in MB (0: no limit; default 8192, or CATC_LIMIT_MEMORY).",
            metavar="MB",
            use=Use.LOAD,
        ),
    )


def timeout_option(help: str = "Give up after this many seconds (exit 3).") -> Option:
    return Option("timeout", ("--timeout",), Kind.SECONDS, help)


def json_option(schema: str) -> Option:
    return Option("as_json", ("--json",), Kind.FLAG, f"Print a {schema} JSON document.", default=False, use=Use.OUTPUT)


def backend_option() -> Option:
    """``--backend``: the solver (:data:`catc.smt.backend.BACKENDS`)."""
    from catc.smt.backend import BACKENDS, DEFAULT_BACKEND

    return Option(
        "backend",
        ("--backend",),
        Kind.CHOICE,
        "The solver: z3, or cvc5 (through its Python API).",
        default=DEFAULT_BACKEND,
        choices=tuple(BACKENDS),
        show_default=True,
    )


def presolve_option() -> Option:
    """``--no-presolve``: skip the relaxed reachability analysis (catc.semantics.relaxed)."""
    return Option(
        "presolve",
        ("--no-presolve",),
        Kind.NO_FLAG,
        "Ask the solver everything: no relaxed reachability analysis first (it proves many "
        "infeasible problems in milliseconds, for every horizon).",
    )


def progress_option() -> Option:
    """``--progress``: the status line of a long query even when standard error is not a
    terminal (one line per update there), and with ``--json``."""
    return Option(
        "show_progress",
        ("--progress",),
        Kind.FLAG,
        "Show what the query is doing on standard error even when it is not a terminal "
        "(one line per update; default: a status line on a terminal only).",
        default=False,
        use=Use.OUTPUT,
    )


def diagram_option() -> Option:
    return Option(
        "diagram",
        ("--diagram",),
        Kind.OUTPUT_FILE,
        "Write the composition as an SVG string diagram.",
        use=Use.OUTPUT,
    )


def certificate_option() -> Option:
    """``--certificate FILE``: the proof of a "no" (:mod:`catc.queries.certify`)."""
    return Option(
        "certificate",
        ("--certificate",),
        Kind.OUTPUT_FILE,
        "Write a catc.certificate/1 proof of the answer (a final UNSAT, a core), for 'catc certify' (docs/semantics.md).",
        use=Use.OUTPUT,
    )


def objectives_option(minimize_help: str, maximize_help: str) -> Option:
    """``--minimize``/``--maximize``: one option of the API (``objectives``), two spellings
    whose order of occurrence is the lexicographic order."""
    return Option(
        "objectives",
        ("--minimize", "--maximize"),
        Kind.OBJECTIVES,
        minimize_help + "\n" + maximize_help,
        metavar="EXPR",
    )


# ====================================================================== queries


class Operation:
    """What a query and a target (:class:`catc.targets.base.Target`) share: named options
    that every interface reads, and the ``run`` they feed (a mixin of those records)."""

    __slots__ = ()
    options: tuple[Option, ...]

    def option(self, name: str) -> Option:
        for o in self.options:
            if o.name == name:
                return o
        raise KeyError(name)

    def defaults(self) -> dict[str, Any]:
        return {o.name: o.default for o in self.options}

    def run_options(self, values: Mapping[str, Any]) -> dict[str, Any]:
        """The keyword arguments of ``run`` among ``values`` (an option's name → value)."""
        return {o.name: values[o.name] for o in self.options if o.use is Use.RUN and o.name in values}


class Query(Operation, Record):
    """A query as every interface sees it.

    ``run(instance, **options)`` answers it (``options``: those with ``use=Use.RUN``, plus
    ``progress`` when ``progress`` is true); ``check(instance, options)`` returns why the
    options cannot be used with this instance (an input error), or None; ``to_json(instance,
    result)`` is the ``--json`` document; ``render(console, instance, result, options)``
    prints the human answer (``options``: every option's value, outputs included);
    ``artifacts(instance, result, options)`` writes the files the output options ask for
    (by default ``--diagram``: the composition as SVG) and returns what to tell the user.
    Its failures are :class:`InputError` s.  ``objective_texts(options)``: the ``(sense,
    text)`` objective terms the query's input files carry (a certificate of ``--minimize``
    objectives); the interface checks them against the model as it does ``--minimize``'s
    and passes them to ``run`` as ``objectives`` (only the interfaces may parse text)."""

    __slots__ = (
        "name",
        "summary",
        "description",
        "options",
        "run",
        "to_json",
        "render",
        "check",
        "artifacts",
        "progress",
        "schema",
        "objective_texts",
    )
    name: str
    summary: str
    description: str
    options: tuple[Option, ...]
    run: Callable[..., Result]
    to_json: Callable[[ir.Instance, Any], dict]
    render: Callable[[Any, ir.Instance, Any, Mapping[str, Any]], None]
    check: Callable[[ir.Instance, Mapping[str, Any]], str | None] | None
    artifacts: Callable[[ir.Instance, Any, Mapping[str, Any]], list[str]]
    progress: bool
    schema: str
    objective_texts: Callable[[Mapping[str, Any]], Sequence[tuple[str, str]]] | None

    def __init__(
        self,
        name: str,
        *,
        summary: str,
        description: str,
        options: tuple[Option, ...],
        run: Callable[..., Result],
        to_json: Callable[[ir.Instance, Any], dict],
        render: Callable[[Any, ir.Instance, Any, Mapping[str, Any]], None],
        check: Callable[[ir.Instance, Mapping[str, Any]], str | None] | None = None,
        artifacts: Callable[[ir.Instance, Any, Mapping[str, Any]], list[str]] | None = None,
        progress: bool = False,
        objective_texts: Callable[[Mapping[str, Any]], Sequence[tuple[str, str]]] | None = None,
    ) -> None:
        set_field(self, "name", name)
        set_field(self, "summary", summary)
        set_field(self, "description", description)
        if progress:
            options = (*options, progress_option())
        set_field(self, "options", common_options() + options)
        set_field(self, "run", run)
        set_field(self, "to_json", to_json)
        set_field(self, "render", render)
        set_field(self, "check", check)
        set_field(self, "artifacts", artifacts or diagram_artifact)
        set_field(self, "progress", progress)
        set_field(self, "schema", f"catc.{name}/1")
        set_field(self, "objective_texts", objective_texts)


def diagram_artifact(inst: ir.Instance, result: Any, options: Mapping[str, Any]) -> list[str]:
    """``--diagram FILE``: the result's composition (``result.plan``) as an SVG string diagram."""
    path = options.get("diagram")
    plan = getattr(result, "plan", None)
    if not path or plan is None:
        return []
    from catc.present.diagram import render_svg

    svg = render_svg(inst, plan, states=list(result.states), title=f"{inst.problem.name} ({inst.domain.name})")
    try:
        with open(path, "w", encoding="utf-8") as out:
            out.write(svg)
    except OSError as exc:
        raise InputError(f"cannot write the diagram to {path}: {exc.strerror or exc}", code=codes.CANNOT_WRITE) from exc
    return [f"diagram written to {path}"]


def unknown_why(reason: str | None) -> str:
    """Why an answer is unknown, in the words solve uses ("the solver gave up (timeout)")."""
    return f"the solver gave up ({reason})" if reason else "the solver gave up"
