"""Events from an MQTT topic: ``catrt run STATE --events mqtt://[USER@]HOST[:PORT]/TOPIC``
(the ``mqtt`` extra: paho-mqtt ≥ 2; docs/runtime.md).  The password, if the broker wants one,
is read from ``CATRT_MQTT_PASSWORD``, never from the address (a command line is visible to
every user of the machine).

Each message's payload is one event, the UTF-8 text of one JSON object — what one line of an
events file holds; a payload that is not UTF-8, or longer than 1 MB, is rejected (E1001) like
such a line, located at ``mqtt://HOST:PORT/TOPIC#N`` (the N-th message of this run).  A blank
payload (an empty retained message clears a retained one) is no event and is skipped.

paho's network thread never calls the runtime: it puts the messages into a queue that the
loop's thread drains (:func:`catrt.loop.loop`), so the runtime stays single-threaded.  The
subscription is QoS 1 in a persistent session (the client id is derived from the machine and
the state folder), and a message is acknowledged only once the runtime has handled it — so
the broker keeps the messages sent while catrt is down, and delivers again one that was in
flight when catrt died; an event with an ``id`` is then a no-op.  paho reconnects on its own
after a lost connection.  paho-mqtt is imported only here, when an MQTT source is used.
"""

from __future__ import annotations

import hashlib
import os
import queue
import socket
import sys
import threading
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeGuard

from catgrammar import codes
from catrt.events import MAX_LINE

SCHEME = "mqtt://"
DEFAULT_PORT = 1883
QOS = 1
KEEPALIVE = 30  # seconds
CONNECT_TIMEOUT = 10.0  # seconds for the broker's CONNACK and SUBACK
NEEDS_EXTRA = "an MQTT event source needs the 'mqtt' extra: pip install 'catc-lang[mqtt]'"
PASSWORD_VARIABLE = "CATRT_MQTT_PASSWORD"


class MqttError(Exception):
    """The subscription cannot start: a malformed address, no broker there, a refusal
    (``code`` E0701), or no paho-mqtt (E0706)."""

    def __init__(self, code: str, message: str) -> None:
        super().__init__(message)
        self.code = code


def is_address(source: str | None) -> TypeGuard[str]:
    return source is not None and source.startswith(SCHEME)


@dataclass(frozen=True)
class Address:
    host: str
    port: int
    topic: str
    user: str | None = None

    @staticmethod
    def parse(text: str) -> Address:
        """``mqtt://[USER@]HOST[:PORT]/TOPIC`` (HOST may be ``[IPv6]``; TOPIC may hold the
        wildcards ``+`` and ``#``; all taken as written: no %-decoding)."""
        netloc, _, topic = text.removeprefix(SCHEME).partition("/")
        user, at, netloc = netloc.rpartition("@")
        if ":" in user:
            raise MqttError(codes.BAD_ARGUMENT, f"a password in the address: give it in {PASSWORD_VARIABLE} instead "
                                                "(a command line is visible to every user of the machine)")  # fmt: skip
        if at and not user:
            raise MqttError(codes.BAD_ARGUMENT, f"'{text}': no user before '@'; write mqtt://[USER@]HOST[:PORT]/TOPIC")
        host, port = netloc, str(DEFAULT_PORT)
        if netloc.startswith("["):
            host, _, rest = netloc[1:].partition("]")
            if rest:
                port = rest.removeprefix(":") if rest.startswith(":") else "?"
        elif ":" in netloc:
            host, _, port = netloc.rpartition(":")
        if not host:
            raise MqttError(codes.BAD_ARGUMENT, f"'{text}': no host; write mqtt://HOST[:PORT]/TOPIC")
        if not port.isdigit() or not 0 < int(port) < 65536:
            raise MqttError(codes.BAD_ARGUMENT, f"'{text}': the port '{port}' is not a number from 1 to 65535")
        problem = _topic_problem(topic)
        if problem is not None:
            raise MqttError(codes.BAD_ARGUMENT, f"'{text}': {problem}; write mqtt://HOST[:PORT]/TOPIC")
        return Address(host, int(port), topic, user or None)

    @property
    def server(self) -> str:
        return f"[{self.host}]:{self.port}" if ":" in self.host else f"{self.host}:{self.port}"

    def where(self, topic: str, n: int) -> str:
        return f"{SCHEME}{self.server}/{topic}#{n}"

    def __str__(self) -> str:
        return f"{SCHEME}{self.user + '@' if self.user else ''}{self.server}/{self.topic}"


def _topic_problem(topic: str) -> str | None:
    """What makes ``topic`` no MQTT topic filter (MQTT 3.1.1 §4.7), or None."""
    if not topic:
        return "no topic"
    if "\0" in topic or len(topic.encode("utf-8", "surrogatepass")) > 65535:
        return "a topic holds no NUL character and at most 65535 bytes"
    levels = topic.split("/")
    for i, level in enumerate(levels):
        if ("+" in level and level != "+") or ("#" in level and (level != "#" or i != len(levels) - 1)):
            return f"the topic '{topic}': + and # stand alone in a level, and # only in the last one"
    return None


def client_id(folder: Path) -> str:
    """The same for every run on this state folder on this machine: the broker keeps the
    session (the subscription and the messages not yet acknowledged) between runs."""
    key = f"{socket.gethostname()}:{folder.resolve()}".encode("utf-8", "surrogateescape")
    return "catrt-" + hashlib.sha256(key).hexdigest()[:16]  # 22 characters: MQTT 3.1.1 servers take 23


@dataclass(frozen=True)
class Message:
    """One message for the runtime: an event line and where it came from."""

    where: str
    text: str
    mid: int
    qos: int


