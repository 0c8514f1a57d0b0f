"""The runtime's fast path for events that only set values (issue 26: ≥ 10× the keep rate):
the event's values are put into the checked model — no source is parsed or checked again —
and a kept composition's grounding is reused while the values it reads stay the same.  Every
test compares the fast path with the whole check, which stays the reference."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
from pathlib import Path

import pytest
from shop_models import SHOP, shop

from catrt.api import connect, init
from catrt.apply import apply_change, check, check_values
from catrt.enact import generation_name
from catrt.events import parse_event
from catrt.runtime import MODEL_FOLDER

ROOT = Path(__file__).resolve().parent.parent
MISSION = ROOT / "examples" / "search-and-rescue" / "mission.cat"

# a lamp whose software's parameters read two resources (power, spare): its artifacts change
# when they do, and only then
MODEL = """\
(define (domain lamps)
  (:requirements :numeric :sets :grounding)
  (:sorts room - symbol)
  (:constants hall porch - room)
  (:resources
    (power real :unit W :bounds (0 100))
    (lit (set room))
    (dimmed bool)
    (spare int :bounds (0 10))
    (mood real))
  (:morphism lamp :kind software :uses 1
    :precondition (>= power 3)
    :effect (and (add lit hall) (decrease power 1))
    :ground (software :image "example/lamp:1" :node lamp
                      :params ((watts power) (spares spare)))))

(define (problem light)
  (:domain lamps)
  (:init (= power 4) (= spare 2) (= mood 1))
  (:goal (member hall lit))
  (:horizon 1))
"""


@pytest.fixture
def lamps(tmp_path: Path) -> Path:
    model = tmp_path / "lamps.cat"
    model.write_text(MODEL, encoding="utf-8")
    state = tmp_path / "st"
    init(state, str(model))
    return state


def values(inst) -> dict:
    return {name: getattr(iv.value, "value", None) for name, iv in inst.problem.init.items()}


@pytest.mark.parametrize(
    "body",
    [
        {"power": "21/2"},
        {"power": "2500 mW"},  # converted to W as a .cat literal is
        {"dimmed": True},
        {"spare": "7", "mood": "-3.25"},
        {"power": "100", "dimmed": "false"},
    ],
)
def test_setting_values_gives_the_model_the_whole_check_gives(lamps: Path, body: dict):
    with connect(lamps) as rt:
        r = rt.runtime
        state, origins = apply_change(
            r.state, r.current.instance, r.sources, parse_event(json.dumps({"set": body}), "t")
        )
        quick = check_values(r.current, state, {"set": body})
        whole = check(state, r.sources, str(lamps / MODEL_FOLDER), origins)
    assert quick is not None
    assert values(quick.instance) == values(whole.instance)
    assert quick.files == whole.files  # the same texts: the same digest in the manifest
    assert quick.instance.domain == whole.instance.domain


@pytest.mark.parametrize("body", [{"power": "101"}, {"spare": "11"}, {"power": "-1"}])
def test_a_value_out_of_bounds_takes_the_whole_check_and_is_refused_there(lamps: Path, body: dict):
    with connect(lamps) as rt:
        r = rt.runtime
        state, _ = apply_change(r.state, r.current.instance, r.sources, parse_event(json.dumps({"set": body}), "t"))
        assert check_values(r.current, state, {"set": body}) is None
        outcome = rt.submit({"id": "x", "set": body})
    assert outcome.status == "rejected" and "E1002" in outcome.message and "bounds" in outcome.message


def test_events_of_other_kinds_take_the_whole_check(lamps: Path):
    with connect(lamps) as rt:
        r = rt.runtime
        for body in ({"set": {"power": "5"}, "horizon": 2}, {"goal": "(member porch lit)"}):
            state, _ = apply_change(r.state, r.current.instance, r.sources, parse_event(json.dumps(body), "t"))
            assert check_values(r.current, state, body) is None


def test_a_kept_composition_parses_no_source(monkeypatch: pytest.MonkeyPatch, tmp_path: Path):
    """Today's code parsed every source (~11 on the mission) for each event."""
    import catgrammar.parser as parser

    state = tmp_path / "st"
    init(state, str(MISSION))
    calls = []
    real = parser.parse_source
    monkeypatch.setattr(parser, "parse_source", lambda *a, **k: calls.append(1) or real(*a, **k))
    with connect(state) as rt:
        before = len(calls)
        for i in range(12):
            outcome = rt.submit({"id": f"k{i}", "set": {"range-to-base": str(1 + i % 9)}})
            assert outcome.decision is not None and outcome.decision.action == "keep"
        during = len(calls) - before
    assert during == 0


