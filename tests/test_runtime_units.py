"""catrt's input side, unit by unit: events (catrt.events), applying them to the model
(catrt.apply), the configuration (catrt.config), shell sensors (catrt.sensors) and the spool
folder (catrt.spool).  tests/test_runtime.py drives the whole loop; this file pins what each
piece accepts and refuses, and that a refusal changes nothing.

Codes: E1001 a line that is not an event, or an event field that cannot apply; E1002 an event
whose model does not check; E1007 a bad config.toml; E1008 shell sensors without
--allow-shell; E1009 a sensor that failed or printed something that is not a value.

Expected values are derived by hand from the model texts, never copied from catrt's output:

* examples/detection/person.cat: resources mounted (set module), ram (real, bounds (0 *)),
  topics (set topic), detects (set class); ram starts at 16; morphisms mount-rgb-camera,
  camera-driver, open-vocab-detector.
* TINY below: ram real (0 *) = 2, restarts int (0 3) = 0, online bool = false (by default),
  ambient of the enumeration lighting (bright dark) = bright, mounted (set module) = {} with
  the constants lidar and camera.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import subprocess
import sys
import time
from fractions import Fraction
from pathlib import Path

import pytest
from click.testing import CliRunner
from conftest import ROOT, run_catc

pytest.importorskip("jsonschema", reason="the runtime extra")

from catrt.events import MAX_LINE, EventError, exact, parse_event, read_lines

PERSON = ROOT / "examples" / "detection" / "person.cat"
TINY = """\
(define (domain tiny)
  (:requirements :numeric :sets)
  (:sorts module - symbol
          lighting - (enum bright dark))
  (:constants lidar camera - module)
  (:resources
    (ram real :bounds (0 *))
    (restarts int :bounds (0 3))
    (online bool)
    (ambient lighting)
    (mounted (set module)))
  (:morphism boot
    :uses 1
    :precondition (and (>= ram 1) (not online))
    :effect (assign online true)))

(define (problem start)
  (:domain tiny)
  (:init (= ram 2) (= restarts 0) (= ambient bright))
  (:goal online))
"""


# ---------------------------------------------------------------- helpers


@pytest.fixture(scope="module")
def pristine(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Path]:
    """A state folder for each model, made once by catrt's own init; tests work on copies."""
    from catrt.create import create

    root = tmp_path_factory.mktemp("pristine")
    (root / "tiny.cat").write_text(TINY, encoding="utf-8")
    out = {}
    for name, problem in (("person", PERSON), ("tiny", root / "tiny.cat")):
        create(root / name, str(problem)).close()
        out[name] = root / name
    return out


@pytest.fixture
def person(pristine: dict[str, Path], tmp_path: Path) -> Path:
    return Path(shutil.copytree(pristine["person"], tmp_path / "person"))


@pytest.fixture
def tiny(pristine: dict[str, Path], tmp_path: Path) -> Path:
    return Path(shutil.copytree(pristine["tiny"], tmp_path / "tiny"))


@pytest.fixture(scope="module")
def tiny_resources(tmp_path_factory: pytest.TempPathFactory):
    from catc.api import load

    path = tmp_path_factory.mktemp("tiny") / "tiny.cat"
    path.write_text(TINY, encoding="utf-8")
    return load(str(path)).instance.resources


@contextlib.contextmanager
def runtime(state: Path):
    """The runtime on ``state`` in this process (approvals: never); what it said, collected."""
    from catrt.config import load_config
    from catrt.runtime import Runtime
    from catrt.store import Store

    said: list = []
    rt = Runtime(state, Store.open(state, write=True), load_config(state), approve="never", say=said.append)
    try:
        yield rt, said
    finally:
        rt.close()


def snapshot(rt) -> dict:
    """Everything a rejected event must leave as it was (the journal only grows)."""
    return {
        "store": rt.store.state(),
        "memory": rt.state.to_json(),
        "files": {p.name: p.read_bytes() for p in sorted((rt.folder / "model").iterdir())},
        "approvals": rt.store.approvals(),
    }


def journal(state: Path) -> list[dict]:
    from catrt.store import Store

    store = Store.open(state, write=False)
    try:
        return list(store.entries())
    finally:
        store.close()


def stored_model(state: Path) -> dict:
    from catrt.store import Store

    store = Store.open(state, write=False)
    try:
        return store.get("model")
    finally:
        store.close()


def catrt(*args: str | Path, input: str | bytes | None = None):
    """``catrt`` in this process; an exception escaping click is a test failure (exit 70 is
    catrt's own 'internal error', also a failure wherever a test checks the exit code)."""
    from catrt.cli import main

    res = CliRunner().invoke(main, [str(a) for a in args], input=input, catch_exceptions=True)
    if res.exception is not None and not isinstance(res.exception, SystemExit):
        raise AssertionError(f"catrt {args} raised {res.exception!r}") from res.exception
    return res


def event_line(doc: dict) -> str:
    return json.dumps(doc)


def ram_as(literal: str) -> str:
    """A set event whose ram is the JSON text ``literal`` (a number, or a constant)."""
    return '{"set": {"ram": ' + literal + "}}"


def refused(line: str, where: str = "ev.jsonl:7") -> EventError:
    with pytest.raises(EventError) as info:
        parse_event(line, where)
    return info.value


# ---------------------------------------------------------------- events: what parses


KINDS = [
    {"set": {"ram": "8", "online": True, "mounted": ["lidar", "camera"]}},
    {"goal": "(member person detects)"},
    {"metric": "maximize ram"},
    {"metric": None},
    {"softs": ["(>= ram 1) :weight 2", "true :weight 1"]},
    {"softs": []},
    {"horizon": 4},
    {"horizon": None},
    {"catalog": {"add": "(:morphism x :uses 1)"}},
    {"catalog": {"remove": ["camera-driver"]}},
    {"health": {"failed": ["camera-driver"]}},
    {"health": {"recovered": ["camera-driver"]}},
    {"set": {"ram": "8"}, "goal": "true", "horizon": 2, "health": {"failed": ["a"], "recovered": ["b"]}},
    {"approve": "r1"},
    {"reject": "r2"},
]


@pytest.mark.parametrize("doc", KINDS, ids="+".join)
def test_every_event_kind_parses(doc):
    """Not E1001: every kind of the schema, alone and together, with v, id and at."""
    event = parse_event(event_line({"v": 1, "id": "e-1", "at": "2024-05-01T10:00:00Z", **doc}), "ev.jsonl:3")
    assert event.id == "e-1" and event.given_id and event.where == "ev.jsonl:3"
    assert event.body == {"at": "2024-05-01T10:00:00Z", **doc}  # v and id are not part of the body
    assert event.is_approval == ("approve" in doc or "reject" in doc)
    assert event.to_json() == {"v": 1, "id": "e-1", "at": "2024-05-01T10:00:00Z", **doc}


