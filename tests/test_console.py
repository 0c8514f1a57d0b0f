"""catrt serve, the operator console (docs/runtime.md, The console), through Starlette's
TestClient: every route, and the security rules (the token, CSRF, read-only, no path out of
the store).  The SAR mission is driven to its second request (r2: the dark room), approved
from the console, and the loop's next run deploys the composition expect.toml names."""

from __future__ import annotations

import html
import json
import stat
from pathlib import Path

import pytest
from conftest import ROOT

pytest.importorskip("starlette")
pytest.importorskip("httpx")

from starlette.testclient import TestClient
from test_runtime import catrt, journal

from catrt.console.app import make_app
from catrt.console.token import TOKEN_FILE, read_token

SAR = ROOT / "examples" / "search-and-rescue"


def sar_to_r2(folder: Path) -> None:
    """The mission's events up to IV-dark (r1 approved by its event, r2 pending)."""
    events = (SAR / "mission-events.jsonl").read_text(encoding="utf-8").splitlines()[:5]
    assert json.loads(events[-1])["id"] == "IV-dark"
    (folder.parent / "to-r2.jsonl").write_text("\n".join(events) + "\n", encoding="utf-8")
    assert catrt("init", folder, SAR / "mission.cat").returncode == 0
    res = catrt("run", folder, "--events", folder.parent / "to-r2.jsonl", "--approve", "never")
    assert res.returncode == 0, res.stderr


@pytest.fixture(scope="module")
def sar(tmp_path_factory: pytest.TempPathFactory) -> Path:
    folder = tmp_path_factory.mktemp("console") / "state"
    sar_to_r2(folder)
    return folder


def client(folder: Path, *, read_only: bool = False, token: str | None = None) -> TestClient:
    token = token or read_token(folder)
    assert token
    c = TestClient(make_app(folder, token, read_only=read_only))
    c.headers["Authorization"] = f"Bearer {token}"
    return c


def csrf_of(page: str) -> str:
    marker = "name='csrf' value='"
    assert marker in page
    return page.split(marker, 1)[1].split("'", 1)[0]


def spooled(folder: Path) -> list[dict]:
    return [json.loads(line) for p in sorted((folder / "spool").glob("*")) if p.is_file()
            for line in p.read_text(encoding="utf-8").splitlines() if line.strip()]  # fmt: skip


# ---------------------------------------------------------------- the token


def test_init_writes_a_token_only_its_owner_reads(sar: Path) -> None:
    path = sar / TOKEN_FILE
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert len(read_token(sar) or "") >= 32


def test_no_token_is_401_and_a_wrong_one_403_on_every_route(sar: Path) -> None:
    c = TestClient(make_app(sar, "right-token"))
    for url in ("/", "/journal", "/requests/r2", "/diff", "/verify", "/status.json", "/events", "/static/console.js"):
        assert c.get(url).status_code == 401, url
        assert c.get(url, headers={"Authorization": "Bearer wrong-token"}).status_code == 403, url
    c.cookies.set("catrt_console", "right-token-but-longer")
    for url in ("/", "/journal", "/events"):
        assert c.get(url).status_code == 403, url
    c.cookies.clear()
    assert c.get("/?token=wrong").status_code == 403
    assert c.post("/requests/r2", data={"verdict": "approve"}).status_code == 401
    assert c.post("/requests/r2", data={"verdict": "approve"}, headers={"Authorization": "Bearer x"}).status_code == 403


def test_the_token_in_the_address_becomes_a_cookie_and_leaves_the_address(sar: Path) -> None:
    c = TestClient(make_app(sar, "tok-123"))
    res = c.get("/journal?token=tok-123&x=1", follow_redirects=False)
    assert res.status_code == 303
    assert res.headers["location"] == "/journal?x=1"
    cookie = res.headers["set-cookie"]
    assert "catrt_console=tok-123" in cookie and "HttpOnly" in cookie and "samesite=strict" in cookie.lower()
    assert c.get("/journal").status_code == 200  # the cookie from now on


def test_pages_forbid_framing_and_scripts_from_elsewhere(sar: Path) -> None:
    res = client(sar).get("/")
    assert res.headers["x-frame-options"] == "DENY"
    assert "script-src 'self'" in res.headers["content-security-policy"]
    for asset in ("console.js", "console.css"):  # no CDN: nothing the assets fetch from elsewhere
        text = client(sar).get(f"/static/{asset}").text
        assert "http:" not in text and "https:" not in text and "//" not in text.replace("// ", "")


def test_no_path_from_the_browser_leaves_the_store(sar: Path) -> None:
    c = client(sar)
    for url in ("/static/../token.py", "/static/%2e%2e/app.py", "/static/..%2fapp.py", "/requests/..%2f..%2fetc"):
        res = c.get(url)
        assert res.status_code == 404, url
        assert "csrf_for" not in res.text and "def make_app" not in res.text
    assert c.get("/diff?a=../1&b=2").status_code == 400
    assert c.get("/diff?a=1&b=99").status_code == 404


# ---------------------------------------------------------------- the pages


def test_home_draws_the_deployed_generation_with_theta_and_units(sar: Path) -> None:
    manifest = json.loads((sar / "generations" / "000002" / "manifest.json").read_text(encoding="utf-8"))
    page = client(sar).get("/").text
    assert "<h2 id='generation'>generation 2</h2>" in page
    assert "<svg" in page and 'class="activation' in page  # catc's string diagram, drawn inline
    for step in manifest["plan"]["steps"]:
        for a in step:
            assert f"<td>{a['morphism']}</td>" in page
    assert "<td>return-to-range</td><td>behavior</td><td>d = 4 m</td>" in page  # expect.toml: 4 m back to base
    assert manifest["units"]["return-to-range"] == {"d": "m"}
    assert "href='/requests/r2'" in page


