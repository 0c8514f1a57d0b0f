"""The ``ground`` target: from a composition to the artifacts a robot runs
(:mod:`catc.targets.grounding`): instructions.md, compose.yaml, params.yaml, bt.xml and
manifest.json.

Without a composition the problem is solved first: optimised (as ``catc optimize``) when it
has a metric or soft constraints, else as ``catc solve``.  The composition is replayed by the
independent validator and its grounding annotations resolved.  ``catc ground`` (its
``--diff`` mode too) is :mod:`catc.interfaces.cli.ground`."""

from __future__ import annotations

import hashlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from catc import ir
from catc.queries.base import Kind, Option, Use
from catc.semantics.plan import Plan
from catc.targets.base import InputError, Target, horizon_option, load_options
from catc.targets.grounding.diff import NotAGrounding as NotAGrounding
from catc.targets.grounding.resolve import GroundingConflict
from catc.targets.grounding.resolve import GroundingError as GroundingError
from catgrammar import codes


class NoComposition(Exception):
    """Solving found no composition to ground (``result``: the query's answer)."""

    def __init__(self, query: Any, result: Any) -> None:
        super().__init__(f"no composition to ground: {result.status.value}")
        self.query = query
        self.result = result


class InvalidComposition(Exception):
    """The composition is not one of this model (``violations``: the validator's)."""

    def __init__(self, where: str, violations: Sequence[Any]) -> None:
        super().__init__(f"{where} is not a composition of this model")
        self.where = where
        self.violations = list(violations)


@dataclass(frozen=True)
class Grounding:
    """A composition ground: the plan, the validator's states, the resolved grounding
    (:class:`catc.targets.grounding.resolve.Grounded`), the artifacts' bytes by file name and
    the manifest (catc.ground/1)."""

    plan: Plan
    states: tuple[Mapping[str, object], ...]
    grounded: Any
    files: dict[str, bytes]
    manifest: dict


def model_sha256(inst: ir.Instance) -> str:
    """A hash of the model's source files (domain, imports, problem), independent of where
    they lie: the sha256 of their sorted sha256s."""
    files = {inst.domain.span.file if inst.domain.span else None, inst.problem.span.file if inst.problem.span else None}
    files |= {m.span.file for m in inst.morphisms.values() if m.span is not None}
    files |= {r.span.file for r in inst.resources.values() if r.span is not None}
    digests = []
    for name in files:
        if name is None:
            continue
        try:
            digests.append(hashlib.sha256(Path(name).read_bytes()).hexdigest())
        except OSError:
            continue
    return hashlib.sha256("\n".join(sorted(digests)).encode()).hexdigest()


def composition(inst: ir.Instance, horizon: int | None, timeout: float | None) -> Plan:
    """The composition to deploy: the optimum when the problem says what is best, else the
    shortest (:class:`NoComposition` when there is none)."""
    from catc.queries import registry
    from catc.queries.base import ExitCode

    query = registry.get(registry.deploy_query(inst))
    result = query.run(inst, horizon=horizon, timeout=timeout)
    if result.exit_code is not ExitCode.OK or getattr(result, "plan", None) is None:
        raise NoComposition(query, result)
    plan: Plan = result.plan  # type: ignore[attr-defined]
    return plan


def replayed(inst: ir.Instance, plan: Plan, where: str) -> tuple[Mapping[str, object], ...]:
    """The validator's states for ``plan`` (:class:`InvalidComposition` when it is not one)."""
    from catc.semantics.validate import validate

    report = validate(inst, plan, horizon=max(len(plan), 1))
    if not report.ok:
        raise InvalidComposition(where, report.violations)
    return tuple(report.states)


def grounding_of(inst: ir.Instance, plan: Plan, states: tuple[Mapping[str, object], ...]) -> Grounding:
    """The artifacts of a replayed composition (``GroundingError`` — ``GroundingConflict`` when
    two annotations disagree — located at the annotation, ValueError for a value no artifact
    can carry)."""
    from catc.targets.grounding.artifacts import artifacts, manifest
    from catc.targets.grounding.resolve import ground as resolve

    grounded = resolve(inst, plan, states)
    files = artifacts(grounded)
    return Grounding(plan, states, grounded, files, manifest(grounded, files, model_sha256(inst), inst))


def ground(
    inst: ir.Instance, *, plan: Plan | None = None, horizon: int | None = None, timeout: float | None = None
) -> Grounding:
    """Ground ``plan`` (default: the problem solved first); :class:`InputError` when it cannot."""
    try:
        chosen = composition(inst, horizon, timeout) if plan is None else plan
        return grounding_of(inst, chosen, replayed(inst, chosen, "the plan" if plan else "the solver's composition"))
    except (NoComposition, InvalidComposition) as exc:
        raise InputError(str(exc), codes.BAD_ARGUMENT) from None
    except (GroundingConflict, ValueError) as exc:
        raise InputError(str(exc), codes.BAD_GROUNDING) from None