def test_ids_given_are_kept_and_missing_ones_are_fresh():
    """An id given is the event's (the runtime's duplicate check uses it, not E1001 here);
    without one each event gets its own auto-<32 hex> id and is never a duplicate."""
    given = parse_event('{"id": "sensor 7 / reading 3", "set": {"ram": "1"}}', "x:1")
    assert given.id == "sensor 7 / reading 3" and given.given_id
    a, b = (parse_event('{"set": {"ram": "1"}}', "x:1") for _ in range(2))
    for e in (a, b):
        assert not e.given_id and e.id.startswith("auto-") and len(e.id) == 5 + 32
        int(e.id[5:], 16)
    assert a.id != b.id
    assert a.to_json()["id"] == a.id and a.to_json()["v"] == 1


@pytest.mark.parametrize(
    "text, value",
    [
        ("22.73", Fraction(2273, 100)),
        ("0.1", Fraction(1, 10)),
        ("1/3", Fraction(1, 3)),
        ("-2/6", Fraction(-1, 3)),
        ("1e-3", Fraction(1, 1000)),  # an exponent is a decimal too: kept, and exact
        ("6.02E23", Fraction(602 * 10**21)),
        ("+.5e+3", Fraction(500)),
        ("007", Fraction(7)),
        (" 4.5 ", Fraction(9, 2)),
        ("1e-1000", Fraction(1, 10**1000)),  # 1000 digits below the point: still allowed
    ],
)
def test_decimal_strings_stay_exact(text, value):
    """Not E1001: a number written as text is the rational it spells, never a float."""
    assert exact(text) == value
    event = parse_event(event_line({"set": {"ram": text}}), "x:1")
    assert event.body["set"]["ram"] == text  # kept as written; applying it stores the exact value


@pytest.mark.parametrize("literal, value", [("22.73", Fraction(2273, 100)), ("0.1", Fraction(1, 10)),
                                            ("1e-3", Fraction(1, 1000)), ("16", Fraction(16)),
                                            ("-0.5", Fraction(-1, 2))])  # fmt: skip
def test_json_numbers_are_read_as_the_decimal_written(literal, value):
    """Not E1001: the schema says a JSON number is read as the decimal it is written as.
    22.73 as a binary float is 22.730000000000000426..., which must never reach the model."""
    event = parse_event(ram_as(literal), "x:1")
    text = event.body["set"]["ram"]
    assert isinstance(text, str) and exact(text) == value


def test_a_json_number_as_horizon_must_be_an_integer():
    """E1001 for 24.5 (a horizon counts steps), located at the line."""
    error = refused('{"horizon": 24.5}')
    assert error.where == "ev.jsonl:7" and "horizon" in error.message
    assert "24.5 is not of type 'integer', 'null'" in error.message  # JSON's words, not Decimal('24.5')
    assert parse_event('{"horizon": 24.0}', "ev.jsonl:7").body["horizon"] == 24  # a whole number written so


def test_a_key_given_twice_is_refused_not_overwritten():
    """E1001: JSON allows {"set": A, "set": B} and most readers keep B silently."""
    error = refused('{"set": {"ram": "1"}, "set": {"ram": "64"}}')
    assert "the key 'set' appears twice" in error.message
    error = refused('{"set": {"ram": "1", "ram": "64"}}')
    assert "the key 'ram' appears twice" in error.message


@pytest.mark.parametrize(
    "value",
    ["-", "+", ".", "1/0", "0x10", "1_000", "12abc", "1e99999", "1..2", "1/2/3", "--1", "1e9999"],
)
def test_text_that_looks_like_a_number_but_is_not_one_is_refused(value):
    """E1001 naming set.ram: '1e9999' is refused too (10,000 digits would crash the
    runtime's own number printing: Python refuses to print an int of more than 4,300)."""
    error = refused(event_line({"set": {"ram": value}}))
    assert error.where == "ev.jsonl:7"
    assert error.message.startswith("set.ram: ") and "not a number" in error.message


@pytest.mark.parametrize("literal", ["1e99999999", "1e1001", "-1e-1001", "1" * 1001, "0." + "0" * 1000 + "1"])
def test_a_json_number_too_large_to_be_a_measurement_is_refused_at_once(literal):
    """E1001, in well under a second: 1e99999999 is a 24-byte line that would otherwise be
    expanded to a 100-million-digit integer (minutes of CPU, the runtime frozen)."""
    start = time.perf_counter()
    error = refused(ram_as(literal))
    assert time.perf_counter() - start < 1.0
    assert error.message.startswith("set.ram: ") and "1000 digits" in error.message


def test_text_numbers_have_at_most_1000_digits_above_and_below():
    """E1001 / E1009: the same bound for text (a sensor may print 4 KiB of digits)."""
    assert exact("1" * 1000) == int("1" * 1000) and exact("1" * 1001) is None
    assert exact("1/" + "3" * 1000) == Fraction(1, int("3" * 1000)) and exact("1/" + "3" * 1001) is None
    assert exact("7" * 1001 + "/1") is None and exact("1e1000") is None and exact("1e999") == 10**999


@pytest.mark.parametrize("constant", ["NaN", "Infinity", "-Infinity"])
def test_json_constants_that_are_not_numbers_are_refused(constant):
    """E1001: Python's json reads NaN and Infinity; an event must not."""
    error = refused(ram_as(constant))
    assert error.where == "ev.jsonl:7" and constant.lstrip("-") in error.message


@pytest.mark.parametrize("digits", ["١٢", "１２", "१२"])
def test_digits_of_other_scripts_are_not_numbers(digits):
    """E1001 at apply time (the text does not start like a number, so the event parses),
    E1009 for a sensor: \\d in a Unicode regex would read Arabic-Indic or full-width 12."""
    assert exact(digits) is None


# ---------------------------------------------------------------- events: what is refused


