"""params.yaml: one ROS 2 parameter file for every node of the deployment.

The layout is the one ROS 2's C parser (rcl) reads for a launch of many nodes::

    /**:
      camera_driver:
        ros__parameters:
          image_topic: image_raw
          memory_gb: 0.5

(rclpy's own Python loader refuses this nested form; rcl's, which every node uses when it
is given ``--params-file``, accepts it.)  Values keep their types: a real θ is a double
(``0.5``, never ``0``), an int θ an integer, a symbol a string, a set of symbols a list of
strings.  A node without parameters still gets an empty ``ros__parameters``.
"""

from __future__ import annotations

from typing import Any

from catc.targets.grounding.resolve import Grounded
from catc.targets.grounding.yamlio import dump


def params_document(grounded: Grounded) -> dict[str, Any]:
    nodes: dict[str, Any] = {}
    for service in grounded.services:
        if service.node is None:
            continue
        nodes[service.node] = {"ros__parameters": dict(service.params)}
    return {"/**": nodes}


def params_yaml(grounded: Grounded) -> str:
    return dump(params_document(grounded))
