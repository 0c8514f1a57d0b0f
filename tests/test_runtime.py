"""catrt end to end: the store, the loop of Algorithm 1, approvals, enactment, replay and
verify, each through the real ``catrt`` process (a crash must be a real process dying).

Expected values are derived by hand from the models, never copied from catrt's output:
the detection model (examples/detection) needs ram ≥ ram-req ≥ 0.5 for the driver and then
ram ≥ 4 for the detector, so its least restoration from ram 1 is ram → 4.5 and any ram ≥ 4.5
keeps the deployed composition valid."""

from __future__ import annotations

import json
import os
import signal
import sqlite3
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import fake_docker as fake_docker_module
import pytest
from conftest import ROOT

DETECTION = ROOT / "examples" / "detection" / "person.cat"
CATRT = [sys.executable, "-c", "from catrt.cli import entry; entry()"]


def catrt(*args: str | Path, stdin: str | None = None, env: dict[str, str] | None = None,
          cwd: Path | None = None) -> subprocess.CompletedProcess[str]:  # fmt: skip
    return subprocess.run(
        [*CATRT, *map(str, args)], input=stdin, capture_output=True, text=True, env={**os.environ, **(env or {})},
        cwd=cwd, timeout=300,
    )  # fmt: skip


def lines(*events: dict | str) -> str:
    return "".join((e if isinstance(e, str) else json.dumps(e)) + "\n" for e in events)


def journal(state: Path) -> list[dict]:
    from catrt.store import Store

    store = Store.open(state, write=False)
    try:
        return list(store.entries())
    finally:
        store.close()


def stored(state: Path, key: str):
    from catrt.store import Store

    store = Store.open(state, write=False)
    try:
        return store.get(key)
    finally:
        store.close()


def ram_of(state: Path) -> Fraction:
    return Fraction(stored(state, "model")["problem"]["init"]["ram"])


def assert_consistent(state: Path) -> None:
    """verify (SQLite integrity, gap-free journal, replay == stored state, generations match
    their manifests, current → the deployed one) and replay both exit 0."""
    res = catrt("verify", state, "--json")
    doc = json.loads(res.stdout)
    assert res.returncode == 0 and doc["ok"], doc
    res = catrt("replay", state)
    assert res.returncode == 0, res.stdout + res.stderr
    seqs = [e["seq"] for e in journal(state)]
    assert seqs == list(range(1, len(seqs) + 1))


@pytest.fixture
def state(tmp_path: Path) -> Path:
    folder = tmp_path / "st"
    res = catrt("init", folder, DETECTION)
    assert res.returncode == 0, res.stderr
    return folder


# ---------------------------------------------------------------- the loop on detection


def test_the_loop_keeps_restores_with_approval_and_rejects(state: Path):
    res = catrt("run", state, "--events", "-", "--json", stdin=lines(
        {"id": "low", "set": {"ram": "1"}},        # infeasible: restore ram → 4.5, request r1
        {"approve": "r1"},                         # approved: ram 4.5, the deployed A₀ is valid again
        {"id": "low", "set": {"ram": "2"}},        # a duplicate id: nothing happens
        '{"id": "torn", "set": {"ram": ',          # malformed: rejected, located, nothing changes
        {"id": "plenty", "set": {"ram": "64"}},    # A₀ still valid: keep, no new generation
    ))  # fmt: skip
    assert res.returncode == 0, res.stderr
    out = [json.loads(line) for line in res.stdout.splitlines()]
    start, low, approved, dup, torn, plenty = out
    assert start["decision"]["action"] == "compose" and start["generation"] == 1
    assert low["status"] == "accepted" and low["decision"]["action"] == "restore"
    assert low["decision"]["proposal"]["set"] == {"ram": "4.5"}  # by hand: 0.5 + 4
    assert approved["status"] == "accepted" and approved["decision"]["action"] == "keep"
    assert dup["status"] == "duplicate"
    assert torn["status"] == "rejected" and torn["where"] == "<stdin>:4:31"  # the line ends after 30 characters
    assert "E1001" in torn["message"]
    assert plenty["decision"]["action"] == "keep" and plenty["generation"] is None
    assert ram_of(state) == 64
    kinds = [e["kind"] for e in journal(state)]
    assert kinds.count("enact-done") == 1 and kinds.count("rejected") == 1
    events = [e["event_id"] for e in journal(state) if e["kind"] == "event"]
    assert events.count("low") == 1 and "torn" not in events
    assert (state / "current").resolve() == (state / "generations" / "000001").resolve()
    assert_consistent(state)


