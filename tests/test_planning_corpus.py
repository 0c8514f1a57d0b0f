"""The planning corpus (catc.bench.planning, issue 27): the hand counts its table relies on,
checked by a breadth-first search of this file's own, and ``catc bench --corpus planning``.

The search reads the PDDL through unified-planning's reader only: it grounds each action by
enumerating its parameters' objects, evaluates preconditions, effects and goals with its own
exact evaluator (PDDL semantics: every effect reads the state before the action, a delete
and an add of the same atom leave it true), and explores the states layer by layer. It shares
nothing with catc's import, IR or forward search, so its shortest length is an independent
count; the plan it finds is replayed by UP's validator, a check on its successor function.
Fluents that nothing reads (no precondition, goal, effect value or condition: farmland's
``cost``, rover's ``recharges``) are left out of the state: they cannot change which actions
apply, and without them the unsolvable members have finitely many states.
"""

from __future__ import annotations

import itertools
import operator
from collections.abc import Callable
from fractions import Fraction
from pathlib import Path
from typing import Any

import pytest
from click.testing import CliRunner

pytest.importorskip("unified_planning")

from catc.bench import planning

# ---------------------------------------------------------------- an independent BFS


def _fraction(node: Any) -> Fraction:
    return Fraction(node.constant_value())