def test_a_step_that_checks_the_model_whole_parses_only_the_problem(monkeypatch: pytest.MonkeyPatch, lamps: Path):
    """power 4 → 2 breaks the lamp (it needs 3): the queries run on the model checked whole,
    which parsed and checked every source again (issue 24: 5.5 of a 6.5 s step at n = 400);
    now the domain's file is reused and only the written problem is parsed."""
    from catc.frontend import workspace

    parsed: list[str] = []
    real = workspace.parse_source
    monkeypatch.setattr(workspace, "parse_source", lambda src, *a, **k: parsed.append(src.path) or real(src, *a, **k))
    with connect(lamps) as rt:
        before = len(parsed)
        outcome = rt.submit({"id": "low", "set": {"power": "2"}})
        assert outcome.decision is not None and outcome.decision.action == "restore"
        assert [Path(p).name for p in parsed[before:]] == ["problem.cat"]
        approved = rt.submit({"id": "ok", "approve": "r1"})  # an approval: the whole check too
        assert approved.decision is not None and approved.decision.action == "keep"
    assert [Path(p).name for p in parsed[before:]] == ["problem.cat", "problem.cat"]


def test_the_grounding_follows_the_values_it_reads(lamps: Path):
    """Reused only while power and spare are the same: each change of them is a new
    generation, and its artifacts are those the whole check and a fresh grounding give."""
    said = []
    with connect(lamps, say=said.append) as rt:
        generations = [rt.runtime.incumbent["generation"]]
        for i, body in enumerate([{"mood": "2"}, {"power": "9"}, {"mood": "3"}, {"spare": "3"}, {"power": "9"}]):
            outcome = rt.submit({"id": f"e{i}", "set": body})
            assert outcome.decision.action == "keep", outcome.message
            generations.append(rt.runtime.incumbent["generation"])
        params = (lamps / "generations" / generation_name(generations[-1]) / "params.yaml").read_text()
        fresh, _ = rt.runtime._artifacts(check(rt.runtime.state, rt.runtime.sources, str(lamps / MODEL_FOLDER)),
                                         rt.runtime.current.model and _plan(rt))  # fmt: skip
    # mood is read by no grounding: no new generation; power and spare are
    assert generations == [1, 1, 2, 2, 3, 3]
    assert "watts: 9.0" in params and "spares: 3" in params
    assert fresh[0]["params.yaml"].decode() == params


def _plan(rt):
    from catc.api import read_plan

    return read_plan(rt.runtime.current.instance, rt.runtime.incumbent["plan"])


def test_a_loop_on_a_file_writes_the_model_files_at_its_end(lamps: Path, tmp_path: Path):
    from catrt.loop import loop

    feed = tmp_path / "events.jsonl"
    feed.write_text("".join(json.dumps({"id": f"e{i}", "set": {"mood": str(i)}}) + "\n" for i in range(1, 30)))
    with connect(lamps) as rt:
        loop(rt.runtime, str(feed), once=True, stop=threading.Event(), sensors=())
        text = (lamps / MODEL_FOLDER / "problem.cat").read_text(encoding="utf-8")
        assert "(= mood 29)" in text
        from catc.api import load

        again = load(lamps / MODEL_FOLDER / "problem.cat").instance
        assert values(again) == values(rt.runtime.current.instance)


