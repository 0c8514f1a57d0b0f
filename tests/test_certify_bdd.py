"""Certificates of forward-search UNSATs over more reachable states than the explicit list
takes (issue 31, ``method: "bdd"``): the reachable states as a reduced ordered BDD, written as
a shared ``let``/``ite`` DAG, inductive over the sequential one-step encoding and goal-free —
checked by the z3 binary and cvc5; a BDD missing a state, holding a goal state, edited after
its obligations were written, or malformed is rejected."""

from __future__ import annotations

import copy
import itertools
import json
import random

import pytest
from conftest import ROOT

from catc.api import loads
from catc.queries.base import InputError
from catc.queries.certify import CertifyStatus, NotCertifiable, certificate, certify, cvc5_command, z3_command
from catc.queries.certify.bdd import FALSE, TRUE, bdd_json, bdd_obligations, build_set, count, force_order
from catc.queries.solve import solve
from catc.semantics.search import reachable_states

needs_checkers = pytest.mark.skipif(
    z3_command() is None or cvc5_command() is None, reason="needs the z3 binary (z3-solver) and cvc5 (PyPI)"
)

# Two switches that turn each other off (never both on) and three counters 0..12 no analysis
# but the search bounds: 3 · 13³ = 6,591 reachable states, above the 2,000 the explicit list
# takes, and none a goal state.
WIDE = """
(define (domain toggle)
  (:requirements :numeric)
  (:resources (a bool) (b bool) (n int :unit count :bounds (0 12)) (m int :unit count :bounds (0 12))
              (k int :unit count :bounds (0 12)))
  (:morphism press-a :effect (and (assign a true) (assign b false)))
  (:morphism press-b :effect (and (assign b true) (assign a false)))
  (:morphism count-n :precondition (< n 12) :effect (increase n 1))
  (:morphism count-m :precondition (< m 12) :effect (increase m 1))
  (:morphism count-k :precondition (< k 12) :effect (increase k 1)))
(define (problem both-on)
  (:domain toggle)
  (:init (= a false) (= b false) (= n 0) (= m 0) (= k 0))
  (:goal (and a b)))
"""

# The same with one counter 0..3: 3 · 4 = 12 states, the explicit list's size unless the
# limit is lowered (``state_limit``).
SMALL = WIDE.replace("(m int :unit count :bounds (0 12))", "").replace("(k int :unit count :bounds (0 12))", "")
SMALL = SMALL.replace("(:morphism count-m :precondition (< m 12) :effect (increase m 1))", "")
SMALL = SMALL.replace("(:morphism count-k :precondition (< k 12) :effect (increase k 1))", "")
SMALL = SMALL.replace("(0 12)", "(0 3)").replace("(< n 12)", "(< n 3)").replace(" (= m 0) (= k 0)", "")


def model(text):
    return loads({"toggle.cat": text}, "toggle.cat").instance


def searched(text, **limits):
    inst = model(text)
    result = solve(inst, strategy="search", sequential=True, horizon=50)
    assert result.status.value == "unsat" and result.final and result.reason.startswith("forward search")
    return inst, certificate(inst, result, **limits)


def both_proved(result):
    assert result.status is CertifyStatus.CERTIFIED, result.obligations
    for row in result.obligations:
        assert {c: a["answer"] for c, a in row["checkers"].items()} == {"z3": "unsat", "cvc5": "unsat"}
        assert row["proved_by"] and "catc.search" not in row["proved_by"]


def accepts(nodes, root, atoms, vector):
    """Walk the BDD (certificate numbering) on one vector of atom values."""
    k = root
    while k >= 2:
        a, low, high = nodes[k - 2]
        k = high if vector[a] else low
    return k == TRUE


# ---------------------------------------------------------------- the ROBDD itself


@pytest.mark.parametrize("seed", range(6))
def test_the_bdd_accepts_exactly_the_set_it_was_built_from(seed):
    rng = random.Random(seed)
    width = 6
    every = list(itertools.product([False, True], repeat=width))
    chosen = set(rng.sample(every, rng.randrange(0, len(every) + 1)))
    bdd, root = build_set(sorted(chosen), width)
    nodes = [list(n) for n in bdd.nodes]
    assert {v for v in every if accepts(nodes, root, width, v)} == chosen  # brute force over all 64
    assert count(nodes, root, width) == len(chosen)
    assert all(low != high for _, low, high in bdd.nodes)  # reduced: no redundant test
    assert len(set(bdd.nodes)) == len(bdd.nodes)  # hash-consed: no two equal nodes