class _Ground:
    """A PDDL task as unified-planning reads it, ground by hand: the relevant fluents, the
    initial state, the ground actions as (name, objects, applicable, successor), the goal."""

    def __init__(self, domain: Path, problem: Path) -> None:
        from unified_planning.io import PDDLReader
        from unified_planning.model import EffectKind

        self.problem = p = PDDLReader().parse_problem(str(domain), str(problem))
        env = p.environment
        em, sub, fve = env.expression_manager, env.substituter, env.free_vars_extractor
        read: set[str] = set()
        for e in p.goals:
            read |= {f.fluent().name for f in fve.get(e)}
        for a in p.actions:
            for e in a.preconditions:
                read |= {f.fluent().name for f in fve.get(e)}
            for eff in a.effects:
                assert not eff.is_forall(), "no forall effects in the corpus"
                for e in (eff.value, eff.condition):
                    read |= {f.fluent().name for f in fve.get(e)}
        init = {k: v for k, v in p.initial_values.items() if k.fluent().name in read}
        self.fluents = sorted(init, key=str)
        self.index = {f: i for i, f in enumerate(self.fluents)}
        self.start = tuple(
            v.bool_constant_value() if v.is_bool_constant() else _fraction(v) for v in (init[f] for f in self.fluents)
        )
        self.goal = self._compile(em.And(p.goals))
        self.actions: list[tuple[str, tuple[Any, ...], Callable[..., bool], Callable[..., tuple[Any, ...]]]] = []
        for a in p.actions:
            domains = [list(p.objects(param.type)) for param in a.parameters]
            for objs in itertools.product(*domains):
                binding = {em.ParameterExp(param): em.ObjectExp(o) for param, o in zip(a.parameters, objs, strict=True)}
                pre = self._compile(sub.substitute(em.And(a.preconditions), binding))
                effects = []
                for eff in a.effects:
                    fluent = sub.substitute(eff.fluent, binding)
                    if fluent not in self.index:
                        continue  # a fluent nothing reads
                    kind = {EffectKind.ASSIGN: "=", EffectKind.INCREASE: "+", EffectKind.DECREASE: "-"}[eff.kind]
                    value = self._compile(sub.substitute(eff.value, binding))
                    cond = self._compile(sub.substitute(eff.condition, binding))
                    effects.append((self.index[fluent], kind, value, cond))
                self.actions.append((a.name, objs, pre, self._successor(effects)))

    def _compile(self, node: Any) -> Callable[[tuple[Any, ...]], Any]:
        """The expression as a function of the state (a tuple in ``self.fluents``' order)."""
        if node.is_bool_constant():
            b = node.bool_constant_value()
            return lambda s: b
        if node.is_int_constant() or node.is_real_constant():
            q = _fraction(node)
            return lambda s: q
        if node.is_object_exp():
            o = node.object()
            return lambda s: o
        if node.is_fluent_exp():
            if node not in self.index:
                raise AssertionError(f"{node}: read but without an initial value")
            i = self.index[node]
            return lambda s: s[i]
        args = [self._compile(a) for a in node.args]
        if node.is_and():
            return lambda s: all(f(s) for f in args)
        if node.is_or():
            return lambda s: any(f(s) for f in args)
        if node.is_not():
            return lambda s: not args[0](s)
        binary = {
            "is_equals": operator.eq,
            "is_le": operator.le,
            "is_lt": operator.lt,
            "is_minus": operator.sub,
            "is_div": operator.truediv,
        }
        for test, op in binary.items():
            if getattr(node, test)():
                x, y = args
                return lambda s: op(x(s), y(s))
        if node.is_plus():
            return lambda s: sum((f(s) for f in args), Fraction(0))
        if node.is_times():

            def times(s: tuple[Any, ...]) -> Fraction:
                out = Fraction(1)
                for f in args:
                    out *= f(s)
                return out

            return times
        raise AssertionError(f"the test's evaluator does not know {node.node_type}: {node}")

    @staticmethod
    def _successor(effects: list[Any]) -> Callable[[tuple[Any, ...]], tuple[Any, ...]]:
        def apply(s: tuple[Any, ...]) -> tuple[Any, ...]:
            fired = [(i, kind, value(s)) for i, kind, value, cond in effects if cond(s)]
            out = list(s)
            # deletes first, then adds and numeric effects, every value read in s
            for i, kind, v in sorted(fired, key=lambda e: e[2] is not False):
                out[i] = v if kind == "=" else (out[i] + v if kind == "+" else out[i] - v)
            return tuple(out)

        return apply

    def shortest(self, limit: int = 400_000) -> list[tuple[str, tuple[Any, ...]]] | None:
        """A shortest plan (breadth-first), or None when no reachable state meets the goal;
        fails when more than ``limit`` states are reachable."""
        parent: dict[tuple[Any, ...], Any] = {self.start: None}
        layer = [self.start]
        while layer:
            for s in layer:
                if self.goal(s):
                    plan, at = [], s
                    while parent[at] is not None:
                        at, step = parent[at]
                        plan.append(step)
                    return plan[::-1]
            nxt = []
            for s in layer:
                for name, objs, pre, apply in self.actions:
                    if pre(s):
                        t = apply(s)
                        if t not in parent:
                            parent[t] = (s, (name, objs))
                            nxt.append(t)
            assert len(parent) <= limit, f"more than {limit} reachable states"
            layer = nxt
        return None

    def validates(self, plan: list[tuple[str, tuple[Any, ...]]]) -> bool:
        from unified_planning.engines import ValidationResultStatus
        from unified_planning.engines.plan_validator import SequentialPlanValidator
        from unified_planning.plans import ActionInstance, SequentialPlan

        p = self.problem
        seq = SequentialPlan([ActionInstance(p.action(name), objs) for name, objs in plan])
        res = SequentialPlanValidator(environment=p.environment).validate(p, seq)
        return bool(res.status is ValidationResultStatus.VALID)


def _ground(task: planning.Task, tmp_path: Path) -> _Ground:
    d, p = tmp_path / "domain.pddl", tmp_path / "problem.pddl"
    d.write_text(task.domain)
    p.write_text(task.problem)
    return _Ground(d, p)