def test_a_rejected_event_changes_nothing(state: Path):
    catrt("run", state, "--events", "-", stdin="")
    before = stored(state, "model")
    res = catrt("run", state, "--events", "-", stdin=lines(
        {"id": "g", "goal": "(and (member person detects) (nonsense))"},  # E1002: the model check refuses it
        {"id": "s", "set": {"no-such-resource": "1"}},
        {"id": "h", "set": {"ram": "-1"}},                                  # outside ram's bounds (0 *)
    ))  # fmt: skip
    assert res.returncode == 0
    assert "E1002" in res.stderr and "goal:1:" in res.stderr and "nonsense" in res.stderr
    assert res.stderr.count("rejected") == 3
    assert stored(state, "model") == before
    assert not [e for e in journal(state) if e["kind"] == "event"]
    assert_consistent(state)


def test_requests_are_superseded_rejected_or_unknown(state: Path):
    res = catrt("run", state, "--events", "-", "--json", stdin=lines(
        {"id": "a", "set": {"ram": "1"}},     # r1
        {"id": "b", "set": {"ram": "2"}},     # r2; r1 superseded
        {"approve": "r1"},                    # E1010: no longer pending
        {"reject": "r2"},
        {"approve": "r9"},                    # E1010: never asked
    ))  # fmt: skip
    out = [json.loads(line) for line in res.stdout.splitlines()]
    assert [o["decision"]["proposal"]["set"] for o in out[1:3]] == [{"ram": "4.5"}, {"ram": "4.5"}]
    assert out[3]["status"] == "rejected" and "E1010" in out[3]["message"]
    assert out[4]["status"] == "accepted" and "rejected" in out[4]["message"]
    assert out[5]["status"] == "rejected" and "E1010" in out[5]["message"]
    from catrt.store import Store

    store = Store.open(state, write=False)
    assert {a["id"]: a["status"] for a in store.approvals()} == {"r1": "superseded", "r2": "rejected"}
    store.close()
    assert ram_of(state) == 2  # a rejected restoration is not applied
    assert_consistent(state)


def test_auto_approval_applies_the_restoration(state: Path):
    res = catrt("run", state, "--events", "-", "--approve", "auto", stdin=lines({"id": "a", "set": {"ram": "1"}}))
    assert res.returncode == 0, res.stderr
    assert ram_of(state) == Fraction(9, 2)
    verdicts = [e["data"]["verdict"] for e in journal(state) if e["kind"] == "approval"]
    assert verdicts == ["approved"]
    assert_consistent(state)


def test_a_recomposition_writes_a_new_generation_with_the_difference(tmp_path: Path):
    """Two interchangeable cameras; the deployed one's driver fails (a health event): the
    runtime recomposes with the other camera.  By hand: from budget 10, keeping camera A
    mounted (4) still leaves 6 for camera B, so camera A stays and the least churn is 2
    (mount-b and driver-b in; driver-a's removal is forced, not chosen, so it is not counted
    — docs/runtime.md); the hardware step is mounting B, nothing is unmounted."""
    model = tmp_path / "two-cameras.cat"
    model.write_text(TWO_CAMERAS)
    folder = tmp_path / "st"
    assert catrt("init", folder, model).returncode == 0
    res = catrt("run", folder, "--events", "-", "--json", stdin=lines({"id": "f", "health": {"failed": ["driver-a"]}}))
    assert res.returncode == 0, res.stderr
    start, failed = (json.loads(line) for line in res.stdout.splitlines())
    first = {a["morphism"] for step in start["decision"]["plan"]["steps"] for a in step}
    # the cheaper camera a (budget 10 → a costs 4, b 6): maximize budget picks a
    assert first == {"mount-a", "driver-a", "detector"}
    assert failed["decision"]["action"] == "recompose" and failed["generation"] == 2
    second = {a["morphism"] for step in failed["decision"]["plan"]["steps"] for a in step}
    assert second == {"mount-a", "mount-b", "driver-b", "detector"}
    assert "least churn 2, besides removing driver-a" in failed["message"]
    compose = (folder / "current" / "compose.yaml").read_text()
    assert "driver_b" in compose and "driver_a" not in compose
    done = [e for e in journal(folder) if e["kind"] == "enact-done"][-1]["data"]
    assert done["hardware"] == {"unmount": [], "mount": ["mount-b"]}
    assert_consistent(folder)


