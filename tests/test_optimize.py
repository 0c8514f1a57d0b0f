"""`catc optimize`: optima of the examples (hand-derived in expect.toml) and against brute force."""

from __future__ import annotations

import json
import tomllib
from fractions import Fraction

import pytest
from conftest import ROOT, run_catc, run_catc_process
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from test_solve_property import domains, successors, to_cat

from catc import ir
from catc.frontend.workspace import load_instance
from catc.ir.views import apply_view
from catc.queries.optimize import OptStatus, optimize
from catc.smt.backend import Check
from catgrammar.diagnostics import Diagnostics


def optimum_cases():
    for expect in sorted((ROOT / "examples").glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            if "optimum" in case:
                yield pytest.param(
                    expect.parent, case, id=f"{expect.parent.name}/{case['file']}:{case.get('problem', '')}"
                )


@pytest.mark.parametrize("strategy", ["deepen", "single"])
@pytest.mark.parametrize("folder, case", list(optimum_cases()))
def test_example_optimum(folder, case, strategy):
    diags = Diagnostics()
    _, inst = load_instance(None, str(folder / case["file"]), diags, problem_name=case.get("problem"))
    result = optimize(apply_view(inst, None), strategy=strategy, deepen_from=0)
    assert result.status is OptStatus.OPT
    assert [v.value for v in result.values] == [Fraction(x) for x in case["optimum"]]
    assert all(v.attained for v in result.values)
    for morphism, params in case.get("params_optimum", {}).items():
        acts = [a for _, a in result.plan.activations if a.morphism == morphism]
        assert any(all(a.params[k] == Fraction(v) for k, v in params.items()) for a in acts), acts
    if "soft_violated" in case:
        assert [o.violated for o in result.softs] == case["soft_violated"]


def test_optimize_cli_json_and_exit_codes():
    res = run_catc("optimize", str(ROOT / "examples/gpu-allocation/max-confidence.cat"), "--json")
    doc = json.loads(res.stdout)
    assert res.exit_code == 0 and doc["schema"] == "catc.optimize/1" and doc["status"] == "opt"
    assert doc["objectives"][0] == {
        "sense": "maximize",
        "term": "confidence",
        "value": "21/25",
        "decimal": "0.84",
        "attained": True,
        "bound": None,
    }
    res = run_catc("optimize", str(ROOT / "examples/navigation/coarse.cat"), "--maximize", "travelled")
    assert res.exit_code == 1 and "UNSAT" in res.stdout


def test_command_line_objective_replaces_the_metric():
    res = run_catc(
        "optimize", str(ROOT / "examples/gpu-allocation/max-confidence.cat"), "--minimize", "confidence", "--json"
    )
    doc = json.loads(res.stdout)
    # the least confidence gives the detector its least memory, 1 GB: 0.5 + 0.08 = 0.58
    assert doc["objectives"][0]["value"] == "29/50"


def test_bad_command_line_objective_is_a_located_input_error():
    res = run_catc(
        "optimize", str(ROOT / "examples/gpu-allocation/max-confidence.cat"), "--maximize", "(+ confidense 1)"
    )
    assert res.exit_code == 2 and "<--maximize>:1:" in res.stderr and "did you mean 'confidence'" in res.stderr


def test_nothing_to_optimise_is_an_input_error():
    res = run_catc("optimize", str(ROOT / "examples/detection/person.cat"))
    assert res.exit_code == 2 and "nothing to optimise" in res.stderr


def test_unattained_infimum_is_reported_as_such():
    res = run_catc("optimize", str(ROOT / "examples/navigation/farthest.cat"), "--minimize", "travelled")
    assert res.exit_code == 0 and "infimum 0, not attained" in res.stdout


def reachable_max_counter(nb, morphs, init_bools, init_c, goal, horizon):
    """Brute force: the largest final counter over every composition that reaches the goal
    (idle steps allowed, so every state reachable within the horizon counts)."""
    best = None
    frontier = {(init_bools, init_c, tuple(0 for _ in morphs))}
    for depth in range(horizon + 1):
        for b, c, _ in frontier:
            if all(l.holds(b, c) for l in goal):
                best = c if best is None else max(best, c)
        if depth < horizon:
            frontier = frontier | {succ for state in frontier for succ in successors(morphs, state)}
    return best


@pytest.mark.parametrize("strategy", ["deepen", "single"])
@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow]
)
@given(domain=domains())
def test_optimum_agrees_with_brute_force(tmp_path, domain, strategy):
    path = tmp_path / "random.cat"
    path.write_text(to_cat(*domain).replace("(:requirements :numeric)", "(:requirements :numeric :optimization)"))
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, [d.message for d in diags]
    expected = reachable_max_counter(*domain)
    result = optimize(
        inst, [ir.Objective(ir.Sense.MAXIMIZE, ir.ResourceRef("c", ir.INT))], strategy=strategy, deepen_from=0
    )
    if expected is None:
        assert result.status is OptStatus.UNSAT
    else:
        assert result.status is OptStatus.OPT and result.values[0].value == expected


