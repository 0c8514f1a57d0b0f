"""A composition with its grounding annotations resolved: every hole, parameter and port
bound to the value it has in this composition.

θ come from the activation, resources from the state before the activation's step (the
validator's replay), literals from the model.  Reserve (fresh) symbols, which no one named,
are given names a robot can use: ``topic#1`` becomes ``topic_1``.  Reals stay exact here
(:class:`Real`); each artifact decides how to write them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from fractions import Fraction
from typing import Any

from catc import ir
from catc.ir.grounding import (
    BehaviorGrounding,
    Deployment,
    HardwareGrounding,
    Profile,
    RealLiteral,
    SoftwareGrounding,
    Template,
    Value,
    ValueKind,
    ros_node_name,
)
from catc.ir.numbers import ratio_text
from catc.semantics.plan import Plan
from catgrammar.record import Record, set_field
from catgrammar.span import Span


class Real(Fraction):
    """An exact real value that a target must write as a floating-point number."""


class Key(str):
    """A blackboard key (behaviour ports): written ``{key}``."""


class HardwareStep(Record):
    __slots__ = ("step", "morphism", "instruction", "check", "parts")
    step: int  # 1-based step of the composition
    morphism: str
    instruction: str
    check: str | None
    parts: tuple[str, ...]

    def __init__(self, step: int, morphism: str, instruction: str, check: str | None, parts: tuple[str, ...]) -> None:
        set_field(self, "step", step)
        set_field(self, "morphism", morphism)
        set_field(self, "instruction", instruction)
        set_field(self, "check", check)
        set_field(self, "parts", parts)


class Service(Record):
    """A container of the deployment: a software component, a behaviour's skill, or the
    behaviour-tree executor.  ``params`` are its node's ROS 2 parameters, ``remap`` its
    topic remappings (both resolved)."""

    __slots__ = ("name", "morphism", "image", "node", "profile", "params", "remap")
    name: str
    morphism: str | None
    image: str
    node: str | None
    profile: Profile
    params: tuple[tuple[str, Any], ...]
    remap: tuple[tuple[str, str], ...]

    def __init__(
        self,
        name: str,
        morphism: str | None,
        image: str,
        node: str | None,
        profile: Profile,
        params: tuple[tuple[str, Any], ...] = (),
        remap: tuple[tuple[str, str], ...] = (),
    ) -> None:
        set_field(self, "name", name)
        set_field(self, "morphism", morphism)
        set_field(self, "image", image)
        set_field(self, "node", node)
        set_field(self, "profile", profile)
        set_field(self, "params", params)
        set_field(self, "remap", remap)


class BehaviorNode(Record):
    """A node of the behaviour tree: its ID and its ports as BT.CPP reads them (text, with
    ``{key}`` for a blackboard entry)."""

    __slots__ = ("morphism", "node_id", "inputs", "outputs")
    morphism: str
    node_id: str
    inputs: tuple[tuple[str, str], ...]
    outputs: tuple[tuple[str, str], ...]

    def __init__(
        self, morphism: str, node_id: str, inputs: tuple[tuple[str, str], ...], outputs: tuple[tuple[str, str], ...]
    ) -> None:
        set_field(self, "morphism", morphism)
        set_field(self, "node_id", node_id)
        set_field(self, "inputs", inputs)
        set_field(self, "outputs", outputs)


class Grounded(Record):
    """Everything the artifacts are made of, in the composition's order."""

    __slots__ = ("project", "hardware", "services", "behaviours", "missing", "plan")
    project: str
    hardware: tuple[HardwareStep, ...]
    services: tuple[Service, ...]
    behaviours: tuple[tuple[BehaviorNode, ...], ...]  # per step that has any, in plan order
    missing: tuple[str, ...]  # morphisms used without grounding data
    plan: Plan

    def __init__(
        self,
        project: str,
        hardware: tuple[HardwareStep, ...],
        services: tuple[Service, ...],
        behaviours: tuple[tuple[BehaviorNode, ...], ...],
        missing: tuple[str, ...],
        plan: Plan,
    ) -> None:
        set_field(self, "project", project)
        set_field(self, "hardware", hardware)
        set_field(self, "services", services)
        set_field(self, "behaviours", behaviours)
        set_field(self, "missing", missing)
        set_field(self, "plan", plan)


