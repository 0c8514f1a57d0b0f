"""``catc bench``: the command line — check the baseline is installed, choose the problems and
tables, run the session in a work folder, print Markdown or JSON."""

from __future__ import annotations

import json
import shlex
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any, NoReturn

import click

from catc.bench.lifelong import query_rows
from catc.bench.machine import machine
from catc.bench.problems import (
    LIFELONG_BUDGET_CUT,
    PERTURBATIONS,
    QUICK_PERTURBATIONS,
    QUICK_RUNTIME_ROWS,
    RUNTIME_ROWS,
    SAR_BUDGET_CUT,
)
from catc.bench.runners import BenchInputError
from catc.bench.session import Bench
from catc.bench.tables import TABLES, jsonable, markdown
from catc.interfaces.command import EXIT_INPUT


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
        file = getattr(mod, "__file__", None)
        if file:
            dirs.append(str(Path(file).parent))
    if dirs:
        subprocess.run([sys.executable, "-m", "compileall", "-q", *dirs], capture_output=True, check=False)


CORPORA = ("all", "wheel", "planning")


def default_examples() -> Path:
    return Path(__file__).resolve().parents[3] / "examples"


@dataclass
class _Selection:
    """What to run: the runtime rows, the perturbations, every problem to measure, the queries."""

    runtime_files: list[str]
    perturbations: list[tuple[str, str, str]]
    measure: list[str]
    queries: bool
    sar_queries: bool
    no_answers: tuple[str, ...] = ()  # the certificates table: paths containing one of these ("": all)

    @classmethod
    def of(cls, quick: bool, only: tuple[str, ...], tables: tuple[str, ...]) -> _Selection:
        def keep(f: str) -> bool:
            return not only or any(t in f for t in only)

        rt_files = [f for f in (QUICK_RUNTIME_ROWS if quick else RUNTIME_ROWS) if keep(f)]
        perts = [p for p in PERTURBATIONS if (not quick or p[0] in QUICK_PERTURBATIONS) and (keep(p[1]) or keep(p[2]))]
        measure = list(rt_files) if "runtimes" in tables else []
        if "perturbations" in tables:
            measure += [t for _, b, t in perts for t in (b, t) if t not in measure]
        return cls(
            rt_files,
            perts,
            measure,
            "queries" in tables and keep(LIFELONG_BUDGET_CUT),
            not quick and keep(SAR_BUDGET_CUT),
            (LIFELONG_BUDGET_CUT,) if quick else (only or ("",)),
        )


def _command_text(runs: int) -> str:
    """The command line as typed (``catc bench ...``), for the report's header."""
    argv = (
        ["catc", "bench"] + sys.argv[2:]
        if len(sys.argv) > 1 and sys.argv[1] == "bench"
        else ["catc", "bench", f"--runs {runs}"]
    )
    return " ".join(shlex.quote(a) if " " not in a else a for a in argv)


def _input_error(exc: Exception | str) -> NoReturn:
    click.echo(f"error: {exc}", err=True)
    sys.exit(EXIT_INPUT)


def _log(msg: str) -> None:
    click.echo(f"[bench] {msg}", err=True)


def _document(bench: Bench, sel: _Selection, tables: tuple[str, ...], command: str) -> dict[str, Any]:
    """Measure, then the catc.bench/1 document (the perturbation and query rows run their own tools)."""
    bench.measure(sel.measure)
    return {
        "schema": "catc.bench/1",
        "command": command,
        "machine": machine(),
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "runs": bench.runs,
        "smtplan": bench.smtplan or "not installed",
        "runtimes": bench.runtime_rows(sel.runtime_files) if "runtimes" in tables else None,
        "perturbations": bench.perturbation_rows(sel.perturbations) if "perturbations" in tables else None,
        "queries": query_rows(bench, include_sar=sel.sar_queries) if sel.queries else None,
        "certificates": _certificates(bench, sel.no_answers) if "certificates" in tables else None,
    }


def _certificates(bench: Bench, keep: tuple[str, ...]) -> list[dict[str, Any]]:
    """The certificates table: the final UNSATs of the examples, answered and certified."""
    from catc.bench.certificates import certificate_rows

    return certificate_rows(bench.examples, bench.runs, bench.timeout, bench.workdir, bench.log, keep)


