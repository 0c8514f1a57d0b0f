"""The console in a real headless browser (Debian's ``chromium`` and ``chromium-driver``,
driven by selenium): the SAR mission driven to its second request (r2, the dark room) while
``catrt run`` works on the spool, approved from the page, and the page showing the new
generation.  A screenshot of every page is kept under $CATRT_CONSOLE_SHOTS (default
``.ci-artifacts/console``) for CI to publish, and to be looked at.

Marked ``browser``: .ci/run installs chromium and runs it (``pytest -m browser``)."""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from conftest import ROOT

pytestmark = pytest.mark.browser

webdriver = pytest.importorskip("selenium.webdriver")
pytest.importorskip("starlette")
if shutil.which("chromium") is None or shutil.which("chromedriver") is None:
    pytest.skip("needs Debian's chromium and chromium-driver", allow_module_level=True)

from selenium.webdriver.common.by import By  # noqa: E402
from selenium.webdriver.support.ui import WebDriverWait  # noqa: E402
from test_console import sar_to_r2  # noqa: E402
from test_runtime import CATRT  # noqa: E402

from catrt.console.token import read_token  # noqa: E402

SHOTS = Path(os.environ.get("CATRT_CONSOLE_SHOTS", ROOT / ".ci-artifacts" / "console"))
PATIENCE = 240  # seconds a page may take to show what is waited for (a slow CI machine): a bound, not a timing


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def started(args: list[str]) -> subprocess.Popen[str]:
    return subprocess.Popen([*CATRT, *args], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def stop(process: subprocess.Popen[str]) -> None:
    if process.poll() is None:
        process.send_signal(signal.SIGTERM)
        try:
            process.wait(timeout=60)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


def listening(port: int, server: subprocess.Popen[str]) -> None:
    """Wait until the server accepts connections (or has died)."""
    deadline = time.monotonic() + PATIENCE
    while time.monotonic() < deadline:
        assert server.poll() is None, server.communicate()[1]
        with socket.socket() as s:
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return
        time.sleep(0.2)
    pytest.fail("catrt serve did not start listening")


@pytest.fixture
def browser() -> Iterator[webdriver.Chrome]:
    options = webdriver.ChromeOptions()
    options.binary_location = shutil.which("chromium") or ""
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1400,1000"):
        options.add_argument(arg)
    service = webdriver.ChromeService(executable_path=shutil.which("chromedriver"))
    driver = webdriver.Chrome(options=options, service=service)
    try:
        yield driver
    finally:
        driver.quit()


def shot(driver: webdriver.Chrome, name: str) -> None:
    SHOTS.mkdir(parents=True, exist_ok=True)
    height = driver.execute_script("return document.body.scrollHeight")
    driver.set_window_size(1400, min(max(int(height) + 200, 600), 4000))
    driver.save_screenshot(str(SHOTS / f"{name}.png"))


def shows(driver: webdriver.Chrome, text: str) -> None:
    """Wait until the page shows ``text`` (the page may reload meanwhile: live updates)."""
    script = "return document.body ? document.body.innerText : ''"
    WebDriverWait(driver, PATIENCE).until(lambda d: text in d.execute_script(script))


def test_sar_restoration_approved_in_the_browser(tmp_path: Path, browser: webdriver.Chrome) -> None:
    folder = tmp_path / "state"
    sar_to_r2(folder)
    token = read_token(folder)
    port = free_port()
    server = started(["serve", str(folder), "--port", str(port)])
    loop = started(["run", str(folder), "--approve", "never"])
    try:
        listening(port, server)
        base = f"http://127.0.0.1:{port}"

        browser.get(f"{base}/?token=not-{token}")
        shows(browser, "wrong token")
        shot(browser, "00-wrong-token")

        browser.get(f"{base}/?token={token}")  # the cookie from now on; the address loses the token
        shows(browser, "generation 2")
        assert "token" not in browser.current_url
        assert browser.find_elements(By.CSS_SELECTOR, "figure.diagram svg")
        shot(browser, "01-deployed")

        browser.get(f"{base}/journal")
        shows(browser, "approval-request")
        shot(browser, "02-journal")

        browser.get(f"{base}/diff?a=1&b=2")
        shows(browser, "generations 1 → 2")
        shot(browser, "03-diff")

        browser.get(f"{base}/verify?run=1")
        shows(browser, "verify: ok")
        shot(browser, "04-verify")

        browser.get(f"{base}/requests/r2")
        shows(browser, "least restoration")
        shot(browser, "05-request")
        browser.find_element(By.ID, "preview").click()
        shows(browser, "mount-thermal-camera")  # what approving r2 would deploy
        shot(browser, "06-preview")
        browser.get(f"{base}/requests/r2")
        shows(browser, "least restoration")
        browser.find_element(By.ID, "approve").click()
        shows(browser, "queued: approve r2")

        browser.get(f"{base}/")  # the loop takes the approval in; the page follows it (server-sent events)
        shows(browser, "generation 3")
        shows(browser, "mount-thermal-camera")  # expect.toml, event4-dark: the thermal camera in the dark
        shot(browser, "07-new-generation")
    finally:
        stop(loop)
        stop(server)
    assert loop.returncode == 0, loop.stderr.read() if loop.stderr else ""