def test_the_bdd_is_canonical_on_known_sets():
    assert build_set([], 3)[1] == FALSE
    whole, root = build_set(list(itertools.product([False, True], repeat=3)), 3)
    assert root == TRUE and whole.nodes == []  # every vector: no test at all
    xor, root = build_set([(False, True), (True, False)], 2)
    assert len(xor.nodes) == 3  # x0 ? ¬x1 : x1 — one node on x0, two on x1
    cube, root = build_set([(True, False, True)], 3)
    assert len(cube.nodes) == 3


def test_force_moves_what_morphisms_touch_together_next_to_each_other():
    # two independent pairs, interleaved: FORCE puts each pair side by side
    order = force_order(["a", "x", "b", "y"], [frozenset({"a", "b"}), frozenset({"x", "y"})])
    assert {frozenset(order[:2]), frozenset(order[2:])} == {frozenset({"a", "b"}), frozenset({"x", "y"})}


# ---------------------------------------------------------------- certificates


@needs_checkers
def test_a_forward_search_no_above_the_state_limit_is_certified_by_its_bdd():
    inst, doc = searched(WIDE)  # the default limit: 6,591 states are above it
    assert doc["method"] == "bdd" and doc["producer"] == "catc.search" and doc["sequential"] is True
    spec = doc["bdd"]
    assert spec["states"] == 3 * 13**3
    # a, b one atom each; n, m, k one per value 0..12
    assert sorted(map(tuple, spec["atoms"]), key=str) == sorted(
        [("a", True), ("b", True)] + [(r, str(v)) for r in "nmk" for v in range(13)], key=str
    )
    assert len(spec["nodes"]) < 200  # the counters are independent: the BDD is a chain, not 6,591 rows
    assert [o["name"] for o in doc["obligations"]] == ["initiation", "consecution", "goal"]
    both_proved(certify(inst, doc))


@needs_checkers
def test_a_lowered_limit_certifies_a_small_model_by_its_bdd():
    inst, doc = searched(SMALL, state_limit=5)
    assert doc["method"] == "bdd" and doc["bdd"]["states"] == 12
    names, states = reachable_states(inst, 100)
    atoms = [tuple(a) for a in doc["bdd"]["atoms"]]
    column = {n: i for i, n in enumerate(names)}
    for vector in itertools.product([False, True], repeat=len(atoms)):  # every atom vector, by brute force
        state = {}
        for (name, value), bit in zip(atoms, vector):
            if value is True:
                state[name] = bit
            elif bit:
                state.setdefault(name, []).append(value)
        valued = {name for name, value in atoms if value is not True}  # a number: one atom per value
        one_value = all(len(state.get(name, [])) == 1 for name in valued)
        reachable = one_value and any(
            all(s[column[n]] == (v if isinstance(v, bool) else int(v[0])) for n, v in state.items()) for s in states
        )
        assert accepts(doc["bdd"]["nodes"], doc["bdd"]["root"], len(atoms), vector) == reachable
    both_proved(certify(inst, doc))
    assert searched(SMALL)[1]["method"] == "reachable"  # at the default limit: the explicit list


def test_more_states_than_the_bdd_limit_are_not_certified():
    inst = model(SMALL)
    with pytest.raises(NotCertifiable, match="more than 10"):
        certificate(inst, solve(inst, strategy="search", sequential=True, horizon=50), state_limit=5, bdd_limit=10)


def forged(inst, doc, states):
    """``doc`` with its BDD rebuilt from ``states`` and its obligations written for it."""
    names = reachable_states(inst, 100)[0]
    bad = copy.deepcopy(doc)
    bad["bdd"] = bdd_json(inst, names, states)
    bad["obligations"] = bdd_obligations(inst, bad["bdd"], bad["horizon"])
    for o in bad["obligations"]:
        o["producer"] = "catc.search"
    return bad


@needs_checkers
def test_a_bdd_missing_a_reachable_state_fails_consecution():
    inst, doc = searched(SMALL, state_limit=5)
    _, states = reachable_states(inst, 100)
    dropped = (True, False, 2)  # a on, n = 2: reached from (False, False, 2) by press-a
    assert dropped in states and states[0] != dropped
    result = certify(inst, forged(inst, doc, [s for s in states if s != dropped]))
    assert result.status is CertifyStatus.REFUTED
    assert {r["name"]: r["status"] for r in result.obligations} == {
        "initiation": "proved",
        "consecution": "refuted",
        "goal": "proved",
    }


