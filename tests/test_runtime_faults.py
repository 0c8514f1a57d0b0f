"""catrt under the faults a robot meets (issue 26; docs/runtime.md "Faults and what catrt
does"): a changed source, a garbled or truncated store, a read-only folder, a deleted lock
file, events from streams, an endless line, a full disk.  Each fault is injected by the test
(bytes overwritten, a read-only bind mount, an ENOSPC shim) and each must end in its own code,
never in exit 70 (an internal error), with nothing accepted lost and the store never rewritten."""

from __future__ import annotations

import hashlib
import json
import os
import shutil
import sqlite3
import subprocess
import sys
import threading
from fractions import Fraction
from pathlib import Path

import pytest
from test_runtime import CATRT, DETECTION, catrt, journal, lines, ram_of

DB = "catrt.sqlite"
INTERNAL_ERROR = 70


@pytest.fixture(scope="session")
def state_template(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A store whose first decision is made (so that an event's transaction is the next):
    made once a test process — ``catrt init`` and ``run`` are two processes, about 1 s of CPU
    (issue 28) — and never handed to a test itself."""
    folder = tmp_path_factory.mktemp("store-template") / "st"
    assert catrt("init", folder, DETECTION).returncode == 0
    res = catrt("run", folder, "--events", "-", stdin=lines({"id": "e1", "set": {"ram": 8}}))
    assert res.returncode == 0, res.stderr
    return folder


@pytest.fixture
def state(tmp_path: Path, state_template: Path) -> Path:
    """The test's own copy of :func:`state_template`, which its faults are injected into
    (``current`` stays a relative link; the console token keeps its mode).  Only the journal's
    record of the dry enactment names the template's folder: a record of what ran, which
    ``verify`` and ``replay`` pass on a copy as on the original."""
    folder = tmp_path / "st"
    shutil.copytree(state_template, folder, symlinks=True)
    return folder


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def event_ids(state: Path) -> list[str]:
    return [e["event_id"] for e in journal(state) if e["kind"] == "event"]


# ---------------------------------------------------------------- a changed source


def test_a_changed_source_stops_the_loop_and_verify_names_it(state: Path):
    db = sqlite3.connect(state / DB)
    name, text = db.execute("SELECT name, text FROM sources ORDER BY name").fetchone()
    changed = text.replace("(= ram 16)", "(= ram 10)") if "(= ram 16)" in text else text + " "
    assert changed != text
    with db:
        db.execute("UPDATE sources SET text = ? WHERE name = ?", (changed, name))
    db.close()
    before = journal(state)
    res = catrt("run", state, "--events", "-", stdin=lines({"id": "e2", "set": {"ram": 6}}))
    assert res.returncode == 2 and "error[E1013]" in res.stderr and name in res.stderr, res.stderr
    assert journal(state) == before  # nothing was decided on the changed model
    res = catrt("verify", state)
    assert res.returncode == 1 and "E1013" in res.stderr and name in res.stderr, res.stderr


# ---------------------------------------------------------------- a garbled journal


def garble(state: Path, marker: bytes = b'"model_sha256":"') -> None:
    data = bytearray((state / DB).read_bytes())
    at = data.rindex(marker) + len(marker)
    data[at : at + 8] = b"\xff" * 8  # no longer UTF-8, the page's structure intact
    (state / DB).write_bytes(bytes(data))


def test_a_garbled_journal_is_reported_by_verify_and_refused_by_run(state: Path):
    garble(state)
    before = digest(state / DB)
    res = catrt("verify", state)
    assert res.returncode == 1 and "garbled" in res.stderr, res.stdout + res.stderr
    res = catrt("run", state, "--events", "-", stdin=lines({"id": "e2", "set": {"ram": 6}}))
    assert res.returncode == 2 and "error[E1014]" in res.stderr, res.stderr
    assert digest(state / DB) == before  # nothing appended
    for command in ("status", "journal", "replay"):
        assert catrt(command, state).returncode != INTERNAL_ERROR


# ---------------------------------------------------------------- a truncated store


@pytest.mark.parametrize("size", [0, 100, 4096, 40_000])
def test_a_truncated_store_gets_a_clear_code_from_every_command_and_is_never_rewritten(state: Path, size: int):
    assert (state / DB).stat().st_size > 40_000  # else the store is not truncated by the test
    with open(state / DB, "r+b") as fh:
        fh.truncate(size)
    before = digest(state / DB)
    event = state.parent / "e.jsonl"
    event.write_text(lines({"id": "e9", "set": {"ram": 6}}))
    for args in (["status"], ["journal"], ["verify"], ["replay"], ["diff"], ["run", "--events", event],
                 ["event", event], ["approve", "r1"]):  # fmt: skip
        res = catrt(args[0], state, *args[1:])
        assert res.returncode == 2 and "error[E1014]" in res.stderr, (args, res.stderr)
    assert (state / DB).stat().st_size == size and digest(state / DB) == before


# ---------------------------------------------------------------- a read-only folder


def test_a_read_only_state_folder_is_said_to_be_one(state: Path):
    if shutil.which("unshare") is None or shutil.which("mount") is None:
        pytest.skip("needs unshare and mount for a read-only bind")
    probe = subprocess.run(["unshare", "-m", "true"], capture_output=True)
    if probe.returncode != 0:
        pytest.skip("no mount namespaces here")
    command = " ".join(CATRT[:2]) + " '" + CATRT[2] + "'"
    script = (
        f"mount --bind {state} {state} && mount -o remount,bind,ro {state} && "
        f"{command} run {state} --events /dev/null; echo rc=$?; {command} init {state}/new {DETECTION}; echo rc=$?"
    )
    res = subprocess.run(["unshare", "-m", "sh", "-c", script], capture_output=True, text=True, timeout=300)
    assert res.stdout.split() == ["rc=2", "rc=2"], res.stdout + res.stderr
    assert res.stderr.count("read-only") == 2 and res.stderr.count("error[E1015]") == 2, res.stderr


# ---------------------------------------------------------------- one writer


def test_deleting_the_lock_file_lets_no_second_writer_in(state: Path):
    from catrt.store import Store

    first = Store.open(state, write=True)
    try:
        (state / "lock").unlink()
        res = catrt("run", state, "--events", "-", stdin=lines({"id": "e2", "set": {"ram": 6}}))
        assert res.returncode == 2 and "error[E1003]" in res.stderr, res.stderr
    finally:
        first.close()
    assert event_ids(state) == ["e1"]


# ---------------------------------------------------------------- streams


def test_events_from_dev_null_dev_stdin_and_process_substitution(state: Path):
    assert catrt("run", state, "--events", "/dev/null").returncode == 0
    res = catrt("run", state, "--events", "/dev/stdin", stdin=lines({"id": "e2", "set": {"ram": 6}}))
    assert res.returncode == 0, res.stderr
    event = json.dumps({"id": "e3", "set": {"ram": 7}}).replace('"', '\\"')
    command = " ".join(CATRT[:2]) + " '" + CATRT[2] + "'"
    res = subprocess.run(["bash", "-c", f'{command} run {state} --events <(echo "{event}")'], capture_output=True,
                         text=True, timeout=300)  # fmt: skip
    assert res.returncode == 0, res.stderr
    assert event_ids(state) == ["e1", "e2", "e3"] and ram_of(state) == 7


def test_events_from_a_fifo(state: Path):
    fifo = state.parent / "events.fifo"
    os.mkfifo(fifo)
    proc = subprocess.Popen([*CATRT, "run", str(state), "--events", str(fifo)], stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip

    def write() -> None:
        with open(fifo, "w") as fh:  # blocks until the FIFO is opened for reading
            fh.write(lines({"id": "e2", "set": {"ram": 6}}, {"id": "e3", "set": {"ram": 5}}))

    writer = threading.Thread(target=write, daemon=True)
    writer.start()
    _, err = proc.communicate(timeout=300)
    if writer.is_alive():  # catrt ended without opening the FIFO: open it here, so the writer ends
        fd = os.open(fifo, os.O_RDONLY | os.O_NONBLOCK)
        writer.join()
        os.close(fd)
    assert proc.returncode == 0, err
    assert event_ids(state) == ["e1", "e2", "e3"] and ram_of(state) == 5


# ---------------------------------------------------------------- an endless line


#: catrt, writing its own peak resident memory (VmHWM, per process image: not the pytest
#: process it was forked from, unlike ru_maxrss) to the file HWM_FILE names when it exits
HWM = """
import atexit, os
def hwm():
    with open("/proc/self/status") as status, open(os.environ["HWM_FILE"], "w") as out:
        out.write(next(line for line in status if line.startswith("VmHWM:")).split()[1])
atexit.register(hwm)
from catrt.cli import entry
entry()
"""


def test_a_300_mb_line_is_rejected_at_the_line_limit_in_bounded_memory(state: Path):
    from catrt.events import MAX_LINE

    if not Path("/proc/self/status").exists():
        pytest.skip("needs /proc to read the peak memory")
    hwm = state.parent / "hwm"
    proc = subprocess.Popen([sys.executable, "-c", HWM, "run", str(state), "--events", "-"], stdin=subprocess.PIPE,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                            env={**os.environ, "HWM_FILE": str(hwm)})  # fmt: skip
    chunk = b"x" * (1 << 20)
    assert proc.stdin is not None and proc.stderr is not None
    for _ in range(300):  # 300 MB, no newline
        proc.stdin.write(chunk)
    proc.stdin.close()
    err = proc.stderr.read().decode()
    assert proc.wait(timeout=300) == 0 and "error[E1001]" in err and f"longer than {MAX_LINE} bytes" in err, err
    # the line read whole would take 300 MB as bytes and as much again as text
    assert int(hwm.read_text()) < 250 * 1024, hwm.read_text()  # kB
    assert event_ids(state) == ["e1"]


# ---------------------------------------------------------------- a full disk

#: catrt with its store's COMMIT failing as SQLite fails on ENOSPC, the first FULL_COMMITS times
SHIM = """
import os, sqlite3
import catrt.loop, catrt.store
catrt.loop.BACKOFF = (0.0,) * 10
left = [int(os.environ["FULL_COMMITS"])]
connect = catrt.store._connect
class Full:
    def __init__(self, db): self.db = db
    def __getattr__(self, name): return getattr(self.db, name)
    def execute(self, sql, *args):
        if sql == "COMMIT" and left[0] > 0:
            left[0] -= 1
            raise sqlite3.OperationalError("database or disk is full")
        return self.db.execute(sql, *args)
catrt.store._connect = lambda path: Full(connect(path))
from catrt.cli import entry
entry()
"""


def full_disk_run(state: Path, commits: int, *events: dict) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-c", SHIM, "run", str(state), "--events", "-"], input=lines(*events),
                          capture_output=True, text=True, env={**os.environ, "FULL_COMMITS": str(commits)},
                          timeout=300)  # fmt: skip


def test_a_full_disk_is_retried_and_the_event_lands_once(state: Path):
    res = full_disk_run(state, 3, {"id": "e2", "set": {"ram": 6}})
    assert res.returncode == 0, res.stderr
    assert res.stderr.count("error[E1016]") == 3 and "trying again" in res.stderr, res.stderr
    assert event_ids(state) == ["e1", "e2"] and ram_of(state) == 6
    assert catrt("verify", state).returncode == 0


def test_a_disk_that_stays_full_stops_the_loop_without_acknowledging(state: Path):
    res = full_disk_run(state, 1000, {"id": "e2", "set": {"ram": 6}})
    assert res.returncode == 2 and "error[E1016]" in res.stderr.splitlines()[-1], res.stderr
    assert event_ids(state) == ["e1"] and ram_of(state) == 8
    res = catrt("run", state, "--events", "-", stdin=lines({"id": "e2", "set": {"ram": 6}}))  # space freed
    assert res.returncode == 0 and event_ids(state) == ["e1", "e2"]


# ---------------------------------------------------------------- paper cuts


def test_approve_with_its_arguments_swapped_gets_a_hint(state: Path, tmp_path: Path, monkeypatch):
    monkeypatch.chdir(state.parent)
    res = catrt("approve", "r4", state.name)
    assert res.returncode == 2 and "E1005" in res.stderr and f"catrt approve {state.name} r4" in res.stderr, res.stderr


def test_events_carry_units_converted_exactly_as_in_cat_files(state: Path):
    # ram is in GB (examples/detection/domain.cat): 1 MB = 10^6 B, 1 GiB = 2^30 B
    res = catrt("run", state, "--events", "-", stdin=lines({"id": "e2", "set": {"ram": "8192 MB"}}))
    assert res.returncode == 0 and ram_of(state) == Fraction(8192, 1000), res.stderr
    res = catrt("run", state, "--events", "-", stdin=lines({"id": "e3", "set": {"ram": "7.5 GiB"}}))
    assert res.returncode == 0 and ram_of(state) == Fraction(15, 2) * 2**30 / 10**9, res.stderr
    res = catrt("run", state, "--events", "-", stdin=lines({"id": "e4", "set": {"ram": "2 s"}}))
    assert "e4: rejected: error[E1001]" in res.stderr and "time" in res.stderr, res.stderr
    assert ram_of(state) == Fraction(15, 2) * 2**30 / 10**9
    assert catrt("replay", state).returncode == 0


def test_a_rejection_at_reading_names_the_event_id(state: Path):
    res = catrt("run", state, "--events", "-", stdin=lines({"id": "q7", "set": {"ram": "2.3.4"}}))
    assert "<stdin>:1: q7: rejected: error[E1001]" in res.stderr, res.stderr


def test_verify_names_the_edited_artifact(state: Path):
    generation = state / "generations" / "000001"
    manifest = json.loads((generation / "manifest.json").read_text())
    name = sorted(manifest["artifacts"])[0]
    (generation / name).write_bytes((generation / name).read_bytes() + b"\n# edited\n")
    res = catrt("verify", state)
    assert res.returncode == 1 and f"generation 000001: {name} differs from its manifest" in res.stderr, res.stderr


# ---------------------------------------------------------------- a full disk behind MQTT


class _FullCommits:
    """The store's connection, its COMMIT failing as SQLite fails on ENOSPC ``left`` times."""

    def __init__(self, db, left: int) -> None:
        self.db, self.left = db, left

    def __getattr__(self, name):
        return getattr(self.db, name)

    def execute(self, sql, *args):
        if sql == "COMMIT" and self.left > 0:
            self.left -= 1
            raise sqlite3.OperationalError("database or disk is full")
        return self.db.execute(sql, *args)


class _Subscriber:
    """MQTT as the loop sees it: the messages, then nothing (and the loop is stopped)."""

    def __init__(self, stop, *texts: str) -> None:
        from catrt.mqtt import Message

        self.stop, self.acked = stop, []
        self.inbox = [Message("mqtt robot/events", text, i + 1, 1) for i, text in enumerate(texts)]

    def get(self, timeout: float):
        if self.inbox:
            return self.inbox.pop(0)
        self.stop.set()
        return None

    def ack(self, message) -> None:
        self.acked.append(message.mid)

    def close(self) -> None:
        pass


@pytest.mark.parametrize("full", [3, 1000])
def test_a_full_disk_behind_mqtt_is_retried_and_acknowledged_only_once_handled(
    state: Path, monkeypatch: pytest.MonkeyPatch, full: int
):
    """3 full commits: retried with back-off, then handled and acknowledged; a disk that stays
    full: E1016 and the message not acknowledged (the broker delivers it again)."""
    import threading

    from catrt import loop as catrt_loop
    from catrt.api import connect
    from catrt.store import StoreError

    monkeypatch.setattr(catrt_loop, "BACKOFF", (0.0,) * 10)
    said = []
    with connect(state, say=said.append) as rt:
        store = rt.runtime.store
        store.db = _FullCommits(store.db, full)
        stop = threading.Event()
        sub = _Subscriber(stop, json.dumps({"id": "e2", "set": {"ram": 6}}))
        if full > len(catrt_loop.BACKOFF):
            with pytest.raises(StoreError) as exc:
                catrt_loop._mqtt(rt.runtime, sub, catrt_loop._Sensors(()), stop)
            assert exc.value.code == "E1016"
        else:
            catrt_loop._mqtt(rt.runtime, sub, catrt_loop._Sensors(()), stop)
        store.db = store.db.db
    tries = [o.message for o in said if "E1016" in o.message]
    if full > 10:
        assert sub.acked == [] and event_ids(state) == ["e1"] and len(tries) == 10
    else:
        assert sub.acked == [1] and event_ids(state) == ["e1", "e2"] and len(tries) == 3
        assert catrt("verify", state).returncode == 0
