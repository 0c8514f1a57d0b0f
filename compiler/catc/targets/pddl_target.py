"""``catc export pddl``: PDDL 2.1 numeric (``--flavor enhsp``, :mod:`catc.targets.pddl`) or
PDDL+ (``--flavor smtplan``, :mod:`catc.targets.pddlplus`) domain and problem, with an export
report; the files checked by parsers catc did not write, and ``--run`` runs a planner on them.

Exit codes follow docs/cli.md: 0 written; 1 ``--run`` found no plan; 2 usage errors,
unreadable input, or a model the export refuses (e.g. a real θ without a grid step in the
enhsp flavour), and a missing ``baselines`` extra, Java or SMTPlan+ binary; 3 the planner
gave up (``--run``).
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from fractions import Fraction
from pathlib import Path
from typing import Any

from catc import ir
from catc.queries.base import ExitCode, InputError, Kind, Option, Use
from catc.targets.base import Echo, OptionError, Target, horizon_option, load_options
from catc.targets.pddl_base import Flavor
from catgrammar import codes, limits
from catgrammar.terminal import printable


class MissingParser(RuntimeError):
    """A parser the export is checked with is not installed (the 'baselines' extra)."""


def grid(specs: tuple[str, ...]) -> dict[str, Fraction]:
    """``--grid PARAM=STEP`` options → the steps, exact (:class:`OptionError` when malformed)."""
    out: dict[str, Fraction] = {}
    for spec in specs:
        name, sep, step = spec.partition("=")
        try:
            if not sep or not name:
                raise ValueError
            value = Fraction(step)
        except (ValueError, ZeroDivisionError):
            raise OptionError(
                f"expected PARAM=STEP (e.g. camera-driver.ram-req=0.25), got {spec!r}", "--grid"
            ) from None
        if value <= 0:
            raise OptionError(f"grid step must be positive, got {spec!r}", "--grid")
        out[name] = value
    return out


def prepare(values: dict[str, Any]) -> None:
    values["grid"] = grid(tuple(values.get("grid") or ()))


def _parsers_present(plus: bool, strict: bool) -> None:
    """InputError (E0706) naming the extra when a parser the check needs is missing."""
    import importlib.util

    needed = ["unified_planning"] if plus or strict else []
    needed += [] if plus else ["pddl_plus_parser"]

    def absent(name: str) -> bool:
        try:
            return importlib.util.find_spec(name) is None
        except ImportError:
            return True

    missing = [name for name in needed if absent(name)]
    if missing:
        names = " and ".join(m.replace("_", "-") for m in missing)
        raise InputError(
            f"{names} {'is' if len(missing) == 1 else 'are'} missing (the export is parsed by it before it is "
            "shown): pip install 'catc-lang[baselines]', or pass --no-check; nothing was written",
            codes.MISSING_EXTRA,
        )


def export(
    inst: ir.Instance,
    *,
    grid: Mapping[str, Fraction | int | str] | None = None,
    horizon: int | None = None,
    flavor: Flavor | str = Flavor.ENHSP,
    timeout: float | None = None,
) -> Any:
    """The :class:`catc.targets.pddl_base.Export` of ``inst`` (:class:`InputError` when the
    model cannot be exported in this flavour)."""
    from catc.targets.pddl import export_pddl
    from catc.targets.pddl_base import ExportError

    try:
        steps = {k: Fraction(v) for k, v in (grid or {}).items()}
        return export_pddl(inst, grid=steps, horizon=horizon, flavor=flavor)
    except ExportError as exc:
        raise InputError(str(exc), codes.EXPORT_UNSUPPORTED) from None


def to_json(inst: ir.Instance, ex: Any) -> dict:
    return {
        "schema": "catc.export-pddl/1",
        "flavor": Flavor(ex.flavor).value,
        "domain": ex.domain,
        "problem": ex.problem,
        "report": ex.report.markdown(f"problem {inst.problem.name} of domain {inst.domain.name}"),
        "actions": actions_json(ex),
        "dials": dials_json(ex),
    }


def render(inst: ir.Instance, ex: Any) -> str:
    return ex.domain + "\n" + ex.problem


def actions_json(ex: Any) -> dict:
    from catc.semantics.plan import value_to_json

    return {
        n: {"morphism": a.morphism, "params": {k: value_to_json(v) for k, v in a.params.items()}}
        for n, a in ex.actions.items()
    }


def dials_json(ex: Any) -> dict:
    """The smtplan flavour's dials: how to read each real θ off a timed plan."""
    from catc.semantics.plan import value_to_json

    return {
        k: {
            "morphism": d.morphism,
            "param": d.param,
            "lower": value_to_json(d.lower),
            "upper": None if d.upper is None else value_to_json(d.upper),
            "fluent": d.fluent,
            "start": d.start,
            "stop": d.stop,
            "process": d.process,
            "lock": d.lock,
            "reset": d.reset,
        }
        for k, d in ex.dials.items()
    }