def _run(
    examples: Path, runs: int, timeout: float, keep_dir: str | None, sel: _Selection, tables: tuple[str, ...]
) -> dict[str, Any]:
    """The document, measured in ``keep_dir`` (kept) or a temporary folder; input errors exit 2."""
    from catc.targets.enhsp import BaselineMissing
    from catc.targets.pddl import ExportError

    command = _command_text(runs)
    tmp = None
    if keep_dir:
        work = Path(keep_dir)
        work.mkdir(parents=True, exist_ok=True)
    else:
        tmp = tempfile.TemporaryDirectory(prefix="catc-bench-")
        work = Path(tmp.name)
    try:
        return _document(Bench(examples, runs, timeout, work, _log), sel, tables, command)
    except (BenchInputError, ExportError, OSError, BaselineMissing) as exc:
        _input_error(exc)
    finally:
        if tmp is not None:
            tmp.cleanup()


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
    default=None,
    help="Seconds per tool run [default: 120; 60 for the planning corpus, the limit of its table].",
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
@click.option(
    "--corpus",
    type=click.Choice(CORPORA),
    is_flag=False,
    flag_value="all",
    default=None,
    help="Instead: a PDDL corpus beside ENHSP, every plan checked by UP's validator (docs/interop.md): "
    "'wheel' (unified-planning's wheel and the counters/sailing families, imported by catc import pddl), "
    "'planning' (the planning corpus: families of growing plan length, each shortest length counted by hand), "
    "'all' (both; the default of a bare --corpus). --only, --timeout, --keep, --json and --save-json apply.",
)
@click.option(
    "--second",
    is_flag=True,
    help="With --corpus planning: also a second planner, pyperplan A*/LM-cut (classical) or TAMER (numeric) "
    "(the planners extra).",
)
def bench_command(
    runs: int,
    quick: bool,
    only: tuple[str, ...],
    tables: tuple[str, ...],
    timeout: float,
    examples_dir: str | None,
    as_json: bool,
    no_compile: bool,
    save_json: str | None,
    keep_dir: str | None,
    corpus: str | None = None,
    second: bool = False,
) -> None:
    """Run catc and ENHSP on the same example problems and print the comparison tables.

    Needs the baselines extra (up-enhsp) and Java 17.  Markers are judged against the
    examples' expect.toml.
    """
    from catc.targets.enhsp import BaselineMissing, enhsp_jar, java

    try:
        java()
        enhsp_jar()
    except BaselineMissing as exc:
        _input_error(exc)
    if corpus is not None:
        _corpus(corpus, timeout, only, keep_dir, save_json, second, as_json)
        return
    if second:
        _input_error("--second applies to the planning corpus only (catc bench --corpus planning --second)")
    timeout = 120.0 if timeout is None else timeout
    examples = Path(examples_dir) if examples_dir else default_examples()
    if not examples.is_dir():
        _input_error(f"examples folder not found: {examples} (pass --examples DIR)")
    tables = tuple(tables) or TABLES
    if not no_compile:
        byte_compile()
    doc = _run(examples, runs, timeout, keep_dir, _Selection.of(quick, only, tables), tables)
    text = json.dumps(jsonable(doc), indent=1, ensure_ascii=False)
    if save_json:
        Path(save_json).write_text(text + "\n")
    if as_json:
        click.echo(text)
    else:
        click.echo(markdown(doc))


def _corpus_command(which: str) -> str:
    """The command line as typed, or (called from Python) ``catc bench --corpus WHICH``."""
    if len(sys.argv) > 1 and sys.argv[1] == "bench":
        return " ".join(shlex.quote(a) for a in ["catc", "bench", *sys.argv[2:]])
    return f"catc bench --corpus {which}"


def _corpus(
    which: str,
    timeout: float | None,
    only: tuple[str, ...],
    keep_dir: str | None,
    save_json: str | None,
    second: bool,
    as_json: bool = False,
) -> None:
    """``--corpus``: the wheel corpus and its growth table, the planning corpus, or both
    (docs/interop.md), Markdown on stdout; a corpus that ``--only`` leaves empty is left out."""
    from catc.bench import planning
    from catc.bench.corpus import run_corpus, wheel_dir

    if wheel_dir() is None:
        _input_error("the corpora read unified-planning's test PDDL: pip install 'catc-lang[up]'")
    if second and which == "wheel":
        _input_error("--second applies to the planning corpus only (catc bench --corpus planning --second)")
    if second:
        import importlib

        try:
            for engine in ("up_pyperplan", "up_tamer"):
                importlib.import_module(engine)
        except ImportError:
            _input_error("--second runs pyperplan and TAMER: pip install 'catc-lang[planners]'")
    texts: list[str] = []
    doc: dict[str, Any] = {}
    with tempfile.TemporaryDirectory(prefix="catc-corpus-") as tmp:
        work = Path(keep_dir) if keep_dir else Path(tmp)
        work.mkdir(parents=True, exist_ok=True)
        if which in ("wheel", "all"):
            rows, text = run_corpus(work, 120.0 if timeout is None else timeout, only, log=_log)
            if rows:
                texts.append(text)
                doc["wheel"] = [
                    {k: str(v) if v is not None else None for k, v in vars(r).items() if k != "case"}
                    | {"problem": r.case.name}
                    for r in rows
                ]
        if which in ("planning", "all"):
            chosen = planning.select(only, exact=False)
            if chosen:
                prows = planning.run_tasks(
                    chosen, 60.0 if timeout is None else timeout, second=second, work=work / "planning", log=_log
                )
                texts.append(
                    "## The planning corpus\n\n"
                    + planning.markdown(prows, _corpus_command(which), smt=False, second=second)
                    + "\n"
                )
                doc["planning"] = planning.jsonable(prows)
    if not doc:
        _input_error(f"--only {' --only '.join(only)} matches no problem of the corpus")
    out: Any = doc["wheel"] if which == "wheel" else doc["planning"] if which == "planning" else doc
    text = json.dumps(out, indent=1, default=str, ensure_ascii=False)
    if save_json:
        Path(save_json).write_text(text + "\n")
    if as_json:
        click.echo(text)
    else:
        click.echo("\n".join(texts), nl=False)
