"""The console's web app: pages built on the server from the store, a small script for live
updates (server-sent events), the token on every request, a CSRF value on every form.

No value from the browser names a path: generations are numbers, requests are checked
against the store's pending ones, static files come from this package only.
"""

from __future__ import annotations

import asyncio
import json
import secrets
import time
from collections.abc import AsyncIterator, Awaitable, Callable
from html import escape
from pathlib import Path
from typing import Any

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.base import BaseHTTPMiddleware
from starlette.requests import Request
from starlette.responses import HTMLResponse, JSONResponse, RedirectResponse, Response, StreamingResponse
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from catrt.console.token import csrf_for, same

COOKIE = "catrt_console"
STATIC = Path(__file__).parent / "static"


class Console:
    """What the routes share: the state folder, the token, the mode, the diagram cache."""

    def __init__(self, folder: Path, token: str, read_only: bool, poll: float = 1.0) -> None:
        self.folder, self.token, self.read_only, self.poll = folder, token, read_only, poll
        self.secret = secrets.token_bytes(32)
        self.csrf = csrf_for(self.secret, token)
        self._diagrams: dict[tuple[int, str], str] = {}

    def store(self) -> Any:
        from catrt.store import Store

        return Store.open(self.folder, write=False)


# ---------------------------------------------------------------- security


class _Guard(BaseHTTPMiddleware):
    """The token on every request: ``?token=`` once (it is then kept in a cookie and the address
    is cleaned), the cookie, or ``Authorization: Bearer``.  None: 401; a wrong one: 403."""

    def __init__(self, app: Any, console: Console) -> None:
        super().__init__(app)
        self.console = console

    async def dispatch(self, request: Request, call_next: Callable[[Request], Awaitable[Response]]) -> Response:
        token = self.console.token
        given = request.query_params.get("token")
        if given is not None:
            if not same(given, token):
                return _refused(403, "wrong token")
            clean = request.url.remove_query_params("token")
            response: Response = RedirectResponse(str(clean.path) + (f"?{clean.query}" if clean.query else ""), 303)
            response.set_cookie(COOKIE, token, httponly=True, samesite="strict", path="/")
            return response
        header = request.headers.get("authorization", "")
        given = header[7:] if header.lower().startswith("bearer ") else request.cookies.get(COOKIE)
        if given is None:
            return _refused(401, "a token is needed: open the address catrt serve printed")
        if not same(given, token):
            return _refused(403, "wrong token")
        response = await call_next(request)
        response.headers["X-Frame-Options"] = "DENY"
        response.headers["Content-Security-Policy"] = (
            "default-src 'none'; script-src 'self'; style-src 'self' 'unsafe-inline'; img-src 'self' data:; "
            "connect-src 'self'; form-action 'self'; frame-ancestors 'none'"
        )
        response.headers["Referrer-Policy"] = "no-referrer"
        return response


def _refused(status: int, why: str) -> Response:
    return HTMLResponse(_page("refused", f"<p class='error'>{escape(why)}</p>"), status)


def _writable(console: Console, request: Request, form: Any) -> Response | None:
    """None when a form may write; else the refusal (read-only console, CSRF value missing or wrong)."""
    if console.read_only:
        return _refused(403, "this console is read-only (catrt serve --read-only)")
    if not same(form.get("csrf"), console.csrf):
        return _refused(403, "the form's CSRF value is missing or wrong: reload the page")
    return None


# ---------------------------------------------------------------- pages


def _page(title: str, body: str, seq: int | None = None) -> str:
    nav = " · ".join(
        f"<a href='{href}'>{name}</a>"
        for href, name in (("/", "deployed"), ("/journal", "journal"), ("/diff", "diff"), ("/verify", "verify"))
    )
    live = f" data-seq='{seq}'" if seq is not None else ""
    return (
        "<!doctype html><html lang='en'><head><meta charset='utf-8'>"
        "<meta name='viewport' content='width=device-width, initial-scale=1'>"
        f"<title>catrt · {escape(title)}</title><link rel='stylesheet' href='/static/console.css'>"
        f"<script src='/static/console.js' defer></script></head><body{live}>"
        f"<header><strong>catrt console</strong> <nav>{nav}</nav> <span id='live'></span></header>"
        f"<main><h1>{escape(title)}</h1>{body}</main></body></html>"
    )


