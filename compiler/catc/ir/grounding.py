"""What a component becomes on the robot: the checked grounding annotations of morphisms.

A morphism's ``:ground`` block says, for its kind:

* **hardware** — a human instruction with holes for θ (``"Mount the camera on rail slot
  {slot}"``), what to check afterwards, and the parts needed;
* **software** — the container image, the ROS 2 node, its parameters and topic remappings
  bound to θ, resources or literals, and its CORAL profile;
* **behavior** — the BehaviorTree.CPP node ID and its input and output ports, bound to θ,
  literals or blackboard keys (and optionally the image of the skill that implements it).

A :class:`Value` names where a bound value comes from; the grounding targets
(:mod:`catc.targets.grounding`) resolve it against a composition: θ from the activation,
resources from the state before the step.
"""

from __future__ import annotations

import re
from enum import Enum
from fractions import Fraction

from catgrammar.record import Record
from catgrammar.record import set_field as _set
from catgrammar.span import Span


class ValueKind(str, Enum):
    PARAM = "param"  # a θ of the morphism
    RESOURCE = "resource"  # a resource, in the state before the morphism's step
    LITERAL = "literal"  # a number, a Boolean or a string
    KEY = "key"  # a blackboard entry (behaviour ports): written as {key}


class RealLiteral(Fraction):
    """A number literal written as a real (``2.0``, ``1e3``): a real even when it is whole, so
    an artifact writes it as a float (rclcpp refuses an integer for a double parameter)."""


class Value(Record):
    """Where a bound value comes from: ``name`` for PARAM, RESOURCE and KEY; ``literal``
    (a Fraction, a bool or a str) for LITERAL."""

    __slots__ = ("kind", "name", "literal", "span")
    _compared = ("kind", "name", "literal")
    kind: ValueKind
    name: str | None
    literal: Fraction | bool | str | None
    span: Span | None

    def __init__(
        self,
        kind: ValueKind,
        name: str | None = None,
        literal: Fraction | bool | str | None = None,
        span: Span | None = None,
    ) -> None:
        _set(self, "kind", kind)
        _set(self, "name", name)
        _set(self, "literal", literal)
        _set(self, "span", span)


class Template(Record):
    """Text with holes: ``parts`` alternate literal text and the names of θ in the holes
    (``"Mount on slot {slot}"`` → ``("Mount on slot ", Value(PARAM, "slot"))``)."""

    __slots__ = ("parts", "span")
    _compared = ("parts",)
    parts: tuple[str | Value, ...]
    span: Span | None

    def __init__(self, parts: tuple[str | Value, ...], span: Span | None = None) -> None:
        _set(self, "parts", parts)
        _set(self, "span", span)


class Profile(str, Enum):
    """CORAL's component roles (compose ``profiles:`` and the image label ``coral.profile``)."""

    DRIVERS = "drivers"
    SKILLSETS = "skillsets"
    EXECUTORS = "executors"


class HardwareGrounding(Record):
    __slots__ = ("instruction", "check", "parts", "span")
    _compared = ("instruction", "check", "parts")
    instruction: Template
    check: Template | None
    parts: tuple[str, ...]
    span: Span | None

    def __init__(
        self,
        instruction: Template,
        check: Template | None = None,
        parts: tuple[str, ...] = (),
        span: Span | None = None,
    ) -> None:
        _set(self, "instruction", instruction)
        _set(self, "check", check)
        _set(self, "parts", parts)
        _set(self, "span", span)


class SoftwareGrounding(Record):
    """A ROS 2 node in a container: ``params`` (name → value) become its parameter file
    entries, ``remap`` (topic → value) its remappings."""

    __slots__ = ("image", "node", "profile", "params", "remap", "span")
    _compared = ("image", "node", "profile", "params", "remap")
    image: str
    node: str
    profile: Profile
    params: tuple[tuple[str, Value], ...]
    remap: tuple[tuple[str, Value], ...]
    span: Span | None

    def __init__(
        self,
        image: str,
        node: str,
        profile: Profile = Profile.DRIVERS,
        params: tuple[tuple[str, Value], ...] = (),
        remap: tuple[tuple[str, Value], ...] = (),
        span: Span | None = None,
    ) -> None:
        _set(self, "image", image)
        _set(self, "node", node)
        _set(self, "profile", profile)
        _set(self, "params", params)
        _set(self, "remap", remap)
        _set(self, "span", span)


