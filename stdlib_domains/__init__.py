"""The standard library of .cat domains, importable by name with ``(:import NAME)``.

Each ``NAME.cat`` file in this folder defines ``(domain NAME)``.  Adding a domain: one file
here and one line in :data:`DOMAINS` (``tests/test_where_things_go.py`` checks that the two
agree and that each file defines the domain it is named after).
"""

#: name → what the domain holds (the first line of its file says it too)
DOMAINS: dict[str, str] = {
    "compute": "the computational partial state: processor cores, memory, GPU memory",
    "compute-boards": "compute modules that add CPU cores, memory and disk to the robot",
    "detectors": "closed-set object detectors on any image topic",
    "electromechanical": "the robot's body as resources",
    "external": "the external partial state: what the world and the mission give",
    "information": "the informational partial state: what is published",
    "mobility": "SLAM and the behaviours of a mobile robot",
    "perception": "detection resources and a generic open-vocabulary detector",
    "robot-base": "resources shared by every robot model in this repository",
    "sensors": "cameras and LiDARs with their ROS 2 drivers",
    "speech": "a microphone and speaker, speech-to-text and text-to-speech",
    "vlm": "vision-language models that describe a scene from an image topic",
}
