"""diagnose: why there is no composition — an irreducible set of conflicting source constructs.

An irreducible unsatisfiable subset (paper eq. diagnose) of the labelled constructs
(:mod:`catc.smt.labelled`): the solver's core, shrunk by deletion, then checked member by
member (dropping any one restores feasibility).  ``all_cores`` explores further cores by
excluding a member of each core found (a hitting-set tree), bounded by count and time.

Diagnoses are *relative to the composition* when the problem has ``(:deployed ...)`` (or one
is given): the components used are then fixed to exactly the deployed ones, so the core
names what stops that composition rather than the whole causal chain.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field

from catc import ir
from catc.semantics.horizon import default_horizon
from catc.semantics.validate import ValidationFailure
from catc.smt.backend import Check
from catc.smt.labelled import LabelledModel


@dataclass
class Diagnosis:
    status: str  # "unsat" (cores found) | "sat" (nothing to diagnose) | "unknown"
    cores: list[list[str]] = field(default_factory=list)
    total: int = 0  # labelled constraints considered
    relative_to: tuple[str, ...] | None = None
    horizon: int = 0
    checks: int = 0
    complete: bool = True  # --all: the search ended (not cut by count or time)
    timings: dict[str, float] = field(default_factory=dict)


def _shrink(model: LabelledModel, core: list[str], deadline: float | None) -> list[str] | None:
    """Deletion-based minimisation of an unsat core to an irreducible one."""
    core = list(core)
    i = 0
    while i < len(core):
        trial = core[:i] + core[i + 1 :]
        r, smaller = model.check(trial, _remaining(deadline))
        if r is Check.UNSAT:
            keep = set(smaller)
            core = [l for l in trial if l in keep]
        elif r is Check.SAT:
            i += 1
        else:
            return None
    return core


def _irreducible(model: LabelledModel, core: list[str], deadline: float | None) -> bool:
    r, _ = model.check(core, _remaining(deadline))
    if r is not Check.UNSAT:
        return False
    return all(model.check([l for l in core if l != x], _remaining(deadline))[0] is Check.SAT for x in core)


def _remaining(deadline: float | None) -> float | None:
    return None if deadline is None else max(0.001, deadline - time.perf_counter())


def diagnose(
    inst: ir.Instance,  # relative_to: None = the problem's (:deployed ...); () = no composition
    *,
    horizon: int | None = None,
    sequential: bool = False,
    relative_to: Iterable[str] | None = None,
    all_cores: bool = False,
    max_cores: int = 5,
    timeout: float | None = None,
    progress: Callable[[str], None] | None = None,
) -> Diagnosis:
    start = time.perf_counter()
    deadline = start + timeout if timeout else None
    k = default_horizon(inst) if horizon is None else horizon
    components = (tuple(relative_to) or None) if relative_to is not None else (inst.problem.deployed or None)
    model = LabelledModel(inst, k, sequential=sequential, components=components)
    result = Diagnosis("unknown", total=len(model.labels), relative_to=components, horizon=k)
    result.timings["encode"] = time.perf_counter() - start
    say = progress or (lambda message: None)
    say(f"checking {len(model.labels)} requirements together")
    r, core = model.check(model.labels, _remaining(deadline))
    if r is Check.SAT:
        result.status = "sat"
    elif r is Check.UNSAT:
        found: list[list[str]] = []
        # Hitting-set tree: every further core must avoid one member of each core found.
        frontier: list[frozenset[str]] = [frozenset()]
        seen: set[frozenset[str]] = set()
        while frontier and len(found) < (max_cores if all_cores else 1):
            if deadline is not None and time.perf_counter() > deadline:
                result.complete = False
                break
            excluded = frontier.pop(0)
            if excluded in seen:
                continue
            seen.add(excluded)
            labels = [l for l in model.labels if l not in excluded]
            r, core = model.check(labels, _remaining(deadline))
            if r is not Check.UNSAT:
                continue
            say(f"{len(found)} core(s) found; shrinking a core of {len(core)} requirements")
            mus = _shrink(model, core, deadline)
            if mus is None:
                result.complete = False
                break
            if not _irreducible(model, mus, deadline):  # pragma: no cover - _shrink guarantees it
                raise ValidationFailure(f"the core {mus} is not irreducible")
            if sorted(mus) not in [sorted(c) for c in found]:
                found.append(mus)
            frontier.extend(excluded | {x} for x in mus)
        if all_cores and frontier and len(found) >= max_cores:
            result.complete = False
        result.cores = found
        result.status = "unsat" if found else "unknown"
    result.checks = model.checks
    result.timings["total"] = time.perf_counter() - start
    return result