TWO_CAMERAS = """\
(define (domain two-cameras)
  (:requirements :numeric :sets :optimization :grounding)
  (:sorts part topic - symbol)
  (:constants cam-a cam-b - part  image - topic)
  (:resources
    (mounted (set part))
    (topics (set topic))
    (budget real :bounds (0 *))
    (seeing bool))
  (:morphism mount-a :kind hardware :uses 1
    :precondition (and (>= budget 4) (not (member cam-a mounted)))
    :effect (and (decrease budget 4) (add mounted cam-a))
    :ground (hardware :instruction "Mount camera A" :check "LED on" :parts ("camera A")))
  (:morphism mount-b :kind hardware :uses 1
    :precondition (and (>= budget 6) (not (member cam-b mounted)))
    :effect (and (decrease budget 6) (add mounted cam-b))
    :ground (hardware :instruction "Mount camera B" :check "LED on" :parts ("camera B")))
  (:morphism driver-a :kind software :uses 1
    :precondition (member cam-a mounted)
    :effect (add topics image)
    :ground (software :image "example/driver-a:1" :node driver_a))
  (:morphism driver-b :kind software :uses 1
    :precondition (member cam-b mounted)
    :effect (add topics image)
    :ground (software :image "example/driver-b:1" :node driver_b))
  (:morphism detector :kind software :uses 1
    :precondition (member image topics)
    :effect (assign seeing true)
    :ground (software :image "example/detector:1" :node detector)))

(define (problem see)
  (:domain two-cameras)
  (:init (= budget 10))
  (:goal seeing)
  (:horizon 3)
  (:metric maximize budget))
"""


# ---------------------------------------------------------------- the store


def test_one_writer_at_a_time(state: Path):
    from catrt.store import Store, StoreError

    holder = Store.open(state, write=True)
    try:
        res = catrt("run", state, "--events", "-", stdin="")
        assert res.returncode == 2 and "error[E1003]" in res.stderr and "one writer at a time" in res.stderr
        with pytest.raises(StoreError) as err:
            Store.open(state, write=True)
        assert err.value.code == "E1003"
        assert catrt("status", state).returncode == 0  # readers need no lock
    finally:
        holder.close()
    assert catrt("run", state, "--events", "-", stdin="").returncode == 0


def test_a_store_of_another_version_is_refused_or_migrated(state: Path, monkeypatch):
    from catrt import store as store_module

    db = sqlite3.connect(state / "catrt.sqlite")
    db.execute("UPDATE meta SET value = '99' WHERE key = 'schema_version'")
    db.commit()
    db.close()
    res = catrt("run", state, "--events", "-", stdin="")
    assert res.returncode == 2 and "error[E1004]" in res.stderr and "newer catrt" in res.stderr
    assert "error[E1004]" in catrt("status", state).stderr
    # an older store this catrt knows how to migrate: migrated when opened for writing, journaled
    db = sqlite3.connect(state / "catrt.sqlite")
    db.execute("UPDATE meta SET value = '1' WHERE key = 'schema_version'")
    db.commit()
    db.close()
    monkeypatch.setattr(store_module, "SCHEMA_VERSION", 2)
    monkeypatch.setitem(store_module.MIGRATIONS, 1, ["CREATE TABLE added_by_v2 (x TEXT)"])
    with pytest.raises(store_module.StoreError) as err:
        store_module.Store.open(state, write=False)
    assert err.value.code == "E1004" and "open it for writing" in str(err.value)
    s = store_module.Store.open(state, write=True)
    assert s.meta()["schema_version"] == "2"
    assert s.db.execute("SELECT name FROM sqlite_master WHERE name = 'added_by_v2'").fetchone()
    assert [e["data"] for e in s.entries(kinds=("migrated",))] == [{"from": 1, "to": 2}]
    s.close()