class GroundingError(ValueError):
    """A composition that cannot be grounded, located: ``span`` is the annotation at fault,
    ``first`` another one it clashes with (or None)."""

    def __init__(self, message: str, span: Span | None, first: Span | None = None) -> None:
        super().__init__(message)
        self.span, self.first = span, first


class GroundingConflict(GroundingError):
    """Two components of one composition would be the same thing on the robot (one ROS 2
    node name, one service name).  ``span`` is the second one's grounding, ``first`` the
    first one's."""


def unexecuted(grounded: Grounded) -> bool:
    """The composition has behaviours and no service runs its tree (no executor image)."""
    return bool(grounded.behaviours) and not any(s.profile is Profile.EXECUTORS for s in grounded.services)


def fresh_text(symbol: str) -> str:
    """A usable name for a reserve value: ``topic#1`` → ``topic_1``."""
    return symbol.replace("#", "_").replace("-", "_")


class _Resolver:
    def __init__(self, inst: ir.Instance, plan: Plan, states: Sequence[Mapping[str, object]]) -> None:
        self.inst, self.plan, self.states = inst, plan, states

    def value(self, v: Value, step: int, params: Mapping[str, object], sort: ir.Sort | None) -> Any:
        """The value of ``v`` for the activation at ``step`` (0-based)."""
        if v.kind is ValueKind.KEY:
            return Key(v.name or "")
        if v.kind is ValueKind.LITERAL:
            raw: object = v.literal
        elif v.kind is ValueKind.PARAM:
            raw = params[v.name or ""]
        else:
            raw = self.states[step][v.name or ""]
        return self._typed(raw, sort)

    def _typed(self, raw: object, sort: ir.Sort | None) -> Any:
        if isinstance(raw, bool):
            return raw
        if isinstance(raw, Fraction):
            if sort is not None and sort.kind is ir.SortKind.INT and raw.denominator == 1:
                return int(raw)
            return Real(raw) if sort is None or sort.kind is not ir.SortKind.INT else raw
        if isinstance(raw, frozenset):
            return [self._typed(e, None) for e in sorted(raw)]
        if isinstance(raw, str):
            return fresh_text(raw) if raw in self.plan.fresh else raw
        return raw

    def sort_of(self, m: ir.Morphism, v: Value) -> ir.Sort | None:
        if v.kind is ValueKind.PARAM:
            p = m.param(v.name or "")
            return p.sort if p is not None else None
        if v.kind is ValueKind.RESOURCE:
            r = self.inst.resources.get(v.name or "")
            return r.sort if r is not None else None
        if v.kind is ValueKind.LITERAL and isinstance(v.literal, Fraction):
            whole = v.literal.denominator == 1 and not isinstance(v.literal, RealLiteral)
            return ir.INT if whole else ir.REAL
        return None

    def text(self, template: Template, step: int, params: Mapping[str, object], m: ir.Morphism) -> str:
        out = []
        for part in template.parts:
            if isinstance(part, str):
                out.append(part)
            else:
                out.append(port_text(self.value(part, step, params, self.sort_of(m, part))))
        return "".join(out)


def topic_name(text: str) -> str:
    """A symbol as a ROS 2 topic name: ``image-raw`` → ``image_raw`` ('-' is not allowed)."""
    return text.replace("-", "_")


def port_text(value: Any) -> str:
    """A resolved value as text (instructions, behaviour-tree ports)."""
    if isinstance(value, Key):
        return "{" + value + "}"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, Fraction):
        return ratio_text(value)
    if isinstance(value, list):
        return ";".join(port_text(v) for v in value)  # BT.CPP's separator for vectors
    return str(value)


