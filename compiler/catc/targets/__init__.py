"""Export to other planners' formats and the baseline harness (DESIGN §6).

``catc export pddl`` (:mod:`catc.targets.pddl`, :mod:`catc.interfaces.export_cli`) writes PDDL 2.1
numeric domain and problem files with an export report; :mod:`catc.targets.enhsp` runs the
ENHSP planner (the ``baselines`` extra: ``pip install 'catc-lang[baselines]'``, and Java 17).
"""

BASELINES_HINT = "install the baselines extra: pip install 'catc-lang[baselines]'"