class BehaviorGrounding(Record):
    """A node of the behaviour tree: its BT.CPP ``node_id`` and ports.  Output ports are
    bound to blackboard keys; an ``image`` makes the skill that implements the node a
    service of its own."""

    __slots__ = ("node_id", "inputs", "outputs", "image", "profile", "span")
    _compared = ("node_id", "inputs", "outputs", "image", "profile")
    node_id: str
    inputs: tuple[tuple[str, Value], ...]
    outputs: tuple[tuple[str, Value], ...]
    image: str | None
    profile: Profile
    span: Span | None

    def __init__(
        self,
        node_id: str,
        inputs: tuple[tuple[str, Value], ...] = (),
        outputs: tuple[tuple[str, Value], ...] = (),
        image: str | None = None,
        profile: Profile = Profile.SKILLSETS,
        span: Span | None = None,
    ) -> None:
        _set(self, "node_id", node_id)
        _set(self, "inputs", inputs)
        _set(self, "outputs", outputs)
        _set(self, "image", image)
        _set(self, "profile", profile)
        _set(self, "span", span)


Grounding = HardwareGrounding | SoftwareGrounding | BehaviorGrounding


class Deployment(Record):
    """How a composition is deployed as a whole: the Compose project name and the image
    that runs the behaviour tree (the ``executors`` service)."""

    __slots__ = ("project", "executor", "span")
    _compared = ("project", "executor")
    project: str
    executor: str | None
    span: Span | None

    def __init__(self, project: str, executor: str | None = None, span: Span | None = None) -> None:
        _set(self, "project", project)
        _set(self, "executor", executor)
        _set(self, "span", span)


# ---------------------------------------------------------------- names the targets accept

# patterns, compiled by re (and kept in its cache) when a name is first checked: most
# commands never check one, and compiling them costs every command's start-up
_ROS_NAME = r"[A-Za-z_][A-Za-z0-9_]*"
_XML_NAME = r"[A-Za-z_][A-Za-z0-9_.-]*"
_SERVICE_NAME = r"[a-zA-Z0-9][a-zA-Z0-9_.-]*"
_IMAGE = r"[a-z0-9]+(?:[._-][a-z0-9]+)*(?::[0-9]+)?(?:/[a-z0-9]+(?:[._-][a-z0-9]+)*)*(?::[\w][\w.-]{0,127})?(?:@sha256:[0-9a-f]{64})?"


def ros_name_problem(name: str) -> str | None:
    """Why ``name`` is not a valid ROS 2 node or parameter name (rmw's rules: letters,
    digits and underscores, not starting with a digit, at most 255 characters), or None."""
    if not name:
        return "it is empty"
    if len(name) > 255:
        return "it is longer than 255 characters"
    if not re.fullmatch(_ROS_NAME, name):
        return "only letters, digits and '_' are allowed, and it must not start with a digit"
    return None


def topic_problem(name: str) -> str | None:
    """Why ``name`` is not a valid relative or absolute ROS 2 topic name, or None."""
    tokens = name[1:].split("/") if name.startswith("/") else name.split("/")
    if not name or any(ros_name_problem(t) for t in tokens):
        return "topic names are '/'-separated tokens of letters, digits and '_', none starting with a digit"
    return None


def xml_name_problem(name: str) -> str | None:
    """Why ``name`` cannot be a BehaviorTree.CPP node ID or port name (an XML name), or None."""
    return None if re.fullmatch(_XML_NAME, name) and not name.lower().startswith("xml") else "it is not an XML name"


def service_name_problem(name: str) -> str | None:
    """Why ``name`` cannot name a Compose service (``[a-zA-Z0-9][a-zA-Z0-9_.-]*``), or None."""
    return None if re.fullmatch(_SERVICE_NAME, name) else "Compose service names are letters, digits, '_', '.' and '-'"


def image_problem(ref: str) -> str | None:
    """Why ``ref`` is not a container image reference (``[host[:port]/]path[:tag][@sha256:…]``,
    lower-case path), or None."""
    return None if re.fullmatch(_IMAGE, ref) else "it is not an image reference such as 'ghcr.io/org/name:1.0'"


def ros_node_name(morphism: str) -> str:
    """The node name derived from a morphism's name when its grounding names none."""
    return morphism.replace("-", "_")
