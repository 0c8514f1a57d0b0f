"""IR expressions back to .cat text (for objectives in reports and synthesised skeletons).

``to_text(parse(x)) `` reads back as the same IR; numbers print exactly (``0.08``,
``(/ 1 3)``), so a printed skeleton loses nothing.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import assert_never

from catc import ir
from catc.ir.numbers import number_text


def _const(e: ir.Const) -> str:
    if isinstance(e.value, bool):
        return "true" if e.value else "false"
    if isinstance(e.value, str):
        return e.value
    return number_text(e.value)


def _call(head: str, args: Iterable[ir.Expr]) -> str:
    return f"({head}{''.join(' ' + to_text(a) for a in args)})"


def to_text(e: ir.Expr) -> str:
    match e:
        case ir.Const():
            return _const(e)
        case ir.ResourceRef() | ir.ParamRef():
            return e.name
        case ir.SetLit():
            return "{" + " ".join(to_text(x) for x in e.elements) + "}"
        case ir.Arith() | ir.BoolOp():
            return _call(e.op.value, e.args)
        case ir.Compare():
            return _call(e.op.value, (e.left, e.right))
        case ir.Ite():
            return _call("if", (e.cond, e.then, e.orelse))
        case ir.Member():
            return _call("member", (e.element, e.set))
        case ir.TotalChurn():
            return "(total-churn)"
        case ir.TotalCost():
            return "(total-cost)"
        case ir.Uses():
            return f"(uses {e.morphism})"
        case ir.ParamValue():
            return f"(param {e.morphism} {e.param})"
        case _:
            assert_never(e)


def effect_text(e: ir.Effect) -> str:
    return f"({e.kind.value} {e.resource} {to_text(e.value)})"
