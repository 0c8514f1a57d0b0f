"""``catrt``: the runtime's command line (docs/runtime.md).

    catrt init STATE [DOMAIN] PROBLEM     a new state folder for a model
    catrt run STATE [--events -|FILE|DIR] the lifelong loop
    catrt event STATE FILE|-              queue events for the running loop (or the next run)
    catrt approve STATE ID [--reject]     answer a pending request
    catrt status STATE                    the model, A₀, pending requests, the last decision
    catrt journal STATE                   every event and decision
    catrt replay STATE                    rebuild the state from the journal and compare
    catrt verify STATE                    integrity, journal, replay, artifacts
    catrt serve STATE [--port N]          the operator console in the browser

Exit codes: 0 done; 1 ``replay``/``verify`` found a problem; 2 input error (a bad argument,
event file or configuration, no store, a store that is locked or of another version); 130
interrupted.  Errors are one line ``WHERE: error[CODE]: message``; no traceback.
"""

from __future__ import annotations

import contextlib
import json
import os
import signal
import sys
import threading
import time
from pathlib import Path
from typing import Any, NoReturn

import click

from catgrammar import codes
from catgrammar.terminal import printable


def echo(text: str, err: bool = False) -> None:
    """Print a line with nothing in it that could drive the terminal (an event's text, a
    path or a message may hold escape sequences); JSON is ASCII already."""
    click.echo(printable(text), err=err)


EXIT_PROBLEM, EXIT_INPUT = 1, 2


def fail(code: str, message: str, where: str = "catrt") -> NoReturn:
    echo(f"{where}: error[{code}]: {message}", err=True)
    sys.exit(EXIT_INPUT)


def _need_extra() -> None:
    for module in ("yaml", "jsonschema"):
        try:
            __import__(module)
        except ImportError:
            fail("E0706", "catrt needs the 'runtime' extra: pip install 'catc-lang[runtime]'")


def open_store(state: str, write: bool) -> Any:
    from catrt.store import Store, StoreError

    try:
        return Store.open(Path(state), write=write)
    except StoreError as exc:
        fail(exc.code, str(exc))


class _Group(click.Group):
    def format_commands(self, ctx: click.Context, formatter: click.HelpFormatter) -> None:
        """Each command's first sentence whole (click cuts it at the terminal's width: "print...")."""
        rows = []
        for name in self.list_commands(ctx):
            cmd = self.get_command(ctx, name)
            if cmd is not None and not cmd.hidden:
                rows.append((name, cmd.get_short_help_str(limit=1000)))
        if rows:
            with formatter.section("Commands"):
                formatter.write_dl(rows)

    def invoke(self, ctx: click.Context) -> Any:
        try:
            return super().invoke(ctx)
        except (click.exceptions.Exit, click.ClickException, click.exceptions.Abort, SystemExit):
            raise
        except KeyboardInterrupt:
            echo("interrupted", err=True)
            sys.exit(130)
        except Exception as exc:
            _store_fault(exc)  # a damaged store, a full disk met mid-command: its own code, never exit 70
            if os.environ.get("CATRT_DEBUG"):
                raise
            echo(f"catrt: internal error: {type(exc).__name__}: {exc}", err=True)
            sys.exit(70)


def _store_fault(exc: Exception) -> None:
    """Exit with the store fault's own code (E1014, E1016, a StoreError's) when ``exc`` is one."""
    import sqlite3

    from catrt.store import StoreError

    if isinstance(exc, StoreError):
        fail(exc.code, str(exc))
    if isinstance(exc, (sqlite3.OperationalError, OSError)) and (
        "disk is full" in str(exc) or getattr(exc, "errno", None) == 28  # ENOSPC
    ):
        fail(codes.DISK_FULL, f"the disk is full: {exc}; the event was not acknowledged")
    if isinstance(exc, OSError) and exc.errno == 30:  # EROFS: a read-only file system or bind mount
        fail(codes.STATE_READ_ONLY, f"the state folder is read-only: {exc}")
    if isinstance(exc, sqlite3.DatabaseError):
        fail(codes.STORE_DAMAGED, f"the store cannot be read: {exc}; run catrt verify, restore it from a backup")


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="catc-lang", prog_name="catrt")
def main() -> None:
    """The catc runtime: a persistent model and the lifelong recomposition loop."""


