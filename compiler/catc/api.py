"""The Python API, at its public address: ``from catc.api import load``.

Everything lives in :mod:`catc.interfaces.api`; this module names what programs may rely on
(docs/api.md).  The second group is what a program embedding catc (the runtime, catrt) uses
besides the IR (:mod:`catc.ir`) and plans (:mod:`catc.semantics.plan`).
"""

from typing import TYPE_CHECKING

from catc.interfaces.api import (
    CatError,
    Definition,
    Model,
    Section,
    Token,
    TokenError,
    composed,
    convert,
    deploy_query,
    deployment,
    diagram,
    diff_artifacts,
    initial_state,
    load,
    loads,
    outline,
    problem_source,
    read_grounding,
    read_plan,
    refuted,
    relax_weights,
    stopped_early,
    text_cache,
    tokens,
    validate,
    warm_start,
    write_files,
)
from catgrammar.limits import Limits

if TYPE_CHECKING:  # the types some of them return, for annotations (no import at run time)
    from catc.queries.diagnose import Diagnosis
    from catc.queries.recompose import Recomposition
    from catc.queries.relax import RelaxResult
    from catc.queries.solve import WarmStart
    from catc.targets.grounding.diff import GroundDiff

__all__ = [
    "CatError",
    "Definition",
    "Diagnosis",
    "GroundDiff",
    "Limits",
    "Model",
    "Recomposition",
    "RelaxResult",
    "Section",
    "Token",
    "TokenError",
    "WarmStart",
    "composed",
    "convert",
    "deploy_query",
    "deployment",
    "diagram",
    "diff_artifacts",
    "initial_state",
    "load",
    "loads",
    "outline",
    "problem_source",
    "read_grounding",
    "read_plan",
    "refuted",
    "relax_weights",
    "stopped_early",
    "text_cache",
    "tokens",
    "validate",
    "warm_start",
    "write_files",
]
