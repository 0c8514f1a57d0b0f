"""compose.yaml: an ordinary Docker Compose file in the style of CORAL.

One service per software component (and per behaviour whose skill has an image), plus the
behaviour-tree executor: each with its ``image``, host networking and IPC (ROS 2 discovery
and shared memory), the generated parameter file and behaviour tree mounted read-only and
named in ``PARAMS`` and ``BT_FILE``, and ``profiles:`` one of ``drivers``, ``skillsets`` or
``executors``.  CORAL 2.0 takes a component's role from its image's labels
(``coral.profile``, and ``coral.version`` matching the CLI's major version) and overwrites
``profiles:`` with it; the file keeps ``profiles:`` for older CORAL and for plain
``docker compose --profile``.  Topic remappings go to the node's command line
(``--ros-args -r FROM:=TO``).
"""

from __future__ import annotations

from typing import Any

from catc.targets.grounding.resolve import Grounded, Service
from catc.targets.grounding.yamlio import dump

#: Where the generated files appear inside every container.
MOUNT = "/catc"


def _service(service: Service, has_tree: bool) -> dict[str, Any]:
    doc: dict[str, Any] = {"image": service.image, "network_mode": "host", "ipc": "host"}
    environment = {"PARAMS": f"{MOUNT}/params.yaml"}
    volumes = [f"./params.yaml:{MOUNT}/params.yaml:ro"]
    if has_tree:
        environment["BT_FILE"] = f"{MOUNT}/bt.xml"
        volumes.append(f"./bt.xml:{MOUNT}/bt.xml:ro")
    doc["environment"] = environment
    doc["volumes"] = volumes
    args = []
    if service.node is not None:
        args = ["--ros-args", "-r", f"__node:={service.node}", "--params-file", f"{MOUNT}/params.yaml"]
        for old, new in service.remap:
            args += ["-r", f"{old}:={new}"]
    if args:
        doc["command"] = args
    doc["profiles"] = [service.profile.value]
    doc["restart"] = "unless-stopped"
    return doc


def compose_document(grounded: Grounded) -> dict[str, Any]:
    has_tree = bool(grounded.behaviours)
    return {
        "name": grounded.project,
        "services": {s.name: _service(s, has_tree) for s in grounded.services},
    }


def compose_yaml(grounded: Grounded) -> str:
    return dump(compose_document(grounded))