def _theta(params: dict[str, Any]) -> str:
    from catrt.views import _value_text

    def text(value: Any, unit: str | None) -> str:  # a whole number comes as an int: shown with its unit too
        exact = isinstance(value, int) and not isinstance(value, bool)
        return _value_text(str(value) if exact else value, unit)

    return ", ".join(f"{escape(k)} = {escape(text(p['value'], p.get('unit')))}" for k, p in params.items())


def _composition_table(composition: dict[str, Any]) -> str:
    rows = []
    for i, step in enumerate(composition["steps"], 1):
        for j, a in enumerate(step):
            rows.append(
                f"<tr><td>{i if j == 0 else '⊗'}</td><td>{escape(a['morphism'])}</td>"
                f"<td>{escape(a['kind'] or '')}</td><td>{_theta(a['params'])}</td></tr>"
            )
    services = composition.get("services") or []
    more = f"<p>services: {escape(', '.join(services))}</p>" if services else ""
    return (
        "<table class='plan'><thead><tr><th>step</th><th>morphism</th><th>kind</th><th>θ</th></tr></thead>"
        f"<tbody>{''.join(rows)}</tbody></table>{more}"
    )


def _diagram(console: Console, store: Any, generation: int) -> str:
    """The generation's composition as catc's string diagram, drawn on the current model; a
    note when it no longer reads there (the table still shows it)."""
    from catc.api import diagram, read_plan
    from catrt.apply import Candidate, Rejection, check
    from catrt.model import ModelState
    from catrt.runtime import MODEL_FOLDER
    from catrt.views import generation_folder

    model = store.get("model")
    key = (generation, json.dumps(model, sort_keys=True))
    if key in console._diagrams:
        return console._diagrams[key]
    try:
        manifest = json.loads((generation_folder(console.folder, generation) / "manifest.json").read_text("utf-8"))
        candidate: Candidate = check(ModelState.from_json(model), store.sources(), str(console.folder / MODEL_FOLDER))
        inst = candidate.instance
        svg = diagram(inst, read_plan(inst, manifest["plan"]), title=f"generation {generation}: {inst.problem.name}")
        html = f"<figure class='diagram'>{svg}</figure>"
    except (OSError, ValueError, KeyError, Rejection) as exc:
        html = f"<p class='note'>no diagram: {escape(str(exc))}</p>"
    console._diagrams = {key: html}
    return html


def _pending_list(pending: list[dict[str, Any]]) -> str:
    if not pending:
        return "<p>no request waits for approval</p>"
    items = "".join(
        f"<li><a href='/requests/{escape(p['id'])}'>{escape(p['id'])}</a>: least restoration "
        f"{escape(_setting(p.get('set', {})))}</li>"
        for p in pending
    )
    return f"<ul class='pending'>{items}</ul>"


def _setting(values: dict[str, Any]) -> str:
    return ", ".join(f"{k} → {v}" for k, v in values.items())


async def home(request: Request) -> Response:
    console: Console = request.app.state.console
    from catrt.views import status_document

    store = console.store()
    try:
        doc = status_document(store, console.folder)
        seq = store.last_seq()
        deployed = doc["deployed"]
        if deployed is None:
            body = "<p>nothing is deployed yet</p>"
        else:
            body = f"<h2 id='generation'>generation {deployed['generation']}</h2>"
            body += _diagram(console, store, deployed["generation"])
            if deployed["composition"]:
                body += _composition_table(deployed["composition"])
    finally:
        store.close()
    m = doc["model"]
    head = (
        f"<p>problem <b>{escape(m['problem'])}</b> of domain <b>{escape(m['domain'])}</b>; "
        f"journal at entry <span id='seq'>{seq}</span></p><h2>waiting for approval</h2>{_pending_list(doc['pending'])}"
    )
    last = doc["last_decision"]
    if last:
        head += f"<p class='decision'>last decision ({escape(last['action'])}): {escape(last['reason'])}</p>"
    return HTMLResponse(_page("deployed", head + body, seq))


async def journal(request: Request) -> Response:
    console: Console = request.app.state.console
    from catrt.views import entry_text

    store = console.store()
    try:
        entries = list(store.entries())
        seq = store.last_seq()
    finally:
        store.close()
    rows = "".join(
        f"<li class='entry {escape(e['kind'])}'><span class='seq'>{e['seq']}</span> "
        f"<span class='kind'>{escape(e['kind'])}</span> <pre>{escape(entry_text(e))}</pre></li>"
        for e in reversed(entries)
    )
    return HTMLResponse(_page("journal", f"<ol class='timeline'>{rows}</ol>", seq))


