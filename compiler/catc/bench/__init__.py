"""``catc bench``: catc and ENHSP side by side on the same problems, in one run (issue 5).

Every trial runs each tool as a fresh process (``python -m catc ...``; ``java -jar enhsp.jar``
through :func:`catc.targets.enhsp.run_enhsp`), interleaved problem by problem, so both pay
their process start-up and see the same machine load.  Wall times are summarised by the
median and the interquartile range; ENHSP's own ``Planning Time (msec)`` is reported beside
its wall time.

Outcome markers are judged against the hand-derived expectations in the examples'
``expect.toml`` (``status``, ``optimum``, ``recompose_*``), with exact rational arithmetic:

* ``SAT`` / ``UNSAT`` — a satisfaction answer (``✗`` appended when it contradicts expect.toml);
* ``OPT`` — a composition whose objective value *equals* the known optimum;
* ``SUBOPT`` — a valid composition whose objective value is worse (e.g. ENHSP on a grid that
  misses the optimum, or with no metric exported);
* ``BETTER ✗`` — a value better than the known optimum (a bug in a tool or in expect.toml);
* ``INVALID`` — an ENHSP plan catc's validator rejects; ``TIMEOUT``; ``ERR``.

ENHSP's plan is read back through the export's ground-action names and replayed by catc's
independent validator (sequential semantics); its objective value is computed from the
validated final state, so the marker does not depend on how (or whether) the export maps
the metric.

Tables: runtimes; one-edit perturbations with model-edit line counts; lifelong queries
(diagnose, relax by bisection for ENHSP, recompose); a capability line for SMTPlan+ (run only
when an ``SMTPlan`` binary is on PATH).

The modules, one job each (nothing outside this package imports it):

* :mod:`~catc.bench.stats` — quartiles, outcome markers (SAT/UNSAT/OPT/SUBOPT...), exact values as text;
* :mod:`~catc.bench.lines` — model-edit line counts: comments and blanks dropped, difflib diffs;
* :mod:`~catc.bench.problems` — the benchmark problems, their grids, their expectations (expect.toml);
* :mod:`~catc.bench.runners` — one tool run as a process: catc, ENHSP (plan replayed by catc), SMTPlan+;
* :mod:`~catc.bench.machine` — the processor, Java and ENHSP the figures were measured with;
* :mod:`~catc.bench.session` — the runtime and perturbation trials, interleaved, and their rows;
* :mod:`~catc.bench.lifelong` — the lifelong-queries rows (diagnose, relax, recompose);
* :mod:`~catc.bench.tables` — the Markdown tables and the JSON document;
* :mod:`~catc.bench.corpus` — ``--corpus wheel``: unified-planning's wheel and the counters/sailing families;
* :mod:`~catc.bench.planning` — ``--corpus planning``: the planning corpus, its hand counts, its table;
* :mod:`~catc.bench.cli` — the ``catc bench`` command.
"""