def write(inst: ir.Instance, ex: Any, options: Mapping[str, Any]) -> list[str]:
    """domain.pddl, problem.pddl, report.md, actions.json (and dials.json for PDDL+).  The
    parsers that check them must be there first (nothing is written without them), unless
    ``--no-check``."""
    if not options.get("no_check"):
        _parsers_present(Flavor(options.get("flavor") or "enhsp") is Flavor.SMTPLAN, bool(options.get("strict_check")))
    limits.check_time("writing the export")
    out = Path(options["output"])
    out.mkdir(parents=True, exist_ok=True)
    dom, prob = out / "domain.pddl", out / "problem.pddl"
    dom.write_text(ex.domain)
    prob.write_text(ex.problem)
    limits.check_time("writing the export")  # (a large export: seconds of writing)
    report = ex.report.markdown(f"problem {inst.problem.name} of domain {inst.domain.name}")
    (out / "report.md").write_text(report)
    limits.check_time("writing the export")
    (out / "actions.json").write_text(json.dumps(actions_json(ex), indent=1) + "\n")
    if ex.dials:
        (out / "dials.json").write_text(json.dumps(dials_json(ex), indent=1) + "\n")
    return [
        f"wrote {dom}, {prob} ({len(ex.actions)} ground actions{f', {len(ex.dials)} dials' if ex.dials else ''}), "
        f"{out / 'report.md'}, {out / 'actions.json'}" + (f", {out / 'dials.json'}" if ex.dials else ""),
        printable(report.rstrip()),
    ]


def check_pddl(domain_file: Path, problem_file: Path, strict: bool = False) -> list[str]:
    """Parse PDDL 2.1 files (the enhsp flavour) with parsers catc did not write, from the
    ``baselines`` extra: PyPI ``pddl-plus-parser`` (numeric PDDL; lax about unknown keywords;
    ~1 s for search-and-rescue's 545 ground actions) and, when ``strict``, unified-planning's
    ``PDDLReader`` too (a misspelt keyword is an error; ~10× slower on large groundings).
    Returns what was checked.

    (The PyPI ``pddl`` package, used before, pins lark<1.2 in every release while catc
    needs lark>=1.2: it cannot be installed beside catc without a conflict.)"""
    done = []
    try:
        from pddl_plus_parser.lisp_parsers import DomainParser, ProblemParser
    except ImportError:
        raise MissingParser(
            "pddl-plus-parser is missing (it parses the export): pip install 'catc-lang[baselines]', or pass --no-check"
        ) from None
    dom = DomainParser(domain_file).parse_domain()
    ProblemParser(problem_file, dom).parse_problem()
    done.append(f"pddl-plus-parser ({len(dom.actions)} actions)")
    if strict:
        try:
            from unified_planning.io import PDDLReader
        except ImportError:
            raise MissingParser(
                "unified-planning is missing (--strict-check parses the export with it): "
                "pip install 'catc-lang[baselines]'"
            ) from None
        problem = PDDLReader().parse_problem(str(domain_file), str(problem_file))
        done.append(f"unified-planning's PDDLReader ({len(problem.actions)} actions)")
    return done


def check_pddlplus(domain_file: Path, problem_file: Path) -> list[str]:
    """Parse PDDL+ files with unified-planning's reader (which supports processes and events)
    and, when installed, PyPI ``pddl-plus-parser``; returns what was checked.

    (Processes and events are PDDL+: the enhsp flavour's :func:`check_pddl` reads PDDL 2.1.)"""
    try:
        from unified_planning.io import PDDLReader
    except ImportError:
        raise MissingParser(
            "unified-planning is missing (it parses the PDDL+ export): "
            "pip install 'catc-lang[baselines]', or pass --no-check"
        ) from None
    problem = PDDLReader().parse_problem(str(domain_file), str(problem_file))
    done = [f"unified-planning's PDDLReader ({len(problem.actions)} actions, {len(problem.processes)} processes)"]
    try:
        from pddl_plus_parser.lisp_parsers import DomainParser, ProblemParser
    except ImportError:
        done.append("pddl-plus-parser not installed: skipped (pip install 'catc-lang[baselines]')")
        return done
    dom = DomainParser(domain_file).parse_domain()
    ProblemParser(problem_file, dom).parse_problem()
    done.append(f"pddl-plus-parser ({len(dom.actions)} actions; it skips :process blocks)")
    return done