def test_not_a_store_and_a_store_twice(tmp_path: Path, state: Path):
    res = catrt("status", tmp_path / "nothing")
    assert res.returncode == 2 and "error[E1005]" in res.stderr and "catrt init" in res.stderr
    (tmp_path / "junk").mkdir()
    (tmp_path / "junk" / "catrt.sqlite").write_bytes(b"not a database, " * 64)
    res = catrt("status", tmp_path / "junk")
    assert res.returncode == 2 and "error[E1005]" in res.stderr
    res = catrt("init", state, DETECTION)
    assert res.returncode == 2 and "error[E1006]" in res.stderr


def test_the_journal_is_append_only(state: Path):
    db = sqlite3.connect(state / "catrt.sqlite")
    for sql in ("UPDATE journal SET kind = 'x' WHERE seq = 1", "DELETE FROM journal WHERE seq = 1"):
        with pytest.raises(sqlite3.DatabaseError, match="append-only"):
            db.execute(sql)
    db.close()


def test_verify_finds_a_tampered_state_and_generation(state: Path):
    assert catrt("run", state, "--events", "-", stdin=lines({"id": "a", "set": {"ram": "8"}})).returncode == 0
    assert_consistent(state)
    compose = state / "generations" / "000001" / "compose.yaml"
    compose.write_text(compose.read_text() + "# edited by hand\n")
    res = catrt("verify", state)
    assert res.returncode == 1 and "error[E1012]" in res.stderr and "differs from its manifest" in res.stderr
    compose.write_text(compose.read_text().replace("# edited by hand\n", ""))
    assert catrt("verify", state).returncode == 0
    db = sqlite3.connect(state / "catrt.sqlite")  # a state row the journal does not explain
    row = json.loads(db.execute("SELECT value FROM state WHERE key = 'model'").fetchone()[0])
    row["problem"]["init"]["ram"] = "7"
    db.execute("UPDATE state SET value = ? WHERE key = 'model'", (json.dumps(row),))
    db.commit()
    db.close()
    res = catrt("replay", state)
    assert res.returncode == 1 and "error[E1012]" in res.stderr and "model" in res.stderr


# ---------------------------------------------------------------- enacting with Docker Compose


def fake_docker(tmp_path: Path, exit_code: int = 0) -> Path:
    """A ``docker`` that records its arguments and working folder (tests/fake_docker.py:
    ``compose config`` by the real Compose binary, ``up`` exits ``exit_code``)."""
    return fake_docker_module.install(tmp_path, up_exit=exit_code)


def compose_calls(tmp_path: Path) -> list[str]:
    """The docker calls that change the robot (not ``version`` and ``ps``)."""
    return [c for c in (tmp_path / "docker.log").read_text().splitlines() if " up " in c + " "]


def test_the_compose_enactor_runs_docker_compose_on_the_generation(tmp_path: Path, state: Path):
    bin_dir = fake_docker(tmp_path)
    env = {"PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"}
    res = catrt("run", state, "--events", "-", "--enactor", "compose", stdin="", env=env)
    assert res.returncode == 0, res.stderr
    gen = (state / "generations" / "000001").resolve()
    calls = compose_calls(tmp_path)
    project = json.loads((gen / "manifest.json").read_text())["project"]
    profiles = "--profile drivers --profile skillsets"  # the detection example's two services' profiles
    assert calls == [f"{gen}|compose -p {project} -f {gen / 'compose.yaml'} {profiles} up -d --remove-orphans"]
    assert "generation 1 enacted" in res.stdout
    assert_consistent(state)


def test_the_compose_files_are_named_absolutely_whatever_the_state_path(tmp_path: Path):
    """docker compose runs inside the generation folder: a relative STATE must not be
    resolved twice (rel/generations/1/rel/generations/1/compose.yaml)."""
    bin_dir = fake_docker(tmp_path)
    assert catrt("init", "rel", DETECTION, cwd=tmp_path).returncode == 0
    env = {"PATH": f"{bin_dir}{os.pathsep}{os.environ['PATH']}"}
    res = catrt("run", "rel", "--events", "-", "--enactor", "compose", stdin="", env=env, cwd=tmp_path)
    assert res.returncode == 0 and "E1011" not in res.stderr, res.stderr
    gen = (tmp_path / "rel" / "generations" / "000001").resolve()
    (call,) = compose_calls(tmp_path)
    assert f"-f {gen / 'compose.yaml'} --profile" in call