@needs_checkers
def test_a_bdd_missing_the_initial_state_fails_initiation():
    inst, doc = searched(SMALL, state_limit=5)
    _, states = reachable_states(inst, 100)
    assert states[0] == (False, False, 0)
    result = certify(inst, forged(inst, doc, states[1:]))
    assert {r["name"]: r["status"] for r in result.obligations}["initiation"] == "refuted"


@needs_checkers
def test_a_bdd_holding_a_goal_state_fails_the_goal():
    inst, doc = searched(SMALL, state_limit=5)
    _, states = reachable_states(inst, 100)
    result = certify(inst, forged(inst, doc, [*states, (True, True, 0)]))
    assert result.status is CertifyStatus.REFUTED
    status = {r["name"]: r["status"] for r in result.obligations}
    assert status["goal"] == "refuted" and status["initiation"] == "proved"


def test_a_bdd_edited_after_its_obligations_were_written_does_not_match():
    inst, doc = searched(SMALL, state_limit=5)
    bad = json.loads(json.dumps(doc))
    node = next(n for n in bad["bdd"]["nodes"] if TRUE in n[1:] and FALSE in n[1:])
    node[1], node[2] = node[2], node[1]  # one test flipped (the count stays: the same states' number)
    bad["bdd"]["states"] = count(bad["bdd"]["nodes"], bad["bdd"]["root"], len(bad["bdd"]["atoms"]))
    result = certify(inst, bad)
    assert result.status is CertifyStatus.REFUTED
    assert {r["status"] for r in result.obligations} == {"mismatch"}


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (lambda b: b["nodes"].append([0, 0, len(b["nodes"]) + 2]), "children numbered below"),
        (lambda b: b["nodes"].append([len(b["atoms"]) - 1, 0, 2]), "not ordered"),
        (lambda b: b.update(states=b["states"] + 1), "another number of states"),
        (lambda b: b["atoms"].append(["nowhere", True]), "not \\[resource, value\\]"),
        (lambda b: b["atoms"].append(["a", "3"]), "does not fit its sort"),
        (lambda b: b.update(root=10**6), "root"),
        (lambda b: b.pop("nodes"), "atoms, nodes, root and states"),
    ],
)
def test_a_malformed_bdd_is_a_located_input_error(edit, message):
    inst, doc = searched(SMALL, state_limit=5)
    bad = json.loads(json.dumps(doc))
    edit(bad["bdd"])
    with pytest.raises(InputError, match=message) as info:
        certify(inst, bad)
    assert info.value.code == "E1302"


def test_the_bdd_certificate_follows_the_schema():
    import jsonschema

    schema = json.loads((ROOT / "docs/schemas/catc.certificate-1.json").read_text())
    jsonschema.validate(json.loads(json.dumps(searched(SMALL, state_limit=5)[1])), schema)


# A symbol resource: one atom per mode reached (idle, run, stop; never broken).
MODES = """
(define (domain modes)
  (:requirements :symbols)
  (:sorts mode - (enum idle run stop broken))
  (:resources (a bool) (b bool) (m mode))
  (:morphism press-a :effect (and (assign a true) (assign b false)))
  (:morphism press-b :effect (and (assign b true) (assign a false)))
  (:morphism go :precondition (= m idle) :effect (assign m run))
  (:morphism halt :precondition (= m run) :effect (assign m stop)))
(define (problem both-on)
  (:domain modes)
  (:init (= a false) (= b false) (= m idle))
  (:goal (and a b)))
"""


@needs_checkers
def test_a_symbols_values_are_atoms_of_the_bdd():
    inst, doc = searched(MODES, state_limit=3)
    assert doc["method"] == "bdd" and doc["bdd"]["states"] == 9
    assert sorted(v for r, v in doc["bdd"]["atoms"] if r == "m") == ["idle", "run", "stop"]
    both_proved(certify(inst, doc))
    _, states = reachable_states(inst, 100)
    result = certify(inst, forged(inst, doc, [s for s in states if "stop" not in s]))  # never stopped
    assert {r["name"]: r["status"] for r in result.obligations}["consecution"] == "refuted"
