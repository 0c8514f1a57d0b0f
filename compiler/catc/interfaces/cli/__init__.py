"""The ``catc`` command line (click).

* :mod:`.group`: the ``catc`` group (:data:`main`), loading each command on first use;
* :mod:`.options`: the queries' commands, built from each query's options;
* :mod:`.targets`: the targets' commands (``catc export NAME``, ``catc compile``), built from
  each target's options, and the route they take; :mod:`.ground`: ``catc ground``'s own;
* :mod:`.check`: ``catc check``.

Exit codes (docs/cli.md): 0 success; 1 model errors (``check``) or infeasible (queries);
2 usage or unreadable input (and, for queries, any input error); 3 the solver gave up.
No command lets a Python traceback reach the user for bad input.
"""

from __future__ import annotations

from catc.interfaces.cli.group import LAZY_COMMANDS, main
from catc.interfaces.cli.options import click_params, limit_options, limited, query_command, raw_values

__all__ = ["LAZY_COMMANDS", "click_params", "limit_options", "limited", "main", "query_command", "raw_values"]

if __name__ == "__main__":  # pragma: no cover
    main()