def test_an_events_path_that_does_not_exist_is_an_error_not_a_new_spool(state: Path, tmp_path: Path):
    res = catrt("run", state, "--events", tmp_path / "typo.jsonl")
    assert res.returncode == 2 and "error[E0701]" in res.stderr and "no such file or folder" in res.stderr
    assert not (tmp_path / "typo.jsonl").exists()
    assert [e["kind"] for e in journal(state)] == ["init"]  # nothing decided either


def test_ask_asks_on_the_terminal(state: Path, tmp_path: Path):
    """--approve ask: the question on the controlling terminal (a pseudo-terminal made here),
    answered y: the restoration is applied.  The events come from a file, so only the
    terminal can answer."""
    import pty
    import time

    events = tmp_path / "ev.jsonl"
    events.write_text(lines({"id": "low", "set": {"ram": "1"}}))
    master, slave = pty.openpty()
    # in a new session, the pty on standard input becomes the child's controlling terminal
    on_tty = "import fcntl, termios; fcntl.ioctl(0, termios.TIOCSCTTY, 0); from catrt.cli import entry; entry()"
    proc = subprocess.Popen([sys.executable, "-c", on_tty, "run", str(state), "--events", str(events), "--approve",
                             "ask"], stdin=slave, stdout=slave, stderr=slave, start_new_session=True)  # fmt: skip
    os.close(slave)
    seen, answered, deadline = b"", False, time.monotonic() + 120
    while time.monotonic() < deadline:
        try:
            chunk = os.read(master, 4096)
        except OSError:  # the child closed the terminal
            break
        seen += chunk
        if not answered and b"[y/N]" in seen:
            os.write(master, b"y\n")
            answered = True
    proc.wait(timeout=60)
    os.close(master)
    text = seen.decode("utf-8", "replace")
    assert proc.returncode == 0, text
    assert "request r1: restore the model by ram → 4.5? [y/N]" in text
    assert ram_of(state) == Fraction(9, 2)


def test_a_failed_enactment_is_journaled_and_the_old_generation_stays(tmp_path: Path):
    model = tmp_path / "two-cameras.cat"
    model.write_text(TWO_CAMERAS)
    folder = tmp_path / "st"
    assert catrt("init", folder, model).returncode == 0
    assert catrt("run", folder, "--events", "-", stdin="").returncode == 0  # generation 1, dry
    env = {"PATH": f"{fake_docker(tmp_path, exit_code=1)}{os.pathsep}{os.environ['PATH']}"}
    res = catrt("run", folder, "--events", "-", "--enactor", "compose", env=env,
                stdin=lines({"id": "f", "health": {"failed": ["driver-a"]}}))  # fmt: skip
    assert res.returncode == 0
    assert "error[E1011]" in res.stderr and "generation 2" in res.stderr and "boom" in res.stderr
    assert stored(folder, "incumbent")["generation"] == 1
    assert (folder / "current").resolve() == (folder / "generations" / "000001").resolve()
    failed = [e for e in journal(folder) if e["kind"] == "enact-failed"]
    assert len(failed) == 1 and failed[0]["data"]["code"] == "E1011"
    assert_consistent(folder)


# ---------------------------------------------------------------- crashes


def two_cameras(tmp_path: Path) -> Path:
    model = tmp_path / "two-cameras.cat"
    model.write_text(TWO_CAMERAS)
    folder = tmp_path / "st"
    assert catrt("init", folder, model).returncode == 0
    return folder