async def request_page(request: Request) -> Response:
    console: Console = request.app.state.console
    from catrt.store import Verdict

    name = request.path_params["request"]
    store = console.store()
    try:
        approvals = {a["id"]: a for a in store.approvals()}
        seq = store.last_seq()
    finally:
        store.close()
    if name not in approvals:
        return HTMLResponse(_page("no such request", f"<p class='error'>no request '{escape(name)}'</p>"), 404)
    a = approvals[name]
    p = a["proposal"]
    relax = "".join(
        f"<tr><td>{escape(r['label'])}</td><td>{escape(str(r['delta']))}</td><td>{escape(str(r['weight']))}</td></tr>"
        for r in p.get("relaxations", [])
    )
    body = (
        f"<p>status: <b id='verdict'>{escape(str(a['status']))}</b></p>"
        f"<h2>core</h2><ul>{''.join(f'<li><code>{escape(c)}</code></li>' for c in p.get('core', []))}</ul>"
        f"<h2>least restoration</h2><p class='restoration'>{escape(_setting(p.get('set', {})))} "
        f"(cost {escape(str(p.get('cost', '?')))}{', proven least' if p.get('proven') else ''})</p>"
        f"<table><thead><tr><th>relaxed</th><th>by</th><th>weight</th></tr></thead><tbody>{relax}</tbody></table>"
    )
    if a["status"] == Verdict.PENDING:
        body += (
            f"<p><a href='/requests/{escape(name)}/preview' id='preview'>what approving it would deploy</a> "
            "(decided as the loop decides: a solve, some seconds)</p>"
        )
        if console.read_only:
            body += "<p class='note'>read-only console: answer with catrt approve</p>"
        else:
            body += (
                f"<form method='post' action='/requests/{escape(name)}'>"
                f"<input type='hidden' name='csrf' value='{console.csrf}'>"
                "<button name='verdict' value='approve' id='approve'>Approve</button> "
                "<button name='verdict' value='reject' id='reject'>Reject</button></form>"
            )
    queued = request.query_params.get("queued")
    if queued in ("approve", "reject"):
        body = f"<p class='queued'>queued: {queued} {escape(name)} — the loop takes it in</p>" + body
    return HTMLResponse(_page(f"request {name}", body, seq))


async def preview_page(request: Request) -> Response:
    """The diff approving a pending request would deploy, decided in memory (nothing written)."""
    console: Console = request.app.state.console
    from catrt.apply import Rejection
    from catrt.console.preview import preview
    from catrt.store import Verdict

    name = request.path_params["request"]

    def run() -> tuple[str, str | None] | None:
        store = console.store()  # SQLite: opened, used and closed in one thread
        try:
            if name not in {a["id"] for a in store.approvals(Verdict.PENDING)}:
                return None
            return preview(store, console.folder, name)
        finally:
            store.close()

    try:
        found = await asyncio.to_thread(run)
    except (Rejection, ValueError) as exc:  # ValueError: a bad config.toml (ConfigError) too
        return HTMLResponse(_page(f"request {name}: preview", f"<p class='error'>{escape(str(exc))}</p>"), 409)
    if found is None:
        return HTMLResponse(_page("not pending", f"<p class='error'>no pending request '{escape(name)}'</p>"), 404)
    reason, diff = found
    body = f"<p class='decision'>the loop would decide: {escape(reason)}</p>"
    body += f"<pre class='diff'>{escape(diff)}</pre>" if diff else "<p>nothing would be deployed</p>"
    body += f"<p><a href='/requests/{escape(name)}'>back to the request</a></p>"
    return HTMLResponse(_page(f"request {name}: what approving it would deploy", body))


async def answer(request: Request) -> Response:
    """Approve or reject: one line in the spool, as ``catrt approve`` writes it."""
    console: Console = request.app.state.console
    from catrt.spool import drop
    from catrt.store import Verdict

    form = await request.form()
    refused = _writable(console, request, form)
    if refused is not None:
        return refused
    verb = form.get("verdict")
    if verb not in ("approve", "reject"):
        return _refused(400, "verdict must be approve or reject")
    name = request.path_params["request"]
    store = console.store()
    try:
        pending = {a["id"] for a in store.approvals(Verdict.PENDING)}
    finally:
        store.close()
    if name not in pending:
        return HTMLResponse(_page("not pending", f"<p class='error'>no pending request '{escape(name)}'</p>"), 409)
    drop(console.folder / "spool", [json.dumps({"id": f"{verb}-{name}-{time.time_ns()}", str(verb): name})])
    return RedirectResponse(f"/requests/{name}?queued={verb}", 303)