@pytest.mark.slow
def test_the_rate_benchmark_fails_when_asked_for_more_than_it_measures():
    """The regression check can fail: against this very tree, 1000× is never met."""
    done = subprocess.run(
        [sys.executable, str(ROOT / "benchmarks" / "runtime_bench.py"), "rate", "--against", str(ROOT),
         "--keep", "20", "--base-keep", "20", "--burst", "6", "--rounds", "1", "--min-ratio", "1000"],
        capture_output=True, text=True, check=False, timeout=600,
    )  # fmt: skip
    assert done.returncode == 1, done.stderr
    assert "REGRESSION" in done.stderr and "| keep |" in done.stdout.replace("this tree (", "").replace(") |", " |")


def _sensor_entries(state: Path) -> list[dict]:
    from catrt.store import Store

    store = Store.open(state, write=False)
    try:
        return [e for e in store.entries() if e["kind"] in ("sensor", "sensor-repeats", "event")]
    finally:
        store.close()


def test_an_unchanged_sensor_answer_is_counted_not_journaled_each_time(lamps: Path):
    """A sensor read 200 times with the same answer (at 0.01 s that is 2 s): today's code
    wrote 200 journal entries; now one entry, and the count of the 199 repeats."""
    from catrt.config import Sensor
    from catrt.views import sensor_counts, status_document

    mood = Sensor("mood", "mood", ("/bin/echo", "5"), every=0.01)
    with connect(lamps) as rt:
        for _ in range(200):
            rt.runtime.read_sensors([mood])
        live = rt.status()["sensors"]["mood"]
    entries = _sensor_entries(lamps)
    kinds = [e["kind"] for e in entries]
    assert kinds == ["sensor", "event", "sensor-repeats"]  # the change, its event, the count at close
    assert entries[2]["data"]["repeats"] == 199 and entries[2]["data"]["value"] == "5"
    assert live["value"] == "5" and live["readings"] == 1  # the count not yet journaled
    from catrt.store import Store

    store = Store.open(lamps, write=False)
    try:
        counts = sensor_counts(store)
        assert status_document(store, lamps)["sensors"] == counts
    finally:
        store.close()
    assert counts["mood"]["readings"] == 200 and counts["mood"]["repeats"] == 199


def test_a_changed_answer_is_journaled_with_the_repeats_before_it(lamps: Path, tmp_path: Path):
    from catrt.config import Sensor

    value = tmp_path / "value"
    probe = Sensor("mood", "mood", ("/bin/cat", str(value)))
    with connect(lamps) as rt:
        for answer, times in (("5", 3), ("6", 4), ("5", 1)):
            value.write_text(answer + "\n")
            for _ in range(times):
                rt.runtime.read_sensors([probe])
        # another event moves the resource: the sensor's same answer is an event again
        assert rt.submit({"id": "hand", "set": {"mood": "9"}}).status == "accepted"
        rt.runtime.read_sensors([probe])
        assert rt.runtime.state.problem.init["mood"] == "5"
    sensed = [
        (e["data"]["value"], e["data"]["repeats_before"]) for e in _sensor_entries(lamps) if e["kind"] == "sensor"
    ]
    assert sensed == [("5", 0), ("6", 2), ("5", 3), ("5", 0)]