LONGER_IS_BETTER = """
(define (domain counter)
  (:requirements :numeric :optimization)
  (:resources (x int) (started bool))
  (:morphism start :uses 1 :precondition (not started) :effect (assign started true))
  (:morphism step :uses 3 :precondition started :effect (increase x 1)))
(define (problem count)
  (:domain counter)
  (:init (= x 0) (= started false))
  (:goal started)
  (:horizon 6)
  (:metric maximize x))
"""


@pytest.mark.parametrize("strategy", ["deepen", "single"])
def test_optimum_needs_more_steps_than_the_shortest_composition(tmp_path, strategy):
    """The shortest composition is `start` alone (x = 0); the optimum uses `step` all three
    times it may, one per step after `start` (a morphism is activated at most once per step),
    so x = 3 in 4 steps.  The deepening strategy must find the better, longer one."""
    path = tmp_path / "counter.cat"
    path.write_text(LONGER_IS_BETTER)
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, [d.message for d in diags]
    result = optimize(inst, strategy=strategy, deepen_from=0)
    assert result.status is OptStatus.OPT and result.values[0].value == 3
    assert sorted(a.morphism for _, a in result.plan.activations) == ["start", "step", "step", "step"]
    assert len(result.plan.steps) == 4


def _counter_instance(tmp_path):
    path = tmp_path / "counter.cat"
    path.write_text(LONGER_IS_BETTER)
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None
    return inst


@pytest.mark.parametrize("behaviour", ["runs out of its budget", "gives up at once"])
def test_deepen_falls_back_to_the_whole_horizon_when_no_refutation_comes(tmp_path, monkeypatch, behaviour):
    """The refutation and the whole-horizon optimisation alternate; when the refutation never
    answers (here: made to time out, or to give up), the whole-horizon optimum (x = 3, by hand
    above) is still found and proven."""
    import time as _time

    import catc.queries.optimum as opt

    calls = []

    def no_refutation(inst, objectives, softs, values, k, sequential, deadline, timings, tactics, share_with=None):
        calls.append(values)
        if behaviour == "runs out of its budget" and deadline is not None:
            _time.sleep(max(0.0, deadline - _time.perf_counter()))
        return Check.UNKNOWN

    monkeypatch.setattr(opt, "_better_exists", no_refutation)
    result = opt.optimize(_counter_instance(tmp_path), strategy="deepen", deepen_from=0)
    # offered for refutation: the first composition found and the short optimum, both
    # `start` alone (x = 0); never anything else
    assert calls == [[0], [0]]
    assert result.status is OptStatus.OPT and result.values[0].value == 3


def test_deepen_at_the_deadline_reports_the_short_optimum_as_best_found(tmp_path, monkeypatch):
    import time as _time

    import catc.queries.optimum as opt

    def slow(inst, objectives, softs, values, k, sequential, deadline, timings, tactics, share_with=None):
        _time.sleep(max(0.0, deadline - _time.perf_counter()))
        return Check.UNKNOWN

    monkeypatch.setattr(opt, "_better_exists", slow)
    result = opt.optimize(_counter_instance(tmp_path), strategy="deepen", timeout=0.2, deepen_from=0)
    # the whole horizon never got time: the shortest composition's optimum, x = 0, best found
    assert result.status is OptStatus.SUBOPT and result.reason == "timeout" and result.values[0].value == 0