@pytest.mark.parametrize("point", ["after-journal", "mid-artifacts", "before-enact-done"])
@pytest.mark.parametrize("hit", [1, 2])  # 1: the start's generation 1; 2: an event's generation 2
def test_a_crash_at_any_point_loses_nothing_and_enacts_once_more(tmp_path: Path, point: str, hit: int):
    folder = two_cameras(tmp_path)
    env = {"CATRT_CRASH_AT": f"{point}:{hit}", "PATH": f"{fake_docker(tmp_path)}{os.pathsep}{os.environ['PATH']}"}
    events = lines({"id": "f", "health": {"failed": ["driver-a"]}})
    res = catrt("run", folder, "--events", "-", "--enactor", "compose", stdin=events, env=env)
    assert res.returncode == -signal.SIGKILL, res.stdout + res.stderr
    enacting = stored(folder, "enacting")
    assert enacting is not None and enacting["generation"] == hit
    if point == "after-journal":
        assert not (folder / "generations" / f"{hit:06d}").exists()
    if point == "mid-artifacts":  # half a generation exists, under a temporary name only
        assert list((folder / "generations").glob(f".tmp-{hit:06d}-*"))
        assert not (folder / "generations" / f"{hit:06d}").exists()
    res = catrt("verify", folder)
    assert res.returncode == 0 and "was being enacted: the next run finishes it" in res.stdout
    # the restart finishes the enactment, then takes the same events again: the accepted one is a duplicate
    res = catrt("run", folder, "--events", "-", "--enactor", "compose", stdin=events,
                env={"PATH": env["PATH"]})  # fmt: skip
    assert res.returncode == 0, res.stderr
    kinds = [e["kind"] for e in journal(folder)]
    assert kinds.count("recovery") == 1
    assert [e["event_id"] for e in journal(folder) if e["kind"] == "event"] == ["f"]
    assert stored(folder, "enacting") is None and stored(folder, "incumbent")["generation"] == 2
    assert (folder / "current").resolve() == (folder / "generations" / "000002").resolve()
    assert not list((folder / "generations").glob(".tmp-*"))
    ups = [c for c in (tmp_path / "docker.log").read_text().splitlines() if "000002" in c and "--remove-orphans" in c]
    # enacted once, or twice when the crash came after docker ran (compose up is idempotent)
    assert len(ups) == (2 if point == "before-enact-done" and hit == 2 else 1)
    assert_consistent(folder)


def test_killed_at_random_times_the_store_stays_whole(tmp_path: Path):
    """A long event stream, the runtime killed (SIGKILL) at seeded random points and
    restarted on the same stream until it gets through: every event is accepted exactly
    once, the journal has no gap, replay equals the state, and the final ram is the stream's
    last value.  The points are the crash hooks' (``CATRT_CRASH_AT=POINT:N``: the N-th time
    the run reaches POINT), not moments of the clock: before (issue 28) a kill after 0.4-2.5
    s of wall time could come before the first event on a loaded machine, for 30 attempts."""
    import random

    rng = random.Random(20261124)
    values = ["1", "3", "4.5", "8", "16", "64", "5/2", "4.75"]
    stream = [{"id": f"e{i}", "set": {"ram": rng.choice(values)}} for i in range(60)]
    events = tmp_path / "events.jsonl"
    events.write_text(lines(*stream))
    folder = tmp_path / "st"
    assert catrt("init", folder, DETECTION).returncode == 0
    kills = 0
    for _attempt in range(40):  # after-journal comes once an accepted event (the other points
        point = f"after-journal:{rng.randint(1, 8)}"  # come once an enactment: rare here)
        res = catrt("run", folder, "--events", events, env={"CATRT_CRASH_AT": point})
        if res.returncode == -signal.SIGKILL:
            kills += 1
            continue
        assert res.returncode == 0, res.stderr
        break
    else:  # killed every time: the last run gets through without a crash point
        assert catrt("run", folder, "--events", events).returncode == 0
    assert kills >= 5  # the test killed it several times (else it proves little)
    accepted = [e["event_id"] for e in journal(folder) if e["kind"] == "event"]
    assert accepted == [e["id"] for e in stream]
    assert ram_of(folder) == Fraction(stream[-1]["set"]["ram"])
    assert_consistent(folder)


# ---------------------------------------------------------------- properties, the Python API, the spool


GOALS = ["(member person detects)", "(and (member person detects) (member image-raw topics))"]


def _event_strategy():
    from hypothesis import strategies as st

    ram = st.sampled_from(["0", "1", "4.5", "5", "16", "1/3", "9/2"]).map(lambda v: {"set": {"ram": v}})
    goal = st.sampled_from(GOALS).map(lambda g: {"goal": g})
    horizon = st.integers(0, 4).map(lambda h: {"horizon": h})
    verdict = st.tuples(st.sampled_from(["approve", "reject"]), st.integers(1, 4)).map(lambda t: {t[0]: f"r{t[1]}"})
    junk = st.sampled_from(['{"set": {"ram": 1.5e', '{"goal": "(and"}', "[]", '{"set": {"nope": "1"}}'])
    return st.one_of(ram, goal, horizon, verdict, junk)


