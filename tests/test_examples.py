"""Every example's expected outcome (examples/*/expect.toml) is checked by solving it.

Each expectation carries the hand derivation it rests on (`why`); none was copied from
catc's own output.  Every SAT answer is also replayed by the independent validator inside
`solve` (a rejected answer raises)."""

from __future__ import annotations

import re
import tomllib
from fractions import Fraction
from pathlib import Path

import pytest
from conftest import ROOT

from catc.frontend.workspace import load_instance
from catc.ir.views import apply_view
from catc.queries.solve import SolveStatus, solve
from catgrammar.diagnostics import Diagnostics

EXAMPLES = ROOT / "examples"


def cases():
    for expect in sorted(EXAMPLES.glob("*/expect.toml")):
        for case in tomllib.loads(expect.read_text())["case"]:
            yield pytest.param(expect.parent, case, id=f"{expect.parent.name}/{case['file']}:{case.get('problem', '')}")


def instance(folder: Path, case: dict):
    diags = Diagnostics()
    _, inst = load_instance(None, str(folder / case["file"]), diags, problem_name=case.get("problem"))
    assert inst is not None, [d.message for d in diags]
    return apply_view(inst, None)


def as_value(v):
    if isinstance(v, (bool, str)):
        return v
    return Fraction(str(v))


@pytest.mark.parametrize("folder, case", list(cases()))
def test_example_outcome(folder, case):
    assert case.get("why"), "every expectation states its independent reason"
    inst = instance(folder, case)
    result = solve(inst)
    assert result.status.value == case["status"]
    if result.status is SolveStatus.UNSAT:
        assert result.final == case.get("final_unsat", False)
        return
    plan = result.plan
    if "steps" in case:
        assert len(plan) == case["steps"]
    used = plan.components
    assert set(case.get("uses", [])) <= used, set(case.get("uses", [])) - used
    assert not set(case.get("not_uses", [])) & used
    for morphism, params in case.get("params", {}).items():
        acts = [a for _, a in plan.activations if a.morphism == morphism]
        assert acts, f"{morphism} is not used"
        assert any(all(a.params[k] == as_value(v) for k, v in params.items()) for a in acts), acts
    final = result.states[-1]
    for name, v in case.get("final", {}).items():
        assert final[name] == as_value(v), (name, final[name])
    for morphism, param in case.get("fresh_params", []):
        values = {a.params[param] for _, a in plan.activations if a.morphism == morphism}
        assert values and all(v in plan.fresh for v in values)
    if "sequential_steps" in case:
        seq = solve(inst, sequential=True)
        assert seq.status is SolveStatus.SAT and len(seq.plan) == case["sequential_steps"]
        assert all(len(step) == 1 for step in seq.plan.steps)


def test_every_example_problem_has_an_expectation():
    expected = set()
    for expect in EXAMPLES.glob("*/expect.toml"):
        for case in tomllib.loads(expect.read_text())["case"]:
            expected.add((expect.parent / case["file"], case.get("problem")))
    for path in EXAMPLES.rglob("*.cat"):
        for name in re.findall(r"\(define\s+\(problem\s+([\w-]+)", path.read_text()):
            assert (path, name) in expected or (path, None) in expected, f"{path}: problem {name} has no expectation"


def test_answers_do_not_depend_on_what_the_process_solved_before():
    """Each query works in its own Z3 context (catc.smt.z3backend): in one shared
    context Z3's search depends on every term seen before, and the detection example's
    driver was given the reserve topic on every second solve (found by the routes test in
    tests/test_entry.py).  Solve every example twice over, in one process."""
    params = [p.values for p in cases()]
    insts = [instance(folder, case) for folder, case in params]

    def answers():
        out = []
        for inst in insts:
            r = solve(inst)
            out.append((r.status, r.plan.steps if r.plan else None, r.states[-1] if r.states else None))
        return out

    first = answers()
    assert answers() == first