# ---------------------------------------------------------------- init


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.argument("paths", nargs=-1, required=True, type=click.Path())
@click.option("--problem", "problem_name", help="The problem to use when the file defines several.")
@click.option(
    "--path", "search_paths", multiple=True, type=click.Path(file_okay=False), help="Extra folder for domains."
)
@click.option("--config", "config_file", type=click.Path(dir_okay=False, exists=True), help="Use this config.toml.")
def init(state: str, paths: tuple[str, ...], problem_name: str | None, search_paths: tuple[str, ...],
         config_file: str | None) -> None:  # fmt: skip
    """A new state folder for the model in [DOMAIN] PROBLEM."""
    _need_extra()
    from catc.api import CatError
    from catrt.create import create
    from catrt.store import StoreError

    if len(paths) > 2:
        raise click.UsageError("give PROBLEM or DOMAIN PROBLEM")
    problem, domain = (paths[-1], paths[0] if len(paths) == 2 else None)
    config_text = Path(config_file).read_text(encoding="utf-8") if config_file else None
    try:
        store = create(Path(state), problem, domain, problem_name=problem_name, search_paths=search_paths,
                       config_text=config_text)  # fmt: skip
    except CatError as exc:
        echo(str(exc), err=True)
        sys.exit(EXIT_INPUT)
    except StoreError as exc:
        fail(exc.code, str(exc))
    model = store.get("model")
    store.close()
    from catrt.console.token import write_token

    write_token(Path(state))  # catrt serve's token (mode 0600)
    echo(f"initialised {state}: problem {model['problem']['name']} of domain {model['problem']['domain']}; "
               f"start the loop with: catrt run {state}")  # fmt: skip


# ---------------------------------------------------------------- run


def _say(as_json: bool) -> Any:
    from catrt.runtime import Status

    def say(o: Any) -> None:
        if as_json:
            doc = {"status": o.status, "event": o.event_id, "where": o.where, "message": o.message,
                   "generation": o.generation, "seq": o.seq,
                   "decision": o.decision.to_json() if o.decision is not None else None,
                   "enactment_error": o.enactment.message if o.enactment is not None else None}  # fmt: skip
            echo(json.dumps(doc))
            return
        took = sum(o.timings.values()) if o.timings else None
        head = f"{o.where}: " + (f"{o.event_id}: " if o.event_id and o.event_id != o.where else "")
        tail = f"  [{took:.2f} s]" if took is not None and o.decision is not None else ""
        stream_err = o.status is Status.REJECTED
        echo(f"{head}{o.status}: {o.message}{tail}", err=stream_err)
        if o.enactment is not None:
            echo(f"{o.enactment.where}: {o.enactment.message}", err=True)

    return say


def _live_view() -> Any:
    """The live view on a terminal (catrt.live)."""
    from rich.console import Console

    from catrt.live import LiveView

    return LiveView(Console())


def _ask(request: dict[str, Any]) -> bool:
    """y/N on the controlling terminal (standard input may be the events)."""
    proposal = request["proposal"]
    said = ", ".join(f"{k} → {v}" for k, v in proposal.get("set", {}).items())
    try:
        with open("/dev/tty", "w", encoding="utf-8") as out, open("/dev/tty", encoding="utf-8") as answer:
            out.write(f"\nrequest {request['id']}: restore the model by {said}? [y/N] ")
            out.flush()
            return answer.readline().strip().lower() in ("y", "yes")
    except OSError:
        return False


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.option("--events", "source", default=None, metavar="-|FILE|DIR|mqtt://[USER@]HOST[:PORT]/TOPIC",
              help="Where events come from: - (standard input), a file, a spool folder (default STATE/spool), or an "
                   "MQTT topic (the 'mqtt' extra).")  # fmt: skip
