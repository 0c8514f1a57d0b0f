"""Checks of the grounding artifacts by the rules of the programs that read them, written
independently of catc's writers (catc.targets.grounding).

* :func:`rcl_params` — ROS 2's C parameter-file parser (rcl_yaml_param_parser, parse.c):
  the map levels (node namespaces, a node name, ``ros__parameters``, parameter namespaces),
  node-name validation (rmw), the value typing of ``get_value`` (Booleans ``y``/``yes``/
  ``on``..., ``strtol`` base-0 integers, ``strtod`` doubles, quoted scalars are strings),
  homogeneous sequences, no aliases, no empty plain values.  Returns the typed parameters
  per node, or raises :class:`RclError` with rcl's complaint.
* :func:`compose_errors` — the compose-spec JSON schema (as check-jsonschema ships it),
  with jsonschema's Draft7Validator, plus what the schema does not require.
* :func:`bt_errors` — BehaviorTree.CPP 4's file structure, ports declared in the
  TreeNodesModel, and blackboard keys read only after they are written.
"""

from __future__ import annotations

import functools
import json
import re
import xml.etree.ElementTree as ET
from importlib import resources

import yaml

# ---------------------------------------------------------------- rcl's parameter files


class RclError(ValueError):
    pass


_TRUE = {"Y", "y", "yes", "Yes", "YES", "true", "True", "TRUE", "on", "On", "ON"}
_FALSE = {"N", "n", "no", "No", "NO", "false", "False", "FALSE", "off", "Off", "OFF"}
_SPECIAL_FLOATS = {".nan", ".NaN", ".NAN", ".inf", ".Inf", ".INF", "+.inf", "+.Inf", "+.INF", "-.inf", "-.Inf", "-.INF"}


def _strtol(text: str) -> int | None:
    """C's strtol(text, &end, 0) consuming all of ``text``, else None."""
    m = re.fullmatch(r"\s*([+-]?)(0[xX][0-9a-fA-F]+|0[0-7]*|[1-9][0-9]*)", text)
    if not m:
        return None
    sign, digits = m.groups()
    if digits.lower().startswith("0x"):
        value = int(digits, 16)
    elif digits.startswith("0") and len(digits) > 1:
        value = int(digits, 8)
    else:
        value = int(digits)
    value = -value if sign == "-" else value
    return value if -(2**63) <= value < 2**63 else None  # errno ERANGE


def _strtod(text: str) -> float | None:
    """C's strtod consuming all of ``text``, else None (decimal, hex, inf, nan)."""
    t = text.strip()
    if re.fullmatch(r"[+-]?(inf|infinity|nan)(\(\w*\))?", t, re.IGNORECASE):
        return float(re.sub(r"\(.*\)", "", t).lower().replace("infinity", "inf"))
    if re.fullmatch(r"[+-]?0[xX]([0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)([pP][+-]?\d+)?", t):
        return float.fromhex(t)
    if re.fullmatch(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?", t):
        return float(t)
    return None


def rcl_value(text: str, quoted: bool) -> object:
    """get_value: the type rcl gives a scalar."""
    if quoted:
        return text
    if text in _TRUE:
        return True
    if text in _FALSE:
        return False
    as_int = _strtol(text)
    if as_int is not None and text:
        return as_int
    if text in _SPECIAL_FLOATS:
        return float(text.replace(".", "").lower())
    as_float = _strtod(text)
    if as_float is not None and text:
        return as_float
    return text


def valid_node_name(name: str) -> bool:
    """rmw_validate_node_name."""
    return bool(re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name)) and len(name) <= 255