_TASKS = {t.name: t for t in planning.tasks()}
# the small members (hand count at most 12) of every solvable family; in the slow group, the
# next ones up to a hand count of 23 (0.1–12 s each here); every unsolvable member (finite: ≤ 1.5 s)
SMALL = [n for n, t in _TASKS.items() if t.optimal is not None and t.optimal <= 12]
MEDIUM = ["gripper-6", "ferry-4", "ferry-6", "blocks-8", "counters-6", "farmland-6", "farmland-7", "sailing-far-7"]
MEDIUM += ["sailing-far-10", "rover-4", "rover-6", "hydropower-10-3", "hydropower-16-4"]
UNSOLVABLE = [n for n, t in _TASKS.items() if t.optimal is None]


def test_the_small_members_cover_every_solvable_family():
    families = {t.family for t in _TASKS.values() if t.optimal is not None}
    assert {_TASKS[n].family for n in SMALL} == families
    assert all(12 < (_TASKS[n].optimal or 0) <= 23 for n in MEDIUM)
    assert {n.rsplit("-", 1)[0] for n in UNSOLVABLE} == {"blocks-cycle", "farmland-short", "counters-tight"}


@pytest.mark.parametrize("name", SMALL + [pytest.param(n, marks=pytest.mark.slow) for n in MEDIUM])
def test_breadth_first_search_finds_exactly_the_hand_count(name, tmp_path):
    task = _TASKS[name]
    g = _ground(task, tmp_path)
    plan = g.shortest()
    assert plan is not None, f"{name}: the search finds no plan"
    assert len(plan) == task.optimal, f"{name}: shortest {len(plan)}, hand count {task.optimal}: {plan}"
    assert g.validates(plan), plan


@pytest.mark.parametrize("name", UNSOLVABLE)
def test_the_unsolvable_members_have_no_reachable_goal_state(name, tmp_path):
    assert _ground(_TASKS[name], tmp_path).shortest() is None


def test_the_search_is_not_vacuous(tmp_path):
    """Its own negative controls: gripper-2 with a goal reachable in one step (pick) answers 1,
    and counters-tight-3 with max_int raised back to n − 1 = 2 (0 < 1 < 2 fits) answers
    0 + 1 + 2 = 3 increments."""
    one = planning.Task(
        "t", "gripper", planning.GRIPPER, planning.gripper(2).replace(
            "(:goal (and (at ball0 roomb) (at ball1 roomb)))", "(:goal (and (carry ball0 left)))"
        ), 1
    )  # fmt: skip
    assert "carry ball0 left" in one.problem
    assert len(_ground(one, tmp_path).shortest() or []) == 1
    tight = _TASKS["counters-tight-3"]
    fits = planning.Task("t", "counters", tight.domain, tight.problem.replace("(= (max_int) 1)", "(= (max_int) 2)"), 3)
    assert fits.problem != tight.problem
    assert len(_ground(fits, tmp_path).shortest() or []) == 3


def test_select_by_name_family_and_substring():
    assert [t.name for t in planning.select(["gripper-2"])] == ["gripper-2"]
    assert {t.family for t in planning.select(["unsolvable"])} == {"unsolvable"}
    # the script's --only is exact; catc bench's also keeps the names containing the text
    assert planning.select(["gripper-1"]) == []
    assert [t.name for t in planning.select(["gripper-1"], exact=False)] == ["gripper-10", "gripper-12", "gripper-16"]


# ---------------------------------------------------------------- catc bench --corpus planning


def _enhsp_missing() -> str | None:
    from catc.targets.enhsp import available

    return available()