@click.option("--once", is_flag=True, help="With a spool folder: handle what is there, then stop.")
@click.option("--approve", "approve", type=click.Choice(["auto", "never", "ask"]), default=None,
              help="Requests for a person: approve at once, never (wait for an approve event), or ask on the terminal "
                   "(default: ask on a terminal, else never).")  # fmt: skip
@click.option(
    "--enactor", type=click.Choice(["dry", "compose"]), default=None, help="Default: the configuration's (dry)."
)
@click.option("--allow-shell", is_flag=True, help="Run the shell sensors the configuration declares.")
@click.option("--json", "as_json", is_flag=True, help="One JSON document per outcome on standard output.")
def run(state: str, source: str | None, once: bool, approve: str | None, enactor: str | None, allow_shell: bool,
        as_json: bool) -> None:  # fmt: skip
    """The lifelong loop: take events, decide, enact, until the events end (- or FILE) or a
    signal (a spool folder, an MQTT topic)."""
    _need_extra()
    from catrt.config import ConfigError, load_config
    from catrt.loop import loop
    from catrt.mqtt import MqttError
    from catrt.runtime import Crash, Runtime, no_crash

    folder = Path(state)
    store = open_store(state, write=True)
    try:
        config = load_config(folder)
    except ConfigError as exc:
        store.close()
        fail("E1007", str(exc))
    if config.sensors and not allow_shell:
        store.close()
        fail("E1008", f"{folder / 'config.toml'} declares {len(config.sensors)} shell sensor(s) "
                      f"({', '.join(s.name for s in config.sensors)}); they run commands on this machine, so "
                      "catrt runs them only when started with --allow-shell")  # fmt: skip
    mode = approve or ("ask" if sys.stdin.isatty() and source != "-" else "never")
    view = _live_view() if not as_json and sys.stdout.isatty() else None
    say, ask = (view.say, view.asking(_ask)) if view is not None else (_say(as_json), _ask)
    crash = os.environ.get("CATRT_CRASH_AT")  # the crash tests (docs/runtime.md)
    try:
        runtime = Runtime(folder, store, config, enactor=enactor, approve=mode, say=say, ask=ask,
                          crash=Crash(crash) if crash else no_crash)  # fmt: skip
    except BaseException:
        store.close()
        raise
    stop = threading.Event()
    try:
        if view is not None:
            view.runtime = runtime
        with view if view is not None else contextlib.nullcontext():
            loop(runtime, source, once=once, stop=stop, sensors=config.sensors if allow_shell else ())
    except MqttError as exc:  # no paho-mqtt (E0706), a malformed address or no broker there (E0701)
        fail(exc.code, str(exc), str(source))
    except FileNotFoundError as exc:  # --events names nothing: a typo, not a new spool folder
        fail(codes.BAD_ARGUMENT, f"{exc}; give -, an events file, a spool folder or an mqtt:// address")
    finally:
        runtime.close()