def _generations(console: Console) -> list[int]:
    root = console.folder / "generations"
    return sorted(int(p.name) for p in root.iterdir() if p.name.isdigit()) if root.is_dir() else []


async def diff_page(request: Request) -> Response:
    console: Console = request.app.state.console
    from catc.api import diff_artifacts, read_grounding
    from catrt.views import diff_text, generation_folder

    generations = _generations(console)
    try:
        a = int(request.query_params.get("a", generations[-2] if len(generations) > 1 else 0))
        b = int(request.query_params.get("b", generations[-1] if generations else 0))
    except ValueError:
        return _refused(400, "generations are numbers")
    options = "".join(f"<option>{g}</option>" for g in generations)
    form = (
        f"<form method='get' action='/diff'><label>from <input name='a' value='{a}' list='gens' size='4'></label> "
        f"<label>to <input name='b' value='{b}' list='gens' size='4'></label> <button>compare</button>"
        f"<datalist id='gens'>{options}</datalist></form>"
    )
    if a not in generations or b not in generations:
        note = (
            "two generations are needed"
            if len(generations) < 2
            else f"generations are {generations[0]}..{generations[-1]}"
        )
        return HTMLResponse(_page("diff", form + f"<p class='note'>{escape(note)}</p>"), 200 if a == b == 0 else 404)
    try:
        d = diff_artifacts(*(read_grounding(str(generation_folder(console.folder, g))) for g in (a, b)))
    except ValueError as exc:
        return HTMLResponse(_page("diff", form + f"<p class='error'>{escape(str(exc))}</p>"), 409)
    return HTMLResponse(_page(f"diff {a} → {b}", form + f"<pre class='diff'>{escape(diff_text(d, a, b))}</pre>"))


async def verify_page(request: Request) -> Response:
    console: Console = request.app.state.console
    if request.query_params.get("run") != "1":
        body = "<p>check the store's integrity, the journal, the replay and every generation's files</p>"
        return HTMLResponse(
            _page("verify", body + "<form method='get'><button name='run' value='1'>verify now</button></form>")
        )
    from catrt.replay import verify

    def run() -> tuple[list[str], list[str]]:
        store = console.store()  # SQLite: opened, used and closed in one thread
        try:
            return verify(store, console.folder)
        finally:
            store.close()

    problems, notes = await asyncio.to_thread(run)
    verdict = "ok" if not problems else f"{len(problems)} problem(s)"
    items = "".join(f"<li class='error'>{escape(p)}</li>" for p in problems) + "".join(
        f"<li>{escape(n)}</li>" for n in notes
    )
    return HTMLResponse(_page("verify", f"<p id='verdict'>verify: {escape(verdict)}</p><ul>{items}</ul>"))


async def status_json(request: Request) -> Response:
    console: Console = request.app.state.console
    from catrt.views import status_document

    store = console.store()
    try:
        return JSONResponse(status_document(store, console.folder))
    finally:
        store.close()


async def events(request: Request) -> Response:
    """Server-sent events: the journal's last sequence number, each time it moves (polled);
    ``?once=1`` ends the stream after the first."""
    console: Console = request.app.state.console
    once = request.query_params.get("once") == "1"

    def last_seq() -> int:
        store = console.store()
        try:
            return int(store.last_seq())
        finally:
            store.close()

    async def stream() -> AsyncIterator[str]:
        seen = -1
        while True:
            seq = await asyncio.to_thread(last_seq)
            if seq != seen:
                seen = seq
                yield f"event: seq\ndata: {seq}\n\n"
                if once:
                    return
            if await request.is_disconnected():
                return
            await asyncio.sleep(console.poll)

    return StreamingResponse(stream(), media_type="text/event-stream", headers={"Cache-Control": "no-store"})


def make_app(folder: Path, token: str, *, read_only: bool = False, poll: float = 1.0) -> Starlette:
    console = Console(folder, token, read_only, poll)
    app = Starlette(
        routes=[
            Route("/", home),
            Route("/journal", journal),
            Route("/requests/{request:str}", request_page, methods=["GET"]),
            Route("/requests/{request:str}", answer, methods=["POST"]),
            Route("/requests/{request:str}/preview", preview_page),
            Route("/diff", diff_page),
            Route("/verify", verify_page),
            Route("/status.json", status_json),
            Route("/events", events),
            Mount("/static", StaticFiles(directory=STATIC), name="static"),
        ],
        middleware=[Middleware(_Guard, console=console)],
    )
    app.state.console = console
    return app