def follow(inst: ir.Instance, ex: Any, options: Mapping[str, Any], echo: Echo) -> int:
    """Parse the written files (unless ``--no-check``), then ``--run`` the planner."""

    out = Path(options["output"])
    dom, prob = out / "domain.pddl", out / "problem.pddl"
    plus = Flavor(options.get("flavor", "enhsp")) is Flavor.SMTPLAN
    if not options.get("no_check"):
        _check(plus, dom, prob, bool(options.get("strict_check")), echo)
    if not options.get("run_planner"):
        return ExitCode.OK
    left = max(0.001, limits.remaining() or options.get("timeout") or 60.0)
    if plus:
        return _run_smtplan(inst, ex, dom, prob, left, echo)
    return _run_enhsp(inst, ex, dom, prob, options.get("planner") or "sat-hadd", left, echo)


def _check(plus: bool, dom: Path, prob: Path, strict: bool, echo: Echo) -> None:
    """Parse the written files with parsers catc did not write."""
    from catgrammar.deadlines import call_within

    try:
        # the parsers never look at catc's clock: they run within the time left (issue 28)
        checked = call_within(
            "parsing the export", lambda: check_pddlplus(dom, prob) if plus else check_pddl(dom, prob, strict)
        )
    except MissingParser as exc:
        raise InputError(str(exc), codes.MISSING_EXTRA) from None
    except limits.Stopped:
        raise
    except Exception as exc:  # the parsers' own errors
        which = "a PDDL+ parser" if plus else "a PDDL parser"
        raise InputError(f"{which} rejects the export: {type(exc).__name__}: {exc}", codes.EXPORT_REJECTED) from None
    for line in checked:
        echo(f"parsed by {line}: ok" if "skipped" not in line else line, False)


def _run_enhsp(inst: ir.Instance, ex: Any, dom: Path, prob: Path, planner: str, timeout: float, echo: Echo) -> int:
    """``--run``: ENHSP on the files, its plan replayed by catc's validator."""
    from catc.semantics.validate import validate
    from catc.targets.enhsp import BaselineMissing, run_enhsp

    try:
        res = run_enhsp(dom, prob, planner=planner, timeout=timeout)
    except BaselineMissing as exc:
        raise InputError(str(exc), codes.BASELINE_UNAVAILABLE) from None
    echo(
        f"ENHSP ({planner}): {res.status.upper()} in {res.wall:.2f} s"
        + (f", {len(res.actions)} actions, metric {res.metric}" if res.status == "sat" else ""),
        False,
    )
    if res.status == "sat":
        plan = ex.plan_from_actions(res.actions)
        for i, name in enumerate(res.actions, 1):
            echo(f"  {i:3d}  {name}", False)
        rep = validate(inst, plan, horizon=len(plan), sequential=True)
        if not rep.ok:
            echo(printable("catc's validator REJECTS the plan: " + "; ".join(map(str, rep.violations[:5]))), True)
            return ExitCode.FAIL
        echo("catc's validator accepts the plan (sequential semantics)", False)
        return ExitCode.OK
    if res.status == "unsat":
        return ExitCode.FAIL
    echo(printable(res.output[-2000:]), True)
    return ExitCode.UNKNOWN