# ---------------------------------------------------------------- event, approve


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.argument("file", type=click.Path(dir_okay=False, allow_dash=True))
def event(state: str, file: str) -> None:
    """Queue the events of FILE (one JSON object a line; - for standard input) for the loop:
    checked first, then put into STATE/spool as one file; none is queued if one is bad."""
    _need_extra()
    from catrt.events import EventError, parse_event, read_lines
    from catrt.spool import drop

    open_store(state, write=False).close()
    from catrt.loop import stdin_text

    stream = stdin_text() if file == "-" else open(file, encoding="utf-8", errors="surrogateescape")  # noqa: SIM115
    with stream:
        lines = list(read_lines(stream, "<stdin>" if file == "-" else file))
    bad = 0
    for where, line in lines:
        try:
            parse_event(line, where)
        except EventError as exc:
            echo(f"{exc.where}: error[E1001]: {exc.message}", err=True)
            bad += 1
    if bad:
        echo(f"{bad} bad event(s): nothing queued", err=True)
        sys.exit(EXIT_INPUT)
    path = drop(Path(state) / "spool", [line for _, line in lines])
    echo(f"queued {len(lines)} event(s) as {path}")


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.argument("request")
@click.option("--reject", is_flag=True, help="Reject the request instead.")
def approve(state: str, request: str, reject: bool) -> None:
    """Approve (or --reject) the pending request REQUEST (see catrt status)."""
    from catrt.spool import drop
    from catrt.store import DB_NAME, Verdict

    if not (Path(state) / DB_NAME).exists() and (Path(request) / DB_NAME).exists():
        fail("E1005", f"{state} holds no catrt store, but {request} does: the state folder comes first: "
                      f"catrt approve {request} {state}")  # fmt: skip
    store = open_store(state, write=False)
    pending = {a["id"] for a in store.approvals(Verdict.PENDING)}
    store.close()
    if request not in pending:
        fail("E1010", f"no pending request '{request}' (pending: {', '.join(sorted(pending)) or 'none'})")
    verb = "reject" if reject else "approve"
    line = json.dumps({"id": f"{verb}-{request}-{time.time_ns()}", verb: request})
    path = drop(Path(state) / "spool", [line])
    echo(f"queued: {verb} {request} ({path})")


# ---------------------------------------------------------------- reading


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.option("--json", "as_json", is_flag=True, help="Print a catrt.status/1 document.")
@click.option("--plan", "plan", is_flag=True, help="Also show the deployed composition: steps, components, θ.")
def status(state: str, as_json: bool, plan: bool) -> None:
    """The model, the deployed composition A₀, pending requests and the last decision."""
    from catrt.views import status_document, status_text

    store = open_store(state, write=False)
    doc = status_document(store, Path(state))
    store.close()
    echo(json.dumps(doc, indent=2) if as_json else status_text(doc, plan))


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.argument("generations", nargs=-1, type=click.IntRange(min=1))
@click.option("--json", "as_json", is_flag=True, help="Print a catc.ground-diff/1 document.")
def diff(state: str, generations: tuple[int, ...], as_json: bool) -> None:
    """What changes on the robot between two generations: GEN_A GEN_B, or GEN_B against the
    one before it, or (none given) the deployed generation against the one before it."""
    from catc.api import diff_artifacts, read_grounding
    from catrt.views import diff_text, generation_folder

    if len(generations) > 2:
        fail("E0701", "give at most two generations: catrt diff STATE [GEN_A] [GEN_B]")
    store = open_store(state, write=False)
    incumbent = store.get("incumbent")
    store.close()
    if not generations:
        if incumbent is None:
            fail("E0701", f"{state}: nothing is deployed yet: no generation to compare")
        generations = (incumbent["generation"],)
    old, new = (generations[0] - 1, generations[0]) if len(generations) == 1 else generations
    if old < 1:
        fail("E0701", f"generation {new} is the first: give two generations to compare")
    try:
        a, b = (read_grounding(str(generation_folder(Path(state), g))) for g in (old, new))
    except ValueError as exc:  # a generation folder that is not whole
        fail("E1005", str(exc))
    d = diff_artifacts(a, b)
    if as_json:
        keys = ("added", "removed", "unmount", "mount", "stop", "start", "recreate")
        doc = {"schema": "catc.ground-diff/1", "from": old, "to": new, **{k: list(getattr(d, k)) for k in keys},
               "tree_changed": d.tree_changed, "commands": d.commands()}  # fmt: skip
        echo(json.dumps(doc, indent=2))
    else:
        echo(diff_text(d, old, new))


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.option("--json", "as_json", is_flag=True, help="One JSON document per entry.")
@click.option("--since", type=click.IntRange(min=0), default=0, help="Entries after this sequence number.")
@click.option("--kind", "kinds", multiple=True, help="Only entries of this kind (repeatable).")
def journal(state: str, as_json: bool, since: int, kinds: tuple[str, ...]) -> None:
    """Every event, rejection, decision, approval, enactment and sensor run, in order."""
    from catrt.views import ENTRY_KINDS, entry_text

    for kind in kinds:
        if kind not in ENTRY_KINDS:
            from catgrammar.diagnostics import did_you_mean

            fail("E0701", f"--kind {kind!r} is not a kind of journal entry{did_you_mean(kind, ENTRY_KINDS)} "
                          f"(kinds: {', '.join(ENTRY_KINDS)})")  # fmt: skip
    store = open_store(state, write=False)
    for entry in store.entries(since, kinds):
        echo(json.dumps(entry, sort_keys=True) if as_json else entry_text(entry))
    store.close()


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.option("--json", "as_json", is_flag=True, help='Print a JSON document: {"schema", "ok", "problems", "notes"}.')
def replay(state: str, as_json: bool) -> None:
    """Rebuild the state from the journal alone; exit 1 when it differs from the stored one."""
    _need_extra()
    from catrt.replay import differences
    from catrt.replay import replay as run_replay

    store = open_store(state, write=False)
    from catrt.views import sensor_counts

    replayed = run_replay(store, Path(state))
    problems = replayed.problems + differences(store, replayed)
    notes = [f"{replayed.entries} journal entries replayed"]
    notes += [f"sensor {name}: {c['readings']} readings" for name, c in sensor_counts(store).items()]
    store.close()
    _report("replay", problems, notes, as_json)


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.option("--json", "as_json", is_flag=True, help='Print a JSON document: {"schema", "ok", "problems", "notes"}.')
def verify(state: str, as_json: bool) -> None:
    """SQLite's integrity check, a gap-free journal, the replay, every generation's files
    against its manifest; exit 1 on any problem."""
    _need_extra()
    from catrt.replay import verify as run_verify

    store = open_store(state, write=False)
    problems, notes = run_verify(store, Path(state))
    store.close()
    _report("verify", problems, notes, as_json)


