"""Warm re-solving (issue 16): ``solve(..., warm=WarmStart())`` answers a problem that differs
from the previous one in initial values or the goal on the previous encoding and solver.

The answers must be the ones a cold solve gives; they are checked against the brute-force
breadth-first search of tests/test_solve_property.py (an independent implementation of the
semantics) over sequences of problems on one domain, and by hand on the search-and-rescue
model.  The counters say whether the encoding was reused, so that a test can fail when the
warm path is never taken.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import pytest
from conftest import ROOT
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_solve_property import COUNTER_MAX, domains, shortest_by_bfs, to_cat

from catc.api import loads
from catc.queries import solve as solve_module
from catc.queries.solve import SolveStatus, WarmStart, solve

SAR = ROOT / "examples" / "search-and-rescue"


def _instance(text: str):
    return loads({"p.cat": text}, "p.cat").instance


@st.composite
def problem_sequences(draw):
    """One random domain and up to five problems on it: other initial values, other goals."""
    nb, morphs, init_bools, init_c, goal, horizon = draw(domains())
    problems = [(init_bools, init_c, goal)]
    base = draw(domains())  # a source of goals over the same resources when nb agrees
    for _ in range(draw(st.integers(1, 4))):
        bools = tuple(draw(st.lists(st.booleans(), min_size=nb, max_size=nb)))
        c = draw(st.integers(0, COUNTER_MAX))
        new_goal = draw(st.sampled_from([goal, base[4]])) if base[0] == nb else goal
        problems.append((bools, c, new_goal))
    return nb, morphs, horizon, problems


@settings(
    max_examples=int(os.environ.get("CATC_PROPERTY_EXAMPLES", "60")),
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
@given(seq=problem_sequences(), assume_all=st.booleans())
def test_warm_answers_agree_with_breadth_first_search(seq, assume_all):
    nb, morphs, horizon, problems = seq
    resources = ["c"] + [f"b{i}" for i in range(nb)]
    warm = WarmStart(resources if assume_all else ())
    for bools, c, goal in problems:
        inst = _instance(to_cat(nb, morphs, bools, c, goal, horizon))
        expected = shortest_by_bfs(nb, morphs, bools, c, goal, horizon)
        result = solve(inst, prune=False, warm=warm)
        if expected is None:
            assert result.status is SolveStatus.UNSAT
        else:
            assert result.status is SolveStatus.SAT and len(result.plan) == expected
    if assume_all:  # every value behind a literal: one encoding answers the whole sequence
        assert warm.cold <= 1 and warm.cold + warm.reused <= len(problems)


def _sar(**init: object) -> str:
    text = (SAR / "mission.cat").read_text().replace("(:metric maximize budget)", "")
    for resource, value in init.items():
        text, n = re.subn(rf"\(= {resource} [^)]*\)", f"(= {resource} {value})", text)
        assert n == 1, resource
    return text


def _sar_instance(text: str):
    return loads({"domain.cat": (SAR / "domain.cat").read_text(), "p.cat": text}, "p.cat").instance


def test_search_and_rescue_events_on_one_encoding():
    """The paper's events as initial values.  By hand (examples/search-and-rescue): event I's
    composition takes 10 steps; out of range (14 > comms-range 10) the relay is needed and it
    still takes 10; with the budget at 500 the LiDAR (20,000) cannot be bought, and nothing
    else reaches `reported` in the dark; in the bright the RGB camera does."""
    warm = WarmStart(["range-to-base", "ambient"])
    answers = []
    for init in (
        {},
        {"range-to-base": 14},
        {"range-to-base": 6},
        {"ambient": "dark"},
        {"ambient": "dark", "range-to-base": 14},
        {},
    ):
        inst = _sar_instance(_sar(**init))
        cold, hot = solve(inst), solve(inst, warm=warm)
        assert hot.status is cold.status
        answers.append(len(hot.plan) if hot.plan is not None else None)
        assert hot.plan is None or len(hot.plan) == len(cold.plan)
    assert answers[0] == 10
    assert warm.cold == 1 and warm.reused == 5  # both changing resources were assumed from the start


def test_a_changed_fact_encodes_afresh_once_then_reuses():
    warm = WarmStart()
    for value in (4, 14, 6, 9):
        result = solve(_sar_instance(_sar(**{"range-to-base": value})), warm=warm)
        assert result.status is SolveStatus.SAT
    # 4: cold (every value a fact); 14: range-to-base changed, cold with it assumed; 6, 9: warm
    assert (warm.cold, warm.reused, warm.assumed) == (2, 2, frozenset({"range-to-base"}))


def test_a_new_goal_reuses_and_a_new_catalog_encodes_afresh():
    warm = WarmStart()  # presolve off: the consumption abstraction would answer without encoding
    text = _sar()
    solve(_sar_instance(text), warm=warm, presolve=False)
    # a goal the mounted RGB camera reaches in one step: mount it
    other = text.replace("(:goal reported)", "(:goal (member rgb-camera mounted))")
    result = solve(_sar_instance(other), warm=warm, presolve=False)
    assert result.status is SolveStatus.SAT and len(result.plan) == 1
    assert [a.morphism for a in result.plan.steps[0]] == ["mount-rgb-camera"]
    assert (warm.cold, warm.reused) == (1, 1)
    # back to the first goal: the same answer as cold
    assert len(solve(_sar_instance(text), warm=warm, presolve=False).plan) == 10 and warm.reused == 2
    domain = (SAR / "domain.cat").read_text().replace(":cost 150", ":cost 151")
    cheaper = loads({"domain.cat": domain, "p.cat": text}, "p.cat").instance
    assert solve(cheaper, warm=warm, presolve=False).status is SolveStatus.SAT
    assert warm.cold == 2  # the catalog changed


def test_a_boolean_left_out_of_the_initial_state_is_a_changed_fact():
    """A Boolean not listed in ``:init`` starts false (docs/semantics.md): leaving it out
    changes its initial value like writing it does.  By hand: `m` needs `ready`."""
    text = """(define (domain d) (:requirements :numeric)
      (:resources (ready bool) (done bool))
      (:morphism m :precondition ready :effect (assign done true)))
    (define (problem p) (:domain d) (:init ready) (:goal done) (:horizon 2))"""
    warm = WarmStart()  # presolve off: the consumption abstraction would answer without encoding
    assert solve(_instance(text), warm=warm, presolve=False).status is SolveStatus.SAT
    unready = _instance(text.replace("(:init ready)", "(:init)"))
    assert solve(unready, warm=warm, presolve=False).status is SolveStatus.UNSAT
    assert warm.cold == 2 and warm.assumed == {"ready"}
    assert solve(_instance(text), warm=warm, presolve=False).status is SolveStatus.SAT and warm.reused == 1


def test_old_values_are_retired_and_answers_stay_right(monkeypatch):
    """With room for two values per resource, a third retires the oldest (its literal is
    asserted false); coming back to it makes a new literal.  By hand: `m` needs x ≥ 3."""
    monkeypatch.setattr(solve_module._WarmSearch, "KEEP", 2)
    text = """(define (domain d) (:requirements :numeric)
      (:resources (x int :bounds (0 9)) (done bool))
      (:morphism m :precondition (>= x 3) :effect (assign done true)))
    (define (problem p) (:domain d) (:init (= x X)) (:goal done) (:horizon 2))"""
    warm = WarmStart(["x"])
    for x in (5, 1, 2, 5, 1, 7, 0, 3, 2, 5):
        result = solve(_instance(text.replace("X", str(x))), warm=warm, presolve=False)
        assert result.status is (SolveStatus.SAT if x >= 3 else SolveStatus.UNSAT), x
    assert warm.cold == 1 and warm.reused == 9
    search = warm._search
    assert search is not None and len(search.inits["x"]) == 2


RAM_MODEL = """(define (domain ram) (:requirements :numeric)
  (:resources (ram int) (a-done bool) (b-done bool) (up bool))
  (:morphism a :uses 1 :precondition (>= ram 6) :effect (and (decrease ram 6) (assign a-done true)))
  (:morphism b :uses 1 :precondition (>= ram 6) :effect (and (decrease ram 6) (assign b-done true)))
  (:morphism both :uses 1 :precondition (and a-done b-done) :effect (assign up true)))