def test_short_horizons_use_the_single_encoding(tmp_path, monkeypatch):
    """Under the default deepen strategy a horizon below DEEPEN_FROM goes straight to one
    encoding: no deepening solve, no refutation."""
    import catc.queries.optimum as opt

    def must_not_run(*args, **kwargs):
        raise AssertionError("the deepening route ran on a short horizon")

    monkeypatch.setattr(opt, "_better_exists", must_not_run)
    monkeypatch.setattr("catc.queries.solve.solve", must_not_run)
    inst = _counter_instance(tmp_path)
    assert inst.problem.horizon < opt.DEEPEN_FROM
    result = opt.optimize(inst)
    assert result.status is OptStatus.OPT and result.values[0].value == 3


def test_objectives_keep_their_command_line_order_across_minimize_and_maximize():
    """Lexicographic order is the order on the command line, also when --minimize and
    --maximize interleave (click groups each option's values; the order is recorded while
    parsing, in-process as in a process)."""
    args = ["--maximize", "confidence", "--minimize", "gpu-used", "--maximize", "(- 0 gpu-used)", "--json"]
    expected = [("maximize", "confidence"), ("minimize", "gpu-used"), ("maximize", "(- 0 gpu-used)")]
    retask = str(ROOT / "examples/gpu-allocation/retask.cat")
    for res in (run_catc("optimize", retask, *args), run_catc_process("optimize", retask, *args)):
        assert res.exit_code == 0, res.output
        assert [(o["sense"], o["term"]) for o in json.loads(res.stdout)["objectives"]] == expected
    res = run_catc(
        "pareto",
        str(ROOT / "examples/gpu-allocation/retask.cat"),
        "--maximize",
        "confidence",
        "--minimize",
        "gpu-used",
        "--json",
    )
    assert [(o["sense"], o["term"]) for o in json.loads(res.stdout)["objectives"]] == expected[:2]


@pytest.mark.parametrize(
    "case, query",
    [("search-and-rescue/event2-out-of-range.cat", ["optimize"]), ("lifelong/cheaper-camera.cat", ["optimize"]),
     ("gpu-allocation/max-confidence.cat", ["optimize"]), ("gpu-allocation/retask.cat", ["optimize"]),
     ("lifelong/cheaper-camera.cat", ["recompose"]), ("lifelong/cheaper-camera.cat", ["recompose", "--priority", "objective"]),
     ("search-and-rescue/cheaper-camera.cat", ["recompose"])],
)  # fmt: skip
def test_the_answer_does_not_depend_on_which_proof_finishes_first(case, query, monkeypatch):
    """The deepening strategy races a refutation ("nothing better within the horizon")
    against optimising over the whole horizon on doubling time budgets.  Whichever wins, the
    composition must be the same (else it would depend on the machine's speed, and so would
    every artifact grounded from it): here the refutation never finishes, so the whole
    horizon is optimised, and the answer must equal the unhindered one."""
    from catc.queries import optimum as opt
    from catc.smt.backend import Check

    path = ROOT / "examples" / case
    free = json.loads(run_catc(query[0], str(path), *query[1:], "--json").stdout)
    monkeypatch.setattr(opt, "_better_exists", lambda *args, **kwargs: Check.UNKNOWN)
    hindered = json.loads(run_catc(query[0], str(path), *query[1:], "--json").stdout)
    assert free["status"] == hindered["status"] == "opt"
    assert hindered["objectives"] == free["objectives"] and hindered["steps"] == free["steps"]


def brute_force_recompose(nb, morphs, init_bools, init_c, goal, horizon, deployed, churn, priority):
    """Brute force: over every composition within the horizon that reaches the goal, the
    lexicographic best of (churn, final counter) — stability first — or (final counter, churn).
    A composition's churn is the weight of the deployed components it leaves unused plus that of
    the new ones it uses (docs/semantics.md); ``used`` counts activations per component."""
    best = None
    frontier = {(init_bools, init_c, tuple(0 for _ in morphs))}
    for depth in range(horizon + 1):
        for b, c, used in frontier:
            if all(l.holds(b, c) for l in goal):
                ch = sum(w for i, w in enumerate(churn) if (used[i] > 0) != (i in deployed))
                key = (ch, -c) if priority == "stability" else (-c, ch)
                best = key if best is None else min(best, key)
        if depth < horizon:
            frontier = frontier | {succ for state in frontier for succ in successors(morphs, state)}
    return best


