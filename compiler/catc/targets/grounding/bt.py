"""bt.xml: the behaviour tree for BehaviorTree.CPP 4.

``<root BTCPP_format="4" main_tree_to_execute="MainTree">`` holds one ``<BehaviorTree>``
whose single child is a ``Sequence`` of the composition's behaviour steps in plan order (an
``AlwaysSuccess`` when the composition has no behaviour);
behaviours that run in one step (⊗) go under a ``Parallel`` that succeeds when all of them
do.  Ports are attributes, ``{key}`` for a blackboard entry.  A ``<TreeNodesModel>`` comes
last and declares every node's ports, as Groot2 and BT.CPP's own checks need.  Built with
ElementTree, so no text from the model reaches the file unescaped.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

from catc.targets.grounding.resolve import BehaviorNode, Grounded

TREE_ID = "MainTree"


def _node(parent: ET.Element, node: BehaviorNode) -> None:
    ET.SubElement(parent, node.node_id, dict(node.inputs + node.outputs))


def _model(root: ET.Element, grounded: Grounded) -> None:
    model = ET.SubElement(root, "TreeNodesModel")
    ports: dict[str, dict[str, str]] = {}
    for step in grounded.behaviours:
        for node in step:
            declared = ports.setdefault(node.node_id, {})
            declared.update({name: "input_port" for name, _ in node.inputs})
            declared.update({name: "output_port" for name, _ in node.outputs})
    for node_id in sorted(ports):
        action = ET.SubElement(model, "Action", {"ID": node_id})
        for name, direction in sorted(ports[node_id].items()):
            ET.SubElement(action, direction, {"name": name})


def bt_xml(grounded: Grounded) -> str:
    root = ET.Element("root", {"BTCPP_format": "4", "main_tree_to_execute": TREE_ID})
    tree = ET.SubElement(root, "BehaviorTree", {"ID": TREE_ID})
    if not grounded.behaviours:  # a tree needs one child; nothing to do succeeds at once
        ET.SubElement(tree, "AlwaysSuccess")
    sequence = ET.SubElement(tree, "Sequence") if grounded.behaviours else tree
    for step in grounded.behaviours:
        if len(step) == 1:
            _node(sequence, step[0])
            continue
        parallel = ET.SubElement(sequence, "Parallel", {"success_count": str(len(step)), "failure_count": "1"})
        for node in step:
            _node(parallel, node)
    _model(root, grounded)
    ET.indent(root)
    return ET.tostring(root, encoding="unicode") + "\n"