def _run_smtplan(inst: ir.Instance, ex: Any, dom: Path, prob: Path, timeout: float, echo: Echo) -> int:
    """``--run --flavor smtplan``: only with an ``SMTPlan`` executable on PATH (no package
    of SMTPlan+ exists); its timed plan is read back with exact θ and validated."""
    from catc.semantics.validate import validate
    from catc.targets.pddlplus import SMTPLAN_HINT, PlanReadError, parse_timed_plan, run_smtplan, smtplan_binary

    if smtplan_binary() is None:
        raise InputError(f"{SMTPLAN_HINT}; the files are written, --run needs the planner", codes.BASELINE_UNAVAILABLE)
    res = run_smtplan(dom, prob, timeout=timeout)
    echo(
        f"SMTPlan+: {res.status.upper()} in {res.wall:.2f} s"
        + (f", {len(res.actions)} timed actions" if res.status == "sat" else ""),
        False,
    )
    if res.status == "nosolution":
        return ExitCode.FAIL
    if res.status != "sat":
        echo(printable(res.output[-2000:]), True)
        return ExitCode.UNKNOWN
    for a in res.actions:
        echo(f"  {a.time}: ({a.name})", False)
    try:
        plan = parse_timed_plan(ex, res.plan_text)
    except PlanReadError as exc:
        echo(printable(f"error: SMTPlan+'s plan cannot be read back: {exc}"), True)
        return ExitCode.FAIL
    rep = validate(inst, plan, horizon=max(len(plan), 1), sequential=True)
    if not rep.ok:
        echo(printable("catc's validator REJECTS the plan: " + "; ".join(map(str, rep.violations[:5]))), True)
        return ExitCode.FAIL
    echo("catc's validator accepts the plan (sequential semantics)", False)
    return ExitCode.OK


_VIEW, _PATH, _PROBLEM = load_options("Export this view (overrides the problem's (:view ...)).")

OPTIONS = (
    Option(
        "output",
        ("-o", "--output"),
        Kind.OUTPUT_FOLDER,
        "Folder for domain.pddl, problem.pddl, report.md and actions.json.",
        use=Use.OUTPUT,
        required=True,
    ),
    Option(
        "grid",
        ("--grid",),
        Kind.TEXTS,
        "Grid step for a real θ (MORPHISM.PARAM or PARAM); repeatable. Required for every real θ "
        "in the enhsp flavour; optional in the smtplan flavour (a θ without a step becomes a PDDL+ dial).",
        default=(),
        metavar="PARAM=STEP",
    ),
    Option(
        "flavor",
        ("--flavor",),
        Kind.CHOICE,
        "enhsp: PDDL 2.1 numeric planning (ENHSP); smtplan: PDDL+ for SMTPlan+ (docs/export.md).",
        default=Flavor.ENHSP.value,
        choices=tuple(f.value for f in Flavor),
        show_default=True,
    ),
    horizon_option("Bound the number of (sequential) actions with a counter."),
    _VIEW,
    _PATH,
    _PROBLEM,
    Option(
        "no_check",
        ("--no-check",),
        Kind.FLAG,
        "Do not parse the written files (with pddl-plus-parser, and unified-planning's reader for PDDL+: the "
        "'baselines' extra).",
        use=Use.OUTPUT,
    ),
    Option(
        "strict_check",
        ("--strict-check",),
        Kind.FLAG,
        "Also parse a PDDL 2.1 export with unified-planning's reader, strict about keywords (slow on large "
        "groundings).",
        use=Use.OUTPUT,
    ),
    Option(
        "run_planner",
        ("--run",),
        Kind.FLAG,
        "Run ENHSP (enhsp) or an SMTPlan binary on PATH (smtplan) and validate its plan with catc's validator.",
        use=Use.OUTPUT,
    ),
    Option(
        "planner",
        ("--planner",),
        Kind.NAME,
        "ENHSP -planner configuration (e.g. opt-blind).",
        default="sat-hadd",
        show_default=True,
        use=Use.OUTPUT,
    ),
    Option(
        "timeout",
        ("--timeout",),
        Kind.SECONDS,
        "Seconds for the whole command: the export, the parsers' check and the planner (--run).",
        default=60.0,
        show_default=True,
    ),
)

TARGET = Target(
    "pddl",
    summary="Write PROBLEM (or DOMAIN PROBLEM) as PDDL planning files.",
    description="--flavor enhsp: PDDL 2.1 numeric planning, real parameters θ discretised on --grid.\n"
    "--flavor smtplan: PDDL+ for SMTPlan+, a real θ without a --grid step is exact (a dial:\n"
    "a fluent raised by a process; docs/export.md).  Whatever PDDL cannot express (holes,\n"
    "soft constraints, reserve values, parallel steps, ...) is listed in report.md.",
    options=OPTIONS,
    run=export,
    to_json=to_json,
    render=render,
    write=write,
    follow=follow,
    prepare=prepare,
)