def unexecuted(grounded: Any) -> bool:
    """The composition has behaviours and no service runs its tree (no executor image)."""
    from catc.targets.grounding.resolve import unexecuted as check

    return check(grounded)


def is_grounding(path: str) -> bool:
    """``path`` is a grounding's folder or its manifest.json (not a plan file)."""
    from catc.targets.grounding.diff import is_grounding as check

    return check(path)


def read_grounding(path: str) -> dict[str, bytes]:
    """A grounding's files, checked against its manifest (:class:`NotAGrounding`)."""
    from catc.targets.grounding.diff import read_grounding as read

    return read(path)


def diff_artifacts(old: Mapping[str, bytes], new: Mapping[str, bytes]) -> Any:
    """What changes on the robot between two groundings' files (no model needed)."""
    from catc.targets.grounding.diff import diff_artifacts as compare

    return compare(old, new)


def write_files(out: Path, g: Grounding) -> list[Path]:
    """Write the artifacts and the manifest into the folder ``out`` (created); OSError."""
    from catc.targets.grounding.artifacts import write as write_artifacts

    return write_artifacts(out, g.files, g.manifest)


def diff(old: Grounding, new: Grounding) -> Any:
    """What changes on the robot from ``old`` to ``new`` (:class:`catc.targets.grounding.diff.GroundDiff`)."""
    from catc.targets.grounding.diff import ground_diff

    return ground_diff(old.grounded, new.grounded)


def render(inst: ir.Instance, g: Grounding) -> str:
    g_ = g.grounded
    return (
        f"GROUNDED  {len(g.plan)} steps of problem {inst.problem.name}: {len(g_.hardware)} hardware steps, "
        f"{len(g_.services)} services, {sum(len(s) for s in g_.behaviours)} behaviour nodes\n"
        + "".join(f"  {name}\n" for name in g.files)
    )


def write(inst: ir.Instance, g: Grounding, options: Mapping[str, Any]) -> list[str]:
    out = options["output"]
    try:
        written = write_files(Path(out), g)
    except OSError as exc:
        raise InputError(f"cannot write to {out}: {exc.strerror or exc}", codes.CANNOT_WRITE) from None
    return [str(p) for p in written]


_VIEW, _PATH, _PROBLEM = load_options(
    "Ground in this view (overrides the problem's (:view ...)).", path_help="Extra folder for domains."
)

TARGET = Target(
    "ground",
    command=("ground",),
    schema="catc.ground/1",
    summary="Write the artifacts a robot runs for a composition (solved, or --plan), or --diff two.",
    description="PATHS is PROBLEM, or DOMAIN PROBLEM.  Writes instructions.md, compose.yaml, params.yaml,\n"
    "bt.xml and manifest.json to -o DIR.  Exit 0 written (or diffed), 1 no composition or an\n"
    "invalid plan, 2 input error, 3 the solver gave up.  Needs the 'grounding' extra.",
    options=(
        Option("output", ("-o", "--output"), Kind.OUTPUT_FOLDER, "Folder for the artifacts (created).", use=Use.OUTPUT),
        Option("plan_file", ("--plan",), Kind.INPUT_FILE, "Ground this catc.plan/1 composition.", use=Use.LOAD),
        Option(
            "diff",
            ("--diff",),
            Kind.FILE_PAIR,
            "What changes on the robot from OLD to NEW: two groundings (folders or manifest.json; no "
            "model needed) or two catc.plan/1 files of this model.",
            metavar="OLD NEW",
            use=Use.OUTPUT,
        ),
        Option(
            "strict",
            ("--strict",),
            Kind.FLAG,
            "A morphism without grounding, or behaviours no executor runs, is an error (exit 2), not a warning.",
            use=Use.OUTPUT,
        ),
        Option(
            "as_json",
            ("--json",),
            Kind.FLAG,
            "Print the manifest (catc.ground/1) or the diff (catc.ground-diff/1).",
            default=False,
            use=Use.OUTPUT,
        ),
        horizon_option("Most steps when solving (no --plan)."),
        _VIEW,
        _PATH,
        _PROBLEM,
        Option("timeout", ("--timeout",), Kind.SECONDS, "Give up after this many seconds (the whole command)."),
    ),
    run=ground,
    to_json=lambda inst, g: g.manifest,
    render=render,
    write=write,
)
