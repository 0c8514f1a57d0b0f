"""catrt's MQTT event source (the 'mqtt' extra) against a real broker on loopback: amqtt's
broker, from the test extra, in a thread of this process with its own asyncio loop, on a free
port of 127.0.0.1; ``catrt run --events mqtt://…`` as a real process, stopped by SIGTERM.

Expected values by hand (as in test_runtime.py): the detection model needs ram ≥ 0.5 for the
driver and then ram ≥ 4 for the detector, so its least restoration from ram 1 is ram → 4.5."""

from __future__ import annotations

import asyncio
import json
import queue
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from fractions import Fraction
from pathlib import Path

import amqtt.broker  # the test extra installs amqtt and paho-mqtt: a missing one fails, it is no skip
import pytest
from conftest import ROOT
from paho.mqtt import client as mqtt

DETECTION = ROOT / "examples" / "detection" / "person.cat"
CATRT = [sys.executable, "-c", "from catrt.cli import entry; entry()"]
TOPIC = "robot/events"
WAIT = 20.0  # seconds: a bound on any one wait, never reached when all is well


def catrt(*args: str | Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run([*CATRT, *map(str, args)], capture_output=True, text=True, timeout=120)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


class Broker:
    """An MQTT broker on 127.0.0.1:``port`` in a thread with its own asyncio loop; it lets in
    any client with a user name (amqtt keeps the session of such a client only, not an
    anonymous one's).  It can be stopped and started again on the same port."""

    def __init__(self) -> None:
        self.port = free_port()
        self.config = {"listeners": {"default": {"type": "tcp", "bind": f"127.0.0.1:{self.port}"}},
                       "plugins": {"amqtt.plugins.authentication.AnonymousAuthPlugin": {"allow_anonymous": False}}}  # fmt: skip
        self.loop: asyncio.AbstractEventLoop | None = None
        self.thread: threading.Thread | None = None
        self.broker: amqtt.broker.Broker | None = None

    def start(self) -> None:
        loop = self.loop = asyncio.new_event_loop()
        started: queue.Queue[object] = queue.Queue()

        async def start() -> amqtt.broker.Broker:
            b = amqtt.broker.Broker(self.config)
            await b.start()
            return b

        def serve() -> None:
            asyncio.set_event_loop(loop)
            try:
                started.put(loop.run_until_complete(start()))
            except BaseException as exc:  # raised in the test below
                started.put(exc)
                return
            loop.run_forever()

        self.thread = threading.Thread(target=serve, name="amqtt-broker", daemon=True)
        self.thread.start()
        b = started.get(timeout=WAIT)
        if isinstance(b, BaseException):
            raise b
        assert isinstance(b, amqtt.broker.Broker)
        self.broker = b

    def stop(self) -> None:
        if self.broker is None or self.loop is None or self.thread is None:
            return
        asyncio.run_coroutine_threadsafe(self.broker.shutdown(), self.loop).result(WAIT)
        self.loop.call_soon_threadsafe(self.loop.stop)
        self.thread.join(WAIT)
        self.loop.close()
        self.broker = None


@pytest.fixture
def broker() -> Iterator[Broker]:
    b = Broker()
    b.start()
    try:
        yield b
    finally:
        b.stop()


@pytest.fixture
def state(tmp_path: Path) -> Path:
    folder = tmp_path / "st"
    res = catrt("init", folder, DETECTION)
    assert res.returncode == 0, res.stderr
    return folder


class Run:
    """``catrt run STATE --events URL --json`` as a process; its output read line by line."""

    def __init__(self, state: Path, url: str) -> None:
        self.proc = subprocess.Popen([*CATRT, "run", str(state), "--events", url, "--json"], stdin=subprocess.DEVNULL,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)  # fmt: skip
        self.out: queue.Queue[str] = queue.Queue()
        self.err: queue.Queue[str] = queue.Queue()
        self.seen: list[str] = []
        for stream, into in ((self.proc.stdout, self.out), (self.proc.stderr, self.err)):
            threading.Thread(target=self._pump, args=(stream, into), daemon=True).start()
        listening = self.next_note("listening on")
        assert url in listening

    @staticmethod
    def _pump(stream, into: queue.Queue[str]) -> None:
        for line in stream:
            into.put(line.rstrip("\n"))

    def _next(self, lines: queue.Queue[str], wanted, what: str) -> str:
        deadline = time.monotonic() + WAIT
        while True:
            try:
                line = lines.get(timeout=max(0.0, deadline - time.monotonic()))
            except queue.Empty:
                raise AssertionError(f"no {what} within {WAIT} s; seen: {self.seen}") from None
            self.seen.append(line)
            if wanted(line):
                return line

    def next_note(self, text: str) -> str:
        return self._next(self.err, lambda line: text in line, f"'{text}'")

    def outcomes(self, n: int) -> list[dict]:
        return [json.loads(self._next(self.out, lambda line: True, f"outcome {i + 1} of {n}")) for i in range(n)]

    def stop(self) -> int:
        """SIGTERM, as a service manager stops it; the exit code."""
        self.proc.send_signal(signal.SIGTERM)
        try:
            return self.proc.wait(WAIT)
        finally:
            self.kill()

    def kill(self) -> None:
        if self.proc.poll() is None:
            self.proc.kill()
            self.proc.wait()


def publish(port: int, payloads: list[bytes]) -> None:
    """Each payload as one QoS 1 message, in order, each acknowledged by the broker."""
    publisher = mqtt.Client(mqtt.CallbackAPIVersion.VERSION2, client_id="test-publisher")
    publisher.username_pw_set("publisher")
    publisher.connect("127.0.0.1", port)
    publisher.loop_start()
    try:
        for payload in payloads:
            publisher.publish(TOPIC, payload, qos=1).wait_for_publish(WAIT)
    finally:
        publisher.disconnect()
        publisher.loop_stop()


def journal(state: Path) -> list[dict]:
    res = catrt("journal", state, "--json")
    assert res.returncode == 0, res.stderr
    entries = [json.loads(line) for line in res.stdout.splitlines()]
    assert [e["seq"] for e in entries] == list(range(1, len(entries) + 1))
    return entries


def ram_of(state: Path) -> Fraction:
    res = catrt("status", state, "--json")
    return Fraction(json.loads(res.stdout)["model"]["init"]["ram"])


def test_events_from_an_mqtt_topic(broker: Broker, state: Path):
    url = f"mqtt://robot@127.0.0.1:{broker.port}/{TOPIC}"
    run = Run(state, url)
    try:
        (start,) = run.outcomes(1)
        assert start["decision"]["action"] == "compose" and start["generation"] == 1
        publish(broker.port, [
            json.dumps({"id": "low", "set": {"ram": "1"}}).encode(),  # infeasible: restore ram → 4.5, request r1
            json.dumps({"approve": "r1"}).encode(),                   # approved: ram 4.5
            b'{"id": "torn", "set": {"ram": ',                        # malformed: E1001, located
            b'{"id": "bin", "set": {"ram": "\xff"}}',                 # not UTF-8: E1001, located
            b'{"id": "big", "set": {"ram": "' + b"1" * 1_000_000 + b'"}}',  # over 1 MB: E1001
            b"",                                                      # blank: no event, skipped
            json.dumps({"id": "low", "set": {"ram": "2"}}).encode(),  # a duplicate id: nothing happens
        ])  # fmt: skip
        low, approved, torn, binary, big, dup = run.outcomes(6)
        assert run.stop() == 0, run.seen
    finally:
        run.kill()

    where = f"mqtt://127.0.0.1:{broker.port}/{TOPIC}#"  # the N-th message of the run
    assert low["status"] == "accepted" and low["decision"]["action"] == "restore" and low["where"] == f"{where}1"
    assert low["decision"]["proposal"]["set"] == {"ram": "4.5"}  # by hand: 0.5 + 4
    assert approved["status"] == "accepted" and approved["decision"]["action"] == "keep"
    assert torn["status"] == "rejected" and "E1001" in torn["message"]
    assert torn["where"] == f"{where}3:31"  # the payload ends after 30 characters
    assert binary["status"] == "rejected" and "not UTF-8" in binary["message"] and "0xff" in binary["message"]
    assert binary["where"] == f"{where}4:31"  # the 31st character is the byte 0xff
    assert big["status"] == "rejected" and big["where"] == f"{where}5" and "longer than 1000000 bytes" in big["message"]
    assert dup["status"] == "duplicate" and dup["where"] == f"{where}7"

    entries = journal(state)
    events = [(e["kind"], e["event_id"]) for e in entries if e["kind"] in ("event", "rejected")]
    assert [k for k, _ in events] == ["event", "event", "rejected", "rejected", "rejected"]  # the duplicate: nothing
    assert events[0][1] == "low" and events[1][1].startswith("auto-")
    rejected = [e["data"] for e in entries if e["kind"] == "rejected"]
    assert [r["code"] for r in rejected] == ["E1001"] * 3
    assert [r["where"] for r in rejected] == [f"{where}3:31", f"{where}4:31", f"{where}5"]
    assert rejected[1]["line"] == '{"id": "bin", "set": {"ram": "\\udcff"}}'  # the byte, escaped, as text
    assert ram_of(state) == Fraction(9, 2)
    res = catrt("verify", state)
    assert res.returncode == 0, res.stdout + res.stderr


def test_messages_sent_while_catrt_is_down_come_at_the_next_start(broker: Broker, state: Path):
    """QoS 1 in a persistent session: the broker keeps what catrt has not acknowledged."""
    url = f"mqtt://robot@127.0.0.1:{broker.port}/{TOPIC}"
    run = Run(state, url)
    try:
        run.outcomes(1)
        assert run.stop() == 0, run.seen
    finally:
        run.kill()
    publish(broker.port, [json.dumps({"id": "later", "set": {"ram": "64"}}).encode()])
    run = Run(state, url)
    try:
        (later,) = run.outcomes(1)  # already deployed: no start decision
        assert run.stop() == 0, run.seen
    finally:
        run.kill()
    assert later["event"] == "later" and later["status"] == "accepted" and later["decision"]["action"] == "keep"
    assert ram_of(state) == 64


def test_catrt_reconnects_when_the_broker_comes_back(broker: Broker, state: Path):
    """A broker restarted (its sessions lost): paho reconnects on its own, catrt subscribes again."""
    run = Run(state, f"mqtt://robot@127.0.0.1:{broker.port}/{TOPIC}")
    try:
        run.outcomes(1)
        broker.stop()
        run.next_note("lost the connection")
        broker.start()
        run.next_note("reconnected")
        publish(broker.port, [json.dumps({"id": "after", "set": {"ram": "32"}}).encode()])
        (after,) = run.outcomes(1)
        assert run.stop() == 0, run.seen
    finally:
        run.kill()
    assert after["event"] == "after" and after["status"] == "accepted"
    assert ram_of(state) == 32


def test_no_broker_there_is_an_input_error(state: Path):
    port = free_port()  # nothing listens on it
    res = catrt("run", state, "--events", f"mqtt://127.0.0.1:{port}/{TOPIC}")
    assert res.returncode == 2, res.stderr
    assert f"error[E0701]: cannot reach the MQTT broker at 127.0.0.1:{port}" in res.stderr, res.stderr
    assert "Traceback" not in res.stderr
    res = catrt("journal", state, "--json")
    kinds = [json.loads(line)["kind"] for line in res.stdout.splitlines()]
    assert kinds == ["init"], "nothing is decided before the broker is reached"


@pytest.mark.parametrize(
    ("address", "message"),
    [
        ("mqtt://127.0.0.1:1883", "no topic"),
        ("mqtt://:1883/t", "no host"),
        ("mqtt://127.0.0.1:99999/t", "the port '99999'"),
        ("mqtt://127.0.0.1/a/#/b", "# only in the last one"),
    ],
)
def test_a_malformed_address_is_an_input_error(state: Path, address: str, message: str):
    res = catrt("run", state, "--events", address)
    assert res.returncode == 2 and f"{address}: error[E0701]: " in res.stderr and message in res.stderr, res.stderr


def test_without_paho_the_message_names_the_extra(state: Path, monkeypatch):
    from click.testing import CliRunner

    from catrt.cli import main

    for name in ("paho", "paho.mqtt", "paho.mqtt.client"):
        monkeypatch.setitem(sys.modules, name, None)
    res = CliRunner().invoke(main, ["run", str(state), "--events", "mqtt://127.0.0.1:1883/robot/events"])
    assert res.exit_code == 2, res.output
    assert "error[E0706]" in res.stderr and "pip install 'catc-lang[mqtt]'" in res.stderr, res.stderr


def test_the_address_and_the_session(tmp_path: Path):
    from catrt.mqtt import Address, client_id

    assert Address.parse("mqtt://broker.local/robot/+/events") == Address("broker.local", 1883, "robot/+/events")
    assert Address.parse("mqtt://[::1]:8883/r/#") == Address("::1", 8883, "r/#")
    assert str(Address.parse("mqtt://[::1]:8883/r/#")) == "mqtt://[::1]:8883/r/#"
    assert client_id(tmp_path) == client_id(tmp_path / ".") != client_id(tmp_path / "other")
    assert len(client_id(tmp_path)) <= 23