@main.command()
@click.argument("state", type=click.Path(file_okay=False))
@click.option("--host", default="127.0.0.1", show_default=True, help="The address to listen on (loopback by default).")
@click.option("--port", default=8130, show_default=True, type=click.IntRange(0, 65535), help="The port.")
@click.option("--token", default=None, help="The access token (default: STATE/console-token, written by init).")
@click.option("--read-only", is_flag=True, help="Show, never write: no approvals from the browser.")
def serve(state: str, host: str, port: int, token: str | None, read_only: bool) -> None:
    """The operator console in the browser: the deployed composition, the journal, pending
    requests to approve or reject, diffs, verify (docs/runtime.md, The console)."""
    try:
        import starlette  # noqa: F401
        import uvicorn
    except ImportError:
        fail("E0706", "catrt serve needs the 'console' extra: pip install 'catc-lang[console]'")
    from catrt.console.app import make_app
    from catrt.console.token import read_token

    open_store(state, write=False).close()
    token = token or read_token(Path(state))
    if not token:
        fail("E0701", f"{state}: no console token: give --token or create STATE/console-token (catrt init writes it)")
    if host not in ("127.0.0.1", "::1", "localhost"):
        echo(f"serve: warning: listening on {host}, not loopback: anyone who can reach it and has the token can "
             "approve", err=True)  # fmt: skip
    shown = f"[{host}]" if ":" in host else host
    echo(f"catrt console{' (read-only)' if read_only else ''}: http://{shown}:{port}/?token={token}")
    uvicorn.run(make_app(Path(state), token, read_only=read_only), host=host, port=port, log_level="warning")


def _report(what: str, problems: list[str], notes: list[str], as_json: bool) -> None:
    if as_json:
        echo(json.dumps({"schema": f"catrt.{what}/1", "ok": not problems, "problems": problems, "notes": notes},
                              indent=2))  # fmt: skip
    else:
        for p in problems:
            echo(f"{what}: error[E1012]: {p}", err=True)
        for n in notes:
            echo(f"{what}: note: {n}")
        echo(f"{what}: {'ok' if not problems else f'{len(problems)} problem(s)'}")
    sys.exit(EXIT_PROBLEM if problems else 0)


def entry() -> None:
    signal.signal(signal.SIGPIPE, signal.SIG_DFL)
    main()