(define (problem p) (:domain ram) (:init (= ram 10)) (:goal up) (:horizon 4))
"""

RAM_SENSOR = """[[sensor]]
name = "ram"
resource = "ram"
argv = ["/bin/echo", "10"]
"""


@pytest.mark.parametrize(("config", "cold"), [(None, 2), (RAM_SENSOR, 1)])
def test_the_runtime_composes_on_one_encoding(tmp_path: Path, config, cold):
    """Nothing can be deployed while two modules each need 6 of the RAM and only 10 or 11
    are there (the relaxation cannot see it, so solve decides); at 12 both fit.  Without a
    sensor, ``ram`` becomes assumed on its first change (one more encoding); with a sensor
    on it, it is assumed from the start and every later decision reuses the first encoding."""
    from catrt.api import connect, init

    model = tmp_path / "ram.cat"
    model.write_text(RAM_MODEL)
    folder = tmp_path / "st"
    init(folder, str(model), config_text=config)
    with connect(folder) as rt:
        (start,) = rt.started
        assert start.decision is not None and start.decision.action in ("restore", "stuck")
        outcomes = [rt.submit({"set": {"ram": str(v)}}) for v in (11, 12)]
        warm = rt.runtime.warm
    assert outcomes[0].decision is not None and outcomes[0].decision.action in ("restore", "stuck")
    assert outcomes[1].decision is not None and outcomes[1].decision.action == "compose"
    assert (warm.cold, warm.reused) == (cold, 3 - cold)


def test_a_reused_solver_forgets_the_previous_calls_time_limit():
    """A call with a time limit sets the solver's; the next call without one must not inherit
    it.  The earlier call's limit is set on the solver directly (a real 1 ms call stops
    before it reaches the solver); 1 ms would make the search-and-rescue solve UNKNOWN."""
    warm = WarmStart(["range-to-base"])
    assert solve(_sar_instance(_sar()), warm=warm).status is SolveStatus.SAT
    assert warm._search is not None
    warm._search.solver.set_timeout(0.001)  # what a call with 1 ms left behind
    again = solve(_sar_instance(_sar(**{"range-to-base": 6})), warm=warm)
    assert again.status is SolveStatus.SAT and warm.reused == 1


@pytest.mark.parametrize("horizon", [0, 3])
def test_warm_single_strategy_and_short_horizons(horizon):
    text = f"""(define (domain d) (:requirements :numeric)
      (:resources (x int :bounds (0 9)))
      (:morphism inc :effect (increase x 1)))
    (define (problem p) (:domain d) (:init (= x X)) (:goal (>= x 3)) (:horizon {horizon}))"""
    warm = WarmStart(["x"])
    for x in (0, 2, 3, 1):
        inst = _instance(text.replace("X", str(x)))
        for strategy in ("incremental", "single"):
            expected = SolveStatus.SAT if 3 - x <= horizon else SolveStatus.UNSAT
            result = solve(inst, warm=warm, strategy=strategy, presolve=False)
            assert result.status is expected, (x, strategy)
            if strategy == "incremental" and expected is SolveStatus.SAT:
                assert len(result.plan) == 3 - x  # one increment per step
