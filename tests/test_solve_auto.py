"""``catc solve``'s default strategy ``auto`` (issue 27): the forward search where it applies
(sequential steps, a ground task it models, as ``catc import pddl`` writes them), the SMT
deepening elsewhere, exactly as ``--strategy incremental`` answers there; ``--json`` names the
strategy used.  Every expectation below is counted by hand from the task, not read off catc."""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path

import pytest

pytest.importorskip("unified_planning")

from conftest import ROOT, run_catc

from catc.frontend.session import load_checked
from catc.queries.solve import STRATEGIES, SolveStatus, solve
from catgrammar.diagnostics import Diagnostics


def _corpus():
    """benchmarks/planning_corpus.py, whose generators write the IPC encodings."""
    spec = importlib.util.spec_from_file_location("planning_corpus", ROOT / "benchmarks" / "planning_corpus.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("planning_corpus", mod)
    spec.loader.exec_module(mod)
    return mod


def _imported(tmp_path: Path, domain: str, problem: str) -> tuple[Path, Path]:
    """``catc import pddl`` of the two texts (no horizon written: the default one)."""
    (tmp_path / "d.pddl").write_text(domain)
    (tmp_path / "p.pddl").write_text(problem)
    out = tmp_path / "cat"
    r = run_catc("import", "pddl", str(tmp_path / "d.pddl"), str(tmp_path / "p.pddl"), "-o", str(out), "-k", "40")
    assert r.exit_code == 0, r.output
    return out / "domain.cat", out / "problem.cat"


def _solve(*args: str | Path) -> tuple[int, dict]:
    r = run_catc("solve", *map(str, args), "--json")
    return r.exit_code, json.loads(r.stdout)


def test_auto_is_the_default_and_every_older_strategy_stays():
    assert STRATEGIES[0] == "auto" and {"incremental", "single", "search", "greedy"} <= set(STRATEGIES)
    r = run_catc("solve", "--help")
    assert "auto" in r.stdout and "[default: auto]" in " ".join(r.stdout.split())


def test_an_imported_gripper_of_23_actions_is_solved_shortest_by_default(tmp_path):
    """gripper with 8 balls, two grippers: each pair of balls costs pick, pick, move, drop,
    drop and a move back, except the last pair (no move back): 4 · 6 − 1 = 23 actions.  No
    plan is shorter: every ball needs a pick and a drop (16), the robot must cross to room b
    at least 4 times (at most 2 balls a crossing) and come back 3 times between (7)."""
    pc = _corpus()
    domain, problem = _imported(tmp_path, pc.GRIPPER, pc.gripper(8))
    code, doc = _solve(domain, problem, "--sequential")
    assert code == 0 and doc["status"] == "sat"
    assert doc["strategy"] == "search"  # the strategy actually used
    assert len(doc["steps"]) == 23 and all(len(step) == 1 for step in doc["steps"])
    assert doc.get("shortest", True) is True  # the key is written only when it is False
    assert doc["sequential"] is True
    actions = json.loads((domain.parent / "actions.json").read_text())
    names = [actions[step[0]["morphism"]].split()[0].strip("(") for step in doc["steps"]]
    assert sorted(set(names)) == ["drop", "move", "pick"]
    assert names.count("pick") == names.count("drop") == 8 and names.count("move") == 7


def test_the_same_task_in_parallel_steps_takes_the_smt_route(tmp_path):
    """Without --sequential the forward search (sequential only) does not apply: ``auto`` is
    ``incremental``, the answer the same document."""
    pc = _corpus()
    domain, problem = _imported(tmp_path, pc.GRIPPER, pc.gripper(2))
    code, doc = _solve(domain, problem)
    code_inc, doc_inc = _solve(domain, problem, "--strategy", "incremental")
    assert doc["strategy"] == "incremental" and code == code_inc == 0
    doc.pop("timings"), doc_inc.pop("timings")
    assert doc == doc_inc


def test_a_model_with_free_parameters_takes_the_smt_route():
    """navigation/coarse.cat's morphisms have parameters θ (real dials): the forward search
    models no parameter, so ``auto`` answers as ``incremental`` does (its expect.toml: UNSAT,
    final), and says so; the solve() API agrees."""
    nav = ROOT / "examples" / "navigation" / "coarse.cat"
    inst = load_checked(nav, None, Diagnostics())
    assert inst is not None and any(m.params for m in inst.morphisms.values())
    code, doc = _solve(nav, "--sequential")
    code_inc, doc_inc = _solve(nav, "--sequential", "--strategy", "incremental")
    assert code == code_inc == 1 and doc["status"] == "unsat" and doc["unsat"]["final"]
    assert doc["strategy"] == "incremental"
    doc.pop("timings"), doc_inc.pop("timings")
    assert doc == doc_inc
    r = solve(inst, sequential=True)
    assert r.strategy == "incremental" and r.status is SolveStatus.UNSAT


def test_exists_steps_keep_the_smt_route(tmp_path):
    """--exists-step is the SMT deepening's encoding: ``auto`` leaves it there."""
    pc = _corpus()
    domain, problem = _imported(tmp_path, pc.GRIPPER, pc.gripper(2))
    code, doc = _solve(domain, problem, "--exists-step")
    assert code == 0 and doc["strategy"] == "incremental" and doc["shortest"] is False


def test_an_unsolvable_ground_task_is_proven_unsolvable_by_default(tmp_path):
    """blocks with 3 blocks and the cyclic goal b0 on b1 on b2 on b0: a block is on at most
    one block and a tower has a bottom block on the table, so no state has the cycle; the
    relaxation cannot see that (each on-fact alone is reachable), the reachable states can.
    The default answers UNSAT for every length (final), by the forward search."""
    pc = _corpus()
    domain, problem = _imported(tmp_path, pc.BLOCKS, pc.blocks(3, cycle=True))
    cert = tmp_path / "proof.json"
    code, doc = _solve(domain, problem, "--sequential", "--certificate", cert)
    assert code == 1 and doc["status"] == "unsat" and doc["strategy"] == "search"
    assert doc["unsat"]["final"] is True
    assert doc["reason"].startswith("forward search:")
    # its certificate (the reachable states as an invariant) checks independently
    res = run_catc("certify", domain, problem, cert, "--json")
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["status"] == "certified"


def test_the_api_defaults_to_auto_and_solve_itself_to_incremental(tmp_path):
    """``model.solve()`` runs through the query registry (default ``auto``), as the command
    does; the Python function ``solve`` keeps ``incremental``, which the queries built on it
    choose.  gripper with 2 balls: pick, pick, move, drop, drop — 5 steps either way."""
    from catc.api import load

    pc = _corpus()
    domain, problem = _imported(tmp_path, pc.GRIPPER, pc.gripper(2))
    model = load(domain, problem)
    by_api = model.solve(sequential=True)
    assert by_api.strategy == "search" and by_api.status is SolveStatus.SAT
    assert by_api.plan is not None and len(by_api.plan.steps) == 5
    plain = solve(model.instance, sequential=True)
    assert plain.strategy == "incremental" and plain.plan is not None and len(plain.plan.steps) == 5


def test_the_import_hint_solves_a_task_longer_than_the_default_horizon(tmp_path):
    """Imported without ``-k``, the problem has no (:horizon ...) and the queries' default is 10
    steps, so the hint ``catc import pddl`` prints must name a horizon: run as printed, it
    solves ferry with 4 cars (board, sail, debark, sail back per car, no last sail back:
    4 · 4 − 1 = 15 actions, more than 10)."""
    pc = _corpus()
    (tmp_path / "d.pddl").write_text(pc.FERRY)
    (tmp_path / "p.pddl").write_text(pc.ferry(4))
    out = tmp_path / "cat"
    r = run_catc("import", "pddl", str(tmp_path / "d.pddl"), str(tmp_path / "p.pddl"), "-o", str(out))
    assert r.exit_code == 0, r.output
    hint = r.stdout.strip().splitlines()[-1].split("solve with --sequential: ", 1)[1]
    argv = hint.split()
    assert argv[:2] == ["catc", "solve"] and "-k" in argv
    code, doc = _solve(*argv[2:])
    assert code == 0 and doc["status"] == "sat" and len(doc["steps"]) == 15