def _validate_name(path: str) -> None:
    if path == "/**":
        return
    namespace, _, node = path.rpartition("/")
    if namespace and namespace != "/**":
        tokens = namespace.strip("/").split("/")
        if not all(re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", t) for t in tokens):
            raise RclError(f"invalid namespace {namespace!r}")
    if node != "*" and not valid_node_name(node):
        raise RclError(f"invalid node name {node!r}")


@functools.cache
def real_rcl_checker() -> str | None:
    """The path of ``ros2-params-check`` — the real rcl parser (rcl_yaml_param_parser) with
    rclcpp's load rules, built from shared/tools/ros2-params — or None where it is absent:
    ``$CATC_ROS2_PARAMS_CHECK``, else on PATH, else built once from ``../shared/tools``
    beside the repository (gcc and libyaml-dev needed)."""
    return _find_real_rcl()


def _find_real_rcl() -> str | None:
    import os
    import shutil
    import subprocess
    import tempfile
    from pathlib import Path

    given = os.environ.get("CATC_ROS2_PARAMS_CHECK")
    if given:
        return given
    found = shutil.which("ros2-params-check")
    if found:
        return found
    tools = Path(__file__).resolve().parents[2] / "shared" / "tools" / "ros2-params"
    if not (tools / "build.sh").exists() or shutil.which("gcc") is None:
        return None
    out = Path(tempfile.mkdtemp(prefix="ros2-params-"))
    proc = subprocess.run(["bash", str(tools / "build.sh"), str(out)], capture_output=True, cwd=out)
    binary = out / "ros2-params-check"
    return str(binary) if proc.returncode == 0 and binary.exists() else None


def rcl_checker_name() -> str:
    """Which checker :func:`rcl_params` uses here (the tests' report header says it)."""
    real = real_rcl_checker()
    return f"the real rcl parser with rclcpp's load rules ({real})" if real else "the re-implemented rcl rules"


_RCL_TYPES = {"bool", "int64", "double", "string", "bool_array", "int64_array", "double_array", "string_array"}


def real_rcl_params(text: str, checker: str) -> dict[str, dict[str, object]]:
    """:func:`rcl_params`, answered by the real parser: the file is written and checked."""
    import json
    import subprocess
    import tempfile

    with tempfile.NamedTemporaryFile("w", suffix=".yaml", encoding="utf-8", delete=False) as fh:
        fh.write(text)
    proc = subprocess.run([checker, fh.name], capture_output=True, text=True)
    first = proc.stdout.splitlines()[0] if proc.stdout else proc.stderr
    if proc.returncode != 0 or not first.startswith("ACCEPTED"):
        raise RclError(first.split(": ", 1)[-1] if "REJECTED" in first else first)
    out: dict[str, dict[str, object]] = {}
    for line in proc.stdout.splitlines()[1:]:
        node, name, kind, value = line[1:].split("\t", 3)
        assert kind in _RCL_TYPES, line
        out.setdefault(node, {})[name] = json.loads(value)
    return out


def rcl_params(text: str) -> dict[str, dict[str, object]]:
    """The parameters per node (full node path → name → typed value), as rcl reads them:
    by the real parser where it is here (:func:`real_rcl_checker`), else by the rules
    re-implemented below."""
    checker = real_rcl_checker()
    if checker is not None:
        return real_rcl_params(text, checker)
    return reimplemented_rcl_params(text)


def reimplemented_rcl_params(text: str) -> dict[str, dict[str, object]]:
    """rcl's rules re-implemented (where the real parser cannot be built)."""
    for event in yaml.parse(text):
        if isinstance(event, yaml.AliasEvent):
            raise RclError("Will not support aliasing")
        if isinstance(event, (yaml.MappingStartEvent, yaml.SequenceStartEvent, yaml.ScalarEvent)) and event.anchor:
            raise RclError("anchors are aliases' other half: rcl refuses files that need them")
    doc = yaml.compose(text)
    if doc is None:
        return {}
    out: dict[str, dict[str, object]] = {}
    _node_level(doc, [], out)
    return out


def _node_level(node: yaml.Node, names: list[str], out: dict) -> None:
    if not isinstance(node, yaml.MappingNode):
        raise RclError(f"Cannot have a value before ros__parameters at line {node.start_mark.line + 1}")
    for key, value in node.value:
        if not isinstance(key, yaml.ScalarNode) or not key.value:
            raise RclError(f"No key at line {key.start_mark.line + 1}")
        if key.value.startswith("ros__parameters"):
            if not names:
                raise RclError(f"There are no node names before ros__parameters at line {key.start_mark.line + 1}")
            path = "/".join(names)
            path = path if path.startswith("/") else "/" + path
            _validate_name(path if names[0] != "/**" else "/".join(names))
            params = out.setdefault("/".join(names), {})
            _params_level(value, [], params)
        else:
            _node_level(value, [*names, key.value], out)


def _params_level(node: yaml.Node, prefix: list[str], params: dict) -> None:
    if not isinstance(node, yaml.MappingNode):
        raise RclError(f"ros__parameters must be a map (line {node.start_mark.line + 1})")
    for key, value in node.value:
        if not isinstance(key, yaml.ScalarNode):
            raise RclError(f"Sequences cannot be key at line {key.start_mark.line + 1}")
        name = ".".join([*prefix, key.value])
        if isinstance(value, yaml.MappingNode):
            _params_level(value, [*prefix, key.value], params)
        elif isinstance(value, yaml.SequenceNode):
            items = [_scalar(v) for v in value.value]
            if len({type(v) for v in items}) > 1:
                raise RclError(f"Sequence should be of same type at line {value.start_mark.line + 1}")
            params[name] = items
        else:
            params[name] = _scalar(value)


def _scalar(node: yaml.Node) -> object:
    if not isinstance(node, yaml.ScalarNode):
        raise RclError(f"nested sequences are not parameters (line {node.start_mark.line + 1})")
    quoted = node.style in ("'", '"')
    if not quoted and node.value == "":
        raise RclError(f"No value at line {node.start_mark.line + 1}")
    return rcl_value(node.value, quoted)


# ---------------------------------------------------------------- Compose


def compose_schema() -> dict:
    """The compose-spec JSON schema as check-jsonschema vendors it (not copied here)."""
    base = resources.files("check_jsonschema") / "builtin_schemas" / "vendor" / "compose-spec.json"
    return json.loads(base.read_text(encoding="utf-8"))


def compose_errors(text: str) -> list[str]:
    from jsonschema import Draft7Validator

    doc = yaml.safe_load(text)
    errors = [
        f"{'/'.join(map(str, e.absolute_path))}: {e.message}"
        for e in Draft7Validator(compose_schema()).iter_errors(doc)
    ]
    for name, service in (doc.get("services") or {}).items():  # what the schema does not require
        if not service.get("image"):
            errors.append(f"{name}: no image")
        if service.get("network_mode") != "host" or service.get("ipc") != "host":
            errors.append(f"{name}: not on the host's network and IPC")
        profiles = service.get("profiles") or []
        if len(profiles) != 1 or profiles[0] not in ("drivers", "skillsets", "executors"):
            errors.append(f"{name}: profiles {profiles} is not one of drivers/skillsets/executors")
        if "PARAMS" not in (service.get("environment") or {}):
            errors.append(f"{name}: no PARAMS")
        command = service.get("command")
        if command is not None:  # a ROS 2 node: its name and its parameter file, as rcl reads arguments
            nodes = [a for a in command if a.startswith("__node:=")]
            if command[:1] != ["--ros-args"] or len(nodes) != 1 or "--params-file" not in command:
                errors.append(f"{name}: the command is not --ros-args with one __node:= and a --params-file")
            for i, arg in enumerate(command):
                if arg == "-r" and (i + 1 == len(command) or ":=" not in command[i + 1]):
                    errors.append(f"{name}: -r without FROM:=TO")
    return errors


# ---------------------------------------------------------------- BehaviorTree.CPP

_CONTROL = {"Sequence", "Parallel", "Fallback", "ReactiveSequence", "ReactiveFallback", "SequenceWithMemory"}
# BT.CPP 4's built-in leaves (registered by every BehaviorTreeFactory; never in a TreeNodesModel).
_BUILTIN_LEAVES = {"AlwaysSuccess", "AlwaysFailure"}
_KEY = re.compile(r"^\{([A-Za-z_][A-Za-z0-9_]*)\}$")


def bt_errors(text: str) -> list[str]:
    root = ET.fromstring(text)
    errors: list[str] = []
    if root.tag != "root" or root.get("BTCPP_format") != "4":
        errors.append('the root is not <root BTCPP_format="4">')
    trees = root.findall("BehaviorTree")
    if len(trees) != 1 or root.get("main_tree_to_execute") != trees[0].get("ID"):
        errors.append("not exactly one BehaviorTree, named by main_tree_to_execute")
    if trees and len(list(trees[0])) != 1:
        errors.append("a BehaviorTree must have exactly one child")
    if list(root)[-1].tag != "TreeNodesModel":
        errors.append("the TreeNodesModel is not last")
    model = {a.get("ID"): {(p.tag, p.get("name")) for p in a} for a in root.iter("Action")}
    written: set[str] = set()
    for tree in trees:
        for node in tree.iter():
            if node.tag in _CONTROL or node.tag in _BUILTIN_LEAVES or node is tree:
                continue
            if node.tag not in model:
                errors.append(f"{node.tag} is not declared in the TreeNodesModel")
                continue
            for attr, value in node.attrib.items():
                direction = {d for d, n in model[node.tag] if n == attr}
                if not direction:
                    errors.append(f"{node.tag}.{attr} is not a declared port")
                key = _KEY.match(value)
                if key and "input_port" in direction and key.group(1) not in written:
                    errors.append(f"{node.tag}.{attr} reads {{{key.group(1)}}} before anything writes it")
            for attr, value in node.attrib.items():
                key = _KEY.match(value)
                if key and any(d == "output_port" and n == attr for d, n in model[node.tag]):
                    written.add(key.group(1))
    return errors


def bt_loads_in_btcpp(text: str) -> None:
    """Register every custom node name, then the tree, with the real BehaviorTree.CPP parser
    (PyPI behaviortreepy), which runs BT.CPP's own XML verification; raises its error."""
    import behaviortreepy as bt

    factory = bt.BehaviorTreeFactory()
    root = ET.fromstring(text)
    for action in root.iter("Action"):
        factory.register_simple_action(action.get("ID"), lambda node: bt.NodeStatus.SUCCESS)
    factory.register_behavior_tree_from_text(text)