def test_journal_is_a_timeline_of_every_entry(sar: Path) -> None:
    page = client(sar).get("/journal").text
    entries = journal(sar)
    for e in entries:
        assert f"<span class='seq'>{e['seq']}</span> <span class='kind'>{e['kind']}</span>" in page
    assert page.index(f">{entries[-1]['seq']}</span>") < page.index(f">{entries[0]['seq']}</span>")  # newest first


def test_a_pending_request_shows_its_core_and_least_restoration(sar: Path) -> None:
    page = client(sar).get("/requests/r2").text
    assert "<code>init/ambient</code>" in page  # the dark room: the ambient light is in the core
    # by relative change (USD and W are unlike units): +850 USD, the battery kept (tests/test_runtime.py)
    assert "budget → " in page and "power → " not in page
    assert "id='approve'" in page and "id='reject'" in page and "href='/requests/r2/preview'" in page
    assert client(sar).get("/requests/r1/preview").status_code == 404  # not pending
    r1 = client(sar).get("/requests/r1").text  # approved by its event: no buttons
    assert "approved" in r1 and "id='approve'" not in r1
    assert client(sar).get("/requests/r9").status_code == 404


def test_diff_between_two_generations(sar: Path) -> None:
    page = client(sar).get("/diff?a=1&b=2").text
    assert "generations 1 → 2" in page and "return-to-range" in page  # expect.toml: it moves back to report


def test_verify_on_demand(sar: Path) -> None:
    c = client(sar)
    assert "verify now" in c.get("/verify").text
    assert "<p id='verdict'>verify: ok</p>" in c.get("/verify?run=1").text


def test_events_send_the_last_journal_sequence_number(sar: Path) -> None:
    res = client(sar).get("/events?once=1")
    assert res.headers["content-type"].startswith("text/event-stream")
    assert res.text == f"event: seq\ndata: {journal(sar)[-1]['seq']}\n\n"
    assert f"data-seq='{journal(sar)[-1]['seq']}'" in client(sar).get("/").text


def test_status_json_is_catrt_status(sar: Path) -> None:
    doc = client(sar).get("/status.json").json()
    assert doc == json.loads(catrt("status", sar, "--json").stdout) | {"state": str(sar)}


# ---------------------------------------------------------------- approving


def test_a_form_without_its_csrf_value_is_refused(sar: Path) -> None:
    c = client(sar)
    assert c.post("/requests/r2", data={"verdict": "approve"}).status_code == 403
    assert c.post("/requests/r2", data={"verdict": "approve", "csrf": "0" * 64}).status_code == 403
    assert spooled(sar) == []


def test_read_only_shows_no_buttons_and_refuses_posts(sar: Path) -> None:
    writable_page = client(sar).get("/requests/r2").text
    c = client(sar, read_only=True)
    page = c.get("/requests/r2").text
    assert "id='approve'" not in page and "read-only" in page
    res = c.post("/requests/r2", data={"verdict": "approve", "csrf": csrf_of(writable_page)})
    assert res.status_code == 403
    assert spooled(sar) == []


def test_approving_a_settled_request_is_refused(sar: Path) -> None:
    c = client(sar)
    csrf = csrf_of(c.get("/requests/r2").text)
    assert c.post("/requests/r1", data={"verdict": "approve", "csrf": csrf}).status_code == 409
    assert c.post("/requests/r2", data={"verdict": "maybe", "csrf": csrf}).status_code == 400
    assert spooled(sar) == []


def test_approved_from_the_console_the_loop_deploys_the_new_generation(tmp_path: Path) -> None:
    folder = tmp_path / "state"
    sar_to_r2(folder)
    c = client(folder)
    preview = c.get("/requests/r2/preview").text  # decided in memory: nothing written
    assert journal(folder)[-1]["kind"] == "approval-request"
    csrf = csrf_of(c.get("/requests/r2").text)
    res = c.post("/requests/r2", data={"verdict": "approve", "csrf": csrf}, follow_redirects=False)
    assert res.status_code == 303 and res.headers["location"] == "/requests/r2?queued=approve"
    (line,) = spooled(folder)
    assert line["approve"] == "r2" and set(line) == {"id", "approve"}  # what catrt approve writes
    assert "queued: approve r2" in c.get(res.headers["location"]).text
    res = catrt("run", folder, "--once")
    assert res.returncode == 0, res.stderr
    page = c.get("/").text
    assert "<h2 id='generation'>generation 3</h2>" in page
    assert "<td>mount-thermal-camera</td>" in page  # expect.toml, event4-dark: the thermal camera in the dark
    assert "approved" in c.get("/requests/r2").text
    deployed = catrt("diff", folder, "2", "3").stdout.strip()  # what the loop did is what the preview said
    assert "mount     mount-thermal-camera" in deployed
    assert f"<pre class='diff'>{html.escape(deployed)}</pre>" in preview


# ---------------------------------------------------------------- catrt serve


def test_serve_without_the_extra_names_it(sar: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    from click.testing import CliRunner

    from catrt.cli import main

    monkeypatch.setitem(__import__("sys").modules, "uvicorn", None)  # as if not installed
    res = CliRunner().invoke(main, ["serve", str(sar)])
    assert res.exit_code == 2
    assert "error[E0706]" in res.output and "catc-lang[console]" in res.output


def test_serve_without_a_token_is_an_input_error(tmp_path: Path) -> None:
    folder = tmp_path / "state"
    assert catrt("init", folder, SAR / "mission.cat").returncode == 0
    (folder / TOKEN_FILE).unlink()
    res = catrt("serve", folder)
    assert res.returncode == 2
    assert "error[E0701]" in res.stderr and "--token" in res.stderr