def _stderr(text: str) -> None:
    sys.stderr.write(text + "\n")
    sys.stderr.flush()


class Subscriber:
    """The subscription: paho's thread fills :attr:`inbox`; :meth:`get` and :meth:`ack` are
    for the loop's thread.  Notes (connection lost, reconnected) are passed to ``note`` on the
    loop's thread too."""

    def __init__(self, address: Address, client: str, note: Callable[[str], None] | None = None) -> None:
        self.address, self.client_id, self.note = address, client, note or _stderr
        self.inbox: queue.Queue[Message | str] = queue.Queue()
        self.received = 0  # paho's thread only
        self.client: Any = None
        self._ready = threading.Event()
        self._failure: str | None = None
        self._closing = False
        self._connections = 0  # paho's thread only

    @staticmethod
    def open(source: str, folder: Path, note: Callable[[str], None] | None = None) -> Subscriber:
        subscriber = Subscriber(Address.parse(source), client_id(folder), note)
        subscriber.start()
        return subscriber

    def start(self, timeout: float = CONNECT_TIMEOUT) -> None:
        """Connect and subscribe, or MqttError saying why not."""
        try:
            from paho.mqtt import client as mqtt
        except ImportError:
            raise MqttError(codes.MISSING_EXTRA, NEEDS_EXTRA) from None
        server = self.address.server
        client = mqtt.Client(mqtt.CallbackAPIVersion.VERSION2, client_id=self.client_id, clean_session=False,
                             manual_ack=True)  # fmt: skip
        client.on_connect, client.on_subscribe = self._on_connect, self._on_subscribe
        client.on_message, client.on_disconnect = self._on_message, self._on_disconnect
        client.reconnect_delay_set(min_delay=1, max_delay=30)
        if self.address.user is not None:
            client.username_pw_set(self.address.user, os.environ.get(PASSWORD_VARIABLE))
        try:
            client.connect(self.address.host, self.address.port, keepalive=KEEPALIVE)
        except (OSError, ValueError) as exc:  # refused, no such host, timed out
            why = getattr(exc, "strerror", None) or str(exc) or type(exc).__name__
            raise MqttError(codes.BAD_ARGUMENT, f"cannot reach the MQTT broker at {server}: {why}") from None
        self.client = client
        client.loop_start()
        if not self._ready.wait(timeout) or self._failure is not None:
            why = self._failure or f"no answer within {timeout:g} s"
            self.close()
            raise MqttError(codes.BAD_ARGUMENT, f"the MQTT broker at {server}: {why}")
        self.note(f"catrt: listening on {self.address} (QoS {QOS}); stop with SIGTERM or Ctrl-C")

    # ------------------------------------------------------------ paho's thread
    def _on_connect(self, client: Any, userdata: Any, flags: Any, reason: Any, properties: Any) -> None:
        if reason.is_failure:
            if not self._ready.is_set():
                self._failure = f"refused the connection: {reason}"
                self._ready.set()
            else:
                self.inbox.put(f"catrt: {self.address.server} refused to reconnect: {reason}; trying again")
            return
        self._connections += 1
        client.subscribe(self.address.topic, qos=QOS)  # again after a reconnection: the broker may have lost it
        if flags.session_present:
            # subscribed in an earlier run; the broker may hold the SUBACK back until the messages it kept
            # for catrt are acknowledged, which they are once the loop runs: do not wait for it
            self._ready.set()

    def _on_subscribe(self, client: Any, userdata: Any, mid: int, reasons: Any, properties: Any) -> None:
        refused = [r for r in reasons if r.is_failure]
        if refused and not self._ready.is_set():
            self._failure = f"refused the subscription to '{self.address.topic}': {refused[0]}"
        elif refused:
            self.inbox.put(f"catrt: {self.address.server} refused the subscription to '{self.address.topic}': "
                           f"{refused[0]}")  # fmt: skip
        elif self._connections > 1:
            self.inbox.put(f"catrt: reconnected to {self.address.server}, subscribed to '{self.address.topic}'")
        self._ready.set()

    def _on_message(self, client: Any, userdata: Any, message: Any) -> None:
        self.received += 1
        payload = bytes(message.payload)
        if not payload.strip():
            if message.qos > 0:
                client.ack(message.mid, message.qos)
            return
        # a payload over MAX_LINE is cut just past it: parse_event rejects it without reading it
        text = payload[: MAX_LINE + 1].decode("utf-8", "surrogateescape")
        self.inbox.put(Message(self.address.where(message.topic, self.received), text, message.mid, message.qos))

    def _on_disconnect(self, client: Any, userdata: Any, flags: Any, reason: Any, properties: Any) -> None:
        if self._ready.is_set() and not self._closing:
            self.inbox.put(f"catrt: lost the connection to {self.address.server} ({reason}); reconnecting")

    # ------------------------------------------------------------ the loop's thread
    def get(self, timeout: float) -> Message | None:
        """The next message, or None after ``timeout`` seconds without one."""
        try:
            item = self.inbox.get(timeout=timeout)
            while isinstance(item, str):
                self.note(item)
                item = self.inbox.get_nowait()
        except queue.Empty:
            return None
        return item

    def ack(self, message: Message) -> None:
        """The runtime has handled (journaled) the message: the broker may forget it."""
        if message.qos > 0:
            self.client.ack(message.mid, message.qos)

    def close(self) -> None:
        """Disconnect; messages not yet handled stay with the broker for the next run."""
        self._closing = True
        if self.client is not None:
            self.client.disconnect()
            self.client.loop_stop()