LONG = '{"goal": "' + "x" * (MAX_LINE + 1) + '"}'
WIDE = '{"goal": "' + "é" * (MAX_LINE // 2 + 1) + '"}'  # fewer characters than MAX_LINE, more bytes

MALFORMED = [
    # (line, the where it is located at, words the message must have)
    ("{}", "ev.jsonl:7", ["needs one of", "set"]),
    ("[]", "ev.jsonl:7", ["JSON object", "list"]),
    ('"set"', "ev.jsonl:7", ["JSON object", "str"]),
    ("null", "ev.jsonl:7", ["JSON object"]),
    ("42", "ev.jsonl:7", ["JSON object"]),
    ("nope", "ev.jsonl:7:1", ["not JSON"]),
    ('{"set": {"ram": "1"}', "ev.jsonl:7:21", ["not JSON"]),  # torn: 20 characters, then the end
    ('{"set": {"ram": "1"}} {"goal": "true"}', "ev.jsonl:7:23", ["not JSON", "Extra data"]),  # two on a line
    ('{"sett": {"ram": "1"}}', "ev.jsonl:7", ["unknown field 'sett'", "did you mean 'set'"]),
    ('{"set": {"ram": "1"}, "colour": "red"}', "ev.jsonl:7", ["unknown field 'colour'"]),
    ('{"goal": 5}', "ev.jsonl:7", ["goal", "string"]),
    ('{"goal": ""}', "ev.jsonl:7", ["goal"]),
    ('{"metric": ""}', "ev.jsonl:7", ["metric"]),
    ('{"softs": "(>= ram 1) :weight 2"}', "ev.jsonl:7", ["softs"]),
    ('{"set": {}}', "ev.jsonl:7", ["set"]),
    ('{"set": {"ram": null}}', "ev.jsonl:7", ["set.ram"]),
    ('{"set": {"ram": {"value": "1"}}}', "ev.jsonl:7", ["set.ram"]),
    ('{"set": {"mounted": ["lidar", 3]}}', "ev.jsonl:7", ["set.mounted"]),
    ('{"set": {"mounted": ["lid ar"]}}', "ev.jsonl:7", ["set.mounted"]),
    ('{"set": {"1ram": "1"}}', "ev.jsonl:7", ["set"]),
    ('{"v": 2, "set": {"ram": "1"}}', "ev.jsonl:7", ["v"]),
    ('{"id": "", "set": {"ram": "1"}}', "ev.jsonl:7", ["id"]),
    ('{"id": 7, "set": {"ram": "1"}}', "ev.jsonl:7", ["id"]),
    ('{"id": "a\\nb", "set": {"ram": "1"}}', "ev.jsonl:7", ["id"]),  # a control character
    ('{"horizon": -1}', "ev.jsonl:7", ["horizon"]),
    ('{"horizon": "3"}', "ev.jsonl:7", ["horizon"]),
    ('{"catalog": {}}', "ev.jsonl:7", ["catalog"]),
    ('{"catalog": {"add": "x", "drop": ["y"]}}', "ev.jsonl:7", ["catalog", "drop"]),
    ('{"health": {"failed": "camera-driver"}}', "ev.jsonl:7", ["health.failed"]),
    ('{"health": {"broken": ["camera-driver"]}}', "ev.jsonl:7", ["health", "broken"]),
    ('{"approve": "r1", "set": {"ram": "1"}}', "ev.jsonl:7", ["'approve' is an event of its own", "set"]),
    ('{"approve": "r1", "reject": "r1"}', "ev.jsonl:7", ["'approve' is an event of its own", "reject"]),
    ('{"approve": ""}', "ev.jsonl:7", ["approve"]),
    ('{"id": "\\ud800", "set": {"ram": "1"}}', "ev.jsonl:7", ["surrogate"]),  # valid JSON, not text
    ('{"goal": "(member person \\udcff)"}', "ev.jsonl:7", ["surrogate"]),
    ("[" * 100_000 + "]" * 100_000, "ev.jsonl:7", ["not an event"]),  # too deep for the parser
    (LONG, "ev.jsonl:7", [f"longer than {MAX_LINE} bytes"]),
    (WIDE, "ev.jsonl:7", [f"longer than {MAX_LINE} bytes"]),
]


@pytest.mark.parametrize("line, where, words", MALFORMED, ids=lambda v: v[:40] if isinstance(v, str) else None)
def test_a_line_that_is_not_an_event_is_refused_and_located(line, where, words):
    """E1001, at SOURCE:LINE (and :COLUMN where the JSON parser knows one), in words that name
    the field at fault."""
    error = refused(line)
    assert error.where == where, error
    for w in words:
        assert w in error.message, (w, error.message)
    assert str(error) == f"{error.where}: {error.message}"
    assert len(error.message) < 1000  # a refusal never echoes a megabyte back


def test_bytes_that_are_not_utf8_are_refused_where_they_are():
    """E1001 at the column of the first bad byte (files and spool folders are read with
    surrogateescape, so the byte arrives as a lone surrogate)."""
    line = b'{"at": "\xff\xfe", "set": {"ram": "1"}}'.decode("utf-8", "surrogateescape")
    error = refused(line)
    assert error.where == "ev.jsonl:7:9" and "not UTF-8" in error.message and "0xff" in error.message
    assert "\udcff" not in str(error)  # the message itself can be printed and journaled


def test_lines_are_numbered_as_in_the_file_and_a_torn_last_line_is_kept():
    """read_lines: blank lines are skipped but counted; CRLF is stripped; the last line
    without its newline is still yielded (parse_event then refuses it: E1001)."""
    import io

    text = '{"goal": "true"}\r\n\n   \n{"horizon": 1}\n{"set": {"ram": '
    got = list(read_lines(io.StringIO(text), "f.jsonl"))
    assert got == [
        ("f.jsonl:1", '{"goal": "true"}'),
        ("f.jsonl:4", '{"horizon": 1}'),
        ("f.jsonl:5", '{"set": {"ram": '),
    ]
    assert refused(got[-1][1], got[-1][0]).where == "f.jsonl:5:17"


def test_catrt_run_locates_a_torn_last_line_and_goes_on(person: Path):
    """E1001 for the torn line (journaled as 'rejected'), the event before it accepted,
    exit 0: a producer that died mid-write costs its last event only."""
    torn = '{"id": "torn", "set": {"ram": '  # 30 characters: the parser wants a value at 31
    res = catrt("run", person, "--events", "-", "--approve", "never",
                input='{"id": "whole", "set": {"ram": "12"}}\n' + torn)  # fmt: skip
    assert res.exit_code == 0, res.output
    assert "<stdin>:2:31: rejected: error[E1001]: not JSON" in res.stderr
    rejected = [e for e in journal(person) if e["kind"] == "rejected"]
    assert [(r["data"]["where"], r["data"]["code"]) for r in rejected] == [("<stdin>:2:31", "E1001")]
    assert stored_model(person)["problem"]["init"]["ram"] == "12"


def test_catrt_run_refuses_bytes_that_are_not_utf8(person: Path, tmp_path: Path):
    """E1001, and the runtime goes on: a file of events with a stray byte must not stop it (the
    rejected line is journaled, so it must be storable text)."""
    events = tmp_path / "events.jsonl"
    events.write_bytes(b'{"at": "\xff", "set": {"ram": "12"}}\n{"id": "after", "set": {"ram": "8"}}\n')
    res = catrt("run", person, "--events", events, "--approve", "never")
    assert res.exit_code == 0, res.output
    assert "error[E1001]" in res.stderr and "not UTF-8" in res.stderr
    rejected = [e["data"] for e in journal(person) if e["kind"] == "rejected"]
    assert [(r["where"], r["code"]) for r in rejected] == [(f"{events}:1:9", "E1001")]  # '{"at": "' is 8 characters
    assert stored_model(person)["problem"]["init"]["ram"] == "8"


def test_catrt_run_refuses_bytes_that_are_not_utf8_on_standard_input(person: Path):
    """E1001 for the line, and the next event is still taken (PYTHONIOENCODING=utf-8:strict is
    what Python does on standard input under en_US.UTF-8)."""
    proc = subprocess.run(
        [sys.executable, "-c", "from catrt.cli import entry; entry()", "run", str(person), "--events", "-",
         "--approve", "never"],
        input=b'{"at": "\xff", "set": {"ram": "12"}}\n{"id": "after", "set": {"ram": "8"}}\n',
        capture_output=True, timeout=60, env={**os.environ, "PYTHONIOENCODING": "utf-8:strict"},
    )  # fmt: skip
    assert proc.returncode == 0, proc.stderr.decode(errors="replace")
    assert b"<stdin>:1:9: rejected: error[E1001]: not UTF-8" in proc.stderr
    assert stored_model(person)["problem"]["init"]["ram"] == "8"


def test_catrt_event_queues_nothing_when_one_line_is_bad(person: Path, tmp_path: Path):
    """E1001 for each bad line, located in the file; none of the file is queued."""
    events = tmp_path / "events.jsonl"
    events.write_bytes(b'{"set": {"ram": "12"}}\n{"set": {"rma": 1.5, "ram": "1e99999"}}\n{"at": "\xff"}\n')
    res = catrt("event", person, events)
    assert res.exit_code == 2
    assert f"{events}:2: error[E1001]: set.ram: '1e99999' is not a number" in res.stderr
    assert f"{events}:3:9: error[E1001]: not UTF-8" in res.stderr
    assert "2 bad event(s): nothing queued" in res.stderr
    assert not [p for p in (person / "spool").iterdir() if p.is_file()]


# ---------------------------------------------------------------- apply: set


def test_setting_an_unknown_resource_is_refused_with_a_suggestion(person: Path):
    """E1001 naming set.rma and suggesting ram; nothing but the journal's 'rejected' entry changes."""
    with runtime(person) as (rt, _):
        before = snapshot(rt)
        seq = rt.store.last_seq()
        outcome = rt.handle_line('{"id": "typo", "set": {"rma": "32"}}', "ev.jsonl:1")
        assert outcome.status == "rejected"
        assert outcome.message == "error[E1001]: set.rma: no resource named 'rma'; did you mean 'ram'?"
        assert snapshot(rt) == before
        new = list(rt.store.entries(seq))
        assert [(e["kind"], e["data"]["code"], e["event_id"]) for e in new] == [("rejected", "E1001", "typo")]
        assert not rt.store.accepted("typo")  # a rejected id can be sent again, fixed


@pytest.mark.parametrize(
    "value, words",
    [
        ({"ram": True}, ["set.ram", "number"]),
        ({"ram": "abc"}, ["set.ram", "number"]),
        ({"ram": ["lidar"]}, ["set.ram", "number"]),
        ({"ram": "١٢"}, ["set.ram", "number"]),  # digits of another script: see the events tests
        ({"restarts": "1.5"}, ["set.restarts", "integer"]),
        ({"restarts": "1/2"}, ["set.restarts", "integer"]),
        ({"online": "yes"}, ["set.online", "true or false"]),
        ({"online": "1"}, ["set.online", "true or false"]),
        ({"online": 1}, ["set.online", "true or false"]),
        ({"ambient": "5"}, ["set.ambient", "symbol"]),
        ({"ambient": True}, ["set.ambient", "symbol"]),
        ({"ambient": ["dark"]}, ["set.ambient", "symbol"]),
        ({"mounted": "lidar"}, ["set.mounted", "list of symbols"]),
        ({"mounted": True}, ["set.mounted", "list of symbols"]),
    ],
)
def test_a_value_of_the_wrong_sort_is_refused(tiny: Path, value, words):
    """E1001: the value cannot be a value of the resource's sort, so it never reaches the model."""
    with runtime(tiny) as (rt, _):
        before = snapshot(rt)
        outcome = rt.handle_line(event_line({"set": value}), "ev.jsonl:1")
        assert outcome.status == "rejected" and outcome.message.startswith("error[E1001]: "), outcome.message
        for w in words:
            assert w in outcome.message
        assert snapshot(rt) == before


@pytest.mark.parametrize(
    "value, field, words",
    [
        ({"restarts": "5"}, "set.restarts", ["E0307", "bounds"]),  # restarts :bounds (0 3)
        ({"restarts": "-1"}, "set.restarts", ["E0307", "bounds"]),
        ({"ram": "-0.5"}, "set.ram", ["E0307", "bounds"]),  # ram :bounds (0 *)
        ({"ambient": "dim"}, "set.ambient", ["E0202", "dim"]),  # lighting is (enum bright dark)
        ({"mounted": ["lidar", "sonar"]}, "set.mounted", ["E0202", "sonar"]),  # module: lidar, camera
    ],
)
def test_a_value_the_model_refuses_is_located_at_its_field(tiny: Path, value, field, words):
    """E1002: a value of the right sort that the model's checker refuses, reported against the
    event's field (a value has no line and column of its own)."""
    with runtime(tiny) as (rt, _):
        before = snapshot(rt)
        outcome = rt.handle_line(event_line({"set": value}), "ev.jsonl:1")
        assert outcome.status == "rejected" and outcome.message.startswith("error[E1002]: "), outcome.message
        assert f"\n  = {field}: error[" in outcome.message
        for w in words:
            assert w in outcome.message
        assert snapshot(rt) == before


@pytest.mark.parametrize("text, value", [("22.73", "22.73"), ("1/3", "1/3"), ("1e-3", "0.001"), (" 4.50 ", "4.5"),
                                         ("2/4", "0.5"), ("1e2", "100")])  # fmt: skip
def test_an_accepted_number_is_stored_exactly(tiny: Path, text, value):
    """Not E1001: the stored value is the exact rational, written as a decimal when it has one."""
    with runtime(tiny) as (rt, _):
        outcome = rt.handle_line(event_line({"set": {"ram": text}}), "ev.jsonl:1")
        assert outcome.status == "accepted", outcome.message
        assert rt.store.get("model")["problem"]["init"]["ram"] == value
        assert Fraction(value) == exact(text)


def test_a_symbol_value_cannot_write_other_initial_values(tiny: Path):
    """E1001: a symbol is put into (:init ...) as it is.  'dark) (= ram 1000) ... ;' would
    close (= ambient ...), set ram, restarts and online, and comment out their real values —
    a model that checks, and differs from the stored state."""
    with runtime(tiny) as (rt, _):
        before = snapshot(rt)
        for value in ["dark) (= ram 1000) (= restarts 3) online) ;", "dark ; comment", "dark)", "dark dim"]:
            outcome = rt.handle_line(event_line({"set": {"ambient": value}}), "ev.jsonl:1")
            assert outcome.status == "rejected" and outcome.message.startswith("error[E1001]: set.ambient: ")
            assert snapshot(rt) == before


# ---------------------------------------------------------------- apply: text fields


INJECTIONS = [
    ({"goal": ") (:init (= ram 100)) ("}, "goal", "closes more than the text opened"),
    ({"goal": "(member person detects)) (:init (= ram 100)) ((and"}, "goal", "closes more"),
    ({"goal": "(member person detects) (:init (= ram 100))"}, "goal", "one condition is expected, 2"),
    ({"goal": "(member person detects) (member image-raw topics)"}, "goal", "one condition is expected, 2"),
    ({"goal": "(and (member person detects)"}, "goal", "1 '(' never closed"),
    ({"goal": "((("}, "goal", "3 '(' never closed"),
    ({"goal": "   "}, "goal", "empty"),
    ({"goal": "; only a comment"}, "goal", "empty"),
    ({"goal": '(member person detects) "'}, "goal", "character the language does not have"),
    ({"goal": "(member person detects)\u0000"}, "goal", "character the language does not have"),
    ({"metric": "maximize ram) (:init (= ram 100)"}, "metric", "closes more"),
    ({"metric": "maximize ram\n) (:goal true"}, "metric", "closes more"),
    ({"metric": "maximize (+ ram 1"}, "metric", "never closed"),
    ({"softs": ["(>= ram 1) :weight 2) (:goal true) (:soft true :weight 1"]}, "softs[0]", "closes more"),
    ({"softs": ["(>= ram 1) :weight 2", ")"]}, "softs[1]", "closes more"),
    ({"softs": ["(>= ram 1"]}, "softs[0]", "never closed"),
    ({"catalog": {"add": "(:resources (evil real))"}}, "catalog.add", "only (:morphism NAME ...)"),
    ({"catalog": {"add": "(:morphism x :uses 1) (:init (= ram 100))"}}, "catalog.add", "only (:morphism NAME ...)"),
    (
        {"catalog": {"add": "(:morphism x :uses 1)) (:resources (evil real)) ((:morphism y"}},
        "catalog.add",
        "closes more",
    ),
    ({"catalog": {"add": "(:morphism x :uses 1"}}, "catalog.add", "never closed"),
    ({"catalog": {"add": "x"}}, "catalog.add", "only (:morphism NAME ...)"),
    ({"goal": "true", "set": {"ram": "1"}, "metric": "x)"}, "metric", "closes more"),  # one bad field: all refused
]


@pytest.mark.parametrize("doc, field, words", INJECTIONS, ids=lambda v: str(v)[:40] if isinstance(v, dict) else None)
def test_text_that_would_escape_its_section_is_refused_and_changes_nothing(person: Path, doc, field, words):
    """E1001: a goal, metric, soft constraint or morphism is one balanced text of its kind, so
    it can never close the section it is written into nor add another."""
    with runtime(person) as (rt, _):
        before = snapshot(rt)
        outcome = rt.handle_line(event_line(doc), "ev.jsonl:1")
        assert outcome.status == "rejected", outcome.message
        assert outcome.message.startswith(f"error[E1001]: {field}: ") and words in outcome.message, outcome.message
        assert snapshot(rt) == before


def test_a_comment_at_the_end_of_a_goal_cannot_swallow_the_section_end(person: Path):
    """Not E1001: '; )' is a comment, and the goal is written with its section's ')' on the
    next line, so the model still checks — and the goal is the one condition given."""
    from catrt.apply import apply_change, check
    from catrt.events import parse_event

    with runtime(person) as (rt, _):
        event = parse_event(event_line({"goal": "(member person detects) ; ) (:init (= ram 100))"}), "x:1")
        state, origins = apply_change(rt.state, rt.current.instance, rt.sources, event)
        candidate = check(state, rt.sources, str(person / "model"), origins)
        assert candidate.instance.problem.name == "detect-person"
        from catc.semantics.validate import initial_state

        assert initial_state(candidate.instance)["ram"] == 16  # not 100


@pytest.mark.parametrize(
    "doc, where, words",
    [
        ({"goal": "(member car detects)"}, "goal:1:9", ["E0202", "car"]),  # "(member " is 8 characters
        ({"goal": "(and (member person detects)\n     (nonsense))"}, "goal:2:7", ["E0211", "nonsense"]),
        ({"catalog": {"add": "(:morphism x :bogus 1)"}}, "catalog.add:1:14", ["E0106", ":bogus"]),
        # the second morphism of the text: its error is located in the field, not in the morphism
        ({"catalog": {"add": "(:morphism a :uses 1)\n(:morphism b :bogus 1)"}}, "catalog.add:2:14", ["E0106"]),
        ({"catalog": {"add": "(:morphism a :uses 1) (:morphism b :bogus 1)"}}, "catalog.add:1:36", ["E0106"]),
        (
            {"catalog": {"add": "(:morphism x :uses 1 :effect (add mounted sonar))"}},
            "catalog.add:1:43",
            ["E0202", "sonar"],  # "(:morphism x :uses 1 :effect (add mounted " is 42 characters
        ),
        ({"catalog": {"add": "(:morphism x :uses 1) (:morphism x :uses 1)"}}, "catalog.add:1:", ["twice"]),
    ],
)
def test_text_the_checker_refuses_is_located_in_the_event(person: Path, doc, where, words):
    """E1002 with the checker's error at FIELD:LINE:COLUMN of the event's own text."""
    with runtime(person) as (rt, _):
        before = snapshot(rt)
        outcome = rt.handle_line(event_line(doc), "ev.jsonl:1")
        assert outcome.message.startswith("error[E1002]: "), outcome.message
        assert f"\n  = {where}" in outcome.message, outcome.message
        for w in words:
            assert w in outcome.message
        assert snapshot(rt) == before


def test_a_valid_goal_change_gives_a_candidate_that_catc_checks(person: Path, tmp_path: Path):
    """Not E1001/E1002: the candidate's files, written out, are a model `catc check` accepts,
    with the new goal; the state it came from is untouched (states are values)."""
    from catrt.apply import apply_change, check

    goal = "(and (member person detects) (member image-raw topics))"
    with runtime(person) as (rt, _):
        old = rt.state
        state, origins = apply_change(
            old, rt.current.instance, rt.sources, parse_event(event_line({"goal": goal}), "x:1")
        )
        candidate = check(state, rt.sources, str(tmp_path / "out"), origins)
    assert old.problem.goal == "(member person detects)" and state.problem.goal == goal
    assert origins == {"goal": "goal"}
    for path, text in candidate.files.items():
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        Path(path).write_text(text, encoding="utf-8")
    problem = tmp_path / "out" / "problem.cat"
    assert f"(:goal {goal}" in problem.read_text(encoding="utf-8")
    res = run_catc("check", problem)
    assert res.exit_code == 0, res.output


def test_catalog_remove_and_health_name_known_morphisms(person: Path):
    """E1001 for a name the catalogue does not have (with a suggestion) and for recovering a
    morphism that is not failed; a known one fails, is cut out of the model, and recovers."""
    with runtime(person) as (rt, _):
        before = snapshot(rt)
        for doc, message in [
            ({"catalog": {"remove": ["camera-drivr"]}}, "catalog.remove: no morphism named 'camera-drivr'; "
                                                        "did you mean 'camera-driver'?"),
            ({"health": {"failed": ["camera-drivr"]}}, "health.failed: no morphism named 'camera-drivr'; "
                                                       "did you mean 'camera-driver'?"),
            ({"health": {"recovered": ["lidar-driver"]}}, "health.recovered: no morphism named 'lidar-driver'"),
            ({"health": {"recovered": ["camera-driver"]}}, "health.recovered: 'camera-driver' is not failed"),
        ]:  # fmt: skip
            outcome = rt.handle_line(event_line(doc), "ev.jsonl:1")
            assert outcome.message.startswith(f"error[E1001]: {message}"), outcome.message
            assert snapshot(rt) == before
        assert rt.handle_line(event_line({"health": {"failed": ["camera-driver"]}}), "x:1").status == "accepted"
        assert rt.store.get("model")["catalog"]["failed"] == ["camera-driver"]
        assert "(:morphism camera-driver" not in (person / "model" / "domain.cat").read_text(encoding="utf-8")
        assert rt.handle_line(event_line({"health": {"recovered": ["camera-driver"]}}), "x:2").status == "accepted"
        assert rt.store.get("model")["catalog"]["failed"] == []
        assert "(:morphism camera-driver" in (person / "model" / "domain.cat").read_text(encoding="utf-8")


def test_adding_a_morphism_the_catalogue_has_is_refused_unless_it_is_replaced(person: Path):
    """E1001: a catalog.add of a name already known would silently replace a component; the
    event must say so by removing it in the same event."""
    text = (
        "(:morphism camera-driver :kind software :uses 1\n"
        "  :parameters ((out topic) (ram-req real :bounds (0.5 2)))\n"
        "  :precondition (and (member rgb-camera mounted) (>= ram ram-req))\n"
        "  :effect (and (add topics out) (decrease ram ram-req)))"
    )
    with runtime(person) as (rt, _):
        before = snapshot(rt)
        outcome = rt.handle_line(event_line({"catalog": {"add": text}}), "ev.jsonl:1")
        assert outcome.message.startswith("error[E1001]: catalog.add: 'camera-driver' is already in the catalogue")
        assert snapshot(rt) == before
        both = {"catalog": {"remove": ["camera-driver"], "add": text}}
        assert rt.handle_line(event_line(both), "ev.jsonl:2").status == "accepted"
        assert [a["morphism"] for a in rt.store.get("model")["catalog"]["added"]] == ["camera-driver"]


# ---------------------------------------------------------------- config


@pytest.mark.parametrize(
    "text, words",
    [
        ("[limits]\ncompose = \n", ["not TOML", "line 2"]),
        ("[limits]\ncompose = 1\ncompose = 2\n", ["not TOML", "line 3"]),
        ('[limits]\ncompose = "fast"\n', ["limits.compose", "'fast'", "number"]),
        ("[limits]\ncompose = true\n", ["limits.compose", "number"]),
        ("[limits]\ncompose = -1\n", ["limits.compose"]),
        ("[limits]\ncomopse = 1\n", ["limits", "comopse"]),
        ("[sensors]\nname = 'a'\n", ["the file", "sensors"]),
        ('[enactor]\nkind = "docker"\n', ["enactor.kind", "docker"]),
        ('[[sensor]]\nname = "a"\nresource = "ram"\nargv = "cat /etc/passwd"\n', ["sensor.0.argv", "array"]),
        ('[[sensor]]\nname = "a"\nresource = "ram"\n', ["sensor.0", "argv"]),
        ('[[sensor]]\nname = "a"\nresource = "ram"\nargv = []\n', ["sensor.0.argv"]),
        ('[[sensor]]\nname = "a"\nresource = "ram"\nargv = ["/bin/echo"]\ntimeout = 0\n', ["sensor.0.timeout"]),
        ('[[sensor]]\nname = "a"\nresource = "ram"\nargv = ["/bin/echo"]\ntimeout = 7200\n', ["sensor.0.timeout"]),
        ('[[sensor]]\nname = "a"\nresource = "ram"\nargv = ["/bin/echo"]\nshell = true\n', ["sensor.0", "shell"]),
        ('[[sensor]]\nname = "a b"\nresource = "ram"\nargv = ["/bin/echo"]\n', ["sensor.0.name"]),
        ('[[sensor]]\nname = "a"\nresource = "ram"\nargv = ["/bin/echo"]\n' * 2, ["two sensors share a name"]),
    ],
)
def test_a_bad_config_is_refused_with_the_file_and_where(tmp_path: Path, text, words):
    """E1007 (catrt's code for a ConfigError): the message starts with the file, then where in
    it — a TOML line, or the key path — and what is wrong."""
    from catrt.config import ConfigError, load_config

    (tmp_path / "config.toml").write_text(text, encoding="utf-8")
    with pytest.raises(ConfigError) as info:
        load_config(tmp_path)
    message = str(info.value)
    assert message.startswith(f"{tmp_path / 'config.toml'}: "), message
    for w in words:
        assert w in message, (w, message)


def test_a_config_that_is_not_utf8_is_refused(tmp_path: Path):
    """E1007, not a traceback."""
    from catrt.config import ConfigError, load_config

    (tmp_path / "config.toml").write_bytes(b"[limits]\ncompose = 1 # \xff\n")
    with pytest.raises(ConfigError, match="cannot read it"):
        load_config(tmp_path)


def test_the_template_and_a_full_config_load(tmp_path: Path):
    """Not E1007: the template catrt init writes, and every key set, load as written."""
    from catrt.config import TEMPLATE, Config, Sensor, load_config

    (tmp_path / "config.toml").write_text(TEMPLATE, encoding="utf-8")
    assert load_config(tmp_path) == Config({"compose": 120, "diagnose": 30, "relax": 30},
                                           {"kind": "dry", "docker": "docker", "timeout": 600, "ready": 60}, ())  # fmt: skip
    (tmp_path / "config.toml").write_text(
        '[[sensor]]\nname = "bat.0"\nresource = "ram"\nargv = ["/bin/echo", "5"]\ntimeout = 0.5\nevery = 3\n'
        '[[sensor]]\nname = "b"\nresource = "ram"\nargv = ["/bin/echo"]\n',
        encoding="utf-8",
    )
    assert load_config(tmp_path).sensors == (Sensor("bat.0", "ram", ("/bin/echo", "5"), 0.5, 3.0),
                                             Sensor("b", "ram", ("/bin/echo",), 2.0, 10.0))  # fmt: skip
    assert load_config(tmp_path / "nowhere") == Config()  # no file: the defaults


def test_catrt_run_refuses_a_bad_config(person: Path):
    """E1007 naming config.toml and the key; exit 2; the store is not touched."""
    (person / "config.toml").write_text('[limits]\ncompose = "fast"\n', encoding="utf-8")
    before = journal(person)
    res = catrt("run", person, "--events", "-", input="")
    assert res.exit_code == 2
    assert res.stderr.startswith(f"catrt: error[E1007]: {person / 'config.toml'}: limits.compose: ")
    assert journal(person) == before


# ---------------------------------------------------------------- sensors


def sensor_config(state: Path, argv: list[str], resource: str = "ram", timeout: float = 5) -> None:
    (state / "config.toml").write_text(
        f'[[sensor]]\nname = "probe"\nresource = "{resource}"\nargv = {json.dumps(argv)}\ntimeout = {timeout}\n',
        encoding="utf-8",
    )


def test_shell_sensors_need_allow_shell(person: Path, tmp_path: Path):
    """E1008 and exit 2 without --allow-shell: the command is never run, nothing is journaled."""
    marker = tmp_path / "ran"
    sensor_config(person, ["/bin/sh", "-c", f"touch {marker}; echo 8"])
    before = journal(person)
    res = catrt("run", person, "--events", "-", "--approve", "never", input="")
    assert res.exit_code == 2
    assert "error[E1008]" in res.stderr and "probe" in res.stderr and "--allow-shell" in res.stderr
    assert not marker.exists()
    assert journal(person) == before


def test_an_allowed_sensor_sets_its_resource(person: Path):
    """Not E1009: with --allow-shell the sensor runs at start, and its reading (8, for ram) is a
    set event; a reading equal to the model's value is no event at all."""
    sensor_config(person, ["/bin/echo", "8"])
    res = catrt("run", person, "--events", "-", "--approve", "never", "--allow-shell", input="")
    assert res.exit_code == 0, res.output
    assert stored_model(person)["problem"]["init"]["ram"] == "8"
    entries = journal(person)
    assert [e["data"]["value"] for e in entries if e["kind"] == "sensor"] == ["8"]
    assert [e["event_id"].startswith("sensor-probe-") for e in entries if e["kind"] == "event"] == [True]
    res = catrt("run", person, "--events", "-", "--approve", "never", "--allow-shell", input="")
    assert len([e for e in journal(person) if e["kind"] == "event"]) == 1  # 8 again: nothing to do


def test_a_hostile_reading_changes_nothing_end_to_end(person: Path):
    """E1009 on standard error and in the journal (with what was printed), the model unchanged."""
    catrt("run", person, "--events", "-", "--approve", "never", input="")  # the first composition
    before = stored_model(person)
    sensor_config(person, ["/bin/echo", "1e999999"])
    res = catrt("run", person, "--events", "-", "--approve", "never", "--allow-shell", input="")
    assert res.exit_code == 0, res.output
    assert "sensor probe: rejected: error[E1009]: '1e999999' is not a number" in res.stderr
    sensors = [e["data"] for e in journal(person) if e["kind"] == "sensor"]
    assert [(s["code"], s["value"], s["output"]) for s in sensors] == [("E1009", None, "1e999999\n")]
    assert stored_model(person) == before


def _alive(pid: int) -> bool:
    """A process that exists and is not a zombie (a container's init may not reap at once)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def test_a_sensor_past_its_timeout_is_killed_with_its_children(tmp_path: Path, tiny_resources):
    """E1009 'timed out': the whole process group dies — the shell and the sleep it started in
    the background — within the timeout, not when the sleep would have ended."""
    from catrt.config import Sensor
    from catrt.sensors import run_sensor

    pids = tmp_path / "pids"
    script = f"sleep 30 & echo $! > {pids}.child; echo $$ > {pids}.shell; wait"
    sensor = Sensor("slow", "ram", ("/bin/sh", "-c", script), timeout=0.5)
    start = time.monotonic()
    reading = run_sensor(sensor, tiny_resources["ram"], tmp_path)
    took = time.monotonic() - start
    assert reading.error == "timed out after 0.5 s" and reading.value is None
    assert 0.5 <= took < 5
    shell, child = (int(Path(f"{pids}.{n}").read_text()) for n in ("shell", "child"))
    deadline = time.monotonic() + 5
    while (_alive(shell) or _alive(child)) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not _alive(shell) and not _alive(child)


def test_a_sensor_that_closes_its_output_but_runs_on_is_killed(tmp_path: Path, tiny_resources):
    """E1009: the output ended, the process did not: the timeout still applies."""
    from catrt.config import Sensor
    from catrt.sensors import run_sensor

    sensor = Sensor("lingers", "ram", ("/bin/sh", "-c", "echo 5; exec >&-; sleep 30"), timeout=0.5)
    start = time.monotonic()
    reading = run_sensor(sensor, tiny_resources["ram"], tmp_path)
    assert reading.error == "timed out after 0.5 s" and time.monotonic() - start < 5


HOSTILE = [
    # (argv, resource, words of the error)
    (["/bin/sh", "-c", "head -c 5000 /dev/zero | tr '\\0' '1'"], "ram", "more than 4096 bytes"),
    (["/usr/bin/yes", "1"], "ram", "more than 4096 bytes"),  # endless: cut at the cap, not the timeout
    (["/bin/sh", "-c", "printf '\\377\\376'"], "ram", "not UTF-8"),
    (["/bin/echo", "NaN"], "ram", "not a number"),
    (["/bin/echo", "inf"], "ram", "not a number"),
    (["/bin/echo", "1e999999"], "ram", "not a number"),
    (["/bin/echo", "1e9999"], "ram", "not a number"),  # 10,000 digits: no measurement
    (["/bin/echo", "１２"], "ram", "not a number"),  # full-width digits
    (["/bin/echo", '{"set": {"ram": "100"}}'], "ram", "not a number"),
    (["/bin/echo", 'dark", "ram": "100'], "ambient", "not a symbol"),
    (["/bin/echo", "dark) (= ram 100"], "ambient", "not a symbol"),
    (["/bin/echo", "lidar camera,sonar"], "mounted", "not a symbol"),
    (["/bin/sh", "-c", "echo 2; echo 3"], "ram", "more than one line"),
    (["/bin/echo", ""], "ram", "not a number"),
    (["/bin/echo", "1.5"], "restarts", "not an integer"),
    (["/bin/echo", "True"], "online", "not true or false"),
    (["/bin/echo", "1"], "online", "not true or false"),
    (["/bin/sh", "-c", "echo 5; exit 3"], "ram", "exited with status 3"),
    (["echo 5"], "ram", "cannot run echo 5"),  # an argument list: never a shell string
    (["/bin/echo", "$(id -u)"], "ram", "not a number"),  # no shell: nothing is expanded
    (["/nonexistent/sensor"], "ram", "cannot run /nonexistent/sensor"),
]


@pytest.mark.parametrize(
    "argv, resource, words", HOSTILE, ids=lambda v: " ".join(v)[:40] if isinstance(v, list) else None
)
def test_a_hostile_sensor_output_is_a_failure(tmp_path: Path, tiny_resources, argv, resource, words):
    """E1009: the output must be exactly one value of the resource's sort; anything else is a
    failure with no value, fast (the 2 s timeout is never what stops these)."""
    from catrt.config import Sensor
    from catrt.sensors import run_sensor

    start = time.monotonic()
    reading = run_sensor(Sensor("s", resource, tuple(argv), timeout=2), tiny_resources[resource], tmp_path)
    assert reading.value is None and reading.error is not None and words in reading.error, reading
    assert time.monotonic() - start < 1.5
    assert len(reading.output) <= 200 and "\udcff" not in reading.output  # journaled: short, printable


@pytest.mark.parametrize(
    "output, resource, value",
    [
        ("2.5\n", "ram", "2.5"),
        ("  1/3 \n", "ram", "1/3"),
        ("1e-3", "ram", "0.001"),
        ("-3", "ram", "-3"),  # a number: the model's bounds decide (E1002), see below
        ("2.0", "restarts", "2"),
        ("true\n", "online", True),
        ("false", "online", False),
        ("dark", "ambient", "dark"),
        ("dim", "ambient", "dim"),  # a symbol: whether lighting has it is the model's check (E1002)
        ("lidar camera lidar\n", "mounted", ["camera", "lidar"]),
    ],
)
def test_a_sensor_output_is_read_strictly_into_its_sort(tiny_resources, output, resource, value):
    """Not E1009: a value of the sort, exact."""
    from catrt.sensors import parse_reading

    assert parse_reading(output, tiny_resources[resource]) == (value, None)


def test_a_failed_or_refused_reading_changes_nothing(tiny: Path, tmp_path: Path):
    """E1009 for output that is no value; E1002 for a value the model refuses (ram -3 is below
    ram's bound 0; dim is no lighting): both journaled, neither changes the model."""
    from catrt.config import Sensor

    with runtime(tiny) as (rt, _):
        before = snapshot(rt)
        seq = rt.store.last_seq()
        [failed] = rt.read_sensors([Sensor("bad", "ram", ("/bin/echo", "NaN"))])
        assert failed.status == "rejected" and failed.message == "error[E1009]: 'NaN' is not a number"
        [low] = rt.read_sensors([Sensor("low", "ram", ("/bin/echo", "-3"))])
        assert low.status == "rejected" and low.message.startswith("error[E1002]: ") and "E0307" in low.message
        [dim] = rt.read_sensors([Sensor("dim", "ambient", ("/bin/echo", "dim"))])
        assert dim.status == "rejected" and dim.message.startswith("error[E1002]: ") and "E0202" in dim.message
        [gone] = rt.read_sensors([Sensor("gone", "battery", ("/bin/echo", "5"))])
        assert gone.message == "error[E1009]: the model has no resource 'battery'"
        assert snapshot(rt) == before
        kinds = [(e["kind"], e["data"].get("code")) for e in rt.store.entries(seq)]
        assert kinds == [("sensor", "E1009"), ("sensor", None), ("rejected", "E1002"), ("sensor", None),
                         ("rejected", "E1002"), ("sensor", "E1009")]  # fmt: skip


def test_a_sensor_sees_a_scrubbed_environment(tmp_path: Path, tiny_resources, monkeypatch):
    """Not E1009: a secret of the runtime's environment never reaches the sensor; it runs with
    PATH=/usr/bin:/bin, in the state folder, with nothing on standard input."""
    from catrt.config import Sensor
    from catrt.sensors import run_sensor

    monkeypatch.setenv("CATRT_TEST_SECRET", "hunter2")
    monkeypatch.setenv("LD_PRELOAD", "/tmp/evil.so")
    out = tmp_path / "seen"
    state = tmp_path / "state"
    state.mkdir()
    script = f"env > {out}.env; pwd > {out}.cwd; cat > {out}.stdin; echo 5"
    reading = run_sensor(Sensor("env", "ram", ("/bin/sh", "-c", script), timeout=2), tiny_resources["ram"], state)
    assert reading.error is None and reading.value == "5"
    env = dict(line.split("=", 1) for line in Path(f"{out}.env").read_text().splitlines() if "=" in line)
    assert "CATRT_TEST_SECRET" not in env and "hunter2" not in Path(f"{out}.env").read_text()
    assert "LD_PRELOAD" not in env and "HOME" not in env
    assert env["PATH"] == "/usr/bin:/bin"
    assert Path(f"{out}.cwd").read_text().strip() == str(state)
    assert Path(f"{out}.stdin").read_bytes() == b""


# ---------------------------------------------------------------- spool


def test_drop_writes_a_whole_file_under_its_final_name(tmp_path: Path):
    """Not E1001: catrt event's way in; no temporary file is left, every line ends."""
    from catrt.spool import drop, pending

    folder = tmp_path / "spool"
    path = drop(folder, ['{"set": {"ram": "1"}}', '{"goal": "true"}\n'], name="0001")
    assert path == folder / "0001.jsonl"
    assert path.read_text(encoding="utf-8") == '{"set": {"ram": "1"}}\n{"goal": "true"}\n'
    assert sorted(p.name for p in folder.iterdir()) == ["0001.jsonl"]
    assert pending(folder) == [path]


def test_the_spool_is_read_in_name_order_and_handled_files_move_to_done(person: Path):
    """E1001 for the bad line of a.jsonl (the rest of the file still counts); a before b
    whatever order they were written in, so b's ram 8 is the last word; temporary and hidden
    files and other suffixes are left alone."""
    spool = person / "spool"
    (spool / "b.jsonl").write_text('{"id": "from-b", "set": {"ram": "8"}}\n', encoding="utf-8")
    time.sleep(0.01)
    (spool / "a.jsonl").write_text('{"id": "from-a", "set": {"ram": "12"}}\nnot json\n', encoding="utf-8")
    for other in (".c.jsonl", "d.jsonl.tmp", "e.txt", ".f.tmp"):
        (spool / other).write_text(event_line({"id": other, "set": {"ram": "1"}}) + "\n", encoding="utf-8")
    res = catrt("run", person, "--once", "--approve", "never")
    assert res.exit_code == 0, res.output
    entries = journal(person)
    assert [e["event_id"] for e in entries if e["kind"] == "event"] == ["from-a", "from-b"]
    assert [e["data"]["where"] for e in entries if e["kind"] == "event"] == ["spool/a.jsonl:1", "spool/b.jsonl:1"]
    assert [(e["data"]["where"], e["data"]["code"]) for e in entries if e["kind"] == "rejected"] == [
        ("spool/a.jsonl:2:1", "E1001")
    ]
    assert stored_model(person)["problem"]["init"]["ram"] == "8"
    assert sorted(p.name for p in (spool / "done").iterdir()) == ["a.jsonl", "b.jsonl"]
    assert sorted(p.name for p in spool.iterdir() if p.is_file()) == [".c.jsonl", ".f.tmp", "d.jsonl.tmp", "e.txt"]
    # a name used again: the earlier file in done/ is kept
    (spool / "a.jsonl").write_text('{"id": "again", "set": {"ram": "9"}}\n', encoding="utf-8")
    assert catrt("run", person, "--once", "--approve", "never").exit_code == 0
    assert sorted(p.name for p in (spool / "done").iterdir()) == ["a.jsonl", "a.jsonl.1", "b.jsonl"]
    assert (
        "from-a" in (spool / "done" / "a.jsonl").read_text() and "again" in (spool / "done" / "a.jsonl.1").read_text()
    )


def test_a_file_being_written_is_not_read_until_it_is_renamed_in(person: Path):
    """Not E1001: the live loop (a real process) ignores a half-written .tmp file for longer
    than it polls, then handles it within seconds of its rename into *.jsonl."""
    spool = person / "spool"
    proc = subprocess.Popen(
        [sys.executable, "-c", "from catrt.cli import entry; entry()", "run", str(person), "--approve", "never"],
        stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
    )  # fmt: skip
    try:
        deadline = time.monotonic() + 20
        while not any(e["kind"] == "decision" for e in journal(person)):  # the start's decision: the loop is up
            assert proc.poll() is None and time.monotonic() < deadline, proc.stderr.read() if proc.stderr else ""
            time.sleep(0.05)
        tmp = spool / ".late.tmp"
        with open(tmp, "w", encoding="utf-8") as fh:
            fh.write('{"id": "late", "set": {"ra')
            fh.flush()
            time.sleep(1.2)  # more than the half-second poll; the watcher saw the file appear
            assert not [e for e in journal(person) if e["kind"] in ("event", "rejected")]
            fh.write('m": "12"}}\n')
        os.rename(tmp, spool / "late.jsonl")
        while not (spool / "done" / "late.jsonl").exists():
            assert proc.poll() is None and time.monotonic() < deadline, "the renamed file was not handled"
            time.sleep(0.05)
        assert [e["event_id"] for e in journal(person) if e["kind"] == "event"] == ["late"]
        assert not [e for e in journal(person) if e["kind"] == "rejected"]
    finally:
        proc.send_signal(signal.SIGTERM)
        proc.wait(timeout=20)
    assert proc.returncode == 0, proc.stderr.read() if proc.stderr else ""
    assert stored_model(person)["problem"]["init"]["ram"] == "12"