def ground(inst: ir.Instance, plan: Plan, states: Sequence[Mapping[str, object]]) -> Grounded:
    """Resolve the grounding of every activation of ``plan`` (``states``: the validator's
    replay, s₀ … sₙ)."""
    r = _Resolver(inst, plan, states)
    hardware: list[HardwareStep] = []
    services: list[Service] = []
    behaviours: list[tuple[BehaviorNode, ...]] = []
    missing: list[str] = []
    uses: dict[str, int] = {}
    for i, step in enumerate(plan.steps):
        nodes: list[BehaviorNode] = []
        for a in step:
            m = inst.morphisms[a.morphism]
            g = m.grounding
            uses[m.name] = uses.get(m.name, 0) + 1
            name = m.name if uses[m.name] == 1 else f"{m.name}-{uses[m.name]}"
            if g is None:
                missing.append(m.name)
            elif isinstance(g, HardwareGrounding):
                hardware.append(_hardware(r, g, i, a.params, m))
            elif isinstance(g, SoftwareGrounding):
                services.append(_software(r, g, i, a.params, m, name))
            else:
                node = _behaviour(r, g, i, a.params, m)
                nodes.append(node)
                if g.image is not None:
                    services.append(Service(name, m.name, g.image, None, g.profile))
        if nodes:
            behaviours.append(tuple(nodes))
    deployment = inst.domain.deployment or Deployment(inst.problem.name)
    if behaviours and deployment.executor is not None:
        services.append(Service("bt-executor", None, deployment.executor, None, Profile.EXECUTORS))
    _distinct(inst, services)
    return Grounded(deployment.project, tuple(hardware), tuple(services), tuple(behaviours), tuple(missing), plan)


def _distinct(inst: ir.Instance, services: Sequence[Service]) -> None:
    """Every service has its own name and every node its own name, or GroundingConflict."""

    def span(s: Service) -> Span | None:
        if s.morphism is None:
            d = inst.domain.deployment
            return d.span if d is not None else None
        g = inst.morphisms[s.morphism].grounding
        return g.span if g is not None else None

    for what, key in (("service", lambda s: s.name), ("ROS 2 node", lambda s: s.node)):
        seen: dict[str, Service] = {}
        for s in services:
            k = key(s)
            if k is None:
                continue
            if k in seen:
                a, b = seen[k].morphism or "the behaviour-tree executor", s.morphism or "the behaviour-tree executor"
                raise GroundingConflict(
                    f"this composition runs two {what}s named '{k}' ({a} and {b}): give one of them another name",
                    span(s),
                    span(seen[k]),
                )
            seen[k] = s


def _hardware(r: _Resolver, g: HardwareGrounding, i: int, params: Mapping[str, object], m: ir.Morphism) -> HardwareStep:
    check = r.text(g.check, i, params, m) if g.check is not None else None
    return HardwareStep(i + 1, m.name, r.text(g.instruction, i, params, m), check, g.parts)


def _software(
    r: _Resolver, g: SoftwareGrounding, i: int, params: Mapping[str, object], m: ir.Morphism, name: str
) -> Service:
    values = tuple((k, r.value(v, i, params, r.sort_of(m, v))) for k, v in g.params)
    for (k, v), (_, source) in zip(values, g.params):
        if v == []:  # rcl reads `[]` as a parameter with no value, and rclcpp refuses to load it
            raise GroundingError(
                f"ROS 2 parameter '{k}' of {m.name} would be an empty list in step {i + 1}: rcl reads [] as no "
                "value and rclcpp refuses to load the file; bind a set that cannot be empty here, or leave the "
                "parameter out and give the node a default",
                source.span or (g.span if g is not None else None),
            )
    remap = tuple((k, topic_name(port_text(r.value(v, i, params, r.sort_of(m, v))))) for k, v in g.remap)
    node = g.node or ros_node_name(m.name)
    if name != m.name:
        node = f"{node}_{name.rsplit('-', 1)[1]}"
    return Service(name, m.name, g.image, node, g.profile, values, remap)


def _behaviour(
    r: _Resolver, g: BehaviorGrounding, i: int, params: Mapping[str, object], m: ir.Morphism
) -> BehaviorNode:
    inputs = tuple((k, port_text(r.value(v, i, params, r.sort_of(m, v)))) for k, v in g.inputs)
    outputs = tuple((k, port_text(r.value(v, i, params, r.sort_of(m, v)))) for k, v in g.outputs)
    return BehaviorNode(m.name, g.node_id, inputs, outputs)
