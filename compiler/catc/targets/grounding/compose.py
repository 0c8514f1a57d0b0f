"""compose.yaml: an ordinary Docker Compose file in the style of CORAL.

One service per software component (and per behaviour whose skill has an image), plus the
behaviour-tree executor: each with its ``image``, host networking and IPC (ROS 2 discovery
and shared memory), the generated parameter file mounted read-only and named in ``PARAMS``
(the behaviour tree, ``BT_FILE``, only for the executor that runs it), and ``profiles:`` one
of ``drivers``, ``skillsets`` or ``executors``.  CORAL 2.0 takes a component's role from its
image's labels (``coral.profile``, and ``coral.version`` matching the CLI's major version) and
overwrites ``profiles:`` with it; the file keeps ``profiles:`` for older CORAL.

A service in a profile starts only when its profile is active, and plain ``docker compose
up`` activates none ("no service selected", exit 0).  So the generated ``.env`` beside the
file activates exactly the profiles the composition uses (``COMPOSE_PROFILES=drivers,...``):
Compose reads it from the project folder, and ``docker compose up -d`` there starts every
service of the composition.  The runtime's enactor passes the same profiles as ``--profile``
options, so it never depends on the folder it runs in.  Topic remappings go to the node's
command line (``--ros-args -r FROM:=TO``).
"""

from __future__ import annotations

from typing import Any

from catc.ir.grounding import Profile
from catc.targets.grounding.resolve import Grounded, Service
from catc.targets.grounding.yamlio import dump

#: Where the generated files appear inside every container.
MOUNT = "/catc"


def _service(service: Service) -> dict[str, Any]:
    doc: dict[str, Any] = {"image": service.image, "network_mode": "host", "ipc": "host"}
    environment = {"PARAMS": f"{MOUNT}/params.yaml"}
    volumes = [f"./params.yaml:{MOUNT}/params.yaml:ro"]
    if service.profile is Profile.EXECUTORS:  # the one that runs the behaviour tree
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
    return {
        "name": grounded.project,
        "services": {s.name: _service(s) for s in grounded.services},
    }


def compose_yaml(grounded: Grounded) -> str:
    return dump(compose_document(grounded))


def profiles(grounded: Grounded) -> list[str]:
    """The profiles the composition's services are in, in CORAL's start order."""
    used = {s.profile for s in grounded.services}
    return [p.value for p in Profile if p in used]


def compose_env(grounded: Grounded) -> str:
    """``.env``: the profiles that ``docker compose up`` in the folder activates."""
    return f"COMPOSE_PROFILES={','.join(profiles(grounded))}\n"