def test_a_decision_past_its_budget_is_undecided_journaled_and_the_loop_goes_on(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
):
    """[limits] decision: every query of one event together.  A fake clock that jumps 10 s
    at each look makes the 5 s budget run out before the recomposition: E1017, the event
    journaled, the deployed composition kept, and the next event handled as ever."""
    import catrt.decide

    model = tmp_path / "lamps.cat"
    model.write_text(MODEL, encoding="utf-8")
    state = tmp_path / "st"
    init(state, str(model), config_text="[limits]\ndecision = 5\n")
    with connect(state) as rt:
        generation = rt.runtime.incumbent["generation"]
        clock = iter(range(0, 10**6, 10))
        monkeypatch.setattr(catrt.decide, "_now", lambda: float(next(clock)))
        low = rt.submit({"id": "low", "set": {"power": "1"}})  # the lamp needs 3: recompose
        monkeypatch.undo()
        assert rt.runtime.incumbent["generation"] == generation  # the deployed composition stays
        again = rt.submit({"id": "again", "set": {"power": "8"}})
    assert low.status == "accepted" and low.decision.action == "undecided" and low.decision.code == "E1017"
    assert "error[E1017]" in low.message and "decision budget of 5 s" in low.message
    assert again.status == "accepted" and again.decision.action == "keep"
    from catrt.store import Store

    store = Store.open(state, write=False)
    try:
        entries = [
            (e["kind"], e["event_id"], e["data"].get("code")) for e in store.entries(kinds=("event", "decision"))
        ]
    finally:
        store.close()
    assert ("event", "low", None) in entries and ("decision", None, "E1017") in entries


# ---------------------------------------------------------------- the relaxation policy


def _proposal(tmp_path: Path, config: str) -> dict:
    """SHOP (tests/shop_models.py): restoring power needs +10 W (half its value), restoring
    the budget +100 USD (a ninth of it)."""
    model = tmp_path / "shop.cat"
    model.write_text(SHOP, encoding="utf-8")
    state = tmp_path / "st"
    init(state, str(model), config_text=config)
    with connect(state) as rt:
        (start,) = rt.started
    assert start.decision.action in ("restore", "stuck"), start.message
    return start.decision.proposal or {}


@pytest.mark.parametrize(
    ("config", "restored"),
    [
        ("", {"budget": "1000"}),  # W and USD: by relative change, 1/9 < 1/2 (not 100 USD > 10 W)
        ("[relax]\nfixed = ['budget']\n", {"power": "30"}),
        # power weighed as said; budget, the one unit left, 1 per USD: 10 × 1/100 < 100 × 1
        ("[relax]\nweights = { power = '1/100' }\n", {"power": "30"}),
        ("[relax]\nweights = { power = 1, budget = 1 }\n", {"power": "30"}),  # said: 1 W counts as 1 USD
    ],
)
def test_restorations_follow_the_relax_policy_and_never_add_unlike_units(tmp_path: Path, config: str, restored):
    assert _proposal(tmp_path, config)["set"] == restored


def test_unlike_units_without_a_scale_ask_for_weights_instead_of_a_proposal(tmp_path: Path):
    """0 W of power, unbounded above, compared only with need: no relative change of it
    exists, and 1 W is not 1 USD."""
    model = tmp_path / "shop.cat"
    model.write_text(shop(power="0", need="30"), encoding="utf-8")
    state = tmp_path / "st"
    init(state, str(model))
    with connect(state) as rt:
        (start,) = rt.started
    assert start.decision.action == "stuck" and start.decision.proposal is None
    assert "different units (USD, W)" in start.decision.reason and "[relax] weights" in start.decision.reason
    init(tmp_path / "st2", str(model), config_text="[relax]\nweights = { power = '1/30' }\n")
    with connect(tmp_path / "st2") as rt:
        (start,) = rt.started
    assert start.decision.proposal["set"] == {"budget": "1000"}  # 100 × 1/900 < 30 × 1/30 (power, need)


def test_every_resource_fixed_leaves_nothing_to_propose(tmp_path: Path):
    assert _proposal(tmp_path, "[relax]\nfixed = ['budget', 'power']\n") == {}


@pytest.mark.parametrize(
    ("text", "words"),
    [("[relax]\nweights = { power = 0 }\n", "relax.weights"), ("[relax]\nfixd = []\n", "fixd"),
     ("[relax]\nweights = { power = '1/0' }\n", "relax.weights")],
)  # fmt: skip
def test_a_bad_relax_policy_is_refused(tmp_path: Path, text: str, words: str):
    from catrt.config import ConfigError, load_config

    (tmp_path / "config.toml").write_text(text, encoding="utf-8")
    with pytest.raises(ConfigError) as exc:
        load_config(tmp_path)
    assert words in str(exc.value)