@pytest.mark.skipif(_enhsp_missing() is not None, reason=str(_enhsp_missing()))
def test_bench_corpus_planning_prints_catc_and_enhsp_on_gripper_2(tmp_path):
    from catc.interfaces.cli import main

    out = tmp_path / "rows.json"
    r = CliRunner().invoke(
        main, ["bench", "--corpus", "planning", "--only", "gripper-2", "--timeout", "20", "--save-json", str(out)]
    )
    assert r.exit_code == 0, r.output
    row = next(line for line in r.stdout.splitlines() if line.startswith("| gripper-2 |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    # gripper-2: pick, pick, move, drop, drop = 5 (the hand count); both planners optimal, both
    # plans accepted by UP's validator
    assert cells[1:5] == ["5", "sat", "5", "yes"] and cells[8] == "yes", row
    assert cells[9:11] == ["sat", "5"] and cells[13] == "yes", row
    assert "| 1–10 | 1 | 1 (1) |" in r.stdout
    assert "    catc bench --corpus planning" in r.stdout
    import json

    (doc,) = json.loads(out.read_text())
    assert doc["task"] == "gripper-2" and doc["hand_count"] == 5 and doc["enhsp_len"] == 5
    # --json instead of the tables; a bare --corpus is both corpora, and the wheel's is left out
    # when --only keeps none of it. counters-tight-3: three counters strictly increasing need a
    # value of 2, max_int is 1 (and the search above exhausts its 8 states): both say unsat
    r = CliRunner().invoke(main, ["bench", "--corpus", "--only", "counters-tight-3", "--timeout", "20", "--json"])
    assert r.exit_code == 0, r.output
    (doc,) = json.loads(r.stdout)["planning"]
    assert doc["catc"].startswith("unsat") and doc["enhsp"] == "unsat" and doc["catc_len"] is None, doc


def test_bench_corpus_refuses_an_unknown_corpus():
    from catc.interfaces.cli import main

    r = CliRunner().invoke(main, ["bench", "--corpus", "ipc"])
    assert r.exit_code == 2 and "'ipc' is not one of" in r.output, r.output


def test_bench_corpus_planning_names_the_extra_when_enhsp_is_missing(monkeypatch):
    import shutil
    import sys

    from catc.interfaces.cli import main

    if shutil.which("java") is None:
        pytest.skip("no Java: the message names Java 17 first (tests/test_bench.py)")
    monkeypatch.setitem(sys.modules, "up_enhsp", None)
    r = CliRunner().invoke(main, ["bench", "--corpus", "planning", "--only", "gripper-2"])
    assert r.exit_code == 2 and "catc-lang[baselines]" in r.output, r.output


@pytest.mark.skipif(_enhsp_missing() is not None, reason=str(_enhsp_missing()))
def test_second_and_an_empty_selection_are_input_errors():
    from catc.interfaces.cli import main

    r = CliRunner().invoke(main, ["bench", "--second", "--quick"])
    assert r.exit_code == 2 and "--second applies to the planning corpus only" in r.output, r.output
    r = CliRunner().invoke(main, ["bench", "--corpus", "planning", "--only", "no-such-task"])
    assert r.exit_code == 2 and "matches no problem" in r.output, r.output


def _planners_missing() -> str | None:
    import importlib.util

    missing = [m for m in ("up_pyperplan", "up_tamer") if importlib.util.find_spec(m) is None]
    return f"no {', '.join(missing)} (the planners extra)" if missing else None


@pytest.mark.slow
@pytest.mark.skipif((_enhsp_missing() or _planners_missing()) is not None, reason="ENHSP or the planners extra")
def test_second_runs_pyperplan_on_gripper_2_and_names_the_extra_when_missing(monkeypatch):
    import sys

    from catc.interfaces.cli import main

    args = ["bench", "--corpus", "planning", "--only", "gripper-2", "--timeout", "30", "--second"]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    row = next(line for line in r.stdout.splitlines() if line.startswith("| gripper-2 |"))
    cells = [c.strip() for c in row.strip("|").split("|")]
    # the second planner's four columns: pyperplan's A*/LM-cut is optimal, so the hand count, 5,
    # and UP's validator accepts its plan
    assert cells[-4].startswith("pyperplan sat") and cells[-3] == "5" and cells[-1] == "yes", row
    monkeypatch.setitem(sys.modules, "up_tamer", None)
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 2 and "catc-lang[planners]" in r.output, r.output