@pytest.mark.parametrize("maxsmt", [True, False])
@settings(
    max_examples=30, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow]
)
@given(domain=domains(), data=st.data())
def test_recompose_agrees_with_brute_force(tmp_path, domain, data, maxsmt):
    """Minimal churn (with weights, both priorities; the other objective: the final counter,
    maximised) against enumeration — for churn as an arithmetic sum and as MaxSMT soft groups."""
    from catc.queries.optimize import Tactics
    from catc.queries.recompose import recompose

    n = len(domain[1])
    deployed = data.draw(st.sets(st.integers(0, n - 1)))
    churn = data.draw(st.lists(st.sampled_from([Fraction(1), Fraction(2), Fraction(1, 4)]), min_size=n, max_size=n))
    priority = data.draw(st.sampled_from(["stability", "objective"]))
    text = to_cat(*domain).replace("(:requirements :numeric)", "(:requirements :numeric :recomposition)")
    for i, w in enumerate(churn):
        text = text.replace(f"(:morphism m{i} ", f"(:morphism m{i} :churn {float(w)} ", 1)  # 1.0, 2.0, 0.25: exact
    text = text.replace("(:horizon", f"(:deployed {' '.join(f'm{i}' for i in sorted(deployed))}) (:horizon", 1)
    path = tmp_path / "random.cat"
    path.write_text(text)
    diags = Diagnostics()
    _, inst = load_instance(None, str(path), diags)
    assert inst is not None, [d.message for d in diags]
    expected = brute_force_recompose(*domain, deployed, churn, priority)
    objective = [ir.Objective(ir.Sense.MAXIMIZE, ir.ResourceRef("c", ir.INT))]
    rec = recompose(inst, priority=priority, objectives=objective, tactics=Tactics(maxsmt_churn=maxsmt))
    if expected is None:
        assert rec.status is OptStatus.UNSAT
        return
    assert rec.status is OptStatus.OPT
    got = {type(v.objective.term): v.value for v in rec.result.values}
    assert (got[ir.TotalChurn], -got[ir.ResourceRef]) == (expected if priority == "stability" else expected[::-1])
    assert rec.churn == got[ir.TotalChurn]


IDLE = """\
(define (domain idle)
  (:requirements :numeric :optimization)
  (:resources (x int :bounds (0 10)) (done bool))
  (:morphism nudge :kind software :effect (increase x 0))
  (:morphism finish :kind software :precondition (not done) :effect (assign done true)))
(define (problem p) (:domain idle) (:init (= x 0) (= done false)) (:goal done) (:horizon 4) (:metric maximize x))
"""


def _idle_instance(tmp_path):
    from catgrammar.diagnostics import Diagnostics

    path = tmp_path / "idle.cat"
    path.write_text(IDLE)
    _, inst = load_instance(None, str(path), Diagnostics())
    assert inst is not None
    return inst


def test_steps_that_change_nothing_are_dropped(tmp_path):
    """Issue 29: optimize answered plans with steps that change nothing (transfer c c ×5),
    when pruning had run out of time.  drop_idle_steps removes them, always."""
    from catc.semantics.compositions import drop_idle_steps
    from catc.semantics.plan import Activation, Plan

    inst = _idle_instance(tmp_path)
    nudge, finish = (Activation("nudge"),), (Activation("finish"),)
    plan = Plan((nudge, finish, nudge, nudge), {})
    assert drop_idle_steps(inst, plan, 4, True).steps == (finish,)
    assert drop_idle_steps(inst, plan, 4, True, accept=lambda p: False).steps == plan.steps  # the check decides
    from catc.queries.optimize import optimize

    result = optimize(inst, prune=False)  # even without pruning
    assert result.plan is not None and all(a.morphism != "nudge" for step in result.plan.steps for a in step)