def test_any_event_sequence_replays_to_the_stored_state(tmp_path_factory):
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    from catrt.api import connect, init
    from catrt.replay import differences, replay

    @settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
    @given(st.lists(st.tuples(_event_strategy(), st.booleans()), max_size=8))
    def run(events):
        folder = tmp_path_factory.mktemp("prop") / "st"
        init(folder, str(DETECTION))
        with connect(folder) as rt:
            for i, (given, with_id) in enumerate(events):
                event = {"id": f"e{i % 3}", **given} if isinstance(given, dict) and with_id else given  # ids repeat
                outcome = rt.submit(event)
                assert outcome.status in ("accepted", "rejected", "duplicate")
            store = rt.runtime.store
            assert store.integrity() == []
            replayed = replay(store, folder)
            assert replayed.problems == [] and differences(store, replayed) == []

    run()


def test_the_python_api_is_a_source_of_events(tmp_path: Path):
    from catrt.api import connect, init, submit
    from catrt.store import StoreError

    folder = tmp_path / "st"
    init(folder, str(DETECTION))
    said = []
    with connect(folder, say=said.append) as rt:
        assert [o.decision.action for o in rt.started] == ["compose"]
        low = rt.submit({"id": "low", "set": {"ram": "1"}})
        assert low.decision.proposal["set"] == {"ram": "4.5"}
        with pytest.raises(StoreError) as err:  # the connection is the single writer
            connect(folder)
        assert err.value.code == "E1003"
        assert rt.status()["pending"][0]["id"] == "r1"
    assert said[-1] is low
    (outcome,) = submit(folder, [{"approve": "r1"}])
    assert outcome.status == "accepted" and ram_of(folder) == Fraction(9, 2)


def test_the_spool_folder_is_read_in_name_order(state: Path):
    assert catrt("event", state, "-", stdin=lines({"id": "a", "set": {"ram": "1"}})).returncode == 0
    assert catrt("event", state, "-", stdin=lines({"id": "b", "set": {"ram": "2"}})).returncode == 0
    res = catrt("event", state, "-", stdin=lines({"id": "c", "set": {"ram": "1"}}, '{"broken'))
    assert res.returncode == 2 and "E1001" in res.stderr and "nothing queued" in res.stderr
    res = catrt("approve", state, "r1")  # nothing asked yet: the loop has not run
    assert res.returncode == 2 and "error[E1010]" in res.stderr
    assert catrt("run", state, "--once").returncode == 0
    assert ram_of(state) == 2  # a, then b (in name order), each asking for ram → 4.5
    assert catrt("approve", state, "r2").returncode == 0
    assert catrt("run", state, "--once").returncode == 0
    assert ram_of(state) == Fraction(9, 2)
    assert not [p for p in (state / "spool").iterdir() if p.is_file()]
    assert len(list((state / "spool" / "done").iterdir())) == 3
    assert_consistent(state)


# ---------------------------------------------------------------- the paper's mission (slow)


