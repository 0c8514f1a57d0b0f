"""The categorical IR: the checked, typed, immutable model every later stage consumes.

Objects of the category are tensor products of resources (:class:`Resource`); generators
are :class:`Morphism` s with typed preconditions and effects; a :class:`View` is a
monoidal functor that sends dropped resources to the unit (see :mod:`catc.ir.views`).  The IR
knows nothing of the parse tree; spans are kept only so that answers and diagnostics can
point back at the source.

Numbers are :class:`fractions.Fraction` everywhere.

The classes live by part — :mod:`~catc.ir.sorts`, :mod:`~catc.ir.expr` (expressions and
their walks), :mod:`~catc.ir.decls` (a domain's declarations), :mod:`~catc.ir.model`
(domain, problem, instance) — and are gathered here, as before, for ``from catc import ir``.
"""

from catc.ir.decls import (
    EMPTY,
    Constant,
    Effect,
    EffectKind,
    Hole,
    Literal,
    Morphism,
    MorphismKind,
    Param,
    Resource,
    View,
    frozen,
)
from catc.ir.expr import (
    Arith,
    ArithOp,
    BoolOp,
    BoolOpKind,
    CmpOp,
    Compare,
    Const,
    Expr,
    Ite,
    Member,
    ParamRef,
    ParamValue,
    ResourceRef,
    SetLit,
    TotalChurn,
    TotalCost,
    Uses,
    children,
    params_in,
    resources_in,
    walk,
)
from catc.ir.label import Label, LabelKind
from catc.ir.model import (
    Domain,
    InitValue,
    Instance,
    Metric,
    MetricMode,
    Objective,
    Problem,
    Sense,
    Soft,
)
from catc.ir.sorts import (
    BOOL,
    INT,
    REAL,
    Sort,
    SortKind,
    set_of,
)
from catgrammar.record import Record  # noqa: F401  # the records' base, for code that enumerates them

__all__ = [
    "BOOL",
    "EMPTY",
    "INT",
    "REAL",
    "Arith",
    "ArithOp",
    "BoolOp",
    "BoolOpKind",
    "CmpOp",
    "Compare",
    "Const",
    "Constant",
    "Domain",
    "Effect",
    "EffectKind",
    "Expr",
    "Hole",
    "InitValue",
    "Instance",
    "Ite",
    "Label",
    "LabelKind",
    "Literal",
    "Member",
    "Metric",
    "MetricMode",
    "Morphism",
    "MorphismKind",
    "Objective",
    "Param",
    "ParamRef",
    "ParamValue",
    "Problem",
    "Resource",
    "ResourceRef",
    "Sense",
    "SetLit",
    "Soft",
    "Sort",
    "SortKind",
    "TotalChurn",
    "TotalCost",
    "Uses",
    "View",
    "children",
    "frozen",
    "params_in",
    "resources_in",
    "set_of",
    "walk",
]
