"""The type checker: AST definitions → categorical IR (:mod:`catc.ir`).

:class:`DomainChecker` resolves imports, sorts, constants, resources, morphisms, holes and
views; :class:`ProblemChecker` checks a problem against its checked domain and yields an
:class:`~catc.ir.Instance`.  Both report every error they find (never only the first) and
return ``None`` when anything was wrong.

The checkers live by part — :mod:`~catc.frontend.check_domain`,
:mod:`~catc.frontend.check_problem`, and what both use in :mod:`~catc.frontend.check_common`
(the grounding annotations: :mod:`~catc.frontend.check_ground`; expressions:
:mod:`~catc.frontend.typecheck`) — and are gathered here, where callers import them from.
"""

from __future__ import annotations

from catc.frontend.check_domain import DomainChecker, split_literals
from catc.frontend.check_problem import ProblemChecker, check_objective_text

__all__ = ["DomainChecker", "ProblemChecker", "check_objective_text", "split_literals"]