@pytest.mark.slow
def test_the_search_and_rescue_mission(tmp_path: Path):
    """examples/search-and-rescue/mission-events.jsonl through the loop, each decision derived
    by hand from the domain (paper §V, Algorithm 1; watts: LiDAR 12, lite camera 3, thermal 4,
    speaker-mic 2, radio 5; 20 W on the robot, +30 W from the external battery):

    * start, the most budget left: LiDAR 20,000 + lite camera 50 + speaker-mic 60 + radio 60,
      drawing 22 W > 20 W so the battery (90) too: 20,260 spent, 4,740 left;
    * II, 14 from base with a radio range of 10: ``report`` needs range-to-base ≤ comms-range,
      so A₀ fails at its last step; adding ``return-to-range`` repairs it: churn 1;
    * III, the budget cut to 500: the LiDAR alone costs 20,000, so no composition exists (the
      core: the budget's initial value and the LiDAR's price); restoring A₀'s own hardware
      needs exactly its cost: budget → 20,260 (+19,760);
    * approved: A₀ holds again with 20,260: kept, no new generation;
    * a refurbished RGB camera enters the catalogue: A₀ does not use it and holds: kept
      without a solver call (stability first: churn 0);
    * IV, dark: both RGB drivers need bright light, so A₀ fails and nothing restores its own
      components; over the whole catalogue the thermal camera (900) is needed: with the battery
      21,110 (+850 budget), or without it 21,020 (+760) and 12 + 4 + 2 + 5 = 23 W (+3 power).
      USD and W are unlike units, so each change counts relative to its value (issue 26; adding
      them, 763 < 850, took 1 W for 1 USD): 850/20,260 ≈ 0.042 < 760/20,260 + 3/20 ≈ 0.19, so
      budget → 21,110 (request r2);
    * approved: the least churn from A₀ swaps the lite camera and its driver for the thermal
      ones, the battery kept (paid for): churn 4;
    * the LiDAR driver fails: SLAM has no other source of ``scan`` and no initial value gives
      one, so there is no composition and no restoration: stuck, waiting.
    """
    folder = tmp_path / "st"
    mission = ROOT / "examples" / "search-and-rescue"
    res = catrt("init", folder, mission / "mission.cat")
    assert res.returncode == 0, res.stderr
    res = catrt("run", folder, "--events", mission / "mission-events.jsonl", "--json")
    assert res.returncode == 0, res.stderr
    start, ii, iii, iii_ok, catalog, iv, iv_ok, failed = (json.loads(line) for line in res.stdout.splitlines())

    def uses(outcome):
        return {a["morphism"] for step in outcome["decision"]["plan"]["steps"] for a in step}

    assert start["decision"]["action"] == "compose" and start["generation"] == 1
    hardware = {m for m in uses(start) if m.startswith("mount-")}
    assert hardware == {"mount-lidar", "mount-rgb-camera-lite", "mount-speaker-mic", "mount-long-range-radio",
                        "mount-external-battery"}  # fmt: skip
    assert ii["decision"]["action"] == "recompose" and ii["decision"]["churn"] == "1" and ii["generation"] == 2
    assert [(c["morphism"], c["change"]) for c in ii["decision"]["changes"]] == [("return-to-range", "added")]
    assert iii["decision"]["action"] == "restore" and iii["decision"]["proposal"]["set"] == {"budget": "20260"}
    assert iii["decision"]["proposal"]["proven"] is True
    assert "core: init/budget, pre/mount-lidar/1" in iii["message"]
    assert iii_ok["decision"]["action"] == "keep" and iii_ok["generation"] is None
    assert catalog["decision"]["action"] == "keep" and catalog["decision"]["solver_calls"] == 0
    assert iv["decision"]["action"] == "restore" and iv["decision"]["proposal"]["set"] == {"budget": "21110"}
    assert iv_ok["decision"]["action"] == "recompose" and iv_ok["decision"]["churn"] == "4"
    assert {(c["morphism"], c["change"]) for c in iv_ok["decision"]["changes"]} == {
        ("mount-rgb-camera-lite", "removed"), ("rgb-lite-driver", "removed"),
        ("mount-thermal-camera", "added"), ("thermal-driver", "added"),
    }  # fmt: skip
    assert failed["decision"]["action"] == "stuck" and failed["decision"]["proposal"] is None
    assert "no change of initial values restores one" in failed["message"]
    assert (folder / "current").resolve() == (folder / "generations" / "000003").resolve()
    diff = json.loads(catrt("status", folder, "--json").stdout)["last_enactment"]["diff"]
    assert (diff["unmount"], diff["mount"]) == (["mount-rgb-camera-lite"], ["mount-thermal-camera"])
    assert (diff["stop"], diff["start"]) == (["rgb-lite-driver"], ["thermal-driver"])
    assert "thermal" in (folder / "current" / "instructions.md").read_text().lower()
    assert_consistent(folder)


def test_nothing_an_event_carries_can_drive_the_terminal(state: Path):
    """An id holding a C1 control sequence introducer (\x9b: colour the terminal) and a
    right-to-left override (hide text) is echoed with each shown as an escape, never raw."""
    sneaky = "e\u009b31m\u202eevil"
    res = catrt("run", state, "--events", "-", stdin=lines({"id": sneaky, "set": {"ram": "8"}}))
    assert res.returncode == 0, res.stderr
    assert "e\\x9b31m\\u202eevil: accepted" in res.stdout
    assert "\u009b" not in res.stdout + res.stderr and "\u202e" not in res.stdout + res.stderr
    assert "\u202e" not in catrt("journal", state).stdout
    assert [e["event_id"] for e in journal(state) if e["kind"] == "event"] == [sneaky]  # stored as given
