"""The targets: what a checked model is turned into for other tools (DESIGN §6).

Each target is one module defining ``TARGET`` (:mod:`catc.targets.base`) and one line in
:mod:`catc.targets.registry`: ``pddl`` (:mod:`catc.targets.pddl_target`; PDDL 2.1 in
:mod:`catc.targets.pddl_exporter`, PDDL+ in :mod:`catc.targets.pddlplus`, what both share in
:mod:`catc.targets.pddl_base`), ``pddlplus``, ``smt2`` (``catc compile``) and ``ground``
(:mod:`catc.targets.ground` over :mod:`catc.targets.grounding`).  :mod:`catc.targets.enhsp`
runs the ENHSP planner (the ``baselines`` extra: ``pip install 'catc-lang[baselines]'``, and
Java 17).
"""

BASELINES_HINT = "install the baselines extra: pip install 'catc-lang[baselines]'"
