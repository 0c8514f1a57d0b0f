"""Grounding: from a composition to the artifacts a robot runs.

:func:`~catc.targets.grounding.resolve.ground` resolves every activation's grounding
annotation against the composition; the writers turn the result into instructions.md
(hardware steps for a person), compose.yaml (Docker Compose, CORAL style), params.yaml (ROS 2
parameters), bt.xml (BehaviorTree.CPP 4) and manifest.json (the plan, the model's hash, every
artifact's sha256); :mod:`~catc.targets.grounding.diff` says what changes on the robot
between two compositions.  Structured formats are built as data and serialised by libraries
(PyYAML, ElementTree), never from text templates.
"""
